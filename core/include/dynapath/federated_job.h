#pragma once
// One federated (FedAsynQ) job as a process runs it: core's public API of
// the federated round, shared by every runner: the in-process trainers
// (TrainFedAsynQ, LocalTrainer), the agent hosting some of a job's learners,
// and the coordinator that combines what the agents send. The learners and
// the averager themselves (core/learn/fedasynq.h) are private to core.
//
//   * LearnerShard: what one learner changed in one round (the wire carries
//     it between agents and the coordinator).
//   * FederatedState: where a job stands between rounds (the shared table
//     and start statistics every learner starts the next round from).
//   * RoundAverager: combines one round's shards, in learner order, into the
//     next state, and says what changed (a RoundAverage).
//   * FederatedLearners: the learners of a job this process plays, split
//     into contiguous ranges among up to one worker per thread. Each worker
//     is a learner with its own copy of the shared table that plays its
//     learners in turn: memory is one table per worker, not one per learner.
//   * FederatedRun: all of a job's learners in this process, with its state,
//     for the in-process trainers.
//
// A round: every worker runs its learners (RunRound, in parallel), then the
// shards are combined (RoundAverager::Combine) and the average applied to
// every worker (Apply). In-process trainers do the three steps in a loop; an
// agent does the first and the last, and waits for the other agents' shards
// between.
//
// Sparse shards: all learners start a round from the same table, so the
// average differs from it only where some learner made an update. A shard
// lists those entries (index, value, visits), at most tau of them, which
// keeps averaging and messages proportional to tau, not to the region size.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "dynapath/q_table.h"
#include "dynapath/result.h"
#include "dynapath/start_statistics.h"
#include "dynapath/stop_token.h"
#include "dynapath/training_job.h"

namespace dynapath {

// Learner internals of core (core/learn/), named here only as pointers.
class RegionModel;
class FedAsynQLearner;
class FederatedAverager;

// What one learner changed in one round.
struct LearnerShard {
  int learner = 0;
  int64_t round = 0;
  std::vector<uint32_t> entries;  // table indices (cell * 8 + action), ascending
  // The learner's value of each entry at round end, in the table's
  // precision: `values` for float tables, `wide_values` for double tables.
  std::vector<float> values;
  std::vector<double> wide_values;
  std::vector<uint32_t> visits;  // N_k(s, a) of each entry in this round (>= 1)
  int start_cell = -1;           // region-local start of the round (-1: none)
  bool reached_station = false;  // the round visited a station
  int64_t steps = 0;             // Q-learning steps taken
};

// The values of a shard in value type V.
template <typename V>
std::vector<V>& ShardValues(LearnerShard& shard) {
  return OfValueType<V>(shard.values, shard.wide_values);
}
template <typename V>
const std::vector<V>& ShardValues(const LearnerShard& shard) {
  return OfValueType<V>(shard.values, shard.wide_values);
}

// Where one federated job stands after some rounds.
struct FederatedState {
  int learners = 0;    // K
  int64_t rounds = 0;  // rounds of the job
  Averaging averaging = Averaging::kEqual;
  QTable shared;          // the shared table
  StartStatistics stats;  // the shared start statistics

  // Before the first round: the job's starting table, no start outcomes.
  // `job` must pass CheckJob.
  static FederatedState Start(const TrainingJob& job);
  // Resumed: the job's starting table (its warm start is the table of the
  // round it resumes at) and the start outcomes counted so far, one per
  // start cell (StartCellCount).
  static FederatedState Resume(const TrainingJob& job, std::vector<uint32_t> attempts,
                               std::vector<uint32_t> successes);
};

// How many start cells (slots of the start statistics) the region of `job`
// has. `job` must pass CheckJob.
size_t StartCellCount(const TrainingJob& job);

// What one round changed in a job's shared table: the averaged entries
// (ascending), their new values in the table's precision, and the
// Q-learning steps the round's learners took.
struct RoundAverage {
  std::vector<uint32_t> entries;
  std::vector<float> values;        // float tables
  std::vector<double> wide_values;  // double tables
  int64_t steps = 0;
};

// Combines the rounds of one federated job (its scratch is reused between
// rounds: no allocation once warmed up).
class RoundAverager {
 public:
  // For the table and averaging of `state`.
  explicit RoundAverager(const FederatedState& state);
  ~RoundAverager();
  RoundAverager(RoundAverager&&) noexcept;
  RoundAverager& operator=(RoundAverager&&) noexcept;

  // Combines one round's shards (exactly one per learner, in learner order)
  // into `state`, which becomes the next round's, and writes what changed
  // to `average`. Error, with nothing changed, when a shard is malformed
  // (wrong learner order or sizes, an entry outside the table or not finite,
  // a start that is no start cell).
  Status Combine(const std::vector<LearnerShard>& shards, FederatedState& state,
                 RoundAverage& average);

 private:
  std::unique_ptr<FederatedAverager> averager_;
};

// The learners of one federated job that this process plays.
class FederatedLearners {
 public:
  // `job` must pass CheckJob and outlive the object. `learners`: the
  // indices played here, in the order their shards are written (all of
  // 0..K-1, or the ones an agent hosts); `shared`: the table the next round
  // starts from; `workers`: how many workers share them (at least one, at
  // most one per learner).
  FederatedLearners(const TrainingJob& job, std::vector<int> learners, const QTable& shared,
                    int workers);
  // The same on the job's model, already built (core's trainers).
  FederatedLearners(const TrainingJob& job, std::shared_ptr<const RegionModel> model,
                    std::vector<int> learners, const QTable& shared, int workers);
  ~FederatedLearners();

  int workers() const { return static_cast<int>(workers_.size()); }
  const std::vector<int>& learners() const { return learners_; }

  // Worker `worker` plays its learners' round `round` from the shared table
  // and start statistics `stats`, writing learner learners()[i]'s shard to
  // shards[i] (so `shards` has room for every learner played here). Workers
  // may run at once, each on its own thread.
  void RunRound(int worker, const StartStatistics& stats, int64_t round, LearnerShard* shards);
  // Brings every worker's table to the round's new shared table.
  void Apply(const RoundAverage& average);

 private:
  const TrainingJob& job_;
  std::shared_ptr<const RegionModel> model_;
  std::vector<int> learners_;
  std::vector<int> first_;  // worker w plays learners_[first_[w] .. first_[w + 1])
  std::vector<std::unique_ptr<FedAsynQLearner>> workers_;
};

// A whole federated job trained in this process: all its learners on
// `workers` workers, and its state. `job` must outlive the run.
class FederatedRun {
 public:
  FederatedRun(const TrainingJob& job, int workers);
  ~FederatedRun();

  int workers() const { return learners_->workers(); }
  int64_t rounds() const { return state_.rounds; }
  // Worker `worker`'s part of round `round` (workers may run at once).
  void RunRound(int worker, int64_t round) {
    learners_->RunRound(worker, state_.stats, round, shards_.data());
  }
  // Once every worker ran the round: combines it and applies the average.
  void FinishRound();

  const TrainingJob& job() const { return job_; }
  // The shared table (after the last finished round).
  const QTable& shared() const { return state_.shared; }
  QTable TakeShared() { return std::move(state_.shared); }
  int64_t steps() const { return steps_; }

 private:
  const TrainingJob& job_;
  FederatedState state_;
  std::unique_ptr<FederatedLearners> learners_;
  std::unique_ptr<RoundAverager> averager_;
  std::vector<LearnerShard> shards_;
  RoundAverage average_;
  int64_t steps_ = 0;
};

// Runs a whole kFedAsynQ job in the calling thread, one learner after the
// other per round. Pure function of the job. Once `stop` is requested
// (checked every round) it returns early, with fewer episodes_or_rounds
// than FederatedRounds: the result is then not the job's and is dropped.
// `work` (may be null) counts the rounds done, for a progress watcher; once
// the call returns it has grown by exactly the job's FederatedRounds (the
// rounds left when stopped count as done).
TrainingResult TrainFedAsynQ(const TrainingJob& job, StopToken stop = nullptr,
                             std::atomic<int64_t>* work = nullptr);

}  // namespace dynapath
