#include "launch/private_network.h"

#include <arpa/inet.h>
#include <dirent.h>
#include <fcntl.h>
#include <net/if.h>
#include <net/route.h>
#include <netinet/in.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace dynapath::launch {
namespace {

Error CreateError(const std::string& detail) {
  return Error::Unavailable("cannot create a private network namespace: " + detail);
}

Error SetUpError(const std::string& detail) {
  return Error::Unavailable("cannot set up the private network: " + detail);
}

std::string ErrnoText(int error) { return std::strerror(error); }

// Closes a file descriptor on every return path.
class FdCloser {
 public:
  explicit FdCloser(int fd) : fd_(fd) {}
  FdCloser(const FdCloser&) = delete;
  FdCloser& operator=(const FdCloser&) = delete;
  ~FdCloser() {
    if (fd_ >= 0) close(fd_);
  }

 private:
  int fd_;
};

// The number of threads of this process, or -1 when /proc cannot tell.
int ThreadCount() {
  DIR* dir = opendir("/proc/self/task");
  if (dir == nullptr) return -1;
  int threads = 0;
  while (const dirent* entry = readdir(dir)) {
    if (entry->d_name[0] != '.') ++threads;
  }
  closedir(dir);
  return threads;
}

// The id map files must be written with a single write() call.
Status WriteProcFile(const char* path, const std::string& text) {
  const int fd = open(path, O_WRONLY | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    return Error::File(error, std::string("open ") + path + ": " + ErrnoText(error));
  }
  FdCloser closer(fd);
  const ssize_t written = write(fd, text.data(), text.size());
  if (written < 0) return Error::Io(std::string("write ") + path + ": " + ErrnoText(errno));
  if (static_cast<size_t>(written) != text.size()) {
    return Error::Io(std::string("write ") + path + ": short write");
  }
  return Ok{};
}

std::string UnshareHint(int error) {
  switch (error) {
    case EPERM:
      return " (user namespaces disabled?)";
    case ENOSPC:
    case EUSERS:
      return " (user namespaces disabled, or too many of them?)";
    case EINVAL:
      return " (the process has more than one thread?)";
    default:
      return "";
  }
}

Status CreateNamespaces() {
  // Read before unshare: inside the new user namespace, until the maps are
  // written, our own ids show as the overflow id.
  const uid_t uid = geteuid();
  const gid_t gid = getegid();
  if (unshare(CLONE_NEWUSER | CLONE_NEWNET) == 0) {
    // "deny" must precede gid_map for an unprivileged writer; kernels older
    // than 3.19 have no setgroups file and need nothing.
    if (access("/proc/self/setgroups", F_OK) == 0) {
      if (Status status = WriteProcFile("/proc/self/setgroups", "deny"); !status) {
        return CreateError(status.error().message);
      }
    }
    if (Status status = WriteProcFile("/proc/self/uid_map", "0 " + std::to_string(uid) + " 1");
        !status) {
      return CreateError(status.error().message);
    }
    if (Status status = WriteProcFile("/proc/self/gid_map", "0 " + std::to_string(gid) + " 1");
        !status) {
      return CreateError(status.error().message);
    }
    return Ok{};
  }
  const int error = errno;
  // Root may be barred from user namespaces (sysctl, container policy) yet
  // still hold CAP_SYS_ADMIN for a plain network namespace.
  if (uid == 0 && (error == EPERM || error == ENOSPC || error == EUSERS)) {
    if (unshare(CLONE_NEWNET) == 0) return Ok{};
    const int net_error = errno;
    return CreateError("unshare: " + ErrnoText(error) + UnshareHint(error) +
                       "; without a user namespace: unshare: " + ErrnoText(net_error));
  }
  return CreateError("unshare: " + ErrnoText(error) + UnshareHint(error));
}

// Brings lo up with multicast and routes 224.0.0.0/4 through it. Multicast
// needs both: a new namespace's lo is down and has no multicast route, so an
// LCM udpm socket there could neither join its group nor send to it.
Status ConfigureLoopback() {
  const int sock = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (sock < 0) return SetUpError("socket: " + ErrnoText(errno));
  FdCloser closer(sock);

  ifreq request{};
  std::strncpy(request.ifr_name, "lo", IFNAMSIZ - 1);
  if (ioctl(sock, SIOCGIFFLAGS, &request) < 0) {
    return SetUpError("reading the flags of lo (SIOCGIFFLAGS): " + ErrnoText(errno));
  }
  request.ifr_flags = static_cast<short>(request.ifr_flags | IFF_UP | IFF_MULTICAST);
  if (ioctl(sock, SIOCSIFFLAGS, &request) < 0) {
    return SetUpError("bringing lo up with multicast (SIOCSIFFLAGS): " + ErrnoText(errno));
  }

  rtentry route{};
  auto* destination = reinterpret_cast<sockaddr_in*>(&route.rt_dst);
  destination->sin_family = AF_INET;
  destination->sin_addr.s_addr = htonl(0xE0000000u);  // 224.0.0.0
  auto* mask = reinterpret_cast<sockaddr_in*>(&route.rt_genmask);
  mask->sin_family = AF_INET;
  mask->sin_addr.s_addr = htonl(0xF0000000u);  // 240.0.0.0 = /4
  char device[] = "lo";
  route.rt_dev = device;
  route.rt_flags = RTF_UP;
  if (ioctl(sock, SIOCADDRT, &route) < 0 && errno != EEXIST) {
    return SetUpError("adding the route 224.0.0.0/4 dev lo (SIOCADDRT): " + ErrnoText(errno));
  }
  return Ok{};
}

Status SetUp() {
  if (Status status = CreateNamespaces(); !status) return status;
  return ConfigureLoopback();
}

constexpr char kTrialSucceeded[] = "ok";

// Runs the whole set-up in a forked child first. Once unshare(CLONE_NEWUSER)
// has succeeded there is no way back to the original namespaces, and some
// systems (AppArmor's restricted user namespaces) allow the unshare but
// refuse the later steps: trying in a child keeps the caller untouched when
// anything fails, so it can fall back to another transport.
Status TryInChild() {
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) < 0) return CreateError("pipe: " + ErrnoText(errno));
  const pid_t child = fork();
  if (child < 0) {
    const int error = errno;
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    return CreateError("fork: " + ErrnoText(error));
  }
  if (child == 0) {
    close(pipe_fds[0]);
    const Status status = SetUp();
    const std::string message = status ? kTrialSucceeded : status.error().message;
    [[maybe_unused]] const ssize_t ignored = write(pipe_fds[1], message.data(), message.size());
    _exit(0);  // no atexit handlers or stdio flushes of the parent's state
  }
  close(pipe_fds[1]);
  std::string message;
  char buffer[512];
  for (;;) {
    const ssize_t got = read(pipe_fds[0], buffer, sizeof buffer);
    if (got > 0) {
      message.append(buffer, static_cast<size_t>(got));
    } else if (got == 0 || errno != EINTR) {
      break;
    }
  }
  close(pipe_fds[0]);
  // The verdict comes through the pipe, not the exit status, which is lost
  // when the caller ignores SIGCHLD; waiting only reaps the child.
  while (waitpid(child, nullptr, 0) < 0 && errno == EINTR) {
  }
  if (message == kTrialSucceeded) return Ok{};
  if (message.empty()) return CreateError("the trial in a child process died");
  return Error::Unavailable(message);
}

}  // namespace

Status EnterPrivateNetwork() {
  // unshare(CLONE_NEWUSER) fails with a bare EINVAL in a threaded process;
  // say what is wrong instead.
  if (const int threads = ThreadCount(); threads > 1) {
    return CreateError("the process has " + std::to_string(threads) +
                       " threads (it must be entered before any thread is started)");
  }
  if (Status status = TryInChild(); !status) return status;
  return SetUp();
}

}  // namespace dynapath::launch
