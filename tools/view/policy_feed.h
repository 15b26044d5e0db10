#pragma once
// The live side of the viewer, without any window system: subscribes to the
// POLICY channel of one run (or of any run), reassembles, validates and
// keeps the latest policy of every approach. Messages are handled on the LCM
// dispatch thread; the viewer takes copies from its own thread.

#include <atomic>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "tools/view/policy_stream.h"

namespace dynapath::view {

class PolicyFeed {
 public:
  // Subscribes to DYNAPATH/<run_id>/POLICY, or to every run's POLICY channel
  // when run_id is empty (then the most recent run is shown). Call before
  // LCM's dispatching starts.
  PolicyFeed(lcm::LCM& lcm, std::string run_id);
  ~PolicyFeed();
  PolicyFeed(const PolicyFeed&) = delete;
  PolicyFeed& operator=(const PolicyFeed&) = delete;

  // Changes whenever a policy arrives.
  int64_t version() const { return version_.load(); }
  int64_t received() const { return received_.load(); }  // valid policies
  int64_t dropped() const { return dropped_.load(); }    // invalid messages

  // The run shown: the one asked for, else the last run heard.
  std::string run() const;
  // Its approaches in the order they were first heard.
  std::vector<std::string> approaches() const;
  // The latest policy of `approach` in the run shown.
  std::optional<policy_t> Latest(const std::string& approach) const;
  // The approach whose policy arrived last.
  std::string LastApproach() const;

 private:
  void OnMessage(const lcm::ReceiveBuffer* buffer, const std::string& channel);

  struct RunState {
    std::vector<std::string> order;
    std::map<std::string, policy_t> latest;
    std::string last;
  };

  lcm::LCM& lcm_;
  lcm::Subscription* subscription_ = nullptr;
  const std::string wanted_run_;
  PolicyAssembler assembler_;  // dispatch thread only
  mutable std::mutex mutex_;
  std::map<std::string, RunState> runs_;
  std::string current_run_;
  std::atomic<int64_t> version_{0}, received_{0}, dropped_{0};
};

}  // namespace dynapath::view
