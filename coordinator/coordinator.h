#pragma once
// The coordinator process's logic: waits for agents, gets the maze from the
// environment simulator, runs every approach (the quadtree, tables,
// retraining decisions and baselines live in core/'s planners; training goes
// to the agents through DistributedTrainer), publishes per-step reports and
// policies, and writes the result files exactly as `dynapath run --local`.

#include <atomic>
#include <string>

#include "coordinator/agent_registry.h"
#include "coordinator/distributed_trainer.h"
#include "coordinator/envsim_client.h"
#include "protocol/bus.h"
#include "protocol/inbox.h"
#include "runtime/run_driver.h"

namespace dynapath::coordinator {

struct CoordinatorOptions {
  runtime::RunPlan plan;
  int min_agents = 1;                  // wait for this many agents before starting
  double agent_wait_seconds = 60.0;    // ... for at most this long
  double agent_timeout_seconds = 2.0;  // an agent silent this long is dropped
  double envsim_timeout_seconds = 5.0;
  // A training batch that makes no progress this long although its agents
  // are alive fails the run (DistributedTrainerOptions::max_stalls).
  double give_up_seconds = 60.0;
  bool publish_policy = true;
  // A test hook (runtime/test_hold.h): stop this process once the first
  // approach's report of this time step is published; -1: never.
  int hold_at_step = -1;
};

class Coordinator {
 public:
  Coordinator(protocol::Bus& bus, CoordinatorOptions options);
  // Runs the whole experiment. Returns 0 on success, 1 on failure (logged;
  // being stopped is one).
  int Run(const std::atomic<bool>& stop);
  const TrafficStats& traffic() const { return trainer_.traffic(); }

 private:
  void PublishStep(const StepView& view, int pass);
  // Run's work: Ok when the experiment ran to its end, else why not
  // (kCancelled when `stop` was set).
  Status RunExperiment(const std::atomic<bool>& stop);

  protocol::Bus& bus_;
  CoordinatorOptions options_;
  protocol::Inbox inbox_;
  AgentRegistry agents_;
  DistributedTrainer trainer_;
  // A member, not a local of RunExperiment: its handlers are subscribed on
  // the Bus, which keeps them until it is destroyed, and a subscription must
  // be made before dispatching starts (a heartbeat delivered while a route
  // is added read a reallocated route list; one delivered after a local
  // client had gone wrote to its dead frame).
  EnvSimClient envsim_;
};

}  // namespace dynapath::coordinator
