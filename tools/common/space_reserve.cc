#include "tools/common/space_reserve.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <string>

namespace dynapath::cli {

SpaceReserve::SpaceReserve(std::string path, size_t bytes) : path_(std::move(path)) {
  const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return;
  // Real bytes, not a sparse file or fallocate: the space must be taken on
  // every file system.
  const std::string zeros(bytes, '\0');
  size_t written = 0;
  while (written < zeros.size()) {
    const ssize_t n = ::write(fd, zeros.data() + written, zeros.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    written += static_cast<size_t>(n);
  }
  const bool closed = ::close(fd) == 0;
  bytes_ = closed ? written : 0;
  if (bytes_ == 0) ::unlink(path_.c_str());
}

bool SpaceReserve::Release() {
  if (path_.empty()) return false;
  ::unlink(path_.c_str());
  path_.clear();
  const bool held = bytes_ > 0;
  bytes_ = 0;
  return held;
}

}  // namespace dynapath::cli
