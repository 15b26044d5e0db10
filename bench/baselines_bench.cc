// Cost of the classical baselines and of policy evaluation on the report's
// hard mazes (GenerateScenario(n, n, kHard, 52)). Targets: PolicyEvaluator and
// the BFS Oracle under 5 ms at 300x300; the report's A* needed ~9 s per time
// step at 300x300. Per time step, Incremental Oracle: 0.1 ms at 300x300 and
// 0.5 ms at 1000x1000.

#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <vector>

#include "core/eval/incremental_policy_evaluation.h"
#include "core/plan/baseline_planners.h"
#include "core/plan/incremental_oracle.h"
#include "dynapath/astar_paths.h"
#include "dynapath/bfs_oracle.h"
#include "dynapath/difficulty.h"
#include "dynapath/grid.h"
#include "dynapath/mdp.h"
#include "dynapath/policy_evaluation.h"
#include "dynapath/q_table.h"
#include "dynapath/quadtree.h"
#include "dynapath/scenario.h"

namespace dynapath {
namespace {

Grid HardMaze(int size) {
  return GenerateScenario(size, size, Difficulty::kHard, ReportSeed(Difficulty::kHard), 0).grid;
}

// A uniform random table: short, bushy policy graphs.
QTable RandomTable(const Grid& grid) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  QTable q(grid.size());
  for (float& v : q.values()) v = value(random);
  return q;
}

// What a trained table looks like: minus the target's station distance plus
// a little noise, so the top-2 graph follows near-shortest paths and most
// starts succeed (the reverse search then visits almost every cell).
QTable TrainedLikeTable(const Grid& grid) {
  std::vector<int32_t> distance, queue;
  NearestStationDistances(grid, distance, queue);
  std::mt19937 random(11);
  std::uniform_real_distribution<float> noise(0.0f, 0.5f);
  QTable q(grid.size());
  for (int cell = 0; cell < grid.size(); ++cell) {
    for (int a = 0; a < kNumActions; ++a) {
      const int r = grid.RowOf(cell) + kActionRowOffset[a];
      const int c = grid.ColOf(cell) + kActionColOffset[a];
      const int32_t d = grid.InBounds(r, c) ? distance[grid.Index(r, c)] : kUnreachable;
      q.row(cell)[a] = static_cast<float>(d == kUnreachable ? -1000 : -d) + noise(random);
    }
  }
  return q;
}

void BM_PolicyEvaluate(benchmark::State& state, bool trained_like) {
  const Grid grid = HardMaze(static_cast<int>(state.range(0)));
  const QTable q = trained_like ? TrainedLikeTable(grid) : RandomTable(grid);
  PolicyEvaluator evaluator;
  PolicyDepths depths;
  for (auto _ : state) {
    evaluator.Evaluate(grid, q, depths);
    benchmark::DoNotOptimize(depths.depth.data());
  }
  state.counters["success_rate"] = ScoreGrid(grid, depths).success_rate();
}
BENCHMARK_CAPTURE(BM_PolicyEvaluate, random_table, false)->Arg(300)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PolicyEvaluate, trained_like_table, true)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond);

void BM_BfsOracle(benchmark::State& state) {
  const Grid grid = HardMaze(static_cast<int>(state.range(0)));
  std::vector<int32_t> distance, queue;
  for (auto _ : state) {
    NearestStationDistances(grid, distance, queue);
    benchmark::DoNotOptimize(distance.data());
  }
}
BENCHMARK(BM_BfsOracle)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

void BM_AStarAllPaths(benchmark::State& state) {
  const Grid grid = HardMaze(static_cast<int>(state.range(0)));
  AStarPlanner planner;
  StationPaths paths;
  for (auto _ : state) {
    planner.ComputeAllPaths(grid, paths);
    benchmark::DoNotOptimize(paths.length.data());
  }
  state.counters["searches"] = static_cast<double>(planner.searches());
  state.counters["expansions"] = static_cast<double>(planner.expansions());
}
BENCHMARK(BM_AStarAllPaths)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

// One time step of an oracle as the runner times and scores it (Adapt, then
// Evaluate), over the report's change sequence of the hard maze (2 x size
// steps, replayed from the start when used up).
template <class OraclePlanner>
void BM_OracleStep(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const Scenario scenario =
      GenerateScenario(size, size, Difficulty::kHard, ReportSeed(Difficulty::kHard));
  Grid grid = scenario.grid;
  OraclePlanner planner;
  planner.Initialize(grid);
  size_t next = 0;
  std::vector<int> changed;
  for (auto _ : state) {
    if (next == scenario.changes.steps.size()) {
      state.PauseTiming();
      grid = scenario.grid;
      planner.Initialize(grid);
      next = 0;
      state.ResumeTiming();
    }
    const ChangeStep& step = scenario.changes.steps[next++];
    ApplyChanges(step, grid);
    changed.clear();
    for (const CellChange& change : step.changes) changed.push_back(change.cell);
    planner.Adapt(grid, changed);
    benchmark::DoNotOptimize(planner.Evaluate(grid));
  }
}
BENCHMARK(BM_OracleStep<BfsOraclePlanner>)->Arg(300)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OracleStep<IncrementalOraclePlanner>)
    ->Arg(300)
    ->Arg(1000)
    ->Unit(benchmark::kMicrosecond);

// The policy evaluation of a learning approach's step without retraining
// (the usual step): the grid changes, then the retraining decision asks the
// success rates of the changed leaves and the runner scores the whole grid.
// Measured both ways: one full PolicyEvaluator pass per step, and the
// incremental evaluation, which repairs around the changed cells.
void BM_EvaluationStep(benchmark::State& state, bool incremental) {
  const int size = static_cast<int>(state.range(0));
  const Scenario scenario =
      GenerateScenario(size, size, Difficulty::kHard, ReportSeed(Difficulty::kHard));
  const QTable q = TrainedLikeTable(scenario.grid);
  const QuadTree tree(size, size);
  Grid grid = scenario.grid;
  IncrementalPolicyEvaluation evaluation;
  PolicyEvaluator evaluator;
  PolicyDepths depths;
  auto restart = [&] {
    grid = scenario.grid;
    evaluation.Reset(tree);
    benchmark::DoNotOptimize(evaluation.Score(grid, q, tree.root()));
  };
  restart();
  size_t next = 0;
  std::vector<int> changed;
  for (auto _ : state) {
    if (next == scenario.changes.steps.size()) {
      state.PauseTiming();
      restart();
      next = 0;
      state.ResumeTiming();
    }
    const ChangeStep& step = scenario.changes.steps[next++];
    ApplyChanges(step, grid);
    changed.clear();
    for (const CellChange& change : step.changes) changed.push_back(change.cell);
    if (incremental) {
      evaluation.GridChanged(changed);
      for (int cell : changed)
        benchmark::DoNotOptimize(evaluation.Score(grid, q, tree.LeafOf(cell)));
      benchmark::DoNotOptimize(evaluation.Score(grid, q, tree.root()));
    } else {
      evaluator.Evaluate(grid, q, depths);
      for (int cell : changed) {
        benchmark::DoNotOptimize(ScoreRegion(grid, depths, tree.node(tree.LeafOf(cell)).region));
      }
      benchmark::DoNotOptimize(ScoreGrid(grid, depths));
    }
  }
}
BENCHMARK_CAPTURE(BM_EvaluationStep, full, false)
    ->Arg(300)
    ->Arg(1000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EvaluationStep, incremental, true)
    ->Arg(300)
    ->Arg(1000)
    ->Unit(benchmark::kMicrosecond);

// A* Static's per-step cost: scoring the stored paths on a changed grid.
void BM_ScoreStoredPaths(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const Scenario scenario =
      GenerateScenario(size, size, Difficulty::kHard, ReportSeed(Difficulty::kHard));
  AStarPlanner planner;
  StationPaths paths;
  planner.ComputeAllPaths(scenario.grid, paths);
  Grid current = scenario.grid;
  for (const ChangeStep& step : scenario.changes.steps) ApplyChanges(step, current);
  for (auto _ : state) benchmark::DoNotOptimize(ScoreStoredPaths(current, paths));
}
BENCHMARK(BM_ScoreStoredPaths)->Arg(300)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dynapath

BENCHMARK_MAIN();
