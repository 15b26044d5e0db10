#pragma once
// Trains quadtree nodes on agent processes over LCM: the Trainer the
// coordinator gives the planners instead of LocalTrainer, with the same
// results.
//
// A Train call is one batch. Placement: by default whole jobs are spread over
// the agents (largest first); each agent runs its jobs with all their
// learners and returns final tables: no per-round traffic. When a batch has
// fewer jobs than agents and its federated rounds are long enough that
// parallel learners save more than a round's messages cost (EstimatedRoundUs
// against split_min_round_us and against the measured round trip to the
// agents: auto placement runs whole jobs until it has measured one, and never
// splits rounds shorter than a round trip), or when placement is kSplit, every job's
// learners are split over the agents instead, which publish
// their shards each round; the agents and the coordinator all combine them in
// learner order (protocol::RoundCombiner: RoundAverager, exactly as
// in-process), the coordinator's tables being the authoritative ones.
//
// Faults: an agent that falls silent is dropped; the batch gets a new epoch
// in which its work is reassigned, split jobs from the last round the
// coordinator completed (it holds their shared tables and start statistics),
// whole jobs from their start. Lost messages are re-sent: agents ask each
// other for missing shards (shards_t.needs_round), and the coordinator asks
// for a round's shards as soon as an agent is past it (agents keep their last
// protocol::kAgentKeptRounds rounds); the coordinator repeats
// the batch when an agent's heartbeat shows it lacks the batch, or has sent
// something that did not arrive; agents answer a repeat by re-sending. A
// batch that still makes no progress (repeats lost too: a lossy link) is
// reassigned away from the agents that owe, and fails after a bound
// (DistributedTrainerOptions::stall_seconds, max_stalls) instead of waiting
// forever. A split batch that restarts the same round again and again runs
// its jobs whole instead (auto placement then stops splitting for the run).

#include <algorithm>
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coordinator/agent_registry.h"
#include "dynapath/job_batch_t.hpp"
#include "dynapath/job_result_t.hpp"
#include "dynapath/shards_t.hpp"
#include "dynapath/trainer.h"
#include "protocol/bus.h"
#include "protocol/inbox.h"
#include "protocol/liveness.h"
#include "runtime/run_driver.h"

namespace dynapath::coordinator {

// The longest wait between two repeats of a batch that makes no progress.
inline constexpr int64_t kMaxRepeatIntervalMs = 1000;
// The wait before the next repeat of a batch already repeated
// repeats_since_progress times without progress: first_interval_ms doubled
// each time, capped at kMaxRepeatIntervalMs (never below first_interval_ms).
int64_t RepeatIntervalMs(int64_t first_interval_ms, int repeats_since_progress);

struct DistributedTrainerOptions {
  // How long to wait for at least one live agent before a batch fails.
  double agent_wait_seconds = 60.0;
  // How long a split round may make no progress before the batch is
  // repeated, and the longest wait before a repeat for whole jobs (which
  // repeat after twice the measured round trip + 20 ms, at least 30 ms:
  // the time from sending a batch to an agent's heartbeat acknowledging it).
  double resend_seconds = 0.2;
  runtime::Placement placement = runtime::Placement::kAuto;
  // kAuto splits a batch's learners when one round of all its jobs is
  // estimated to take at least this long on one thread. A split round costs
  // every agent a message out, one in per other agent and a combine:
  // 0.3-0.5 ms on the 2-core development machine (docs/PERFORMANCE.md), so
  // with two agents splitting pays from about twice that.
  double split_min_round_us = 2000.0;
  // Bounds on a batch that makes no progress although its agents are live (a
  // lossy link: heartbeats get through, large messages do not). When the
  // batch has been repeated for stall_seconds without a shard or result
  // arriving, the stall is logged and the work is reassigned to the other
  // live agents (the stalled ones get no new work for avoid_seconds, unless
  // no other agent is live); after max_stalls such reassignments in a row
  // the batch fails with the reason.
  double stall_seconds = 5.0;
  int max_stalls = 11;  // the coordinator's --give-up 60 s
  double avoid_seconds = 30.0;
  // When set and true, Train gives up at once (status() kCancelled): every
  // wait checks it at least every 50 ms.
  const std::atomic<bool>* stop = nullptr;
};

// The options of a coordinator's trainer: wait `agent_wait_seconds` for an
// agent, give a batch that makes no progress up after about
// `give_up_seconds` (max_stalls from stall_seconds).
DistributedTrainerOptions MakeTrainerOptions(double agent_wait_seconds, double give_up_seconds,
                                             runtime::Placement placement);

// Waits, running `inbox`, until `min_agents` agents are live: the ids of the
// live agents (" 1 2"), kCancelled once `stop` (may be null) is set, or
// kUnavailable after `wait_seconds`.
Result<std::string> WaitForAgents(const AgentRegistry& agents, protocol::Inbox& inbox,
                                  int min_agents, double wait_seconds,
                                  const std::atomic<bool>* stop);

// Estimated single-thread time of one federated round of `nodes`' jobs: K
// learners x tau steps x the measured cost of a step (25 ns in regions that
// fit the caches, 90 ns in 300x300 ones; bench/core_bench).
double EstimatedRoundUs(const std::vector<Region>& regions, const FedAsynQOptions& options);

// The slowest recent round, updated with one more round's wall time: the
// larger of the two, the old one decaying by an eighth per round, so one slow
// round (a pause, a reassignment) is forgotten within some tens of rounds.
int64_t SlowRoundMs(int64_t previous_ms, int64_t round_ms);

// Traffic of the training protocol (for the benchmark).
struct TrafficStats {
  int64_t batches = 0;
  int64_t rounds = 0;                       // split rounds combined
  int64_t messages_out = 0, bytes_out = 0;  // batch messages published
  int64_t messages_in = 0, bytes_in = 0;    // shards and results accepted
  int64_t resends = 0, epochs = 0;
  int64_t stalls = 0;           // batches reassigned for lack of progress
  int64_t split_fallbacks = 0;  // split batches run whole after repeated restarts
  int64_t round_requests = 0;   // split rounds asked for again (shards lost on the way)
  double round_trip_ms = -1;    // smoothed batch-to-acknowledgement time (-1: none yet)
};

class DistributedTrainer : public Trainer {
 public:
  // Subscribes to shards and results on `bus`; runs its work on `inbox`, the
  // coordinator thread's mailbox (Train calls inbox.RunFor while waiting).
  DistributedTrainer(protocol::Bus& bus, protocol::Inbox& inbox, const AgentRegistry& agents,
                     DistributedTrainerOptions options = {});
  ~DistributedTrainer() override;

  // Once status() has failed (stopped: kCancelled; no agent left for longer
  // than agent_wait_seconds, or a batch that cannot make progress:
  // kUnavailable), returns at once and commits nothing.
  TrainingStats Train(const std::vector<NodeId>& nodes, const std::vector<uint64_t>& seeds,
                      const LearnerConfig& config, const QuadTree& tree, const Grid& grid,
                      RootQTable& root) override;

  Status status() const override { return status_; }
  const TrafficStats& traffic() const { return traffic_; }
  // The flag Train watches (see DistributedTrainerOptions::stop).
  void set_stop(const std::atomic<bool>* stop) { options_.stop = stop; }

 private:
  struct JobState;
  struct Batch;

  void OnShards(const shards_t& message, int64_t bytes);
  void OnResult(const job_result_t& message, int64_t bytes);
  // Split: asks the agents for their shards of the round the coordinator
  // collects (a shards_t without shards, needs_round = that round).
  void RequestRound();
  std::vector<int> WaitForAgents();
  bool ShouldSplit(const Batch& batch, size_t agents) const;
  // One federated round of the batch's jobs on one thread (estimated).
  static double RoundUs(const Batch& batch);
  void StartEpoch(std::vector<int> agents);
  void PublishBatch();
  void CheckAgents();
  // The batch made no progress for stall_seconds: reassign or fail.
  void OnStall(const std::vector<int>& owing);
  std::vector<int> LiveAgents() const;  // live, preferring those not avoided
  void SampleRoundTrip(const AgentInfo& info);
  int64_t ResendIntervalMs() const;
  // Split: how long an agent that has not yet sent the round being
  // collected is taken to be computing it, not to have lost it: three of the
  // slowest recent rounds, at most the give-up time (a hung agent is still
  // reassigned). 0 until a round was seen.
  int64_t ComputingPatienceMs() const;
  // False once status_ has failed; sets it to kCancelled when `stop` is set.
  bool Going();
  bool Done() const;
  // A line on the batch in hand (jobs done, or the split round), logged every
  // few seconds while a batch lasts: a large map's training takes minutes.
  void LogProgress(int64_t elapsed_ms) const;

  protocol::Bus& bus_;
  protocol::Inbox& inbox_;
  const AgentRegistry& agents_;
  DistributedTrainerOptions options_;
  int64_t next_batch_id_ = 0;
  std::unique_ptr<Batch> batch_;           // the batch in hand (coordinator thread only)
  std::map<int, int64_t> avoid_until_ms_;  // agents that stalled a batch lately
  bool split_disabled_ = false;            // kAuto: splitting kept failing in this run
  double round_trip_ms_ = -1;              // smoothed, over all agents
  // CheckAgents' clock of the coordinator's own pauses: agents' silence is
  // counted from its last resume, heartbeats sent meanwhile being unread.
  protocol::ResumeClock resume_clock_{std::max<int64_t>(agents_.timeout_ms() / 2, 1000)};
  int64_t slow_round_ms_ = 0;              // the slowest recent split round (SlowRoundMs)
  TrafficStats traffic_;
  Status status_ = Ok{};
};

}  // namespace dynapath::coordinator
