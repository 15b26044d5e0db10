#include "dynapath/federated_job.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <utility>

#include "core/learn/fedasynq.h"
#include "core/learn/region_model.h"

namespace dynapath {

namespace {
FederatedState StartOn(const TrainingJob& job, const RegionModel& model) {
  FederatedState state;
  state.learners = job.federated.learners;
  state.rounds = FederatedRounds(job.region, job.federated);
  state.averaging = job.federated.averaging;
  state.shared = StartingTable(job);
  state.stats = StartStatistics(model.start_cells());
  return state;
}
}  // namespace

FederatedState FederatedState::Start(const TrainingJob& job) {
  return StartOn(job, RegionModel(job));
}

FederatedState FederatedState::Resume(const TrainingJob& job, std::vector<uint32_t> attempts,
                                      std::vector<uint32_t> successes) {
  const RegionModel model(job);
  FederatedState state = StartOn(job, model);
  state.stats = StartStatistics(model.start_cells(), std::move(attempts), std::move(successes));
  return state;
}

size_t StartCellCount(const TrainingJob& job) { return RegionModel(job).start_cells().size(); }

RoundAverager::RoundAverager(const FederatedState& state)
    : averager_(std::make_unique<FederatedAverager>(static_cast<int>(state.shared.size()),
                                                    state.averaging)) {}
RoundAverager::~RoundAverager() = default;
RoundAverager::RoundAverager(RoundAverager&&) noexcept = default;
RoundAverager& RoundAverager::operator=(RoundAverager&&) noexcept = default;

Status RoundAverager::Combine(const std::vector<LearnerShard>& shards, FederatedState& state,
                              RoundAverage& average) {
  Status combined = Ok{};
  WithValueType(state.shared.precision(), [&]<typename V>(V*) {
    combined = averager_->Combine(shards, state.shared, state.stats, average.entries,
                                  OfValueType<V>(average.values, average.wide_values));
  });
  if (!combined) return combined;
  average.steps = 0;
  for (const LearnerShard& shard : shards) average.steps += shard.steps;
  return Ok{};
}

FederatedLearners::FederatedLearners(const TrainingJob& job, std::vector<int> learners,
                                     const QTable& shared, int workers)
    : FederatedLearners(job, std::make_shared<const RegionModel>(job), std::move(learners), shared,
                        workers) {}

FederatedLearners::FederatedLearners(const TrainingJob& job,
                                     std::shared_ptr<const RegionModel> model,
                                     std::vector<int> learners, const QTable& shared, int workers)
    : job_(job), model_(std::move(model)), learners_(std::move(learners)) {
  const int count = static_cast<int>(learners_.size());
  workers = std::max(1, std::min(workers, count));
  for (int w = 0; w <= workers; ++w) first_.push_back(w * count / workers);
  for (int w = 0; w < workers; ++w) {
    // The index given here is only RunRound's; workers play theirs by index.
    workers_.push_back(std::make_unique<FedAsynQLearner>(*model_, learners_[first_[w]]));
    workers_.back()->set_count_visits(job.federated.averaging != Averaging::kEqual);
    workers_.back()->Reset(shared);
  }
}

FederatedLearners::~FederatedLearners() = default;

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
  auto model = std::make_shared<const RegionModel>(job);
  state_ = StartOn(job, *model);
  learners_ = std::make_unique<FederatedLearners>(job, std::move(model), AllLearners(job),
                                                  state_.shared, workers);
  averager_ = std::make_unique<RoundAverager>(state_);
  shards_.resize(learners_->learners().size());
}

FederatedRun::~FederatedRun() = default;

void FederatedRun::FinishRound() {
  // The shards of our own learners on this job's model are well formed.
  [[maybe_unused]] const Status combined = averager_->Combine(shards_, state_, average_);
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
