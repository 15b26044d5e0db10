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

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "dynapath/fragment_t.hpp"

namespace dynapath::protocol {

// The LCM fingerprint at the start of an encoded message (0 when shorter
// than 8 bytes): which type it claims to be.
int64_t PeekFingerprint(const uint8_t* data, int size);

struct FragmentLimits {
  int64_t max_message_bytes = 0;   // largest whole message accepted
  int64_t max_buffered_bytes = 0;  // all partial messages together
  size_t max_partials = 0;         // partial messages kept at once
  int64_t lifetime = 0;            // not added to for longer: forgotten (caller's clock)
};

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
  };
  // Adds a decoded, validated piece received on `channel` at `now`. A
  // complete message's pieces tile it exactly and its fingerprint matches
  // the one its pieces announced.
  Outcome Add(const std::string& channel, const fragment_t& fragment, int64_t now);

  const FragmentLimits& limits() const { return limits_; }
  size_t pending() const { return partials_.size(); }
  int64_t buffered_bytes() const { return buffered_; }
  int64_t expired() const { return expired_; }  // forgotten after `lifetime`
  int64_t evicted() const { return evicted_; }  // pushed out by newer partial messages

 private:
  struct Partial {
    int64_t fingerprint = 0;
    int32_t total_size = 0;
    int32_t count = 0;
    int64_t held = 0;  // bytes charged to the budget
    // index -> (offset, bytes)
    std::map<int32_t, std::pair<int32_t, std::vector<uint8_t>>> pieces;
    int64_t first_seen = 0;
    int64_t last_seen = 0;
  };
  using Key = std::pair<std::string, int64_t>;  // (channel, message id)

  void Erase(std::map<Key, Partial>::iterator it);
  // Evicts the partial message least recently added to (never `keep`).
  bool EvictOldest(const Key& keep);

  FragmentLimits limits_;
  int64_t buffered_ = 0;
  int64_t expired_ = 0;
  int64_t evicted_ = 0;
  std::map<Key, Partial> partials_;
};

}  // namespace dynapath::protocol
