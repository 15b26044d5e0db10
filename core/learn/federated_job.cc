#include "dynapath/federated_job.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <utility>

namespace dynapath {

FederatedState FederatedState::Start(const TrainingJob& job, const RegionModel& model) {
  FederatedState state;
  state.learners = job.federated.learners;
  state.rounds = FederatedRounds(job.region, job.federated);
  state.averaging = job.federated.averaging;
  state.shared = StartingTable(job);
  state.stats = StartStatistics(model.start_cells());
  return state;
}

FederatedState FederatedState::Resume(const TrainingJob& job, const RegionModel& model,
                                      std::vector<uint32_t> attempts,
                                      std::vector<uint32_t> successes) {
  FederatedState state = Start(job, model);
  state.stats = StartStatistics(model.start_cells(), std::move(attempts), std::move(successes));
  return state;
}

Status CombineRound(const std::vector<LearnerShard>& shards, FederatedAverager& averager,
                    FederatedState& state, RoundAverage& average) {
  Status combined = Ok{};
  WithValueType(state.shared.precision(), [&]<typename V>(V*) {
    combined = averager.Combine(shards, state.shared, state.stats, average.entries,
                                OfValueType<V>(average.values, average.wide_values));
  });
  if (!combined) return combined;
  average.steps = 0;
  for (const LearnerShard& shard : shards) average.steps += shard.steps;
  return Ok{};
}

FederatedLearners::FederatedLearners(const TrainingJob& job, const RegionModel& model,
                                     std::vector<int> learners, const QTable& shared, int workers)
    : job_(job), learners_(std::move(learners)) {
  const int count = static_cast<int>(learners_.size());
  workers = std::max(1, std::min(workers, count));
  for (int w = 0; w <= workers; ++w) first_.push_back(w * count / workers);
  for (int w = 0; w < workers; ++w) {
    // The index given here is only RunRound's; workers play theirs by index.
    workers_.push_back(std::make_unique<FedAsynQLearner>(model, learners_[first_[w]]));
    workers_.back()->set_count_visits(job.federated.averaging != Averaging::kEqual);
    workers_.back()->Reset(shared);
  }
}

void FederatedLearners::RunRound(int worker, const StartStatistics& stats, int64_t round,
                                 LearnerShard* shards) {
  const int first = first_[worker];
  workers_[worker]->RunRoundsAndRevert(learners_.data() + first, first_[worker + 1] - first, stats,
                                       job_.seed, round, job_.federated.sync_period,
                                       shards + first);
}

void FederatedLearners::Apply(const RoundAverage& average) {
  for (auto& worker : workers_) {
    WithValueType(worker->table().precision(), [&]<typename V>(V*) {
      worker->ApplyAverage(average.entries, OfValueType<V>(average.values, average.wide_values));
    });
  }
}

namespace {
std::vector<int> AllLearners(const TrainingJob& job) {
  std::vector<int> learners(static_cast<size_t>(std::max(1, job.federated.learners)));
  for (size_t k = 0; k < learners.size(); ++k) learners[k] = static_cast<int>(k);
  return learners;
}
}  // namespace

FederatedRun::FederatedRun(const TrainingJob& job, int workers) : job_(job) {
  model_ = std::make_unique<RegionModel>(job);
  state_ = FederatedState::Start(job, *model_);
  learners_ =
      std::make_unique<FederatedLearners>(job, *model_, AllLearners(job), state_.shared, workers);
  averager_ =
      std::make_unique<FederatedAverager>(static_cast<int>(state_.shared.size()), state_.averaging);
  shards_.resize(learners_->learners().size());
}

void FederatedRun::FinishRound() {
  // The shards of our own learners on this job's model are well formed.
  [[maybe_unused]] const Status combined = CombineRound(shards_, *averager_, state_, average_);
  assert(combined.ok());
  learners_->Apply(average_);
  steps_ += average_.steps;
}

TrainingResult TrainFedAsynQ(const TrainingJob& job, StopToken stop, std::atomic<int64_t>* work) {
  FederatedRun run(job, 1);
  int64_t rounds = 0, counted = 0;
  for (int64_t round = 0; round < run.rounds(); ++round) {
    // Rounds done so far, counted where the stop flag is checked.
    if (work != nullptr && round > counted) {
      work->fetch_add(round - counted, std::memory_order_relaxed);
      counted = round;
    }
    if (StopRequested(stop)) break;
    rounds = round + 1;
    run.RunRound(0, round);
    run.FinishRound();
  }
  // The last round, or the rounds left when stopped: the job's whole budget
  // is then counted.
  if (work != nullptr && run.rounds() > counted) {
    work->fetch_add(run.rounds() - counted, std::memory_order_relaxed);
  }
  TrainingResult result;
  result.node = job.node;
  result.steps = run.steps();
  result.episodes_or_rounds = rounds;
  result.table = run.TakeShared();
  return result;
}

}  // namespace dynapath
