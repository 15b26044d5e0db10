#include "launch/logger_drain.h"

#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

namespace dynapath::launch {
namespace {

// The inodes of the sockets `pid` holds open ("socket:[INODE]" links).
std::optional<std::set<unsigned long>> SocketInodes(pid_t pid) {
  std::set<unsigned long> inodes;
  std::error_code error;
  const std::filesystem::path fds = "/proc/" + std::to_string(pid) + "/fd";
  for (const auto& entry : std::filesystem::directory_iterator(fds, error)) {
    const std::string target = std::filesystem::read_symlink(entry.path(), error).string();
    unsigned long inode = 0;
    if (!error && std::sscanf(target.c_str(), "socket:[%lu]", &inode) == 1) inodes.insert(inode);
  }
  if (error) return std::nullopt;
  return inodes;
}

// Calls visit(inode, local, queues) for each row of a /proc/net/udp-style
// table whose inode is in `inodes`. Columns: sl local rem st
// tx_queue:rx_queue tr:when retrnsmt uid timeout inode ...
template <class Visit>
void ForOwnRows(const std::string& table, const std::set<unsigned long>& inodes, Visit visit) {
  std::ifstream in(table);
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string sl, local, remote, state, queues, timer, retransmits, uid, timeout;
    unsigned long inode = 0;
    if (!(row >> sl >> local >> remote >> state >> queues >> timer >> retransmits >> uid >>
          timeout >> inode)) {
      continue;
    }
    if (inodes.count(inode) != 0) visit(inode, local, queues);
  }
}

// Calls visit(inode, local, queues) for each UDP socket (IPv4 and IPv6) of
// `pid`; false when /proc cannot say.
template <class Visit>
bool ForEachUdpSocket(pid_t pid, Visit visit) {
  const std::optional<std::set<unsigned long>> inodes = SocketInodes(pid);
  if (!inodes) return false;
  const std::string net = "/proc/" + std::to_string(pid) + "/net/";
  ForOwnRows(net + "udp", *inodes, visit);
  ForOwnRows(net + "udp6", *inodes, visit);
  return true;
}

// Whether `pid` has exited (a zombie not yet reaped) or is gone.
bool Exited(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!std::getline(in, stat)) return true;
  const size_t name_end = stat.rfind(')');  // the command's name may hold spaces
  return name_end == std::string::npos || name_end + 2 >= stat.size() || stat[name_end + 2] == 'Z';
}

std::optional<long long> FileSize(const std::string& file) {
  struct stat status {};
  if (stat(file.c_str(), &status) != 0) return std::nullopt;
  return static_cast<long long>(status.st_size);
}

// A socket the child inherited from this process (LCM's are not
// close-on-exec) is this process's, not one the child opened.
std::set<unsigned long> InheritableSockets() {
  return SocketInodes(getpid()).value_or(std::set<unsigned long>{});
}

std::optional<bool> HasOwnUdpSocketOnPort(pid_t pid, int port,
                                          const std::set<unsigned long>& inherited) {
  bool found = false;
  const bool known =
      ForEachUdpSocket(pid, [&](unsigned long inode, const std::string& local, const std::string&) {
        const size_t colon = local.rfind(':');  // ADDRESS:PORT, both in hex
        if (inherited.count(inode) == 0 && colon != std::string::npos &&
            std::stoi(local.substr(colon + 1), nullptr, 16) == port) {
          found = true;
        }
      });
  if (!known) return std::nullopt;
  return found;
}

}  // namespace

std::optional<long long> QueuedUdpBytes(pid_t pid) {
  long long total = 0;
  const bool known =
      ForEachUdpSocket(pid, [&](unsigned long, const std::string&, const std::string& queues) {
        const size_t colon = queues.find(':');
        if (colon != std::string::npos) total += std::stoll(queues.substr(colon + 1), nullptr, 16);
      });
  if (!known) return std::nullopt;
  return total;
}

std::optional<int> UdpmPort(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0) return std::nullopt;
  std::string address = url.substr(7);
  address = address.substr(0, address.find('?'));
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos) return 7667;  // LCM's default port
  const std::string digits = address.substr(colon + 1);
  if (digits.empty() || digits.size() > 5 ||
      digits.find_first_not_of("0123456789") != std::string::npos) {
    return std::nullopt;
  }
  const int port = std::stoi(digits);
  if (port < 1 || port > 65535) return std::nullopt;
  return port;
}

std::optional<bool> HasUdpSocketOnPort(pid_t pid, int port) {
  return HasOwnUdpSocketOnPort(pid, port, InheritableSockets());
}

bool WaitForLoggerToSubscribe(pid_t pid, int port, std::chrono::milliseconds cap) {
  const auto deadline = std::chrono::steady_clock::now() + cap;
  // Read once: what the logger inherited was fixed when it started.
  const std::set<unsigned long> inherited = InheritableSockets();
  while (std::chrono::steady_clock::now() < deadline) {
    if (Exited(pid)) return false;
    const std::optional<bool> subscribed = HasOwnUdpSocketOnPort(pid, port, inherited);
    if (!subscribed) return false;  // gone, or /proc cannot say
    if (*subscribed) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

bool WaitForLoggerToDrain(pid_t pid, const std::string& file, std::chrono::milliseconds quiet,
                          std::chrono::milliseconds cap) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + cap;
  std::optional<long long> last_size = FileSize(file);
  auto unchanged_since = Clock::now();
  while (Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const std::optional<long long> size = FileSize(file);
    if (size != last_size) {
      last_size = size;
      unchanged_since = Clock::now();
      continue;
    }
    const std::optional<long long> queued = QueuedUdpBytes(pid);
    if (queued && *queued > 0) {
      unchanged_since = Clock::now();
      continue;
    }
    if (Clock::now() - unchanged_since >= quiet) return true;
  }
  return false;
}

}  // namespace dynapath::launch
