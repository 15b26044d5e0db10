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

#include "protocol/log_reader.h"

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: policy_replay LOG [LCM_URL]\n");
    return 2;
  }
  dynapath::Result<dynapath::protocol::LogReader> log =
      dynapath::protocol::LogReader::Open(argv[1]);
  if (!log) {
    std::fprintf(stderr, "policy_replay: %s\n", log.error().message.c_str());
    return 1;
  }
  std::vector<std::pair<std::string, std::vector<unsigned char>>> events;
  while (true) {
    auto next = log->Next();
    if (!next) {
      std::fprintf(stderr, "policy_replay: %s\n", next.error().message.c_str());
      return 1;
    }
    if (!*next) break;
    const std::string& channel = (*next)->channel;
    if (channel.size() < 7 || channel.compare(channel.size() - 7, 7, "/POLICY") != 0) continue;
    events.emplace_back(channel, std::move((*next)->data));
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
