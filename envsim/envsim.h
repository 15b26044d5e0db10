#pragma once
// The environment simulator's logic: holds the ground-truth maze and its
// change sequence and hands them out one time step at a time. Lock-step (the
// default): a step is answered as soon as the coordinator asks for it, i.e.
// when it finished the previous one. Free-running (hz > 0): the environment
// advances at that rate whatever the coordinator does, and a step is only
// answered once it has happened. Every approach is a pass over the same
// sequence. Requests are idempotent; the coordinator repeats lost ones.

#include <atomic>
#include <string>

#include "dynapath/experiment.h"
#include "dynapath/scenario.h"
#include "dynapath/step_request_t.hpp"
#include "protocol/bus.h"
#include "protocol/inbox.h"
#include "protocol/liveness.h"

namespace dynapath::envsim {

struct EnvSimOptions {
  double hz = 0.0;  // 0: lock-step
  // As an agent's: a silent coordinator is waited for this long.
  double coordinator_timeout_seconds = 60.0;
  double startup_timeout_seconds = 60.0;
  // A test hook (runtime/test_hold.h): stop this process once the first
  // approach's changes of this time step are sent; -1: never.
  int hold_at_step = -1;
};

struct ScenarioInfo {
  Scenario scenario;
  RunLabels labels;
  uint64_t seed = 0;
  std::string source;
};

enum class EnvSimExit { kCoordinatorFinished, kCoordinatorFailed, kCoordinatorGone, kStopped };

class EnvSim {
 public:
  EnvSim(protocol::Bus& bus, ScenarioInfo info, EnvSimOptions options);
  EnvSimExit Run(const std::atomic<bool>& stop);
  int64_t requests_answered() const { return answered_; }

 private:
  void OnRequest(const step_request_t& request);
  int ReachedStep() const;

  protocol::Bus& bus_;
  ScenarioInfo info_;
  EnvSimOptions options_;
  protocol::Inbox inbox_;
  protocol::CoordinatorWatch coordinator_;
  int64_t started_ms_ = 0;
  std::vector<step_request_t> pending_;  // free-running: asked before they happened
  int64_t answered_ = 0;
};

}  // namespace dynapath::envsim
