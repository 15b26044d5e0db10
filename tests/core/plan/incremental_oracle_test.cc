#include "core/plan/incremental_oracle.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "dynapath/astar_paths.h"
#include "dynapath/bfs_oracle.h"
#include "dynapath/experiment.h"
#include "dynapath/local_trainer.h"
#include "dynapath/map_scenario.h"
#include "dynapath/scenario.h"
#include "dynapath/thread_pool.h"
#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

using test_grids::Distances;
using test_grids::FromText;
using test_grids::RandomGrid;

// Random edits of any kind (obstacle, free, station), `count` cells at once,
// clustered around one cell half of the time so repairs overlap.
std::vector<int> RandomEdit(Grid& grid, int count, std::mt19937& random) {
  std::vector<int> changed;
  const int centre = static_cast<int>(random() % grid.size());
  for (int k = 0; k < count; ++k) {
    int cell = static_cast<int>(random() % grid.size());
    if (random() % 2 == 0) {
      const int r = grid.RowOf(centre) + static_cast<int>(random() % 5) - 2;
      const int c = grid.ColOf(centre) + static_cast<int>(random() % 5) - 2;
      if (grid.InBounds(r, c)) cell = grid.Index(r, c);
    }
    const int v = static_cast<int>(random() % 100);
    grid.set(cell, v < 45 ? Cell::kObstacle : v < 95 ? Cell::kFree : Cell::kStation);
    changed.push_back(cell);
  }
  return changed;
}

void ExpectSameAsFullSearch(IncrementalOraclePlanner& planner, const Grid& grid,
                            const std::string& where) {
  const std::vector<int32_t> full = Distances(grid);
  ASSERT_EQ(planner.distances(), full) << where;
  const PolicyScore expected = ScoreDistances(grid, full);
  const PolicyScore score = planner.Evaluate(grid);
  EXPECT_EQ(score.starts, expected.starts) << where;
  EXPECT_EQ(score.successes, expected.successes) << where;
  EXPECT_EQ(score.total_length, expected.total_length) << where;
}

TEST(IncrementalOracleTest, RepairEqualsFullSearchOnRandomEdits) {
  std::mt19937 random(11);
  for (int trial = 0; trial < 40; ++trial) {
    const int rows = 1 + static_cast<int>(random() % 25),
              cols = 1 + static_cast<int>(random() % 25);
    Grid grid = RandomGrid(rows, cols, static_cast<int>(random() % 600),
                           static_cast<int>(random() % 30), random);
    IncrementalOraclePlanner planner;
    planner.Initialize(grid);
    ExpectSameAsFullSearch(planner, grid, "initial");
    for (int step = 1; step <= 60; ++step) {
      const std::vector<int> changed =
          RandomEdit(grid, 1 + static_cast<int>(random() % 12), random);
      planner.Adapt(grid, changed);
      ExpectSameAsFullSearch(planner, grid,
                             "trial " + std::to_string(trial) + " step " + std::to_string(step));
      if (HasFatalFailure()) return;
    }
  }
}

TEST(IncrementalOracleTest, WallClosingAndOpeningACorridor) {
  // Closing the only gap sends the right side's distances to "unreachable";
  // reopening it restores them.
  Grid grid = FromText(
      "C..#....\n"
      "...#....\n"
      "........\n");
  IncrementalOraclePlanner planner;
  planner.Initialize(grid);
  EXPECT_EQ(planner.distances()[grid.Index(0, 7)], 7);
  grid.set(2, 3, Cell::kObstacle);
  planner.Adapt(grid, {grid.Index(2, 3)});
  ExpectSameAsFullSearch(planner, grid, "closed");
  EXPECT_EQ(planner.distances()[grid.Index(0, 7)], kUnreachable);
  grid.set(2, 3, Cell::kFree);
  planner.Adapt(grid, {grid.Index(2, 3)});
  ExpectSameAsFullSearch(planner, grid, "reopened");
  EXPECT_EQ(planner.distances()[grid.Index(0, 7)], 7);
}

TEST(IncrementalOracleTest, StationMovesAndRemovals) {
  Grid grid = FromText(
      "C.........\n"
      "..........\n");
  IncrementalOraclePlanner planner;
  planner.Initialize(grid);
  grid.set(0, 0, Cell::kFree);
  grid.set(1, 9, Cell::kStation);
  planner.Adapt(grid, {grid.Index(0, 0), grid.Index(1, 9)});
  ExpectSameAsFullSearch(planner, grid, "moved");
  grid.set(1, 9, Cell::kObstacle);
  planner.Adapt(grid, {grid.Index(1, 9)});
  ExpectSameAsFullSearch(planner, grid, "no station");
  EXPECT_EQ(planner.Evaluate(grid).successes, 0);
}

TEST(IncrementalOracleTest, SameFiguresAsBfsOracleOnReportScenarios) {
  ThreadPool pool(1);
  LocalTrainer trainer(pool);
  for (const auto& [size, difficulty, seed] :
       {std::tuple{30, Difficulty::kHard, 52u}, std::tuple{40, Difficulty::kMedium, 51u},
        std::tuple{20, Difficulty::kEasy, 50u}}) {
    const Scenario scenario = GenerateScenario(size, size, difficulty, seed);
    const ApproachRun bfs =
        RunApproach(scenario, Approach::kBfsOracle, PlannerOptions{}, &trainer, {"x", "y"});
    const ApproachRun incremental =
        RunApproach(scenario, Approach::kIncrementalOracle, PlannerOptions{}, &trainer, {"x", "y"});
    ASSERT_EQ(bfs.steps.size(), incremental.steps.size());
    for (size_t t = 0; t < bfs.steps.size(); ++t) {
      EXPECT_EQ(bfs.steps[t].success_rate, incremental.steps[t].success_rate) << t;
      EXPECT_EQ(bfs.steps[t].average_path_length, incremental.steps[t].average_path_length) << t;
    }
  }
}

// A rectangular map with static walls, where only movers move:
// the same figures as the BFS Oracle at every step.
TEST(IncrementalOracleTest, SameFiguresAsBfsOracleOnARectangularMapWithMovers) {
  ThreadPool pool(1);
  LocalTrainer trainer(pool);
  for (const auto& [rows, cols, seed] : {std::tuple{23, 61, 3u}, std::tuple{57, 9, 8u}}) {
    Grid grid(rows, cols);
    for (int r = 2; r < rows; r += 4) {
      for (int c = 0; c < cols; ++c) {
        if ((c + r) % 7 != 0) grid.set(r, c, Cell::kObstacle);  // walls with gaps
      }
    }
    CRandom random(seed);
    ASSERT_TRUE(PlaceOnFreeCells(grid, 4, Cell::kStation, random).ok());
    Result<std::vector<int>> movers =
        PlaceOnFreeCells(grid, rows * cols / 20, Cell::kObstacle, random);
    ASSERT_TRUE(movers.ok());
    Scenario scenario{grid, GenerateMoverChanges(grid, *movers, 40, random)};
    const ApproachRun bfs =
        RunApproach(scenario, Approach::kBfsOracle, PlannerOptions{}, &trainer, {"x", "y"});
    const ApproachRun incremental =
        RunApproach(scenario, Approach::kIncrementalOracle, PlannerOptions{}, &trainer, {"x", "y"});
    ASSERT_EQ(bfs.steps.size(), 41u);
    EXPECT_GT(bfs.steps[0].success_rate, 0.0);  // the stations are reachable
    EXPECT_NE(bfs.steps.front().average_path_length, bfs.steps.back().average_path_length);
    ASSERT_EQ(bfs.steps.size(), incremental.steps.size());
    for (size_t t = 0; t < bfs.steps.size(); ++t) {
      EXPECT_EQ(bfs.steps[t].success_rate, incremental.steps[t].success_rate)
          << rows << "x" << cols << " " << t;
      EXPECT_EQ(bfs.steps[t].average_path_length, incremental.steps[t].average_path_length) << t;
    }
  }
}

}  // namespace
}  // namespace dynapath
