// policy_replay LOG [URL]: publishes the POLICY events of an LCM log (whole
// messages and fragment_t pieces, byte for byte) on LCM, 50 events a second,
// over and over until killed. Gives dynapath-view a run to watch in the
// tests; only ever started inside a private network namespace.

#include <chrono>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>
#include <utility>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: policy_replay LOG [LCM_URL]\n");
    return 2;
  }
  lcm::LogFile log(argv[1], "r");
  if (!log.good()) {
    std::fprintf(stderr, "policy_replay: cannot read %s\n", argv[1]);
    return 1;
  }
  std::vector<std::pair<std::string, std::vector<unsigned char>>> events;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    const std::string channel = event->channel;
    if (channel.size() < 7 || channel.compare(channel.size() - 7, 7, "/POLICY") != 0) continue;
    const auto* data = static_cast<const unsigned char*>(event->data);
    events.emplace_back(channel, std::vector<unsigned char>(data, data + event->datalen));
  }
  if (events.empty()) {
    std::fprintf(stderr, "policy_replay: no POLICY events in %s\n", argv[1]);
    return 1;
  }
  lcm::LCM lcm(argc == 3 ? argv[2] : "");
  if (!lcm.good()) {
    std::fprintf(stderr, "policy_replay: cannot open LCM\n");
    return 1;
  }
  while (true) {
    for (const auto& [channel, bytes] : events) {
      lcm.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
}
