#pragma once
// The agent process's logic: hosts learners for the training batches the
// coordinator sends, returns shards per round (learners of split jobs) or
// final tables (whole jobs), and holds nothing that matters beyond the batch
// in hand. Transport-agnostic: it talks through a protocol::Bus, so the same
// class runs as a process (udpm) or as threads of an embedded run (memq).

#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "dynapath/heartbeat_t.hpp"
#include "dynapath/job_batch_t.hpp"
#include "dynapath/job_result_t.hpp"
#include "dynapath/model_round_t.hpp"
#include "dynapath/model_shards_t.hpp"
#include "dynapath/shards_t.hpp"
#include "dynapath/thread_pool.h"
#include "protocol/bus.h"
#include "protocol/convert.h"
#include "protocol/inbox.h"
#include "protocol/liveness.h"
#include "protocol/resend_gate.h"
#include "protocol/round_combiner.h"

namespace dynapath::agent {

struct AgentOptions {
  int id = 1;
  int threads = 1;
  // Exit when no coordinator heartbeat came for this long (after one was
  // seen), or when none was ever seen for startup_timeout_seconds.
  // A silent coordinator may be paused (SIGSTOP, a debugger, a swapping
  // host), not dead: waited for this long, with "silent for N s" logged. A
  // launcher that sees its coordinator die stops the agents itself.
  double coordinator_timeout_seconds = 60.0;
  double startup_timeout_seconds = 60.0;
  double heartbeat_seconds = 0.1;
  // Process mode: when the coordinator is gone while a long job is being
  // computed, end the process at once (nothing in an agent needs saving).
  bool exit_process_when_orphaned = false;
  // Identifies this process among agents that share an id (sent in the
  // heartbeat's message field): two agents of a run with one id would take
  // each other's work, so the one with the larger instance leaves.
  uint64_t instance = 0;
};

enum class AgentExit {
  kCoordinatorFinished,
  kCoordinatorFailed,
  kCoordinatorGone,
  kStopped,
  kIdCollision
};

// A random agent id in [1, 2^31 - 1] (the wire's agent fields are int32)
// from the kernel's random source, and a random 64-bit instance.
int RandomAgentId();
uint64_t RandomInstance();

class Agent {
 public:
  // Subscribes on `bus`; construct before the bus is dispatched.
  Agent(protocol::Bus& bus, AgentOptions options);
  ~Agent();

  // Serves batches until the coordinator finishes, fails or disappears, or
  // `stop` becomes true.
  AgentExit Run(const std::atomic<bool>& stop);

 private:
  // Run's stop flag, for the learners of whole jobs (they end early once
  // it is set, and their cut-short tables are not sent).
  const std::atomic<bool>* stop_ = nullptr;
  struct HostedJob;

  void OnBatch(const job_batch_t& batch);
  void OnShards(const shards_t& shards);
  // A round of a federated training of convQ's model: computes the shards
  // of the learners it assigns here and publishes them (a repeat of the
  // round in hand: re-sends them).
  void OnModelRound(const model_round_t& round);
  void RunWholeJobs(const job_batch_t& batch, const std::vector<int>& jobs);
  // Computes this agent's shards of every round it can, combining each round
  // as soon as all agents' shards are there, until a round waits for others.
  void ContinueSplit();
  void ComputeRound();
  void PublishShards(const shards_t& shards, int64_t needs_round);
  // Waiting for others' shards too long: re-send ours (with needs_round).
  void NudgeIfStalled();
  void Resend();
  // A heartbeat now (any thread): the coordinator times its round trips and
  // notices missing results by them, so it should not wait for the next tick.
  void Beat();

  protocol::Bus& bus_;
  AgentOptions options_;
  protocol::Inbox inbox_;
  protocol::CoordinatorWatch coordinator_;
  ThreadPool pool_;

  // Batch in hand (agent thread only).
  int64_t batch_id_ = -1;
  int32_t epoch_ = -1;
  bool importance_ = false;
  std::vector<std::unique_ptr<HostedJob>> split_jobs_;  // jobs with learners here
  std::unique_ptr<protocol::RoundCombiner> combiner_;   // all agents' rounds of them
  int64_t computed_round_ = -1;                         // last round computed here
  std::deque<shards_t> sent_;                           // our last rounds' shards (agent.cc)
  protocol::ResendGate resend_gate_;                    // answers to others' needs_round
  int64_t shard_resends_ = 0;                           // rounds re-sent in answer
  int64_t waiting_since_ms_ = 0;                        // when our shards of the round went out
  int64_t next_nudge_ms_ = 0;
  int64_t nudge_interval_ms_ = 0;
  int64_t round_compute_ms_ = 0;       // how long computing our last round took
  std::vector<job_result_t> results_;  // whole jobs finished in this batch
  // The convQ training round in hand (agent thread only): its round and
  // epoch, and the shards sent for it (none: no learner of it here).
  int32_t model_round_ = 0;
  int32_t model_epoch_ = -1;
  std::optional<model_shards_t> model_sent_;

  // What the heartbeat reports (written by the agent thread).
  std::atomic<int64_t> reported_batch_{-1};
  std::atomic<int32_t> reported_epoch_{0};
  std::atomic<int64_t> reported_round_{-1};
  // Another agent's heartbeat with our id (dispatch thread): its instance.
  std::atomic<uint64_t> collided_with_{0};
  std::atomic<protocol::HeartbeatSender*> heartbeat_{nullptr};  // while Run runs
};

}  // namespace dynapath::agent
