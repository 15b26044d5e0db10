#include "tools/view/policy_feed.h"

#include <spdlog/spdlog.h>

#include <chrono>

namespace dynapath::view {
namespace {

int64_t NowUs() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

PolicyFeed::PolicyFeed(lcm::LCM& lcm, std::string run_id)
    : lcm_(lcm), wanted_run_(std::move(run_id)) {
  // Run ids hold no regex metacharacters (protocol::CheckRunId).
  const std::string channel =
      "DYNAPATH/" + (wanted_run_.empty() ? std::string("[^/]+") : wanted_run_) + "/POLICY";
  subscription_ = lcm_.subscribe(channel, &PolicyFeed::OnMessage, this);
  // A fragmented policy arrives as a burst of pieces.
  subscription_->setQueueCapacity(10000);
  current_run_ = wanted_run_;
}

PolicyFeed::~PolicyFeed() { lcm_.unsubscribe(subscription_); }

void PolicyFeed::OnMessage(const lcm::ReceiveBuffer* buffer, const std::string& channel) {
  std::optional<policy_t> policy =
      assembler_.Feed(channel, static_cast<const uint8_t*>(buffer->data),
                      static_cast<int>(buffer->data_size), NowUs());
  const PolicyStreamCounters& counters = assembler_.counters();
  if (counters.dropped > dropped_.load()) {
    // At most one warning per ten drops after the first few.
    if (counters.dropped <= 3 || counters.dropped % 10 == 0) {
      spdlog::warn("dropped a message on {}: {} ({} dropped so far)", channel, assembler_.why(),
                   counters.dropped);
    }
    dropped_ = counters.dropped;
  }
  if (!policy) return;
  {
    std::lock_guard lock(mutex_);
    RunState& state = runs_[policy->run_id];
    if (!state.latest.count(policy->approach)) state.order.push_back(policy->approach);
    state.last = policy->approach;
    if (wanted_run_.empty()) current_run_ = policy->run_id;
    state.latest[policy->approach] = std::move(*policy);
  }
  ++received_;
  ++version_;
}

std::string PolicyFeed::run() const {
  std::lock_guard lock(mutex_);
  return current_run_;
}

std::vector<std::string> PolicyFeed::approaches() const {
  std::lock_guard lock(mutex_);
  auto it = runs_.find(current_run_);
  return it == runs_.end() ? std::vector<std::string>{} : it->second.order;
}

std::optional<policy_t> PolicyFeed::Latest(const std::string& approach) const {
  std::lock_guard lock(mutex_);
  auto it = runs_.find(current_run_);
  if (it == runs_.end()) return std::nullopt;
  auto policy = it->second.latest.find(approach);
  if (policy == it->second.latest.end()) return std::nullopt;
  return policy->second;
}

std::string PolicyFeed::LastApproach() const {
  std::lock_guard lock(mutex_);
  auto it = runs_.find(current_run_);
  return it == runs_.end() ? std::string() : it->second.last;
}

}  // namespace dynapath::view
