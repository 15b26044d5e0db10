#pragma once
// A checked reader of LCM log files (what lcm-logger and `dynapath run --log`
// write), used instead of liblcm's: liblcm trusts each event header and
// callocs `datalen + 1` bytes (a length of 0x7fffffff wraps and crashes it),
// and cannot say where a log is broken. Here every header is checked against
// the bytes left in the file and the format's limits before anything is
// read, and a corrupt or truncated log is one error naming the byte offset.
//
// Format (big-endian): per event, sync word 0xEDA1DA01, int64 event number,
// int64 timestamp (microseconds), int32 channel length, int32 data length,
// the channel's bytes, the data's bytes.

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dynapath/result.h"

namespace dynapath::protocol {

struct LogEvent {
  int64_t offset = 0;  // of the event's header in the file
  int64_t number = 0;
  int64_t timestamp = 0;
  std::string channel;
  std::vector<uint8_t> data;
};

class LogReader {
 public:
  // Longest channel name liblcm accepts (LCM_MAX_CHANNEL_NAME_LENGTH).
  static constexpr int32_t kMaxChannelBytes = 63;
  // Largest event: liblcm's udpm provider delivers at most 256 MB.
  static constexpr int32_t kMaxEventBytes = 256 * 1024 * 1024;

  // Errors: the path cannot be opened or is a directory.
  static Result<LogReader> Open(const std::string& path);

  // The next event; nullopt at the end of the log; an error naming the
  // byte offset when the log is corrupt or ends inside an event.
  Result<std::optional<LogEvent>> Next();

  const std::string& path() const { return path_; }
  int64_t size() const { return size_; }

 private:
  struct Closer {
    void operator()(std::FILE* file) const { std::fclose(file); }
  };
  LogReader(std::string path, std::FILE* file, int64_t size)
      : path_(std::move(path)), file_(file), size_(size) {}
  Error Corrupt(int64_t offset, const std::string& what) const;

  std::string path_;
  std::unique_ptr<std::FILE, Closer> file_;
  int64_t size_ = 0;
  int64_t offset_ = 0;
};

}  // namespace dynapath::protocol
