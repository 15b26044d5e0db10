#pragma once
// A run's view of LCM: typed publish and subscribe on the run's channels, with
// what the transport does not give:
//
//   * Authentication (auth.h). Every published message carries a trailer
//     with a tag under the run's key; a received message without a valid
//     tag, or seen before, is dropped and counted before anything decodes it.
//   * Validation. Every received message is decoded by hand (never trusting
//     LCM's typed handlers, which print and continue on garbage), checked for
//     the run id and by protocol::Validate (sizes, bounds, finite values), and
//     dropped with a counted, rate-limited warning when anything is wrong.
//   * Fragmentation. Messages above a size limit travel as fragment_t pieces
//     of at most one UDP datagram each. The receiver keeps pieces across
//     re-sends of the same message, so a resend fills gaps instead of
//     starting over (udpm loses whole multi-MB messages often).
//   * Fault injection (tests only): drop or duplicate published messages.
//
// Handlers run on the thread that calls lcm::LCM::handle (the dispatch
// thread) and must be quick: components post the work to their own thread.
// Subscribe before dispatching starts. Publish is safe from any thread.

#include <atomic>
#include <cstdint>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "core/limits.h"
#include "core/rng.h"
#include "lcmtypes/protocol/auth.h"
#include "lcmtypes/protocol/decode.h"
#include "lcmtypes/protocol/fragments.h"
#include "lcmtypes/protocol/validate.h"

namespace dynapath::protocol {

struct BusOptions {
  // Encoded messages above this many bytes are fragmented (0: never).
  int fragment_above = 128 * 1024;
  int fragment_size = 60000;  // payload bytes per fragment: one UDP datagram
  // Pause between two fragments of a message. LCM's udpm receiver copies
  // datagrams into a fixed ring buffer its dispatch thread drains; a burst
  // of several 60 KB fragments overruns it and loses the message (measured:
  // one in two 250 KB job batches on loopback without pausing).
  int fragment_pause_us = 300;
  // Test-only fault injection on publish: probability of dropping a message
  // (or fragment) and of sending it twice.
  double drop_probability = 0.0;
  double duplicate_probability = 0.0;
  uint64_t fault_seed = 1;
  // The run's key. The default, the well-known insecure key, suits tests
  // and one-process (memq://) use; processes take it from --secret-file or
  // the launcher, or --insecure (runtime/process_options.h).
  RunKey key = InsecureKey();
  // Cells of the run's grid (at most): the fragment caps derive from it
  // (protocol/limits.h). Unknown: the protocol's largest grid.
  int64_t max_grid_cells = int64_t{kMaxGridSide} * kMaxGridSide;
};

struct BusCounters {
  int64_t published = 0;
  int64_t received = 0;         // messages delivered to handlers
  int64_t dropped = 0;          // all dropped messages, the two below included
  int64_t unauthenticated = 0;  // no valid tag (forged, another key, corrupt)
  int64_t replayed = 0;         // a (sender, counter) seen before or too old
  int64_t fragments_received = 0;
  int64_t injected_drops = 0;
  int64_t injected_duplicates = 0;
};

class Bus {
 public:
  Bus(lcm::LCM& lcm, std::string run_id, BusOptions options = {});
  ~Bus();
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  const std::string& run_id() const { return run_id_; }
  std::string Channel(std::string_view name) const;

  template <class T>
  void Publish(std::string_view name, const T& message) {
    std::vector<uint8_t> bytes(static_cast<size_t>(message.getEncodedSize()));
    message.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    PublishBytes(Channel(name), bytes, static_cast<int64_t>(T::getHash()));
  }

  // Calls `handler` with every valid T of this run on channel `name`.
  template <class T>
  void Subscribe(std::string_view name, std::function<void(T&)> handler) {
    const std::string channel = Channel(name);
    AddRoute(channel, static_cast<int64_t>(T::getHash()),
             [this, handler = std::move(handler)](const uint8_t* data, int size,
                                                  const std::string& where) {
               T message;
               if (!DecodeExactly(data, size, message)) {
                 return Drop(where, "undecodable " + TypeName<T>());
               }
               if (message.run_id != run_id_) return Drop(where, "message of another run");
               if (std::string error = Validate(message); !error.empty()) {
                 return Drop(where, TypeName<T>() + ": " + error);
               }
               counters_received_.fetch_add(1, std::memory_order_relaxed);
               handler(message);
             });
  }

  BusCounters counters() const;
  // One line for the end of a run: messages published, received, dropped
  // and why.
  std::string TrafficSummary() const;

 private:
  using Deliver = std::function<void(const uint8_t*, int, const std::string&)>;
  struct Route {
    int64_t fingerprint;
    Deliver deliver;
  };

  template <class T>
  static std::string TypeName() {
    return T::getTypeName();
  }

  void PublishBytes(const std::string& channel, const std::vector<uint8_t>& bytes,
                    int64_t fingerprint);
  void PublishRaw(const std::string& channel, const void* data, size_t size);
  void AddRoute(const std::string& channel, int64_t fingerprint, Deliver deliver);
  void OnRaw(const lcm::ReceiveBuffer* buffer, const std::string& channel);
  void Dispatch(const std::string& channel, const uint8_t* data, int size);
  void OnFragment(const std::string& channel, const uint8_t* data, int size);
  void Drop(const std::string& channel, const std::string& why);

  lcm::LCM& lcm_;
  std::string run_id_;
  BusOptions options_;
  std::map<std::string, std::vector<Route>> routes_;
  std::vector<lcm::Subscription*> subscriptions_;
  FragmentAssembler fragments_;  // dispatch thread only
  std::atomic<int64_t> next_message_id_;
  std::mutex fault_mutex_;
  Rng fault_rng_;
  Sealer sealer_;
  Verifier verifier_;  // dispatch thread only
  std::atomic<int64_t> counters_published_{0}, counters_received_{0}, counters_dropped_{0},
      counters_fragments_{0}, counters_injected_drops_{0}, counters_injected_duplicates_{0},
      counters_unauthenticated_{0}, counters_replayed_{0};
  int64_t last_warning_ms_ = -1000000;
  int64_t warnings_suppressed_ = 0;
};

}  // namespace dynapath::protocol
