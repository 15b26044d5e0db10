#pragma once
// The live agent processes of a run, from their heartbeats. Updated on the
// dispatch thread as heartbeats arrive (so an agent's age is real even while
// the coordinator thread is busy evaluating a policy) and read by the
// coordinator thread.

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iterator>
#include <map>
#include <mutex>
#include <set>
#include <vector>

#include "dynapath/heartbeat_t.hpp"

namespace dynapath::coordinator {

struct AgentInfo {
  int id = 0;
  int threads = 0;
  int64_t last_seen_ms = 0;
  int64_t batch_id = -1;  // what its last heartbeat said it holds
  int32_t epoch = 0;
  int64_t round = -1;  // split: last round sent; whole: results sent
};

class AgentRegistry {
 public:
  explicit AgentRegistry(double timeout_seconds)
      : timeout_ms_(static_cast<int64_t>(timeout_seconds * 1000)) {}

  static int64_t NowMs() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }

  // Most agents tracked: heartbeats carry any sender id, so without a cap a
  // flood of made-up ids would grow the registry without end. Dead agents
  // make room first; beyond that, new ids are ignored (and counted).
  static constexpr size_t kMaxAgents = 4096;

  // Records an agent's heartbeat; true when the agent was not live before.
  bool OnHeartbeat(const heartbeat_t& beat) {
    if (beat.role != heartbeat_t::ROLE_AGENT) return false;
    std::lock_guard lock(mutex_);
    if (gone_.count(beat.sender) != 0) return false;
    const auto known = agents_.find(beat.sender);
    if (known == agents_.end() && agents_.size() >= kMaxAgents) {
      // Sweep out dead agents at most every 100 ms: a flood of new ids must
      // not cost a full scan each.
      const int64_t now = NowMs();
      if (now - last_sweep_ms_ >= 100 || timeout_ms_ < 100) {
        last_sweep_ms_ = now;
        for (auto it = agents_.begin(); it != agents_.end();) {
          it = now - it->second.last_seen_ms > timeout_ms_ ? agents_.erase(it) : std::next(it);
        }
      }
      if (agents_.size() >= kMaxAgents) {
        ++ignored_;
        return false;
      }
    }
    const bool is_new =
        known == agents_.end() || NowMs() - known->second.last_seen_ms > timeout_ms_;
    AgentInfo& info = agents_[beat.sender];
    info.id = beat.sender;
    info.threads = beat.threads;
    info.last_seen_ms = NowMs();
    info.batch_id = beat.batch_id;
    info.epoch = beat.epoch;
    info.round = beat.round;
    return is_new;
  }

  // An agent known to have exited (its launcher saw it end): not live from
  // now on, whatever its last heartbeat, and heartbeats of its id still in
  // flight are ignored. For the launcher's own agents only (at most
  // kMaxAgents ids).
  void MarkGone(int id) {
    std::lock_guard lock(mutex_);
    agents_.erase(id);
    gone_.insert(id);
  }

  // Agents heard from within the timeout, ascending ids.
  std::vector<AgentInfo> Live() const {
    std::lock_guard lock(mutex_);
    std::vector<AgentInfo> live;
    const int64_t now = NowMs();
    for (const auto& [id, info] : agents_) {
      if (now - info.last_seen_ms <= timeout_ms_) live.push_back(info);
    }
    return live;
  }

  // `silence_counted_from_ms`: silence before this time is not held against
  // the agent (the coordinator itself was not running then).
  bool IsLive(int id, int64_t silence_counted_from_ms = 0) const {
    std::lock_guard lock(mutex_);
    auto it = agents_.find(id);
    return it != agents_.end() &&
           NowMs() - std::max(it->second.last_seen_ms, silence_counted_from_ms) <= timeout_ms_;
  }

  int64_t timeout_ms() const { return timeout_ms_; }

  // Heartbeats of new agents ignored because kMaxAgents were live.
  int64_t ignored() const {
    std::lock_guard lock(mutex_);
    return ignored_;
  }

  bool Get(int id, AgentInfo& info) const {
    std::lock_guard lock(mutex_);
    auto it = agents_.find(id);
    if (it == agents_.end()) return false;
    info = it->second;
    return true;
  }

 private:
  int64_t timeout_ms_;
  mutable std::mutex mutex_;
  std::map<int, AgentInfo> agents_;
  std::set<int> gone_;  // MarkGone
  int64_t ignored_ = 0;
  int64_t last_sweep_ms_ = -1000000;
};

}  // namespace dynapath::coordinator
