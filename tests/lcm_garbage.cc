// Test tool: publishes garbage on every channel of a run for a while, to
// check that every process drops it (counted) and the run still completes
// with the right results. Three kinds of garbage per channel: random bytes,
// a valid fingerprint of every message type followed by random bytes, and a
// valid message of another run.
//
// `hostile` adds what an attacker on the run's network without its secret
// would send (the hostile-network table, docs/RELIABILITY.md): well-formed messages of this run whose array counts
// announce 2^29 to 2^31-1 elements, floods of one-byte fragment_t pieces
// announcing 256 MB messages, forged heartbeats of this run (an agent 7 that
// does not exist, a coordinator that says it failed), messages with a forged
// authentication trailer, and replays of the run's own authenticated
// messages, captured from the network and sent again.
//
// Usage: lcm_garbage RUN_ID SECONDS [hostile]
// Refuses to run when an interface other than lo exists (host network).

#include <net/if.h>

#include <atomic>
#include <csignal>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <deque>
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

namespace {

std::atomic<bool> stop{false};
void OnSignal(int) { stop = true; }

template <class T>
std::vector<uint8_t> Encode(const T& message) {
  std::vector<uint8_t> bytes(static_cast<size_t>(message.getEncodedSize()));
  message.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// Valid messages of `run` with small arrays: the bodies that get huge
// announced counts patched in.
std::vector<std::vector<uint8_t>> ValidMessages(const std::string& run) {
  std::vector<std::vector<uint8_t>> out;
  dynapath::job_result_t result{};
  result.run_id = run;
  out.push_back(Encode(result));
  dynapath::job_batch_t batch{};
  batch.run_id = run;
  out.push_back(Encode(batch));
  dynapath::changes_t changes{};
  changes.run_id = run;
  out.push_back(Encode(changes));
  dynapath::policy_t policy{};
  policy.run_id = run;
  out.push_back(Encode(policy));
  dynapath::shards_t shards{};
  shards.run_id = run;
  out.push_back(Encode(shards));
  dynapath::grid_t grid{};
  grid.run_id = run;
  out.push_back(Encode(grid));
  return out;
}

void PutBigEndian32(uint8_t* at, uint32_t value) {
  for (int i = 0; i < 4; ++i) at[i] = static_cast<uint8_t>(value >> (24 - 8 * i));
}

// Replays of authenticated messages: the run's own traffic, captured.
class Recorder {
 public:
  void Handle(const lcm::ReceiveBuffer* buffer, const std::string& channel) {
    const auto* data = static_cast<const uint8_t*>(buffer->data);
    const size_t size = buffer->data_size;
    // Only messages with the run's trailer (protocol/auth.h: magic
    // "DPA1" last), not this tool's own garbage.
    if (size < 52 || std::memcmp(data + size - 4, "DPA1", 4) != 0) return;
    if (captured_.size() >= 2000) captured_.pop_front();  // bounded memory
    captured_.emplace_back(channel, std::vector<uint8_t>(data, data + size));
  }
  std::deque<std::pair<std::string, std::vector<uint8_t>>>& captured() { return captured_; }

 private:
  std::deque<std::pair<std::string, std::vector<uint8_t>>> captured_;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && !(argc == 4 && std::string(argv[3]) == "hostile")) {
    std::fprintf(stderr, "usage: lcm_garbage RUN_ID SECONDS [hostile]\n");
    return 2;
  }
  const bool hostile = argc == 4;
  // SIGTERM or SIGINT end the garbage early, with its count printed.
  std::signal(SIGTERM, OnSignal);
  std::signal(SIGINT, OnSignal);
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
  // The hostile extras.
  const std::vector<std::vector<uint8_t>> valid = ValidMessages(run);
  dynapath::heartbeat_t ghost{};  // an agent that does not exist
  ghost.run_id = run;
  ghost.role = dynapath::heartbeat_t::ROLE_AGENT;
  ghost.sender = 7;
  ghost.state = dynapath::heartbeat_t::STATE_RUNNING;
  ghost.threads = 64;
  ghost.batch_id = -1;
  ghost.round = -1;
  dynapath::heartbeat_t failed{};  // the run's coordinator, "failed"
  failed.run_id = run;
  failed.role = dynapath::heartbeat_t::ROLE_COORDINATOR;
  failed.state = dynapath::heartbeat_t::STATE_FAILED;
  failed.message = "forged";
  dynapath::fragment_t piece{};
  piece.run_id = run;
  piece.fingerprint = dynapath::job_batch_t::getHash();
  piece.total_size = 256 * 1024 * 1024;
  piece.count = piece.total_size;
  piece.size = 1;
  piece.data = {0};
  Recorder recorder;
  lcm::LCM listener;  // a second instance: its own socket and queue
  if (hostile) {
    if (!listener.good()) return 1;
    listener.subscribe("DYNAPATH/" + run + "/.*", &Recorder::Handle, &recorder)
        ->setQueueCapacity(1000);
  }
  int64_t sent = 0, replays = 0;
  while (std::chrono::steady_clock::now() < end && !stop) {
    if (hostile) {
      for (const std::string& name : names) {
        const std::string channel = "DYNAPATH/" + run + "/" + name;
        // Huge announced counts at every 4-byte position of a valid body.
        for (const std::vector<uint8_t>& body : valid) {
          bytes = body;
          const size_t at = 8 + random() % (bytes.size() - 11);
          const uint32_t counts[] = {0x7fffffffU, 0x20000000U, 0x40000000U, 0xffffffffU};
          PutBigEndian32(bytes.data() + at, counts[random() % 4]);
          lcm.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
          ++sent;
        }
        // A forged trailer: the right magic, a random tag.
        bytes = valid[random() % valid.size()];
        for (int i = 0; i < 48; ++i) bytes.push_back(static_cast<uint8_t>(random()));
        bytes.insert(bytes.end(), {'D', 'P', 'A', '1'});
        lcm.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
        ++sent;
      }
      // A flood of one-byte pieces of 256 MB messages, each its own message.
      for (int i = 0; i < 40; ++i) {
        piece.message_id = static_cast<int64_t>(random());
        piece.index = static_cast<int32_t>(random() % 1000000);
        piece.offset = piece.index;
        lcm.publish("DYNAPATH/" + run + "/" + names[random() % names.size()], &piece);
        ++sent;
      }
      lcm.publish("DYNAPATH/" + run + "/HEARTBEAT", &ghost);
      lcm.publish("DYNAPATH/" + run + "/HEARTBEAT", &failed);
      sent += 2;
      // Replays of what the run sent since the last round.
      while (listener.handleTimeout(0) > 0) {
      }
      for (auto& [channel, message] : recorder.captured()) {
        lcm.publish(channel, message.data(), static_cast<unsigned>(message.size()));
        ++replays;
      }
      recorder.captured().clear();
    }
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
  std::printf("lcm_garbage: published %lld garbage messages, replayed %lld\n",
              static_cast<long long>(sent), static_cast<long long>(replays));
  return 0;
}
