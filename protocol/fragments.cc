#include "protocol/fragments.h"

#include <algorithm>
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
    // Stray pieces of completed messages go first, then the stalest.
    if (oldest == partials_.end() ||
        std::make_pair(!it->second.after_complete, it->second.last_seen) <
            std::make_pair(!oldest->second.after_complete, oldest->second.last_seen)) {
      oldest = it;
    }
  }
  if (oldest == partials_.end()) return false;
  if (oldest->second.after_complete) {
    ++strays_;
  } else {
    ++evicted_;
  }
  Erase(oldest);
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
    const int64_t lifetime = it->second.after_complete
                                 ? std::min(limits_.lifetime, limits_.completed_lifetime)
                                 : limits_.lifetime;
    if (now - it->second.last_seen > lifetime) {
      ++(it->second.after_complete ? strays_ : expired_);
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
    partial.after_complete = completed_.count(key) != 0;
    it = partials_.emplace(key, std::move(partial)).first;
  }
  Partial& partial = it->second;
  // A piece that disagrees with the others is dropped; the partial message
  // stays (a forged piece cannot cancel a real message).
  if (partial.fingerprint != fragment.fingerprint || partial.total_size != fragment.total_size ||
      partial.count != fragment.count) {
    return dropped("fragment_t inconsistent with its message");
  }
  if (fragment.parity && partial.group_size != 0 && partial.group_size != fragment.group_size) {
    return dropped("parity piece inconsistent with its message");
  }
  partial.last_seen = now;
  if ((fragment.parity ? partial.parities.count(fragment.index)
                       : partial.pieces.count(fragment.index)) != 0) {
    return Outcome{};  // a re-sent piece
  }
  Outcome progress;
  if (partial.first_nack >= 0 && !partial.timed) {
    progress.repair_round_trip = now - partial.first_nack;
    partial.timed = true;
  }
  partial.nacks = 0;
  const int64_t cost = static_cast<int64_t>(fragment.size) + kPieceOverhead;
  while (buffered_ + cost > limits_.max_buffered_bytes && EvictOldest(key)) {
  }
  if (buffered_ + cost > limits_.max_buffered_bytes) {
    Erase(it);
    return dropped("fragment buffer full");
  }
  partial.held += cost;
  buffered_ += cost;
  if (fragment.parity) {
    partial.group_size = fragment.group_size;
    partial.parities.emplace(fragment.index, fragment.data);
    Rebuild(partial, fragment.index);
  } else {
    partial.pieces.emplace(fragment.index, std::make_pair(fragment.offset, fragment.data));
    if (partial.group_size > 0) {
      Rebuild(partial, fragment.index % ParityGroups(partial.count, partial.group_size));
    }
  }
  if (static_cast<int32_t>(partial.pieces.size()) < partial.count) return progress;

  // All pieces are there: they must tile the message exactly.
  std::map<int32_t, const std::vector<uint8_t>*> by_offset;
  for (const auto& [index, piece] : partial.pieces) by_offset.emplace(piece.first, &piece.second);
  Outcome outcome;
  outcome.repair_round_trip = progress.repair_round_trip;
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
  RememberCompleted(key);
  if (!tiles) return dropped("fragment pieces overlap or leave gaps");
  if (PeekFingerprint(outcome.bytes.data(), static_cast<int>(outcome.bytes.size())) !=
      fingerprint) {
    return dropped("reassembled message has the wrong type");
  }
  outcome.kind = Outcome::Kind::kComplete;
  ++completed_count_;
  return outcome;
}

bool FragmentAssembler::Rebuild(Partial& partial, int32_t group) {
  const auto parity = partial.parities.find(group);
  if (parity == partial.parities.end()) return false;
  const int32_t groups = ParityGroups(partial.count, partial.group_size);
  int32_t missing = -1;
  for (int64_t i = group; i < partial.count; i += groups) {
    if (partial.pieces.count(static_cast<int32_t>(i)) != 0) continue;
    if (missing >= 0) return false;  // two missing: only a NACK helps
    missing = static_cast<int32_t>(i);
  }
  if (missing < 0) return false;
  // Every data piece but the last holds as many bytes as the parity piece.
  const std::vector<uint8_t>& sum = parity->second;
  const int64_t piece = static_cast<int64_t>(sum.size());
  const int64_t offset = static_cast<int64_t>(missing) * piece;
  const int64_t size = std::min(piece, static_cast<int64_t>(partial.total_size) - offset);
  const int64_t cost = size + kPieceOverhead;
  if (size < 1 || buffered_ + cost > limits_.max_buffered_bytes) return false;
  std::vector<uint8_t> bytes(sum.begin(), sum.begin() + size);
  for (int64_t i = group; i < partial.count; i += groups) {
    if (i == missing) continue;
    const std::vector<uint8_t>& data = partial.pieces.at(static_cast<int32_t>(i)).second;
    if (static_cast<int64_t>(data.size()) > piece) return false;  // not this layout
    const size_t n = std::min(bytes.size(), data.size());
    for (size_t j = 0; j < n; ++j) bytes[j] ^= data[j];
  }
  partial.pieces.emplace(missing, std::make_pair(static_cast<int32_t>(offset), std::move(bytes)));
  partial.held += cost;
  buffered_ += cost;
  ++rebuilt_;
  return true;
}

void FragmentAssembler::RememberCompleted(const Key& key) {
  if (limits_.max_completed == 0 || !completed_.insert(key).second) return;
  completed_order_.push_back(key);
  while (completed_order_.size() > limits_.max_completed) {
    completed_.erase(completed_order_.front());
    completed_order_.pop_front();
  }
}

std::vector<Nack> FragmentAssembler::DueNacks(int64_t now, int64_t quiet, int64_t retry,
                                              int max_nacks) {
  std::vector<Nack> due;
  for (auto& [key, partial] : partials_) {
    if (partial.count > partial.total_size / std::max(1, limits_.min_piece_bytes) + 1) continue;
    if (partial.after_complete || partial.nacks >= max_nacks || now - partial.last_seen < quiet ||
        (partial.nacks > 0 && now - partial.last_nack < retry)) {
      continue;
    }
    Nack nack;
    nack.channel = key.first;
    nack.message_id = key.second;
    nack.count = partial.count;
    nack.missing.assign((static_cast<size_t>(partial.count) + 7) / 8, 0);
    for (int32_t i = 0; i < partial.count; ++i) {
      if (partial.pieces.count(i) == 0) {
        nack.missing[static_cast<size_t>(i) / 8] |= static_cast<uint8_t>(1u << (i % 8));
        ++nack.missing_count;
      }
    }
    ++partial.nacks;
    partial.last_nack = now;
    if (partial.first_nack < 0) partial.first_nack = now;
    due.push_back(std::move(nack));
  }
  return due;
}

}  // namespace dynapath::protocol
