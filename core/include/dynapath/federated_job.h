#pragma once
// One federated (FedAsynQ) job as a process runs it, in the pieces every
// runner shares: the in-process trainers (TrainFedAsynQ, LocalTrainer), the
// agent hosting some of a job's learners, and the coordinator that combines
// what the agents send.
//
//   * FederatedState: where a job stands between rounds (the shared table
//     and start statistics every learner starts the next round from).
//   * CombineRound: one round's shards, in learner order, into the next
//     state, and what changed (a RoundAverage).
//   * FederatedLearners: the learners of a job this process plays, split
//     into contiguous ranges among up to one worker per thread. Each worker
//     is a FedAsynQLearner with its own copy of the shared table that plays
//     its learners in turn (RunRoundsAndRevert): memory is one table per
//     worker, not one per learner.
//   * FederatedRun: all of a job's learners in this process, with its state,
//     for the in-process trainers.
//
// A round: every worker runs its learners (RunRound, in parallel), then the
// shards are combined (CombineRound) and the average applied to every worker
// (Apply). In-process trainers do the three steps in a loop; an agent does
// the first and the last, and waits for the other agents' shards between.

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "dynapath/fedasynq.h"
#include "dynapath/q_table.h"
#include "dynapath/region_model.h"
#include "dynapath/result.h"
#include "dynapath/start_statistics.h"
#include "dynapath/stop_token.h"
#include "dynapath/training_job.h"

namespace dynapath {

// Where one federated job stands after some rounds.
struct FederatedState {
  int learners = 0;    // K
  int64_t rounds = 0;  // rounds of the job
  Averaging averaging = Averaging::kEqual;
  QTable shared;          // the shared table
  StartStatistics stats;  // the shared start statistics

  // Before the first round: the job's starting table, no start outcomes.
  static FederatedState Start(const TrainingJob& job, const RegionModel& model);
  // Resumed: the job's starting table (its warm start is the table of the
  // round it resumes at) and the start outcomes counted so far.
  static FederatedState Resume(const TrainingJob& job, const RegionModel& model,
                               std::vector<uint32_t> attempts, std::vector<uint32_t> successes);
};

// What one round changed in a job's shared table: the averaged entries
// (ascending), their new values in the table's precision, and the
// Q-learning steps the round's learners took.
struct RoundAverage {
  std::vector<uint32_t> entries;
  std::vector<float> values;        // float tables
  std::vector<double> wide_values;  // double tables
  int64_t steps = 0;
};

// Combines one round's shards (exactly one per learner, in learner order)
// into `state`, which becomes the next round's, and writes what changed to
// `average`. `averager` must be made for the state's table and averaging.
// Error, with nothing changed, when a shard is malformed (FederatedAverager).
Status CombineRound(const std::vector<LearnerShard>& shards, FederatedAverager& averager,
                    FederatedState& state, RoundAverage& average);

// The learners of one federated job that this process plays.
class FederatedLearners {
 public:
  // `job` and `model` must outlive the object. `learners`: the indices
  // played here, in the order their shards are written (all of 0..K-1, or
  // the ones an agent hosts); `shared`: the table the next round starts
  // from; `workers`: how many workers share them (at least one, at most
  // one per learner).
  FederatedLearners(const TrainingJob& job, const RegionModel& model, std::vector<int> learners,
                    const QTable& shared, int workers);

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
  std::vector<int> learners_;
  std::vector<int> first_;  // worker w plays learners_[first_[w] .. first_[w + 1])
  std::vector<std::unique_ptr<FedAsynQLearner>> workers_;
};

// A whole federated job trained in this process: all its learners on
// `workers` workers, and its state. `job` must outlive the run.
class FederatedRun {
 public:
  FederatedRun(const TrainingJob& job, int workers);

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
  std::unique_ptr<RegionModel> model_;
  FederatedState state_;
  std::unique_ptr<FederatedLearners> learners_;
  std::unique_ptr<FederatedAverager> averager_;
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
