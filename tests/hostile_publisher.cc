// Test tool: the attacks of the hostile-network table (docs/RELIABILITY.md), published on a run's
// channels from inside its private network. Usage:
//   hostile_publisher RUN_ID SECONDS MODE [LCM_URL]
// MODE:
//   counts     every type (nested ones through their holders) with a huge,
//              negative or overlong count or string length in each of its
//              variable-length fields, on every channel (rows 1 and 2)
//   fragments  one-byte fragment_t pieces of the run announcing 200 MB (and
//              1.5 MB) messages under fresh message ids, as fast as LCM takes them
//              (row 3)
//   mix        random bytes, right-type random bodies, crafted counts,
//              mutated and truncated messages of every type (row 4)
//   regions    job batches and policies of the run whose regions start at
//              row INT_MAX (row 6)
// Refuses to run when an interface other than lo exists (host network).

#include <net/if.h>

#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <lcm/lcm-cpp.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "tests/protocol/message_types.h"
#include "tests/protocol/schema_encoder.h"

namespace {

using dynapath::protocol::FindSchemaType;
using dynapath::protocol::SchemaTypeCount;
using dynapath::protocol::SchemaTypes;
using dynapath::protocol::testing::AllMessageTypes;
using dynapath::protocol::testing::SchemaEncoder;
using dynapath::protocol::testing::Target;

const std::vector<std::string> kChannels = {"HEARTBEAT",   "ENV_REQUEST", "ENV_GRID",
                                            "ENV_CHANGES", "JOBS",        "SHARDS",
                                            "RESULTS",     "REPORT",      "POLICY"};

template <class T>
std::vector<uint8_t> Encoded(const T& message) {
  std::vector<uint8_t> bytes(static_cast<size_t>(message.getEncodedSize()));
  message.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// Crafted messages of every type: each variable-length field and string
// with absurd counts and lengths.
std::vector<std::vector<uint8_t>> CraftedMessages() {
  std::vector<std::vector<uint8_t>> all;
  SchemaEncoder encoder(99);
  for (const auto& type : AllMessageTypes()) {
    const auto& top = *FindSchemaType(type.name);
    for (int t = 0; t < SchemaTypeCount(); ++t) {
      const auto& holder = SchemaTypes()[t];
      if (!SchemaEncoder::Contains(top, &holder)) continue;
      for (int f = 0; f < holder.num_fields; ++f) {
        const auto& field = holder.fields[f];
        const bool variable = field.num_dims > 0 && field.dims[0].field >= 0;
        if (field.kind == dynapath::protocol::schema::Kind::kString && field.num_dims == 0) {
          for (int64_t length : {int64_t{0x7fffffff}, int64_t{0}, int64_t{-5}}) {
            all.push_back(encoder.Encode(top, type.hash, 1, Target{&holder, f, length}));
          }
        }
        if (!variable) continue;
        for (int64_t count : {int64_t{1} << 29, int64_t{0x7fffffff}, int64_t{-1}}) {
          all.push_back(encoder.Encode(top, type.hash, 1, Target{&holder, f, count}));
        }
      }
    }
  }
  return all;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4 || argc > 5) {
    std::fprintf(stderr,
                 "usage: hostile_publisher RUN_ID SECONDS counts|fragments|mix|regions [URL]\n");
    return 2;
  }
  struct if_nameindex* interfaces = if_nameindex();
  for (auto* i = interfaces; i != nullptr && i->if_index != 0; ++i) {
    if (std::string(i->if_name) != "lo") {
      std::fprintf(stderr, "hostile_publisher: interface %s exists: run me in a private network\n",
                   i->if_name);
      return 2;
    }
  }
  if_freenameindex(interfaces);
  const std::string run = argv[1];
  const double seconds = std::atof(argv[2]);
  const std::string mode = argv[3];
  lcm::LCM lcm(argc == 5 ? argv[4] : "");
  if (!lcm.good()) return 1;
  auto channel = [&](const std::string& name) { return "DYNAPATH/" + run + "/" + name; };
  std::mt19937_64 random(4242);
  const auto end = std::chrono::steady_clock::now() +
                   std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000));
  int64_t sent = 0;
  auto publish = [&](const std::string& name, const std::vector<uint8_t>& bytes) {
    lcm.publish(channel(name), bytes.data(), static_cast<unsigned>(bytes.size()));
    ++sent;
  };

  if (mode == "counts" || mode == "mix") {
    const std::vector<std::vector<uint8_t>> crafted = CraftedMessages();
    SchemaEncoder encoder(7);
    std::vector<std::vector<uint8_t>> valid;
    for (const auto& type : AllMessageTypes()) {
      for (int i = 0; i < 4; ++i)
        valid.push_back(encoder.Encode(*FindSchemaType(type.name), type.hash, 3));
    }
    while (std::chrono::steady_clock::now() < end) {
      for (const std::string& name : kChannels) {
        if (mode == "counts") {
          for (const auto& bytes : crafted) publish(name, bytes);
          continue;
        }
        std::vector<uint8_t> bytes;
        switch (random() % 5) {
          case 0:  // random bytes
            bytes.resize(random() % 3000);
            for (uint8_t& b : bytes) b = static_cast<uint8_t>(random());
            break;
          case 1: {  // a right fingerprint, a random body
            const auto& type = AllMessageTypes()[random() % AllMessageTypes().size()];
            bytes.resize(8 + random() % 500);
            for (int i = 0; i < 8; ++i) bytes[i] = static_cast<uint8_t>(type.hash >> (56 - 8 * i));
            for (size_t i = 8; i < bytes.size(); ++i) bytes[i] = static_cast<uint8_t>(random());
            break;
          }
          case 2:
            bytes = crafted[random() % crafted.size()];
            break;
          case 3:  // a mutated message
            bytes = valid[random() % valid.size()];
            for (int flips = 1 + random() % 4; flips > 0; --flips) {
              bytes[8 + random() % (bytes.size() - 8)] ^= static_cast<uint8_t>(1 + random() % 255);
            }
            break;
          default:  // a truncated message
            bytes = valid[random() % valid.size()];
            bytes.resize(8 + random() % (bytes.size() - 8));
            break;
        }
        publish(name, bytes);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  } else if (mode == "fragments") {
    dynapath::fragment_t piece{};
    piece.run_id = run;
    piece.fingerprint = dynapath::job_batch_t::getHash();
    piece.total_size = 200 * 1024 * 1024;
    piece.count = piece.total_size;
    piece.size = 1;
    piece.data = {0};
    int64_t id = 1;
    while (std::chrono::steady_clock::now() < end) {
      for (int i = 0; i < 256; ++i) {
        // Alternately above any cap and just under a 100x100 run's cap.
        piece.total_size = (i % 2) ? 200 * 1024 * 1024 : 1500 * 1000;
        piece.count = piece.total_size;
        piece.message_id = id++;
        piece.index = static_cast<int32_t>(random() % piece.count);
        piece.offset = piece.index;
        publish(kChannels[random() % kChannels.size()], Encoded(piece));
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  } else if (mode == "regions") {
    dynapath::job_batch_t batch{};
    batch.run_id = run;
    batch.batch_id = 1000000;
    batch.kind = dynapath::job_batch_t::KIND_SINGLE_AGENT;
    batch.max_episodes = batch.replay_capacity = batch.convergence_interval = 1;
    batch.convergence_checks = batch.learners = batch.sync_period = batch.iterations_per_cell = 1;
    dynapath::job_t job{};
    job.row0 = INT_MAX;
    job.rows = 2;
    job.col0 = 0;
    job.cols = 1;
    job.grid_rows = job.grid_cols = 10;
    job.num_cells = 2;
    job.codes = {1, 1};
    batch.jobs = {job};
    batch.num_jobs = 1;
    dynapath::policy_t policy{};
    policy.run_id = run;
    policy.approach = "A* Oracle";
    policy.rows = policy.cols = 2;
    policy.num_cells = 4;
    policy.cells = {1, 1, 1, 2};
    policy.actions = {0, 0, 0, -1};
    policy.reaches = {1, 1, 1, -1};
    policy.num_regions = 1;
    policy.region_row0 = {INT_MAX};
    policy.region_col0 = {0};
    policy.region_rows = {2};
    policy.region_cols = {1};
    while (std::chrono::steady_clock::now() < end) {
      publish("JOBS", Encoded(batch));
      publish("POLICY", Encoded(policy));
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  } else {
    std::fprintf(stderr, "hostile_publisher: unknown mode %s\n", mode.c_str());
    return 2;
  }
  std::fprintf(stderr, "hostile_publisher: %s: %lld messages in %.0f s\n", mode.c_str(),
               static_cast<long long>(sent), seconds);
  return 0;
}
