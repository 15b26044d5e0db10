#include "dynapath/astar_paths.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "dynapath/bfs_oracle.h"
#include "dynapath/change_sequence.h"
#include "dynapath/difficulty.h"
#include "dynapath/grid.h"
#include "dynapath/scenario.h"
#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

using test_grids::Distances;
using test_grids::FromText;

// A random grid of its own generator seeded with `seed`.
Grid RandomGrid(int rows, int cols, int obstacle_per_mille, int station_per_mille, unsigned seed) {
  std::mt19937 random(seed);
  return test_grids::RandomGrid(rows, cols, obstacle_per_mille, station_per_mille, random);
}

// The A* lengths equal the BFS distances and every stored path is a valid
// shortest path: each step is an 8-neighbour move to a non-obstacle cell that
// lowers the length by one, down to a station.
void ExpectExactPaths(const Grid& grid, const StationPaths& paths, const std::string& label) {
  ASSERT_EQ(paths.length, Distances(grid)) << label;
  ASSERT_EQ(paths.next.size(), static_cast<size_t>(grid.size())) << label;
  for (int cell = 0; cell < grid.size(); ++cell) {
    const int32_t length = paths.length[cell];
    const int32_t next = paths.next[cell];
    if (length == kUnreachable) {
      EXPECT_EQ(next, -1) << label << " cell " << cell;
    } else if (length == 0) {
      EXPECT_EQ(grid.at(cell), Cell::kStation) << label << " cell " << cell;
      EXPECT_EQ(next, cell) << label << " cell " << cell;
    } else {
      ASSERT_GE(next, 0) << label << " cell " << cell;
      ASSERT_LT(next, grid.size()) << label << " cell " << cell;
      const int dr = std::abs(grid.RowOf(next) - grid.RowOf(cell));
      const int dc = std::abs(grid.ColOf(next) - grid.ColOf(cell));
      EXPECT_TRUE(dr <= 1 && dc <= 1 && dr + dc > 0) << label << " cell " << cell;
      EXPECT_NE(grid.at(next), Cell::kObstacle) << label << " cell " << cell;
      EXPECT_EQ(paths.length[next], length - 1) << label << " cell " << cell;
    }
  }
}

void ExpectSameScore(const PolicyScore& actual, const PolicyScore& expected,
                     const std::string& label) {
  EXPECT_EQ(actual.starts, expected.starts) << label;
  EXPECT_EQ(actual.successes, expected.successes) << label;
  EXPECT_EQ(actual.total_length, expected.total_length) << label;
}

// A* Static scoring by walking every stored path in full: the plain reading
// of SPEC section 8 that the memoised ScoreStoredPaths must agree with.
// `blocked_paths` counts starts whose stored path hits an obstacle of `current`.
PolicyScore NaiveStoredScore(const Grid& current, const StationPaths& paths, int* blocked_paths) {
  PolicyScore score;
  for (int start = 0; start < current.size(); ++start) {
    if (current.at(start) == Cell::kObstacle) continue;
    ++score.starts;
    if (paths.length[start] == kUnreachable) continue;
    bool open = true;
    int cell = start;
    for (int step = 0;; ++step) {
      if (current.at(cell) == Cell::kObstacle) {
        open = false;
        break;
      }
      if (step == paths.length[start]) break;
      cell = paths.next[cell];
    }
    open = open && current.at(cell) == Cell::kStation;
    if (open) {
      ++score.successes;
      score.total_length += paths.length[start];
    } else if (blocked_paths != nullptr) {
      ++*blocked_paths;
    }
  }
  return score;
}

struct ReportMaze {
  int size;
  Difficulty difficulty;
  unsigned seed;
};

std::vector<ReportMaze> ReportMazes(const std::vector<int>& sizes) {
  std::vector<ReportMaze> mazes;
  for (int size : sizes) {
    for (Difficulty d : {Difficulty::kEasy, Difficulty::kMedium, Difficulty::kHard}) {
      mazes.push_back({size, d, ReportSeed(d)});
    }
  }
  mazes.push_back({50, Difficulty::kHard, kEdgeCaseSeed});
  return mazes;
}

std::string Label(const ReportMaze& maze) {
  return std::to_string(maze.size) + " " + DifficultyName(maze.difficulty) + " seed " +
         std::to_string(maze.seed);
}

TEST(AStarPathsTest, LengthsEqualBfsOnEveryReportMaze) {
  AStarPlanner planner;  // one planner for all sizes: buffer reuse is part of the test
  StationPaths paths;
  for (const ReportMaze& maze : ReportMazes({20, 50, 100, 200, 300})) {
    const Grid grid = GenerateScenario(maze.size, maze.size, maze.difficulty, maze.seed, 0).grid;
    planner.ComputeAllPaths(grid, paths);
    ExpectExactPaths(grid, paths, Label(maze));
    ExpectSameScore(ScoreStoredPaths(grid, paths), ScoreDistances(grid, paths.length), Label(maze));
  }
}

TEST(AStarPathsTest, LengthsEqualBfsOnRandomGrids) {
  AStarPlanner planner;
  StationPaths paths;
  const int shapes[][2] = {{1, 1}, {1, 17}, {17, 1}, {2, 9}, {7, 13}, {30, 30}, {40, 23}};
  const int densities[][2] = {{0, 20}, {100, 10}, {300, 5}, {450, 3}, {600, 20}, {400, 0}};
  unsigned seed = 1;
  for (const auto& shape : shapes) {
    for (const auto& density : densities) {
      for (int repeat = 0; repeat < 4; ++repeat, ++seed) {
        const Grid grid = RandomGrid(shape[0], shape[1], density[0], density[1], seed);
        const std::string label = std::to_string(shape[0]) + "x" + std::to_string(shape[1]) +
                                  " density " + std::to_string(density[0]) + "/" +
                                  std::to_string(density[1]) + " seed " + std::to_string(seed);
        planner.ComputeAllPaths(grid, paths);
        ExpectExactPaths(grid, paths, label);
        ExpectSameScore(ScoreStoredPaths(grid, paths), ScoreDistances(grid, paths.length), label);
      }
    }
  }
}

TEST(AStarPathsTest, HandMadeGrids) {
  AStarPlanner planner;
  StationPaths paths;
  constexpr int32_t U = kUnreachable;
  planner.ComputeAllPaths(FromText("C#.\n#..\n..#\n"), paths);
  EXPECT_EQ(paths.length, (std::vector<int32_t>{0, U, 2, U, 1, 2, 2, 2, U}));
  EXPECT_EQ(paths.next[4], 0);  // through the corner between two obstacles

  // Unreachable pockets: a failed search decides every cell it closed.
  const Grid pocket = FromText("C...\n####\n.#..\n");
  planner.ComputeAllPaths(pocket, paths);
  ExpectExactPaths(pocket, paths, "pocket");
  // Row-major starts (0,1), (0,2), (0,3) each search once (each path only
  // crosses cells already decided); (2,0) fails alone; (2,2) fails and
  // decides (2,3) too.
  EXPECT_EQ(planner.searches(), 5);

  const Grid no_station = FromText("...\n.#.\n");
  planner.ComputeAllPaths(no_station, paths);
  EXPECT_EQ(paths.length, std::vector<int32_t>(6, U));
  EXPECT_EQ(paths.next, std::vector<int32_t>(6, -1));
  EXPECT_EQ(planner.searches(), 0);

  const Grid all_obstacles = FromText("##\n##\n");
  planner.ComputeAllPaths(all_obstacles, paths);
  EXPECT_EQ(paths.length, std::vector<int32_t>(4, U));
  EXPECT_EQ(ScoreStoredPaths(all_obstacles, paths).starts, 0);
}

TEST(AStarPathsTest, SubPathsSpareSearches) {
  // In a corridor, the first start's path covers every other cell.
  AStarPlanner planner;
  StationPaths paths;
  const Grid corridor = FromText("........C\n");
  planner.ComputeAllPaths(corridor, paths);
  ExpectExactPaths(corridor, paths, "corridor");
  EXPECT_EQ(planner.searches(), 1);
}

TEST(AStarPathsTest, IsDeterministic) {
  const Grid grid = GenerateScenario(50, 50, Difficulty::kHard, 52, 0).grid;
  AStarPlanner first, second;
  StationPaths a, b;
  first.ComputeAllPaths(grid, a);
  second.ComputeAllPaths(grid, b);
  first.ComputeAllPaths(grid, b);
  EXPECT_EQ(a.next, b.next);
  EXPECT_EQ(a.length, b.length);
  second.ComputeAllPaths(grid, b);
  EXPECT_EQ(a.next, b.next);
}

// Ctrl-C inside one step: a stop already requested ends the searches at
// once (false, every start decided: unsearched ones unreachable); an unset
// token changes nothing.
TEST(AStarPathsTest, StopEndsTheSearchesEarlyAndAnUnsetTokenChangesNothing) {
  const Grid grid = RandomGrid(60, 70, 200, 5, 11);
  AStarPlanner planner;
  StationPaths plain, unset, stopped;
  ASSERT_TRUE(planner.ComputeAllPaths(grid, plain));
  const std::atomic<bool> no{false}, yes{true};
  ASSERT_TRUE(planner.ComputeAllPaths(grid, unset, &no));
  EXPECT_EQ(unset.length, plain.length);
  EXPECT_EQ(unset.next, plain.next);

  EXPECT_FALSE(planner.ComputeAllPaths(grid, stopped, &yes));
  EXPECT_EQ(planner.searches(), 0);
  int unreachable = 0;
  for (int cell = 0; cell < grid.size(); ++cell) {
    ASSERT_TRUE(stopped.length[cell] >= 0 || stopped.length[cell] == kUnreachable) << cell;
    unreachable += stopped.length[cell] == kUnreachable && grid.at(cell) == Cell::kFree;
  }
  EXPECT_GT(unreachable, 0);
}

TEST(AStarPathsTest, StoredPathCrossingNewObstacleFails) {
  const Grid grid = FromText(
      "C.....\n"
      "......\n");
  AStarPlanner planner;
  StationPaths paths;
  planner.ComputeAllPaths(grid, paths);
  const int start = grid.Index(0, 5);
  ASSERT_EQ(paths.length[start], 5);
  const int blocked = paths.next[paths.next[start]];  // third cell of the path
  Grid current = grid;
  current.set(blocked, Cell::kObstacle);

  int blocked_paths = 0;
  const PolicyScore stored = ScoreStoredPaths(current, paths);
  ExpectSameScore(stored, NaiveStoredScore(current, paths, &blocked_paths), "corridor");
  EXPECT_GE(blocked_paths, 2);  // at least the start and the cell after it
  // The oracle still reaches the station around the new obstacle.
  const PolicyScore oracle = ScoreDistances(current, Distances(current));
  EXPECT_EQ(oracle.successes, oracle.starts);
  EXPECT_EQ(stored.starts, oracle.starts);
  EXPECT_LE(stored.successes, oracle.successes - 2);

  // A station that became a free cell no longer ends a path.
  Grid moved_station = grid;
  moved_station.set(0, 0, Cell::kFree);
  moved_station.set(1, 0, Cell::kStation);
  const PolicyScore orphaned = ScoreStoredPaths(moved_station, paths);
  ExpectSameScore(orphaned, NaiveStoredScore(moved_station, paths, nullptr), "moved station");
  EXPECT_LT(orphaned.successes, orphaned.starts);
}

TEST(AStarPathsTest, StaticPlanUnderChangeSequences) {
  AStarPlanner planner;
  StationPaths static_paths, oracle_paths;
  int total_blocked = 0;
  for (const ReportMaze& maze : ReportMazes({20, 50})) {
    const Scenario scenario = GenerateScenario(maze.size, maze.size, maze.difficulty, maze.seed);
    ASSERT_EQ(static_cast<int>(scenario.changes.steps.size()), 2 * maze.size);
    planner.ComputeAllPaths(scenario.grid, static_paths);
    Grid current = scenario.grid;
    int step = 0;
    for (const ChangeStep& change : scenario.changes.steps) {
      ApplyChanges(change, current);
      const std::string label = Label(maze) + " step " + std::to_string(++step);
      int blocked = 0;
      const PolicyScore stored = ScoreStoredPaths(current, static_paths);
      ExpectSameScore(stored, NaiveStoredScore(current, static_paths, &blocked), label);
      total_blocked += blocked;
      const std::vector<int32_t> distance = Distances(current);
      const PolicyScore oracle = ScoreDistances(current, distance);
      EXPECT_EQ(stored.starts, oracle.starts) << label;
      EXPECT_LE(stored.successes, oracle.successes) << label;
      // A* Oracle: replanning on the changed grid is exact again.
      planner.ComputeAllPaths(current, oracle_paths);
      ASSERT_EQ(oracle_paths.length, distance) << label;
    }
  }
  // The sequences do block stored paths, so the failure branch was exercised.
  EXPECT_GT(total_blocked, 0);
}

}  // namespace
}  // namespace dynapath
