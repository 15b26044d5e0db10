#include "lcmtypes/protocol/fragments.h"

#include <cstring>

namespace dynapath::protocol {

int64_t PeekFingerprint(const uint8_t* data, int size) {
  if (size < 8) return 0;
  uint64_t value = 0;
  for (int i = 0; i < 8; ++i) value = (value << 8) | data[i];
  return static_cast<int64_t>(value);
}

FragmentAssembler::FragmentAssembler(FragmentLimits limits) : limits_(limits) {}

void FragmentAssembler::Erase(std::map<Key, Partial>::iterator it) {
  buffered_ -= it->second.held;
  partials_.erase(it);
}

bool FragmentAssembler::EvictOldest(const Key& keep) {
  auto oldest = partials_.end();
  for (auto it = partials_.begin(); it != partials_.end(); ++it) {
    if (it->first == keep) continue;
    if (oldest == partials_.end() || it->second.last_seen < oldest->second.last_seen) oldest = it;
  }
  if (oldest == partials_.end()) return false;
  Erase(oldest);
  ++evicted_;
  return true;
}

FragmentAssembler::Outcome FragmentAssembler::Add(const std::string& channel,
                                                  const fragment_t& fragment, int64_t now) {
  auto dropped = [](std::string why) {
    Outcome outcome;
    outcome.kind = Outcome::Kind::kDropped;
    outcome.why = std::move(why);
    return outcome;
  };
  if (fragment.total_size < 1 || fragment.total_size > limits_.max_message_bytes) {
    return dropped("fragmented message too big");
  }
  // Every piece holds at least one byte: more pieces than bytes is a lie.
  if (fragment.count < 1 || fragment.count > fragment.total_size || fragment.index < 0 ||
      fragment.index >= fragment.count || fragment.size < 1 || fragment.offset < 0 ||
      static_cast<int64_t>(fragment.offset) + fragment.size > fragment.total_size ||
      static_cast<int64_t>(fragment.data.size()) != fragment.size) {
    return dropped("fragment_t inconsistent with itself");
  }
  // Forget partial messages whose sender gave up or died.
  for (auto it = partials_.begin(); it != partials_.end();) {
    if (now - it->second.last_seen > limits_.lifetime) {
      ++expired_;
      buffered_ -= it->second.held;
      it = partials_.erase(it);
    } else {
      ++it;
    }
  }
  const Key key(channel, fragment.message_id);
  auto it = partials_.find(key);
  if (it == partials_.end()) {
    while (partials_.size() >= limits_.max_partials && EvictOldest(key)) {
    }
    if (partials_.size() >= limits_.max_partials) return dropped("too many partial messages");
    Partial partial;
    partial.fingerprint = fragment.fingerprint;
    partial.total_size = fragment.total_size;
    partial.count = fragment.count;
    partial.first_seen = now;
    it = partials_.emplace(key, std::move(partial)).first;
  }
  Partial& partial = it->second;
  // A piece that disagrees with the others is dropped; the partial message
  // stays (a forged piece cannot cancel a real message).
  if (partial.fingerprint != fragment.fingerprint || partial.total_size != fragment.total_size ||
      partial.count != fragment.count) {
    return dropped("fragment_t inconsistent with its message");
  }
  partial.last_seen = now;
  if (partial.pieces.count(fragment.index) != 0) return Outcome{};  // a re-sent piece
  const int64_t cost = static_cast<int64_t>(fragment.size) + kPieceOverhead;
  while (buffered_ + cost > limits_.max_buffered_bytes && EvictOldest(key)) {
  }
  if (buffered_ + cost > limits_.max_buffered_bytes) {
    Erase(it);
    return dropped("fragment buffer full");
  }
  partial.pieces.emplace(fragment.index, std::make_pair(fragment.offset, fragment.data));
  partial.held += cost;
  buffered_ += cost;
  if (static_cast<int32_t>(partial.pieces.size()) < partial.count) return Outcome{};

  // All pieces are there: they must tile the message exactly.
  std::map<int32_t, const std::vector<uint8_t>*> by_offset;
  for (const auto& [index, piece] : partial.pieces) by_offset.emplace(piece.first, &piece.second);
  Outcome outcome;
  int64_t end = 0;
  bool tiles = by_offset.size() == partial.pieces.size();
  for (const auto& [offset, bytes] : by_offset) {
    if (!tiles || offset != end) {
      tiles = false;
      break;
    }
    end += static_cast<int64_t>(bytes->size());
  }
  tiles = tiles && end == partial.total_size;
  if (tiles) {
    outcome.bytes.resize(static_cast<size_t>(partial.total_size));
    for (const auto& [offset, bytes] : by_offset) {
      std::memcpy(outcome.bytes.data() + offset, bytes->data(), bytes->size());
    }
  }
  const int64_t fingerprint = partial.fingerprint;
  Erase(it);
  if (!tiles) return dropped("fragment pieces overlap or leave gaps");
  if (PeekFingerprint(outcome.bytes.data(), static_cast<int>(outcome.bytes.size())) !=
      fingerprint) {
    return dropped("reassembled message has the wrong type");
  }
  outcome.kind = Outcome::Kind::kComplete;
  return outcome;
}

}  // namespace dynapath::protocol
