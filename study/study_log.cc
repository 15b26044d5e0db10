#include "study/study_log.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace dynapath::study {

void StudyLogSink::sink_it_(const spdlog::details::log_msg& message) {
  spdlog::memory_buf_t formatted;
  formatter_->format(message, formatted);
  if (pending_.size() + formatted.size() <= kMaxPending) {
    pending_.append(formatted.data(), formatted.size());
  } else {
    dropped_ += formatted.size();
  }
  WritePending();
}

void StudyLogSink::WritePending() {
  // Whole lines when possible: a short write (the disk filled up inside the
  // line) leaves the rest pending, to follow when there is room again.
  size_t written = 0;
  while (written < pending_.size()) {
    const ssize_t n = ::write(fd_, pending_.data() + written, pending_.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      error_ = errno;
      break;
    }
    written += static_cast<size_t>(n);
  }
  pending_.erase(0, written);
}

StudyLogSink::Missing StudyLogSink::missing() {
  std::lock_guard<std::mutex> lock(mutex_);
  WritePending();
  return Missing{pending_.size(), dropped_, error_};
}

std::string StudyLogSink::MissingText(const std::string& path) {
  const Missing now = missing();
  if (now.pending == 0 && now.dropped == 0) return "";
  return path + ": " + std::to_string(now.pending + now.dropped) +
         " bytes of log lines could not be written: " + std::strerror(now.error);
}

}  // namespace dynapath::study
