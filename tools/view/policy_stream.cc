#include "tools/view/policy_stream.h"

#include <cstdio>
#include <cstring>
#include <exception>

#include "dynapath/fragment_t.hpp"
#include "protocol/auth.h"
#include "protocol/decode.h"
#include "protocol/fragments.h"
#include "protocol/limits.h"
#include "protocol/log_reader.h"
#include "protocol/validate.h"

namespace dynapath::view {
namespace {

constexpr std::string_view kPrefix = "DYNAPATH/";
constexpr std::string_view kSuffix = "/POLICY";
// A policy_t of the largest grid the protocol accepts (three bytes per cell
// and at most one 16-byte region per cell) with room for its strings.
constexpr int64_t kMaxMessageBytes = 19 * protocol::kMaxGridCells + (1 << 20);

protocol::FragmentLimits PolicyFragmentLimits(int64_t lifetime_us) {
  protocol::FragmentLimits limits;
  limits.max_message_bytes = kMaxMessageBytes;
  // One policy at a time plus as much again of partial ones: a policy log
  // or stream interleaves the fragments of one approach's policies only.
  limits.max_buffered_bytes = 2 * kMaxMessageBytes + (int64_t{1} << 20);
  limits.max_partials = 64;
  limits.lifetime = lifetime_us;
  return limits;
}

}  // namespace

std::optional<std::string> PolicyChannelRun(std::string_view channel) {
  if (channel.size() <= kPrefix.size() + kSuffix.size() || !channel.starts_with(kPrefix) ||
      !channel.ends_with(kSuffix)) {
    return std::nullopt;
  }
  std::string_view run =
      channel.substr(kPrefix.size(), channel.size() - kPrefix.size() - kSuffix.size());
  if (run.find('/') != std::string_view::npos) return std::nullopt;
  return std::string(run);
}

PolicyAssembler::PolicyAssembler(int64_t partial_lifetime_us)
    : fragments_(PolicyFragmentLimits(partial_lifetime_us)) {}

std::optional<policy_t> PolicyAssembler::Drop(std::string why) {
  why_ = std::move(why);
  ++counters_.dropped;
  return std::nullopt;
}

std::optional<policy_t> PolicyAssembler::DecodePolicy(const std::string& run, const uint8_t* data,
                                                      int size) {
  policy_t policy{};
  if (!protocol::DecodeExactly(data, size, policy)) return Drop("undecodable policy_t");
  if (policy.run_id != run) return Drop("policy_t of run '" + policy.run_id + "' on run " + run);
  if (Status valid = protocol::Validate(policy); !valid) {
    return Drop("policy_t: " + valid.error().message);
  }
  ++counters_.policies;
  return policy;
}

std::optional<policy_t> PolicyAssembler::Feed(std::string_view channel, const uint8_t* data,
                                              int size, int64_t now_us) {
  why_.clear();
  const std::optional<std::string> run = PolicyChannelRun(channel);
  if (!run) return Drop("not a POLICY channel");
  // The run's authentication trailer, if any, is not checked here: the
  // viewer and the log reader only show what was on the network.
  size = protocol::PayloadSize(data, size);
  const int64_t fingerprint = protocol::PeekFingerprint(data, size);
  if (fingerprint == static_cast<int64_t>(fragment_t::getHash())) {
    return FeedFragment(std::string(channel), *run, data, size, now_us);
  }
  if (fingerprint != static_cast<int64_t>(policy_t::getHash())) {
    return Drop("message of another type");
  }
  return DecodePolicy(*run, data, size);
}

std::optional<policy_t> PolicyAssembler::FeedFragment(const std::string& channel,
                                                      const std::string& run, const uint8_t* data,
                                                      int size, int64_t now_us) {
  fragment_t fragment{};
  if (!protocol::DecodeExactly(data, size, fragment)) return Drop("undecodable fragment_t");
  if (fragment.run_id != run) return Drop("fragment of another run");
  if (Status valid = protocol::Validate(fragment); !valid) {
    return Drop("fragment_t: " + valid.error().message);
  }
  if (fragment.fingerprint != static_cast<int64_t>(policy_t::getHash())) {
    return Drop("fragment of a message that is no policy_t");
  }
  ++counters_.fragments;
  protocol::FragmentAssembler::Outcome outcome = fragments_.Add(channel, fragment, now_us);
  counters_.expired = fragments_.expired();
  switch (outcome.kind) {
    case protocol::FragmentAssembler::Outcome::Kind::kDropped:
      return Drop(outcome.why);
    case protocol::FragmentAssembler::Outcome::Kind::kIncomplete:
      return std::nullopt;
    case protocol::FragmentAssembler::Outcome::Kind::kComplete:
      break;
  }
  return DecodePolicy(run, outcome.bytes.data(), static_cast<int>(outcome.bytes.size()));
}

Result<PolicyLogSummary> ReadPolicyLog(const std::string& path, const std::string& run_id,
                                       const std::function<void(policy_t&)>& visit) {
  Result<protocol::LogReader> log = protocol::LogReader::Open(path);
  if (!log) return log.error();
  PolicyLogSummary summary;
  // Log time, not wall time: a log reads the same however fast it is read.
  PolicyAssembler assembler;
  while (true) {
    Result<std::optional<protocol::LogEvent>> next = log->Next();
    if (!next) return next.error();
    if (!*next) break;
    const protocol::LogEvent& event = **next;
    ++summary.events;
    const std::optional<std::string> run = PolicyChannelRun(event.channel);
    if (!run || (!run_id.empty() && *run != run_id)) continue;
    ++summary.policy_events;
    std::optional<policy_t> policy = assembler.Feed(
        event.channel, event.data.data(), static_cast<int>(event.data.size()), event.timestamp);
    if (policy) visit(*policy);
  }
  if (summary.events == 0) return Error::Corrupt(path + " is empty or not an LCM log");
  summary.counters = assembler.counters();
  summary.incomplete = static_cast<int64_t>(assembler.pending());
  return summary;
}

}  // namespace dynapath::view
