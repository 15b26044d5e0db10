#include "runtime/reply_witness.h"

#include <functional>
#include <string_view>
#include <vector>

#include "dynapath/change_sequence.h"

namespace dynapath::runtime {

std::string DescribeReplier(const path_reply_t& reply) {
  return "the service of maze fingerprint " +
         FingerprintText(static_cast<uint64_t>(reply.maze_fingerprint)) + " (" + reply.approach +
         ", policy version " + std::to_string(reply.version) + ", step " +
         std::to_string(reply.time_step) + ")";
}

bool ReplyWitness::Saw(const path_reply_t& reply) {
  std::vector<uint8_t> bytes(static_cast<size_t>(reply.getEncodedSize()));
  reply.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  const uint64_t digest = std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  auto [it, first] = seen_.try_emplace(reply.request_id, Seen{digest, DescribeReplier(reply)});
  if (first) {
    if (seen_.size() > kKeptRequests) seen_.erase(seen_.begin());
    return true;
  }
  if (it->second.digest == digest) return true;  // the same reply again
  if (!conflict_) {
    conflict_ = "two services answer this run: request " + std::to_string(reply.request_id) +
                " was answered by " + it->second.service + " and by " + DescribeReplier(reply) +
                "; give each service a run id of its own";
  }
  return false;
}

}  // namespace dynapath::runtime
