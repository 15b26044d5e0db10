#pragma once
// Federated training of convQ's model on agent processes over LCM
// (dynapath train-model --agents N): the coordinator's part. It is the
// shard source of TrainConvQFederated (dynapath/convq_training.h): each
// round it publishes a model_round_t (the training's options, the round's
// model, learner k on agent live[k * agents / K]), collects every learner's
// model_shards_t and hands them back in learner order, so the model is the
// in-process federated training's, bit for bit, whatever the agents.
//
// Like DistributedTrainer it sends the coordinator's heartbeat (agents
// serve it, and exit when it finishes or falls silent) and watches the
// agents' (AgentRegistry). Faults: an agent that owes shards and falls
// silent is dropped and its learners are reassigned to the live agents in a
// new epoch of the round (a shard is a function of the round alone, so
// whoever computes it gives the same bytes); with none live for
// agent_wait_seconds the training fails. An agent process its launcher saw
// exit (AgentExited) is dropped at once, not after the silence; with every
// such process gone and no other agent live the training fails at once
// (NoAgentProcessLeft). A round whose shards do not come
// is repeated (backing off from resend_seconds to 1 s; agents answer a
// repeat by re-sending), and fails after give_up_seconds without a shard
// although agents are live. Every wait watches the stop flag.

#include <atomic>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "coordinator/agent_registry.h"
#include "coordinator/coordinator_heartbeat.h"
#include "dynapath/convq_training.h"
#include "dynapath/model_round_t.hpp"
#include "dynapath/model_shards_t.hpp"
#include "protocol/bus.h"
#include "protocol/inbox.h"
#include "protocol/liveness.h"

namespace dynapath::coordinator {

struct ConvQTrainerOptions {
  int min_agents = 1;                  // the first round waits for this many agents
  double agent_wait_seconds = 60.0;    // ... for at most this long, then fails
  double agent_timeout_seconds = 2.0;  // an agent silent this long is dropped
  double give_up_seconds = 60.0;       // a round without a shard this long fails
  double resend_seconds = 0.2;         // the first repeat of a round still owed
};

struct ConvQTrainerStats {
  int64_t rounds = 0;
  int64_t epochs = 0;          // rounds published again with learners reassigned
  int64_t resends = 0;         // repeats of a round
  int64_t shards = 0;          // shards taken
  std::map<int, int64_t> shards_by_agent;  // ... by the agent that sent them
  int64_t shards_ignored = 0;  // repeated, or of another round
  int64_t shards_refused = 0;  // a learner the training does not have (logged)
};

class ConvQTrainer {
 public:
  // Subscribes on `bus`: construct before it is dispatched.
  ConvQTrainer(protocol::Bus& bus, ConvQTrainerOptions options);
  ~ConvQTrainer();  // Finish()

  // Starts the coordinator's heartbeat.
  void Start();
  // The flag every wait watches (kCancelled once it is set).
  void set_stop(const std::atomic<bool>* stop) { stop_ = stop; }
  // The final heartbeat (FINISHED, or FAILED when a round failed for
  // another reason than being stopped): agents that hear it exit.
  void Finish();

  // An agent process of this training's launcher exited, `how` it ended
  // ("was killed by signal 9"): it is dropped at once, not after
  // agent_timeout_seconds of silence, and its learners of the round in hand
  // go to the live agents. Any thread.
  void AgentExited(int id, const std::string& how);
  // Every agent process the launcher started has exited: unless other
  // agents (started elsewhere) are live, the training fails at once, naming
  // them and how they ended. Any thread.
  void NoAgentProcessLeft();

  // Every learner's shard of `round` from `model`, in learner order, on
  // the agents (options.learners > 0). Errors: kCancelled, kUnavailable
  // (no agent, or no progress), saying why.
  Result<std::vector<ConvQShard>> Round(const ConvQTrainingOptions& options, int round,
                                        const ConvQModel& model);

  const ConvQTrainerStats& stats() const { return stats_; }

 private:
  void OnShards(const model_shards_t& message);
  // Assigns the learners still missing to `live` and publishes the round.
  void Publish(const std::vector<int>& live);
  // Live agents, waiting up to agent_wait_seconds for `min` of them (less
  // those known to have exited); empty when none came (status_ says why).
  std::vector<int> LiveAgents(int min);
  // The launcher's agents all exited and no other agent is live.
  bool NoneLeft() const { return processes_gone_ && agents_.Live().empty(); }
  // "agent 1 was killed by signal 9, agent 2 exited with status 1".
  std::string ExitedAgents() const;
  bool Stopped() const { return stop_ != nullptr && stop_->load(); }

  protocol::Bus& bus_;
  ConvQTrainerOptions options_;
  const std::atomic<bool>* stop_ = nullptr;
  protocol::Inbox inbox_;
  AgentRegistry agents_;
  CoordinatorHeartbeat heartbeat_{bus_};
  bool waited_ = false;
  Status status_ = Ok{};
  ConvQTrainerStats stats_;
  // Agents known to have exited, and how (AgentExited; the calling thread).
  std::map<int, std::string> exited_;
  bool processes_gone_ = false;  // NoAgentProcessLeft

  // The round in hand (the calling thread only).
  int32_t epoch_ = -1;  // increases with every publication of a new assignment
  int round_ = 0;
  model_round_t message_{};
  std::vector<std::optional<ConvQShard>> shards_;
  std::map<int, std::vector<int>> owed_;  // agent -> learners assigned to it
  int64_t last_send_ms_ = 0;
  int64_t last_progress_ms_ = 0;
  int repeats_ = 0;
};

}  // namespace dynapath::coordinator
