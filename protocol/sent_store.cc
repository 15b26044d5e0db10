#include "protocol/sent_store.h"

#include <cstring>
#include <functional>
#include <string_view>

namespace dynapath::protocol {

SentStore::SentStore(int64_t max_bytes, size_t max_messages, int64_t lifetime)
    : max_bytes_(max_bytes), max_messages_(max_messages), lifetime_(lifetime) {}

uint64_t SentStore::Hash(const std::vector<uint8_t>& bytes) {
  return std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

void SentStore::Expire(int64_t now) {
  while (!messages_.empty() && now - messages_.front()->sent_ms > lifetime_) {
    bytes_ -= static_cast<int64_t>(messages_.front()->bytes.size());
    messages_.pop_front();
  }
}

std::shared_ptr<const SentMessage> SentStore::Find(const std::string& channel,
                                                   const std::vector<uint8_t>& bytes, uint64_t hash,
                                                   int piece, int64_t now) {
  Expire(now);
  for (auto it = messages_.rbegin(); it != messages_.rend(); ++it) {
    const SentMessage& m = **it;
    if (m.hash == hash && m.piece == piece && m.bytes.size() == bytes.size() &&
        m.channel == channel && std::memcmp(m.bytes.data(), bytes.data(), bytes.size()) == 0) {
      return *it;
    }
  }
  return nullptr;
}

std::shared_ptr<const SentMessage> SentStore::Get(const std::string& channel, int64_t id,
                                                  int64_t now) {
  Expire(now);
  for (auto it = messages_.rbegin(); it != messages_.rend(); ++it) {
    if ((*it)->id == id && (*it)->channel == channel) return *it;
  }
  return nullptr;
}

void SentStore::Add(std::shared_ptr<const SentMessage> message, int64_t now) {
  Expire(now);
  bytes_ += static_cast<int64_t>(message->bytes.size());
  messages_.push_back(std::move(message));
  while (messages_.size() > 1 && (bytes_ > max_bytes_ || messages_.size() > max_messages_)) {
    bytes_ -= static_cast<int64_t>(messages_.front()->bytes.size());
    messages_.pop_front();
  }
}

}  // namespace dynapath::protocol
