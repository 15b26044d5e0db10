#include "lcmtypes/protocol/fragments.h"

#include <cstring>

namespace dynapath::protocol {

int64_t PeekFingerprint(const uint8_t* data, int size) {
  if (size < 8) return 0;
  uint64_t value = 0;
  for (int i = 0; i < 8; ++i) value = (value << 8) | data[i];
  return static_cast<int64_t>(value);
}

FragmentAssembler::FragmentAssembler(size_t max_partials, int32_t max_message_bytes,
                                     int64_t lifetime)
    : max_partials_(max_partials), max_message_bytes_(max_message_bytes), lifetime_(lifetime) {}

FragmentAssembler::Outcome FragmentAssembler::Add(const std::string& channel,
                                                  const fragment_t& fragment, int64_t now) {
  auto dropped = [](std::string why) {
    Outcome outcome;
    outcome.kind = Outcome::Kind::kDropped;
    outcome.why = std::move(why);
    return outcome;
  };
  if (fragment.total_size > max_message_bytes_) return dropped("fragmented message too big");
  // Forget partial messages whose sender gave up or died.
  for (auto it = partials_.begin(); it != partials_.end();) {
    if (now - it->second.last_seen > lifetime_) {
      ++expired_;
      it = partials_.erase(it);
    } else {
      ++it;
    }
  }
  const auto key = std::make_pair(channel, fragment.message_id);
  auto it = partials_.find(key);
  if (it == partials_.end()) {
    if (partials_.size() >= max_partials_) return dropped("too many partial messages");
    Partial partial;
    partial.fingerprint = fragment.fingerprint;
    partial.total_size = fragment.total_size;
    partial.count = fragment.count;
    partial.bytes.resize(static_cast<size_t>(fragment.total_size));
    partial.present.assign(static_cast<size_t>(fragment.count), false);
    it = partials_.emplace(key, std::move(partial)).first;
  }
  Partial& partial = it->second;
  if (partial.fingerprint != fragment.fingerprint || partial.total_size != fragment.total_size ||
      partial.count != fragment.count || fragment.offset < 0 ||
      static_cast<int64_t>(fragment.offset) + fragment.size > partial.total_size) {
    partials_.erase(it);
    return dropped("fragment_t inconsistent with its message");
  }
  partial.last_seen = now;
  if (!partial.present[static_cast<size_t>(fragment.index)]) {
    std::memcpy(partial.bytes.data() + fragment.offset, fragment.data.data(),
                static_cast<size_t>(fragment.size));
    partial.present[static_cast<size_t>(fragment.index)] = true;
    ++partial.have;
  }
  if (partial.have < partial.count) return Outcome{};
  Outcome outcome;
  outcome.bytes = std::move(partial.bytes);
  const int64_t fingerprint = partial.fingerprint;
  partials_.erase(it);
  if (PeekFingerprint(outcome.bytes.data(), static_cast<int>(outcome.bytes.size())) !=
      fingerprint) {
    return dropped("reassembled message has the wrong type");
  }
  outcome.kind = Outcome::Kind::kComplete;
  return outcome;
}

}  // namespace dynapath::protocol
