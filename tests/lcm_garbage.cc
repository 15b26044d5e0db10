// Test tool: publishes garbage on every channel of a run for a while, to
// check that every process drops it (counted) and the run still completes
// with the right results. Three kinds of garbage per channel: random bytes,
// a valid fingerprint of every message type followed by random bytes, and a
// valid message of another run. Usage: lcm_garbage RUN_ID SECONDS
// Refuses to run when an interface other than lo exists (host network).

#include <net/if.h>

#include <chrono>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "dynapath/changes_t.hpp"
#include "dynapath/fragment_t.hpp"
#include "dynapath/grid_t.hpp"
#include "dynapath/heartbeat_t.hpp"
#include "dynapath/job_batch_t.hpp"
#include "dynapath/job_result_t.hpp"
#include "dynapath/policy_t.hpp"
#include "dynapath/shards_t.hpp"
#include "dynapath/step_report_t.hpp"
#include "dynapath/step_request_t.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: lcm_garbage RUN_ID SECONDS\n");
    return 2;
  }
  struct if_nameindex* interfaces = if_nameindex();
  for (auto* i = interfaces; i != nullptr && i->if_index != 0; ++i) {
    if (std::string(i->if_name) != "lo") {
      std::fprintf(stderr, "lcm_garbage: interface %s exists: run me in a private network\n",
                   i->if_name);
      return 2;
    }
  }
  if_freenameindex(interfaces);
  const std::string run = argv[1];
  const double seconds = std::atof(argv[2]);
  lcm::LCM lcm;
  if (!lcm.good()) return 1;
  const std::vector<std::string> names = {"HEARTBEAT",   "ENV_REQUEST", "ENV_GRID",
                                          "ENV_CHANGES", "JOBS",        "SHARDS",
                                          "RESULTS",     "REPORT",      "POLICY"};
  const std::vector<int64_t> hashes = {
      dynapath::heartbeat_t::getHash(),  dynapath::step_request_t::getHash(),
      dynapath::grid_t::getHash(),       dynapath::changes_t::getHash(),
      dynapath::job_batch_t::getHash(),  dynapath::shards_t::getHash(),
      dynapath::job_result_t::getHash(), dynapath::step_report_t::getHash(),
      dynapath::policy_t::getHash(),     dynapath::fragment_t::getHash()};
  std::mt19937_64 random(12345);
  std::vector<uint8_t> bytes;
  // A valid heartbeat of another run: must be ignored by this run.
  dynapath::heartbeat_t foreign{};
  foreign.run_id = "another-run";
  foreign.role = dynapath::heartbeat_t::ROLE_COORDINATOR;
  foreign.state = dynapath::heartbeat_t::STATE_FAILED;
  const auto end = std::chrono::steady_clock::now() +
                   std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000));
  int64_t sent = 0;
  while (std::chrono::steady_clock::now() < end) {
    for (const std::string& name : names) {
      const std::string channel = "DYNAPATH/" + run + "/" + name;
      bytes.resize(random() % 2000);
      for (uint8_t& b : bytes) b = static_cast<uint8_t>(random());
      lcm.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
      // A real fingerprint (big-endian) with a random body.
      bytes.resize(8 + random() % 200);
      const uint64_t hash = static_cast<uint64_t>(hashes[random() % hashes.size()]);
      for (int i = 0; i < 8; ++i) bytes[i] = static_cast<uint8_t>(hash >> (56 - 8 * i));
      lcm.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
      lcm.publish("DYNAPATH/" + run + "/HEARTBEAT", &foreign);
      sent += 3;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::printf("lcm_garbage: published %lld garbage messages\n", static_cast<long long>(sent));
  return 0;
}
