#pragma once
// Records the LCM messages of the channels matching a regex into an LCM log
// file (the format LogReader reads; lcm-logger's), without losing any to a
// busy or stopped recorder.
//
// Why not lcm-logger: LCM keeps at most 30 received messages per
// subscription by default and drops the rest, and lcm-logger (LCM 1.3.1)
// does not raise that limit. A logger kept off the CPU for a while on a
// loaded machine then wrote 31 of a run's messages once it ran again: its
// socket held them all, its subscription dropped all but 30. Here the
// subscription's queue is raised as the Bus raises its own, so what the
// socket held is written.

#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>

#include "dynapath/result.h"

namespace dynapath::protocol {

class LogRecorder {
 public:
  // Messages one subscription may hold before LCM drops: as the Bus's.
  static constexpr int kQueueCapacity = 100000;

  // Opens `path` for writing (an existing file is refused unless
  // `overwrite`) and subscribes to `channel_regex` on `lcm`. Errors: a bad
  // regex, a file that exists or cannot be written.
  static Result<std::unique_ptr<LogRecorder>> Open(lcm::LCM& lcm, const std::string& channel_regex,
                                                   const std::string& path, bool overwrite);
  ~LogRecorder();  // unsubscribes and closes the file (flushing it)
  LogRecorder(const LogRecorder&) = delete;
  LogRecorder& operator=(const LogRecorder&) = delete;

  // Writes what was recorded so far through to the file (the launcher
  // watches its size to see the recorder idle). Also reports a write error.
  Status Flush();
  // The first write error (disk full, say); later messages are not written.
  Status status() const;

  int64_t events() const { return events_; }
  int64_t bytes() const { return bytes_; }

 private:
  LogRecorder(lcm::LCM& lcm, std::string path, std::unique_ptr<lcm::LogFile> file)
      : lcm_(lcm), path_(std::move(path)), file_(std::move(file)) {}
  void OnMessage(const lcm::ReceiveBuffer* buffer, const std::string& channel);
  void WriteError(const std::string& what);  // keeps the first

  lcm::LCM& lcm_;
  std::string path_;
  std::unique_ptr<lcm::LogFile> file_;
  lcm::Subscription* subscription_ = nullptr;
  int64_t events_ = 0, bytes_ = 0;
  std::string error_;  // empty: no write error
};

}  // namespace dynapath::protocol
