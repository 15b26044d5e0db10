#include "runtime/output_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "runtime/output_check.h"

namespace dynapath::runtime {
namespace {

namespace fs = std::filesystem;

std::string Reason(int error) { return std::strerror(error); }

Error LockError(const std::string& option, const std::string& detail) {
  return Error("option --" + option + ": " + detail, Error::Code::kInvalidArgument, option);
}

// What the holder wrote into the lock file: "pid P (COMMAND)", or what can
// be said without it.
std::string Holder(int fd) {
  std::string text(2048, '\0');
  const ssize_t n = pread(fd, text.data(), text.size(), 0);
  text.resize(n > 0 ? static_cast<size_t>(n) : 0);
  std::istringstream in(text);
  std::string pid, command;
  std::getline(in, pid);
  std::getline(in, command);
  if (pid.empty()) return "another process (it has not written its pid yet)";
  return "pid " + pid + (command.empty() ? "" : " (" + command + ")");
}

bool SameFile(int fd, const std::string& path) {
  struct stat open_file {
  }, named{};
  return fstat(fd, &open_file) == 0 && stat(path.c_str(), &named) == 0 &&
         open_file.st_dev == named.st_dev && open_file.st_ino == named.st_ino;
}

}  // namespace

std::string OwnCommandLine() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string line;
  size_t begin = 0;
  for (size_t end = text.find('\0'); end != std::string::npos; end = text.find('\0', begin)) {
    std::string arg = text.substr(begin, end - begin);
    begin = end + 1;
    if (line.empty()) arg = fs::path(arg).filename().string();  // "dynapath", not its path
    for (char& c : arg) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    if (arg.empty() || arg.find_first_of(" '\"") != std::string::npos) arg = "'" + arg + "'";
    line += (line.empty() ? "" : " ") + arg;
  }
  if (line.size() > 1000) line = line.substr(0, 997) + "...";
  return line;
}

Result<OutputLock> OutputLock::Acquire(const std::string& dir, const std::string& option) {
  if (Status status = PrepareOutputDirectory(dir, option); !status) return status.error();
  const std::string path = (fs::path(dir) / kLockFileName).string();
  // A holder that ends removes the file after unlocking it; a lock taken on
  // such a removed file is retried on the new one.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) {
      const int error = errno;
      return LockError(option,
                 dir + ": cannot create its lock file " + kLockFileName + ": " + Reason(error));
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      const std::string holder = Holder(fd);
      close(fd);
      if (error == EWOULDBLOCK) {
        return Error("option --" + option + ": " + dir + " is in use by " + holder +
                         "; wait for it to end or choose another --" + option,
                     Error::Code::kUnavailable, option);
      }
      return LockError(option, dir + ": cannot lock " + path + ": " + Reason(error));
    }
    if (!SameFile(fd, path)) {  // removed by its last holder meanwhile
      close(fd);
      continue;
    }
    const std::string text = std::to_string(getpid()) + "\n" + OwnCommandLine() + "\n";
    if (ftruncate(fd, 0) != 0 ||
        pwrite(fd, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size())) {
      const int error = errno;
      unlink(path.c_str());  // still ours: locked
      close(fd);
      return LockError(option, dir + ": cannot write its lock file: " + Reason(error));
    }
    return OutputLock(fd, path, true);
  }
  return LockError(option, dir + ": its lock file keeps being replaced");
}

Result<OutputLock> LockResultDirectory(const std::string& dir) {
  Result<OutputLock> lock = OutputLock::Acquire(dir, "out");
  if (!lock) return lock;
  if (Status status = CheckOutputFiles(dir, {"results.csv", "results_detailed.csv"}, "out");
      !status) {
    return status.error();
  }
  return lock;
}

Result<OutputLock> OutputLock::Adopt(const std::string& dir, int fd) {
  const std::string path = (fs::path(dir) / kLockFileName).string();
  if (fd < 0 || fcntl(fd, F_GETFD) < 0) {
    return Error::Option("out-lock-fd", std::to_string(fd) + " is not an open descriptor");
  }
  if (!SameFile(fd, path)) {
    return Error::Option("out-lock-fd",
                         std::to_string(fd) + " is not the lock file " + path + " of --out");
  }
  if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
    return Error::Option("out-lock-fd", std::to_string(fd) + ": " + dir + " is in use by " +
                                            Holder(fd) + ", not locked by our launcher");
  }
  fcntl(fd, F_SETFD, FD_CLOEXEC);
  return OutputLock(fd, path, false);
}

OutputLock::OutputLock(OutputLock&& other) noexcept
    : fd_(other.fd_), path_(std::move(other.path_)), owner_(other.owner_) {
  other.fd_ = -1;
}

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    Release();
    fd_ = other.fd_;
    path_ = std::move(other.path_);
    owner_ = other.owner_;
    other.fd_ = -1;
  }
  return *this;
}

OutputLock::~OutputLock() { Release(); }

void OutputLock::Release() {
  if (fd_ < 0) return;
  // Removed while still locked, so no one can lock the old file after it.
  if (owner_ && SameFile(fd_, path_)) unlink(path_.c_str());
  close(fd_);
  fd_ = -1;
}

}  // namespace dynapath::runtime
