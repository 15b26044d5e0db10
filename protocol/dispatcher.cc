#include "protocol/dispatcher.h"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <fstream>

namespace dynapath::protocol {

std::string ResolveLcmUrl(const std::string& url) {
  if (!url.empty()) return url;
  if (const char* env = std::getenv("LCM_DEFAULT_URL"); env != nullptr && *env != '\0') return env;
  return "udpm://239.255.76.67:7667?ttl=0";
}

bool IsMemq(const std::string& url) { return url.rfind("memq://", 0) == 0; }

int DefaultFragmentSize(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0) return 60000;
  const size_t ttl = url.find("ttl=");
  if (ttl == std::string::npos) return 60000;  // LCM's default ttl is 0
  return std::atoi(url.c_str() + ttl + 4) > 0 ? kFrameFragmentSize : 60000;
}

std::string WithReceiveBuffer(const std::string& url, int64_t kernel_max) {
  if (url.rfind("udpm://", 0) != 0 || url.find("recv_buf_size=") != std::string::npos ||
      kernel_max <= 0) {
    return url;
  }
  const int64_t bytes = std::min(kDefaultReceiveBuffer, kernel_max);
  return url + (url.find('?') == std::string::npos ? "?" : "&") +
         "recv_buf_size=" + std::to_string(bytes);
}

namespace {

// net.core.rmem_max, 0 when unreadable.
int64_t KernelReceiveBufferMax() {
  std::ifstream file("/proc/sys/net/core/rmem_max");
  int64_t bytes = 0;
  if (!(file >> bytes)) return 0;
  return bytes;
}

}  // namespace

Result<std::unique_ptr<lcm::LCM>> OpenLcm(const std::string& url) {
  const std::string resolved = ResolveLcmUrl(url);
  auto lcm = std::make_unique<lcm::LCM>(WithReceiveBuffer(resolved, KernelReceiveBufferMax()));
  if (!lcm->good()) {
    return Error::Io("cannot open LCM at '" + resolved +
                     "' (bad URL, or no multicast route: see docs/howto/NETWORKING.md)");
  }
  return lcm;
}

Dispatcher::Dispatcher(lcm::LCM& lcm) : lcm_(lcm) {
  thread_ = std::thread([this] {
    while (!stop_) {
      if (lcm_.handleTimeout(20) < 0) break;
    }
  });
}

Dispatcher::~Dispatcher() {
  stop_ = true;
  thread_.join();
}

namespace {
// The process's one SIGINT/SIGTERM handler. Only async-signal-safe work:
// atomics, write(2), _exit(2).
std::atomic<bool> g_stop{false};
std::atomic<int> g_signals{0};
std::atomic<const char*> g_first_notice{nullptr};
std::atomic<const char*> g_second_exit_notice{nullptr};

void WriteNotice(const char* text) {
  if (text == nullptr) return;
  size_t length = 0;
  while (text[length] != '\0') ++length;
  [[maybe_unused]] ssize_t written = write(STDERR_FILENO, text, length);
}

extern "C" void OnStopSignal(int) {
  g_stop = true;
  if (g_signals.fetch_add(1) == 0) {
    WriteNotice(g_first_notice.load());
    return;
  }
  if (const char* notice = g_second_exit_notice.load(); notice != nullptr) {
    WriteNotice(notice);
    _exit(130);
  }
}
}  // namespace

const std::atomic<bool>& StopOnSignals() {
  static const bool installed = [] {
    struct sigaction action {};
    action.sa_handler = OnStopSignal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
    return true;
  }();
  (void)installed;
  return g_stop;
}

const std::atomic<bool>& StopOnSignals(const char* first_notice, const char* second_exit_notice) {
  g_first_notice = first_notice;
  g_second_exit_notice = second_exit_notice;
  return StopOnSignals();
}

}  // namespace dynapath::protocol
