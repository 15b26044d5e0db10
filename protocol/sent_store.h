#pragma once
// The sender's side of selective repair (bus.h): the fragmented messages a
// Bus published lately, so that
//   * publishing the same bytes on the same channel again (a component's
//     resend) reuses the message id, and the pieces complete what receivers
//     hold of the earlier attempts instead of starting over, and
//   * a receiver's NACK (fragment_nack_t) is answered with exactly the
//     pieces it lacks.
// Bounded: at most `max_bytes` of messages (the newest is always kept),
// `max_messages` of them, each for `lifetime` ms; the oldest go first.
// Not thread-safe: the Bus guards it.

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

namespace dynapath::protocol {

struct SentMessage {
  std::string channel;
  int64_t id = 0;
  int64_t fingerprint = 0;
  uint64_t hash = 0;
  int piece = 0;  // payload bytes per piece
  std::vector<uint8_t> bytes;
  int64_t sent_ms = 0;
  int32_t count() const {
    return static_cast<int32_t>((bytes.size() + static_cast<size_t>(piece) - 1) /
                                static_cast<size_t>(piece));
  }
};

class SentStore {
 public:
  SentStore(int64_t max_bytes, size_t max_messages, int64_t lifetime);

  static uint64_t Hash(const std::vector<uint8_t>& bytes);
  // The message with these bytes sent on `channel` with pieces of `piece`
  // bytes, or null.
  std::shared_ptr<const SentMessage> Find(const std::string& channel,
                                          const std::vector<uint8_t>& bytes, uint64_t hash,
                                          int piece, int64_t now);
  // The message `id` sent on `channel`, or null.
  std::shared_ptr<const SentMessage> Get(const std::string& channel, int64_t id, int64_t now);
  void Add(std::shared_ptr<const SentMessage> message, int64_t now);

  size_t size() const { return messages_.size(); }
  int64_t bytes() const { return bytes_; }

 private:
  void Expire(int64_t now);
  int64_t max_bytes_;
  size_t max_messages_;
  int64_t lifetime_;
  int64_t bytes_ = 0;
  std::deque<std::shared_ptr<const SentMessage>> messages_;  // oldest first
};

}  // namespace dynapath::protocol
