#include "dynapath/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace dynapath {
namespace {

// "PATH: cannot write: REASON" with the operating system's reason; a file
// that cannot be written is an I/O error whatever the reason (a missing
// folder included).
Error WriteFailure(const std::string& path, int error, const std::string& what = "cannot write") {
  return Error::Io(path + ": " + what + ": " + std::strerror(error));
}

}  // namespace

Result<std::string> ReadTextFile(const std::string& path) {
  struct stat info {};
  if (stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
    return Error::Io(path + ": is a directory, not a file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int error = errno;
    return Error::File(error, path + ": cannot open for reading: " + std::strerror(error));
  }
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad()) return Error::Io(path + ": read error");
  return contents.str();
}

namespace {

Status WriteReplacing(const std::string& path, std::string_view contents, bool durable) {
  // Unique per process and call, so two threads writing one path do not
  // share a temporary file.
  static std::atomic<unsigned> counter{0};
  const std::string temporary =
      path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  struct stat info {};
  if (stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
    return Error::Io(path + ": is a directory, not a file");
  }
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) return WriteFailure(path, errno);
  // Every byte, or the reason it was not written (ENOSPC, EDQUOT, EIO...);
  // close() reports errors of deferred writes too.
  int error = 0;
  size_t written = 0;
  while (written < contents.size()) {
    const ssize_t n = ::write(fd, contents.data() + written, contents.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      error = errno;
      break;
    }
    written += static_cast<size_t>(n);
  }
  // Durable: the bytes reach the disk before the rename makes them the
  // file, so a crash leaves the old file or the new one, never an empty one.
  if (durable && error == 0 && ::fsync(fd) != 0) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) {
    ::unlink(temporary.c_str());
    return WriteFailure(path, error);
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    error = errno;
    ::unlink(temporary.c_str());
    return WriteFailure(path, error, "cannot rename into place");
  }
  if (durable) {  // and the rename itself reaches the disk
    const size_t slash = path.rfind('/');
    const std::string folder = slash == std::string::npos ? "." : path.substr(0, slash + 1);
    const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
      const int synced = ::fsync(dir);
      error = errno;
      ::close(dir);
      if (synced != 0) return WriteFailure(path, error, "cannot sync its folder");
    }
  }
  return Ok{};
}

}  // namespace

Status WriteFileAtomically(const std::string& path, std::string_view contents) {
  return WriteReplacing(path, contents, false);
}

Status WriteFileDurably(const std::string& path, std::string_view contents) {
  return WriteReplacing(path, contents, true);
}

}  // namespace dynapath
