// lcm_loopback_probe: checks that LCM's udpm transport works inside a private
// network (tests/netns_test.sh). It refuses to run where any interface other
// than lo exists, so a test can never put LCM traffic on the host network.
//
//   lcm_loopback_probe loopback CHANNEL   publish one message and hear it back
//   lcm_loopback_probe listen CHANNEL     hear any message on CHANNEL
//   lcm_loopback_probe publish CHANNEL    publish on CHANNEL until the timeout
//
// Options (before the mode): --url URL (default udpm://239.255.76.67:7667?ttl=0),
// --timeout-ms N (default 2000). Exit status: 0 heard (publish: done),
// 3 nothing heard before the timeout, 2 bad usage or a network with other
// interfaces, 1 LCM failure.

#include <net/if.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>

namespace {

constexpr int kExitHeard = 0;
constexpr int kExitLcmFailure = 1;
constexpr int kExitUsage = 2;
constexpr int kExitSilence = 3;

using Clock = std::chrono::steady_clock;

// The interfaces of this network namespace other than lo, comma-separated.
std::string OtherInterfaces() {
  std::string others;
  struct if_nameindex* interfaces = if_nameindex();
  if (interfaces == nullptr) return "(cannot list interfaces)";
  for (const struct if_nameindex* entry = interfaces; entry->if_index != 0; ++entry) {
    if (std::strcmp(entry->if_name, "lo") == 0) continue;
    if (!others.empty()) others += ",";
    others += entry->if_name;
  }
  if_freenameindex(interfaces);
  return others;
}

class Listener {
 public:
  void Handle(const lcm::ReceiveBuffer* buffer, const std::string& /*channel*/) {
    heard_ = true;
    std::printf("heard %u bytes: %.*s\n", buffer->data_size, static_cast<int>(buffer->data_size),
                static_cast<const char*>(buffer->data));
  }
  bool heard() const { return heard_; }

 private:
  bool heard_ = false;
};

// Dispatches messages until one is heard or the deadline passes.
bool WaitForMessage(lcm::LCM& lcm, const Listener& listener, Clock::time_point deadline) {
  while (!listener.heard()) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    if (lcm.handleTimeout(static_cast<int>(left)) < 0) return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  long timeout_ms = 2000;
  int arg = 1;
  for (; arg + 1 < argc && argv[arg][0] == '-'; arg += 2) {
    const std::string option = argv[arg];
    if (option == "--url") {
      url = argv[arg + 1];
    } else if (option == "--timeout-ms") {
      timeout_ms = std::strtol(argv[arg + 1], nullptr, 10);
    } else {
      std::fprintf(stderr, "lcm_loopback_probe: unknown option %s\n", option.c_str());
      return kExitUsage;
    }
  }
  if (argc - arg != 2 || timeout_ms <= 0) {
    std::fputs(
        "usage: lcm_loopback_probe [--url URL] [--timeout-ms N] loopback|listen|publish "
        "CHANNEL\n",
        stderr);
    return kExitUsage;
  }
  const std::string mode = argv[arg];
  const std::string channel = argv[arg + 1];
  if (const std::string others = OtherInterfaces(); !others.empty()) {
    std::fprintf(stderr,
                 "lcm_loopback_probe: refusing to run on a network with interfaces other than "
                 "lo (%s); run it inside 'dynapath netns'\n",
                 others.c_str());
    return kExitUsage;
  }

  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "lcm_loopback_probe: cannot open LCM at %s\n", url.c_str());
    return kExitLcmFailure;
  }
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  const std::string payload = mode + " from pid " + std::to_string(getpid());

  if (mode == "publish") {
    // Repeats so that a listener started at about the same time hears it.
    while (Clock::now() < deadline) {
      if (lcm.publish(channel, payload.data(), static_cast<unsigned>(payload.size())) != 0) {
        std::fprintf(stderr, "lcm_loopback_probe: publish failed\n");
        return kExitLcmFailure;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return kExitHeard;
  }
  if (mode != "loopback" && mode != "listen") {
    std::fprintf(stderr, "lcm_loopback_probe: unknown mode '%s'\n", mode.c_str());
    return kExitUsage;
  }
  Listener listener;
  lcm.subscribe(channel, &Listener::Handle, &listener);
  if (mode == "loopback" &&
      lcm.publish(channel, payload.data(), static_cast<unsigned>(payload.size())) != 0) {
    std::fprintf(stderr, "lcm_loopback_probe: publish failed\n");
    return kExitLcmFailure;
  }
  if (WaitForMessage(lcm, listener, deadline)) return kExitHeard;
  std::fprintf(stderr, "lcm_loopback_probe: nothing heard on %s within %ld ms\n", channel.c_str(),
               timeout_ms);
  return kExitSilence;
}
