// Speed of the Q-learning learners (SPEC sections 6-7) on the report's hard
// mazes (seed 52), mostly the 20x20 one: a quadtree leaf, the region most
// trainings of a run work on.

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <vector>

#include "core/learn/fedasynq.h"
#include "core/learn/single_agent_learner.h"
#include "dynapath/federated_job.h"
#include "dynapath/scenario.h"
#include "dynapath/training_job.h"

namespace dynapath {
namespace {

// 52: the report's seed of the hard mazes.
constexpr unsigned kHardSeed = 52;

// A job over the whole `size` x `size` hard maze of the report's seed.
TrainingJob MazeJob(int size, LearnerKind kind, Averaging averaging) {
  const Grid grid = GenerateScenario(size, size, Difficulty::kHard, kHardSeed, 0).grid;
  TrainingJob job;
  job.node = 0;
  job.region = Region{0, size - 1, 0, size - 1};
  job.codes = RegionCodes(grid, job.region);
  job.warm_start = QTable(job.region.cells());
  job.seed = JobSeed(1, 0, 0);
  job.kind = kind;
  job.federated.averaging = averaging;
  return job;
}

// One federated round per iteration: K learners x tau steps, then averaging
// and the learners' catch-up. Items = Q-learning steps. Sizes: a 20x20 leaf,
// and the root of a 300x300 maze (the largest region a run can train).
// separate:0 plays all learners with one object and table, as TrainFedAsynQ
// does; separate:1 keeps K learner objects, as a distributed run does.
void BM_FedAsynQRound(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const Averaging averaging = state.range(1) == 0 ? Averaging::kEqual : Averaging::kImportance;
  const bool separate = state.range(2) != 0;
  const TrainingJob job = MazeJob(size, LearnerKind::kFedAsynQ, averaging);
  const RegionModel model(job);
  const int learner_count = job.federated.learners;
  std::vector<FedAsynQLearner> learners;
  for (int k = 0; k < (separate ? learner_count : 1); ++k) {
    learners.emplace_back(model, k);
    learners.back().Reset(job.warm_start);
  }
  QTable shared = job.warm_start;
  StartStatistics stats(model.start_cells());
  FederatedAverager averager(model.cells() * kNumActions, averaging);
  std::vector<LearnerShard> shards(static_cast<size_t>(learner_count));
  std::vector<uint32_t> entries;
  std::vector<float> values;
  int64_t round = 0, steps = 0;
  for (auto _ : state) {
    for (int k = 0; k < learner_count; ++k) {
      shards[k] = separate ? learners[k].RunRound(stats, job.seed, round, job.federated.sync_period)
                           : learners[0].RunRoundAndRevert(k, stats, job.seed, round,
                                                           job.federated.sync_period);
      steps += shards[k].steps;
    }
    if (!averager.Combine(shards, shared, stats, entries, values).ok()) std::abort();
    for (FedAsynQLearner& learner : learners) learner.ApplyAverage(entries, values);
    ++round;
  }
  state.SetItemsProcessed(steps);
  state.counters["entries_averaged"] = benchmark::Counter(static_cast<double>(entries.size()));
}
BENCHMARK(BM_FedAsynQRound)
    ->ArgsProduct({{20, 300}, {0, 1}, {0, 1}})
    ->ArgNames({"size", "importance", "separate"});

// A whole federated job (80 rounds on 20x20). Items = Q-learning steps.
void BM_TrainFedAsynQ(benchmark::State& state) {
  const Averaging averaging = state.range(0) == 0 ? Averaging::kEqual : Averaging::kImportance;
  const TrainingJob job = MazeJob(20, LearnerKind::kFedAsynQ, averaging);
  int64_t steps = 0;
  for (auto _ : state) {
    const TrainingResult result = TrainFedAsynQ(job);
    steps += result.steps;
    benchmark::DoNotOptimize(result.table.values().data());
  }
  state.SetItemsProcessed(steps);
}
BENCHMARK(BM_TrainFedAsynQ)->Arg(0)->Arg(1)->ArgName("importance")->Unit(benchmark::kMillisecond);

// A whole single-agent job, to convergence or 10,000 episodes.
void BM_TrainSingleAgent(benchmark::State& state) {
  const TrainingJob job = MazeJob(20, LearnerKind::kSingleAgent, Averaging::kEqual);
  int64_t steps = 0, episodes = 0, runs = 0;
  for (auto _ : state) {
    const TrainingResult result = TrainSingleAgent(job);
    steps += result.steps;
    episodes += result.episodes_or_rounds;
    ++runs;
    benchmark::DoNotOptimize(result.table.values().data());
  }
  state.SetItemsProcessed(steps);
  state.counters["episodes"] =
      benchmark::Counter(static_cast<double>(episodes) / static_cast<double>(runs));
}
BENCHMARK(BM_TrainSingleAgent)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dynapath

BENCHMARK_MAIN();
