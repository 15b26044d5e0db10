#pragma once
// study.log as a spdlog sink that loses nothing silently. spdlog's file
// sink writes through a stdio buffer: when a flush fails (a full disk),
// glibc drops the whole buffer (up to 4 KiB of lines) and the sink throws,
// so the log stopped at the first full page and the lines after it were
// gone without a word. This sink writes each line with write(2) on the
// study's log descriptor (O_APPEND, shared with the components' processes),
// keeps what could not be written (up to 1 MiB) and tries it again with
// every later line and at every flush, and tells the caller what is still
// missing and why.

#include <spdlog/sinks/base_sink.h>

#include <cstddef>
#include <mutex>
#include <string>

namespace dynapath::study {

class StudyLogSink : public spdlog::sinks::base_sink<std::mutex> {
 public:
  // `fd` stays the caller's (not closed here).
  explicit StudyLogSink(int fd) : fd_(fd) {}

  struct Missing {
    size_t pending = 0;  // bytes kept, not written yet
    size_t dropped = 0;  // bytes given up on (beyond the 1 MiB kept)
    int error = 0;       // errno of the last failed write
  };
  // After one more attempt to write what is pending.
  Missing missing();
  // "" when everything was written; otherwise "study.log: 1234 bytes of log
  // lines could not be written: No space left on device".
  std::string MissingText(const std::string& path);

  static constexpr size_t kMaxPending = 1 << 20;

 protected:
  void sink_it_(const spdlog::details::log_msg& message) override;
  void flush_() override { WritePending(); }

 private:
  void WritePending();

  int fd_;
  std::string pending_;
  size_t dropped_ = 0;
  int error_ = 0;
};

}  // namespace dynapath::study
