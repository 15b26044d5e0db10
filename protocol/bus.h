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
//     of at most one UDP datagram each. Publishing the same bytes on the
//     same channel again (a component's resend) reuses the message id
//     (sent_store.h), and the receiver keeps pieces across re-sends, so a
//     resend fills gaps instead of starting over.
//   * Selective repair. A receiver holding part of a message and getting no
//     new piece of it for a quiet period (long enough that reordering does
//     not look like loss) publishes a fragment_nack_t with a bitmap of the
//     pieces it lacks, again after a retry interval while they stay missing;
//     the sender re-sends exactly those. Both intervals follow the measured
//     NACK-to-repair round trip. A message lost whole is the component's to
//     resend (it learns of it from heartbeats).
//   * Fault injection (tests only): drop or duplicate published messages.
//
// Handlers run on the thread that calls lcm::LCM::handle (the dispatch
// thread) and must be quick: components post the work to their own thread.
// Subscribe before dispatching starts. Publish is safe from any thread.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <limits>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "dynapath/limits.h"
#include "dynapath/rng.h"
#include "protocol/auth.h"
#include "protocol/decode.h"
#include "protocol/fragments.h"
#include "protocol/sent_store.h"
#include "protocol/validate.h"

namespace dynapath::protocol {

struct BusOptions {
  // Encoded messages above this many bytes are fragmented (0: never).
  int fragment_above = 128 * 1024;
  int fragment_size = 60000;  // payload bytes per fragment: one UDP datagram
  // Pause after every 60 KB of fragments sent. LCM's udpm receiver copies
  // datagrams into a fixed ring buffer its dispatch thread drains; a burst
  // of several 60 KB fragments overruns it and loses the message (measured:
  // one in two 250 KB job batches on loopback without pausing).
  int fragment_pause_us = 300;
  // Selective repair (NACKs) of fragmented messages. A receiver NACKs a
  // partial message quiet for 1.5 repair round trips + 1 ms (reordering
  // within it is not loss), at least nack_quiet_ms and at most 200 ms; 15 ms
  // until a round trip is measured (nack_quiet_ms if longer). It asks again
  // after 2 round trips + 10 ms, at least nack_retry_ms and at most 1 s.
  // Tests that count NACKs raise both, so that a dispatch thread kept away
  // by a loaded machine is not taken for loss.
  bool repair = true;
  int nack_quiet_ms = 3;
  int nack_retry_ms = 20;
  // Forward repair: one XOR parity piece per `parity_group` data pieces of
  // a fragmented message (interleaved groups, fragment_t.lcm), so that a
  // receiver missing one piece of a group rebuilds it without a NACK round
  // trip. 0: none. On for frame-sized pieces (a LAN: runtime/process_options).
  int parity_group = 0;
  // Parity pieces only while this Bus has seen loss lately (a NACK sent or
  // received in the last parity_hold_ms): a clean LAN pays nothing for
  // them (12.5% more frames cost split placement about 15% there), and a
  // one-off NACK switches them on for a moment only.
  bool parity_after_loss = true;
  int parity_hold_ms = 2000;
  int max_nacks = 30;  // NACKs of a message without progress
  // What the sender keeps for repairs and id reuse.
  int64_t sent_store_bytes = int64_t{64} << 20;
  // Test-only: a fragment for which this returns true is not sent (`repair`:
  // the piece answers a NACK).
  std::function<bool(const fragment_t&, bool repair)> drop_fragment;
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
  // Selective repair.
  int64_t fragments_sent = 0;
  int64_t ids_reused = 0;  // publishes that resent a stored message
  int64_t nacks_sent = 0;
  int64_t nacks_received = 0;         // of messages this Bus sent
  int64_t pieces_repaired = 0;        // pieces re-sent for NACKs
  int64_t parity_sent = 0;            // parity pieces sent (BusOptions::parity_group)
  int64_t pieces_rebuilt = 0;         // received pieces rebuilt from parity pieces
  int64_t partials_evicted = 0;       // incomplete messages dropped for room or age
  int64_t repair_round_trip_ms = -1;  // smoothed NACK-to-repair time
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
               if (Status valid = Validate(message); !valid) {
                 return Drop(where, TypeName<T>() + ": " + valid.error().message);
               }
               counters_received_.fetch_add(1, std::memory_order_relaxed);
               handler(message);
             });
  }

  BusCounters counters() const;
  // The smoothed time from a NACK to its first repaired piece (-1: none
  // measured yet): a round trip to the senders of this run.
  double RepairRoundTripMs() const;
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
  void OnNack(const fragment_nack_t& nack);
  // Sends the pieces of `message` (those set in `only`, if given).
  void SendPieces(const SentMessage& message, const std::vector<uint8_t>* only, bool repair);
  void RepairLoop();
  void Drop(const std::string& channel, const std::string& why);

  lcm::LCM& lcm_;
  std::string run_id_;
  BusOptions options_;
  // Written by Subscribe only before dispatching starts (checked: the route
  // lists are read by the dispatch thread without a lock).
  std::map<std::string, std::vector<Route>> routes_;
  std::atomic<bool> dispatching_{false};
  std::vector<lcm::Subscription*> subscriptions_;
  std::mutex fragments_mutex_;   // the dispatch and repair threads
  FragmentAssembler fragments_;  // guarded by fragments_mutex_
  double repair_rtt_ms_ = 20;    // guarded by fragments_mutex_
  bool repair_rtt_measured_ = false;
  std::mutex sent_mutex_;
  SentStore sent_;  // guarded by sent_mutex_
  std::mutex repair_wait_mutex_;
  std::condition_variable repair_wake_;
  std::atomic<bool> repair_stop_{false};
  std::thread repair_thread_;
  std::atomic<int64_t> next_message_id_;
  std::mutex fault_mutex_;
  Rng fault_rng_;
  Sealer sealer_;
  Verifier verifier_;  // dispatch thread only
  std::atomic<int64_t> counters_published_{0}, counters_received_{0}, counters_dropped_{0},
      counters_fragments_{0}, counters_injected_drops_{0}, counters_injected_duplicates_{0},
      counters_unauthenticated_{0}, counters_replayed_{0}, counters_fragments_sent_{0},
      counters_ids_reused_{0}, counters_nacks_sent_{0}, counters_nacks_received_{0},
      counters_pieces_repaired_{0}, counters_parity_sent_{0};
  // When a NACK was last sent or received (parity_after_loss); none yet.
  std::atomic<int64_t> last_loss_ms_{std::numeric_limits<int64_t>::min() / 2};
  int64_t last_warning_ms_ = -1000000;
  int64_t warnings_suppressed_ = 0;
};

}  // namespace dynapath::protocol
