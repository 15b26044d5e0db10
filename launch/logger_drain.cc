#include "launch/logger_drain.h"

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

// Adds the rx_queue of the rows of a /proc/net/udp-style table whose inode
// is in `inodes`. Columns: sl local rem st tx_queue:rx_queue tr:when
// retrnsmt uid timeout inode ...
void AddQueued(const std::string& table, const std::set<unsigned long>& inodes, long long& total) {
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
    if (inodes.count(inode) == 0) continue;
    const size_t colon = queues.find(':');
    if (colon != std::string::npos) total += std::stoll(queues.substr(colon + 1), nullptr, 16);
  }
}

std::optional<long long> FileSize(const std::string& file) {
  struct stat status {};
  if (stat(file.c_str(), &status) != 0) return std::nullopt;
  return static_cast<long long>(status.st_size);
}

}  // namespace

std::optional<long long> QueuedUdpBytes(pid_t pid) {
  const std::optional<std::set<unsigned long>> inodes = SocketInodes(pid);
  if (!inodes) return std::nullopt;
  long long total = 0;
  const std::string net = "/proc/" + std::to_string(pid) + "/net/";
  AddQueued(net + "udp", *inodes, total);
  AddQueued(net + "udp6", *inodes, total);
  return total;
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
