#pragma once
// Reassembly of fragment_t pieces (messages above one UDP datagram) into the
// whole encoded message, shared by the Bus (live traffic) and the policy log
// reader (tools/view). The caller decodes and validates each fragment_t
// (protocol::Validate, run id) and decodes the whole message it gets back.
//
// Everything here is keyed by what a sender says (message ids, sizes, piece
// counts), so memory is bounded by hard caps, not by the announcements:
// pieces are stored as they arrive (nothing is allocated for the announced
// total), the bytes held by all partial messages together (with a fixed
// bookkeeping cost per piece) never exceed `max_buffered_bytes`, the oldest
// partial messages are evicted to make room, and every drop is counted.
//
// Selective repair (bus.h): a partial message that got no new piece for a
// quiet period is reported by DueNacks with a bitmap of its missing pieces,
// again after a retry interval while it stays incomplete, at most
// max_nacks times without progress. Messages completed lately are
// remembered: pieces of them arriving afterwards (a repair another receiver
// asked for, a duplicate) start a partial message that is never reported,
// is evicted first and is forgotten after a short lifetime, unless the
// whole message arrives again (a sender's repeat), which is delivered again.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "dynapath/fragment_t.hpp"

namespace dynapath::protocol {

// The LCM fingerprint at the start of an encoded message (0 when shorter
// than 8 bytes): which type it claims to be.
int64_t PeekFingerprint(const uint8_t* data, int size);

// Parity groups of a message of `count` data pieces with `group_size`
// (>= 2) pieces per group: piece i is in group i % ParityGroups.
inline int32_t ParityGroups(int32_t count, int32_t group_size) {
  return static_cast<int32_t>((static_cast<int64_t>(count) + group_size - 1) / group_size);
}

struct FragmentLimits {
  int64_t max_message_bytes = 0;   // largest whole message accepted
  int64_t max_buffered_bytes = 0;  // all partial messages together
  size_t max_partials = 0;         // partial messages kept at once
  int64_t lifetime = 0;            // not added to for longer: forgotten (caller's clock)
  // Partial messages of an id completed lately: forgotten sooner.
  int64_t completed_lifetime = 2000;
  size_t max_completed = 1024;  // completed ids remembered
  // Senders' pieces hold at least this many bytes but the last (the Bus's
  // smallest): a partial announcing more pieces is not NACKed, which keeps
  // NACK bitmaps small.
  int32_t min_piece_bytes = 1024;
};

// A receiver's request for the pieces it lacks (fragment_nack_t's content).
struct Nack {
  std::string channel;
  int64_t message_id = 0;
  int32_t count = 0;
  std::vector<uint8_t> missing;  // bit i % 8 of byte i / 8: piece i missing
  // Pieces missing (for the tests and counters).
  int32_t missing_count = 0;
};

// Bit `index` of a NACK bitmap.
inline bool NackBit(const std::vector<uint8_t>& bitmap, int32_t index) {
  const size_t byte = static_cast<size_t>(index) / 8;
  return byte < bitmap.size() && ((bitmap[byte] >> (index % 8)) & 1) != 0;
}

class FragmentAssembler {
 public:
  // What one stored piece costs besides its bytes (map node, vector, heap
  // headers): a flood of one-byte pieces is charged for what it really takes.
  static constexpr int64_t kPieceOverhead = 128;

  explicit FragmentAssembler(FragmentLimits limits);

  struct Outcome {
    enum class Kind { kIncomplete, kComplete, kDropped } kind = Kind::kIncomplete;
    std::vector<uint8_t> bytes;  // kComplete: the whole message
    std::string why;             // kDropped: why
    // A new piece of a message this receiver had NACKed once: the time
    // since that NACK, a round-trip sample of the repair (-1: none).
    int64_t repair_round_trip = -1;
  };
  // Adds a decoded, validated piece received on `channel` at `now`. A
  // complete message's pieces tile it exactly and its fingerprint matches
  // the one its pieces announced.
  Outcome Add(const std::string& channel, const fragment_t& fragment, int64_t now);

  // Partial messages (not of a completed id) that got no new piece for
  // `quiet` and were not reported for `retry` (NACKed fewer than
  // `max_nacks` times since their last new piece): each reported once more.
  std::vector<Nack> DueNacks(int64_t now, int64_t quiet, int64_t retry, int max_nacks);

  const FragmentLimits& limits() const { return limits_; }
  size_t pending() const { return partials_.size(); }
  int64_t buffered_bytes() const { return buffered_; }
  int64_t expired() const { return expired_; }  // forgotten after `lifetime`
  int64_t evicted() const { return evicted_; }  // pushed out by newer partial messages
  int64_t completed() const { return completed_count_; }
  // Partial messages of completed ids forgotten (stray repairs, duplicates).
  int64_t strays() const { return strays_; }
  // Data pieces rebuilt from parity pieces (never sent again, never NACKed).
  int64_t rebuilt() const { return rebuilt_; }

 private:
  struct Partial {
    int64_t fingerprint = 0;
    int32_t total_size = 0;
    int32_t count = 0;
    int64_t held = 0;  // bytes charged to the budget
    // index -> (offset, bytes)
    std::map<int32_t, std::pair<int32_t, std::vector<uint8_t>>> pieces;
    // Parity pieces: group -> XOR of the group's pieces (all of
    // piece_bytes); group_size 0 until the first parity piece.
    std::map<int32_t, std::vector<uint8_t>> parities;
    int32_t group_size = 0;
    int64_t first_seen = 0;
    int64_t last_seen = 0;
    bool after_complete = false;  // an id completed lately: never NACKed
    int nacks = 0;                // NACKs since the last new piece
    int64_t last_nack = 0;
    int64_t first_nack = -1;  // when the first NACK went out (Karn: only it is timed)
    bool timed = false;       // its round trip was sampled
  };
  using Key = std::pair<std::string, int64_t>;  // (channel, message id)

  void Erase(std::map<Key, Partial>::iterator it);
  // Rebuilds the one missing data piece of `group` from its parity piece and
  // the others, if exactly one is missing; false when the sizes do not fit
  // (a sender's lie: nothing is added).
  bool Rebuild(Partial& partial, int32_t group);
  // Evicts a partial message of a completed id, else the one least
  // recently added to (never `keep`).
  bool EvictOldest(const Key& keep);
  void RememberCompleted(const Key& key);

  FragmentLimits limits_;
  int64_t buffered_ = 0;
  int64_t expired_ = 0;
  int64_t evicted_ = 0;
  int64_t completed_count_ = 0;
  int64_t strays_ = 0;
  int64_t rebuilt_ = 0;
  std::map<Key, Partial> partials_;
  std::set<Key> completed_;
  std::deque<Key> completed_order_;
};

}  // namespace dynapath::protocol
