#pragma once
// POLICY messages from raw LCM data, for the log reader and the live viewer:
// recognises DYNAPATH/<run>/POLICY channels, reassembles fragment_t pieces
// (messages above 128 KB: the policies of grids of about 100x100 and more),
// decodes and validates policy_t. Anything wrong is dropped and counted,
// never trusted: sizes, offsets and the message's type are all checked.
// Authentication trailers (protocol/auth.h) are stripped, not
// checked: this reader has no secret and steers nothing.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "dynapath/policy_t.hpp"
#include "dynapath/result.h"
#include "protocol/fragments.h"

namespace dynapath::view {

// The run of a DYNAPATH/<run>/POLICY channel, or nullopt for other channels.
std::optional<std::string> PolicyChannelRun(std::string_view channel);

struct PolicyStreamCounters {
  int64_t policies = 0;   // valid policies delivered
  int64_t fragments = 0;  // valid fragment_t pieces taken
  int64_t dropped = 0;    // undecodable, invalid or inconsistent messages
  int64_t expired = 0;    // partial messages forgotten before they were complete
};

class PolicyAssembler {
 public:
  // Partial messages older than this (in the caller's clock) are forgotten.
  explicit PolicyAssembler(int64_t partial_lifetime_us = 30'000'000);

  // One raw message received on `channel` (a POLICY channel) at `now_us`.
  // Returns a valid policy once one is complete, else nullopt (a piece of a
  // message still missing others, or dropped: see why()).
  std::optional<policy_t> Feed(std::string_view channel, const uint8_t* data, int size,
                               int64_t now_us);

  const PolicyStreamCounters& counters() const { return counters_; }
  // Why the last message was dropped ("" when it was not).
  const std::string& why() const { return why_; }
  // Partial messages still waiting for pieces.
  size_t pending() const { return fragments_.pending(); }

 private:
  std::optional<policy_t> Drop(std::string why);
  std::optional<policy_t> DecodePolicy(const std::string& run, const uint8_t* data, int size);
  std::optional<policy_t> FeedFragment(const std::string& channel, const std::string& run,
                                       const uint8_t* data, int size, int64_t now_us);

  protocol::FragmentAssembler fragments_;
  PolicyStreamCounters counters_;
  std::string why_;
};

struct PolicyLogSummary {
  int64_t events = 0;         // all events of the log
  int64_t policy_events = 0;  // events on POLICY channels (fragments included)
  PolicyStreamCounters counters;
  int64_t incomplete = 0;  // fragmented messages still missing pieces at the end
};

// Calls `visit` with every valid policy of the LCM log at `path`, in log
// order (of run `run_id` only, unless empty). Errors: the file cannot be
// opened, or it holds no LCM events.
Result<PolicyLogSummary> ReadPolicyLog(const std::string& path, const std::string& run_id,
                                       const std::function<void(policy_t&)>& visit);

}  // namespace dynapath::view
