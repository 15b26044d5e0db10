#pragma once
// The replies of `dynapath serve` to one client, by request. One service of
// a run answers each request once, so a second reply to a request that
// differs from the first means two services answer the run (another maze,
// or another policy of it): the client cannot know which one is right and
// says so instead of taking whichever came first.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "dynapath/path_reply_t.hpp"

namespace dynapath::runtime {

// Not thread-safe: the client guards it.
class ReplyWitness {
 public:
  // Requests remembered (the latest): bounded memory however long a client runs.
  static constexpr size_t kKeptRequests = 4096;

  // Records `reply`; false when it is a second, different reply to a
  // request (the first such is kept as conflict()).
  bool Saw(const path_reply_t& reply);
  // The first conflict seen: both replies' services named by their maze
  // fingerprint, approach, policy version and step.
  const std::optional<std::string>& conflict() const { return conflict_; }

 private:
  struct Seen {
    uint64_t digest = 0;  // of the encoded reply
    std::string service;  // its description
  };
  std::map<int64_t, Seen> seen_;
  std::optional<std::string> conflict_;
};

// "the service of maze fingerprint F (approach A, policy version V, step S)".
std::string DescribeReplier(const path_reply_t& reply);

}  // namespace dynapath::runtime
