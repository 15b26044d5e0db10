#pragma once
// The coordinator's training part alone, for a process that trains on agents
// but runs no experiment of its own (dynapath serve --agents N): the
// coordinator's heartbeat (role COORDINATOR: agents serve it and exit when
// it finishes or falls silent), the registry of the agents' heartbeats and a
// DistributedTrainer. It is a Trainer: give it to RunApproach (or a service)
// instead of a LocalTrainer, with the same results. Train runs on the
// calling thread, which also runs the session's inbox while it waits; call
// it from one thread only.

#include <atomic>
#include <memory>
#include <optional>

#include "coordinator/agent_registry.h"
#include "coordinator/coordinator_heartbeat.h"
#include "coordinator/distributed_trainer.h"
#include "dynapath/trainer.h"
#include "protocol/bus.h"
#include "protocol/inbox.h"
#include "protocol/liveness.h"
#include "runtime/run_driver.h"

namespace dynapath::coordinator {

struct TrainingSessionOptions {
  int min_agents = 1;                  // the first Train waits for this many agents
  double agent_wait_seconds = 60.0;    // ... for at most this long, then fails
  double agent_timeout_seconds = 2.0;  // an agent silent this long is dropped
  double give_up_seconds = 60.0;       // DistributedTrainerOptions::max_stalls
  runtime::Placement placement = runtime::Placement::kAuto;
};

class TrainingSession : public Trainer {
 public:
  // Subscribes on `bus`: construct before its dispatching starts.
  TrainingSession(protocol::Bus& bus, TrainingSessionOptions options);
  ~TrainingSession() override;  // Finish(), if not done

  // Starts the heartbeat (agents waiting for a coordinator join from now).
  void Start();
  // The flag every wait of Train watches (kCancelled once it is set).
  void set_stop(const std::atomic<bool>* stop);
  // Sends the final heartbeat a few times (FINISHED, or FAILED when the
  // trainer failed for another reason than being stopped) and stops the
  // heartbeat: agents that hear it exit.
  void Finish();

  TrainingStats Train(const std::vector<NodeId>& nodes, const std::vector<uint64_t>& seeds,
                      const LearnerConfig& config, const QuadTree& tree, const Grid& grid,
                      RootQTable& root) override;
  Status status() const override;

  const TrafficStats& traffic() const { return trainer_.traffic(); }
  const AgentRegistry& agents() const { return agents_; }

 private:
  Status WaitForAgents();

  protocol::Bus& bus_;
  TrainingSessionOptions options_;
  const std::atomic<bool>* stop_ = nullptr;
  protocol::Inbox inbox_;
  AgentRegistry agents_;
  DistributedTrainer trainer_;
  bool waited_ = false;
  Status wait_status_ = Ok{};
  CoordinatorHeartbeat heartbeat_{bus_};
};

}  // namespace dynapath::coordinator
