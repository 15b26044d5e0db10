#include "protocol/log_recorder.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <regex>

namespace dynapath::protocol {

Result<std::unique_ptr<LogRecorder>> LogRecorder::Open(lcm::LCM& lcm,
                                                       const std::string& channel_regex,
                                                       const std::string& path, bool overwrite) {
  // LCM matches channels with GLib's (Perl-like) regexes; ECMAScript's
  // syntax is close enough to name a broken pattern before LCM does.
  try {
    std::regex check(channel_regex, std::regex::ECMAScript);
  } catch (const std::regex_error& error) {
    return Error{"the channel pattern '" + channel_regex + "' is not a regular expression (" +
                 error.what() + ")"};
  }
  if (path.empty()) return Error{"the log file name is empty"};
  struct stat info {};
  if (stat(path.c_str(), &info) == 0) {
    if (S_ISDIR(info.st_mode)) return Error{"cannot write the log " + path + ": it is a folder"};
    if (!overwrite) {
      return Error{"the log " + path + " exists; give another name, or --force to overwrite it"};
    }
  }
  errno = 0;
  auto file = std::make_unique<lcm::LogFile>(path, "w");
  if (!file->good()) {
    return Error{"cannot write the log " + path + ": " +
                 (errno != 0 ? std::strerror(errno) : "cannot open it")};
  }
  std::unique_ptr<LogRecorder> recorder(new LogRecorder(lcm, path, std::move(file)));
  recorder->subscription_ = lcm.subscribe(channel_regex, &LogRecorder::OnMessage, recorder.get());
  if (recorder->subscription_ == nullptr) {
    return Error{"cannot subscribe to '" + channel_regex + "'"};
  }
  recorder->subscription_->setQueueCapacity(kQueueCapacity);
  return recorder;
}

LogRecorder::~LogRecorder() {
  if (subscription_ != nullptr) lcm_.unsubscribe(subscription_);
  // The LogFile closes (and so flushes) the file.
}

void LogRecorder::OnMessage(const lcm::ReceiveBuffer* buffer, const std::string& channel) {
  if (!error_.empty()) return;
  lcm::LogEvent event{};
  event.eventnum = events_;  // liblcm numbers the events itself
  event.timestamp = buffer->recv_utime;
  event.channel = channel;
  event.datalen = static_cast<int32_t>(buffer->data_size);
  event.data = buffer->data;
  errno = 0;
  if (file_->writeEvent(&event) != 0) {
    WriteError(errno != 0 ? std::strerror(errno) : "write failed");
    return;
  }
  ++events_;
  bytes_ += buffer->data_size;
}

void LogRecorder::WriteError(const std::string& what) {
  if (error_.empty()) {
    error_ = "cannot write the log " + path_ + ": " + what + " (after " + std::to_string(events_) +
             (events_ == 1 ? " message)" : " messages)");
  }
}

Status LogRecorder::Flush() {
  if (Status written = status(); !written) return written;
  errno = 0;
  if (std::fflush(file_->getFilePtr()) != 0) {
    WriteError(errno != 0 ? std::strerror(errno) : "flush failed");
    return Error{error_};
  }
  return Ok{};
}

Status LogRecorder::status() const {
  if (!error_.empty()) return Error{error_};
  return Ok{};
}

}  // namespace dynapath::protocol
