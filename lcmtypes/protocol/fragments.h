#pragma once
// Reassembly of fragment_t pieces (messages above one UDP datagram) into the
// whole encoded message, shared by the Bus (live traffic) and the policy log
// reader (tools/view). The caller decodes and validates each fragment_t
// (protocol::Validate, run id) and decodes the whole message it gets back;
// this class checks that the pieces agree with each other, bounds memory
// (partial messages kept, message size), and forgets partial messages whose
// sender gave up.

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

class FragmentAssembler {
 public:
  // `lifetime`: a partial message not added to for longer is forgotten (in
  // the unit of the `now` the caller passes).
  FragmentAssembler(size_t max_partials, int32_t max_message_bytes, int64_t lifetime);

  struct Outcome {
    enum class Kind { kIncomplete, kComplete, kDropped } kind = Kind::kIncomplete;
    std::vector<uint8_t> bytes;  // kComplete: the whole message
    std::string why;             // kDropped: why
  };
  // Adds a decoded, validated piece received on `channel` at `now`. A
  // complete message's fingerprint matches the one its pieces announced.
  Outcome Add(const std::string& channel, const fragment_t& fragment, int64_t now);

  size_t pending() const { return partials_.size(); }
  int64_t expired() const { return expired_; }

 private:
  struct Partial {
    int64_t fingerprint = 0;
    int32_t total_size = 0;
    int32_t count = 0;
    int32_t have = 0;
    std::vector<uint8_t> bytes;
    std::vector<bool> present;
    int64_t last_seen = 0;
  };

  size_t max_partials_;
  int32_t max_message_bytes_;
  int64_t lifetime_;
  int64_t expired_ = 0;
  std::map<std::pair<std::string, int64_t>, Partial> partials_;  // by (channel, message id)
};

}  // namespace dynapath::protocol
