#include "dynapath/goal_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

using test_grids::FromText;
using test_grids::RandomGrid;

std::shared_ptr<const Grid> Shared(const Grid& grid) { return std::make_shared<const Grid>(grid); }

std::vector<int32_t> Cells(const Grid& grid, std::vector<std::pair<int, int>> rc) {
  std::vector<int32_t> cells;
  for (auto [r, c] : rc) cells.push_back(grid.Index(r, c));
  return cells;
}

// Every move of `path` is one of SPEC's 8 moves onto a non-obstacle cell.
void ExpectValidPath(const Grid& grid, const GoalPath& path, int start, int goal) {
  ASSERT_EQ(path.status, GoalStatus::kReached);
  ASSERT_EQ(path.cells.size(), static_cast<size_t>(path.cost) + 1);
  EXPECT_EQ(path.cells.front(), start);
  EXPECT_EQ(path.cells.back(), goal);
  for (size_t i = 0; i < path.cells.size(); ++i) {
    EXPECT_NE(grid.at(path.cells[i]), Cell::kObstacle);
    if (i == 0) continue;
    const int a = path.cells[i - 1], b = path.cells[i];
    EXPECT_LE(std::abs(grid.RowOf(a) - grid.RowOf(b)), 1);
    EXPECT_LE(std::abs(grid.ColOf(a) - grid.ColOf(b)), 1);
    EXPECT_NE(a, b);
  }
}

// A wall with one gap: the only way round; diagonal moves pass between two
// obstacles that touch at a corner (SPEC: a move needs only its target free).
TEST(GoalPaths, ExactPathsOnAHandMadeGrid) {
  const Grid grid = FromText(
      ".....\n"
      "####.\n"
      ".....\n"
      ".#.#.\n"
      "..#..\n");
  for (int hot_after : {1, 1000}) {  // from a field, then by A*
    GoalPlannerOptions options;
    options.hot_after = hot_after;
    options.background_builds = false;
    GoalPlanner planner(options);
    planner.Update(Shared(grid), {});
    const GoalPath path = planner.Plan(0, 0, 4, 0);
    EXPECT_EQ(path.source, hot_after == 1 ? GoalSource::kField : GoalSource::kSearch);
    ASSERT_EQ(path.status, GoalStatus::kReached);
    EXPECT_EQ(path.cost, 8);
    ExpectValidPath(grid, path, grid.Index(0, 0), grid.Index(4, 0));
    if (hot_after == 1) {  // down the field, neighbours in action order
      EXPECT_EQ(
          path.cells,
          Cells(grid, {{0, 0}, {0, 1}, {0, 2}, {0, 3}, {1, 4}, {2, 3}, {3, 2}, {4, 1}, {4, 0}}));
    }
    // Between (3,1) and (4,2), which touch at a corner: allowed.
    const GoalPath corner = planner.Plan(3, 2, 4, 1);
    ASSERT_EQ(corner.status, GoalStatus::kReached);
    EXPECT_EQ(corner.cost, 1);
    EXPECT_EQ(corner.cells, Cells(grid, {{3, 2}, {4, 1}}));
    const GoalPath self = planner.Plan(2, 2, 2, 2);
    EXPECT_EQ(self.cost, 0);
    EXPECT_EQ(self.cells, Cells(grid, {{2, 2}}));
  }
}

TEST(GoalPaths, BadStartsAndGoals) {
  const Grid grid = FromText(
      "..#..\n"
      "..#..\n"
      "###..\n");
  GoalPlannerOptions options;
  options.hot_after = 1;
  GoalPlanner planner(options);
  planner.Update(Shared(grid), {});
  EXPECT_EQ(planner.CheckGoal(-1, 0), GoalCheck::kOutsideGrid);
  EXPECT_EQ(planner.CheckGoal(0, 5), GoalCheck::kOutsideGrid);
  EXPECT_EQ(planner.CheckGoal(0, 2), GoalCheck::kObstacle);
  EXPECT_EQ(planner.CheckGoal(0, 4), GoalCheck::kOk);
  EXPECT_EQ(planner.Plan(0, 0, 0, 4).status, GoalStatus::kNoRoute);
  EXPECT_EQ(planner.Plan(0, 0, 0, 4).cost, -1);
  EXPECT_EQ(planner.Plan(2, 0, 0, 4).status, GoalStatus::kStartObstacle);
  EXPECT_EQ(planner.Plan(3, 0, 0, 4).status, GoalStatus::kStartOutsideGrid);
  EXPECT_EQ(planner.Plan(0, 3, 0, 2).status, GoalStatus::kNoRoute);  // goal on an obstacle
  EXPECT_EQ(planner.Plan(0, 3, 2, 4, /*budget=*/2).status, GoalStatus::kOverBudget);
  EXPECT_EQ(planner.Plan(0, 3, 2, 4, /*budget=*/3).cost, 2);
  GoalPlannerOptions searched;
  searched.hot_after = 1000;
  GoalPlanner landmarked(searched);
  landmarked.Update(Shared(grid), {});
  EXPECT_EQ(landmarked.Plan(0, 0, 0, 4).status, GoalStatus::kNoRoute);
  EXPECT_EQ(landmarked.stats().proved_unreachable, 1);  // the first landmark is (0,0)
  EXPECT_EQ(landmarked.Plan(0, 0, 1, 1).cost, 1);
  GoalPlanner cold;  // before any grid
  EXPECT_EQ(cold.Plan(0, 0, 0, 0).status, GoalStatus::kStartOutsideGrid);
}

// The cache: hits after the first build, LRU eviction under the byte cap,
// a field repaired after updates, rebuilt once it fell behind the log.
TEST(GoalPaths, CacheCountsAndBounds) {
  Grid grid(10, 10);
  GoalPlannerOptions options;
  options.hot_after = 1;
  options.background_builds = false;
  options.landmarks = 0;
  GoalPlanner probe(options);  // one field's bytes: 2 a free cell and a header
  probe.Update(Shared(grid), {});
  probe.Plan(0, 0, 9, 9);
  const size_t one = probe.stats().bytes;
  EXPECT_GE(one, 2 * 100u);
  EXPECT_LT(one, 2 * 100u + 256);
  options.landmarks = 8;              // none fit in half the cache
  options.cache_bytes = one * 3 / 2;  // one field, not two
  options.log_batches = 2;
  GoalPlanner planner(options);
  planner.Update(Shared(grid), {});
  EXPECT_EQ(planner.Plan(0, 0, 9, 9).cost, 9);
  EXPECT_EQ(planner.Plan(0, 5, 9, 9).cost, 9);
  EXPECT_EQ(planner.stats().builds, 1);
  EXPECT_EQ(planner.stats().hits, 1);
  // A second goal evicts the first once asked more often than it (twice).
  EXPECT_EQ(planner.Plan(0, 0, 5, 5).source, GoalSource::kSearch);
  EXPECT_EQ(planner.Plan(0, 0, 5, 5).source, GoalSource::kSearch);
  EXPECT_EQ(planner.stats().evictions, 0);
  const GoalPath third = planner.Plan(0, 0, 5, 5);
  EXPECT_EQ(third.source, GoalSource::kField);
  EXPECT_EQ(third.cost, 5);
  EXPECT_EQ(planner.stats().evictions, 1);
  EXPECT_EQ(planner.stats().fields, 1);
  EXPECT_LE(planner.stats().peak_bytes, options.cache_bytes);
  // A wall across row 3 but for column 9.
  std::vector<int> changed;
  for (int c = 0; c < 9; ++c) {
    grid.set(3, c, Cell::kObstacle);
    changed.push_back(grid.Index(3, c));
  }
  planner.Update(Shared(grid), changed);
  EXPECT_EQ(planner.Plan(0, 0, 5, 5).cost, FreshGoalDistance(grid, 0, grid.Index(5, 5)));
  EXPECT_EQ(planner.stats().repairs, 1);
  for (int k = 0; k < 3; ++k) planner.Update(Shared(grid), {});
  EXPECT_EQ(planner.Plan(0, 0, 5, 5).cost, FreshGoalDistance(grid, 0, grid.Index(5, 5)));
  EXPECT_EQ(planner.stats().rebuilds, 1);
  // No room for any field: every goal searched.
  GoalPlannerOptions none;
  none.cache_bytes = 0;
  GoalPlanner cold(none);
  cold.Update(Shared(grid), {});
  for (int k = 0; k < 3; ++k) EXPECT_EQ(cold.Plan(0, 0, 5, 5).source, GoalSource::kSearch);
  EXPECT_EQ(cold.stats().fields, 0);
  EXPECT_EQ(cold.stats().searches, 3);
}

// Property: on random grids under random updates, every answer (from a
// field, repaired or not, or from A*) costs what a fresh breadth-first
// search on that update's grid says, and its path is a valid one.
TEST(GoalPaths, EveryAnswerMatchesAFreshSearch) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 12; ++trial) {
    const int rows = 5 + static_cast<int>(random() % 20),
              cols = 5 + static_cast<int>(random() % 20);
    Grid grid = RandomGrid(rows, cols, 250 + static_cast<int>(random() % 200), 10, random);
    GoalPlannerOptions options;
    options.hot_after = 1 + static_cast<int>(random() % 3);
    options.background_builds = trial % 2 == 1;
    if (trial % 3 == 0) options.narrow_limit = 6;  // wide fields too
    options.cache_bytes = (random() % 2 == 0) ? size_t{1} << 20 : 3 * (8 * grid.size() + 512);
    options.log_batches = 1 + random() % 4;
    GoalPlanner planner(options);
    planner.Update(Shared(grid), {});
    std::vector<int> goals;
    for (int k = 0; k < 6; ++k) goals.push_back(static_cast<int>(random() % grid.size()));
    for (int step = 0; step < 25; ++step) {
      if (step > 0) {
        std::vector<int> changed;
        const int n = 1 + static_cast<int>(random() % 6);
        for (int k = 0; k < n; ++k) {
          const int cell = static_cast<int>(random() % grid.size());
          grid.set(cell, grid.at(cell) == Cell::kObstacle ? Cell::kFree : Cell::kObstacle);
          changed.push_back(cell);
        }
        planner.Update(Shared(grid), changed);
      }
      if (step % 5 == 4) planner.WaitForBuilds();  // background fields answer too
      for (int q = 0; q < 10; ++q) {
        const int start = static_cast<int>(random() % grid.size());
        const int goal = goals[random() % goals.size()];
        const GoalPath path =
            planner.Plan(grid.RowOf(start), grid.ColOf(start), grid.RowOf(goal), grid.ColOf(goal));
        const int32_t fresh = FreshGoalDistance(grid, start, goal);
        if (grid.at(start) == Cell::kObstacle) {
          EXPECT_EQ(path.status, GoalStatus::kStartObstacle);
          continue;
        }
        EXPECT_EQ(path.cost, fresh) << "trial " << trial << " step " << step;
        if (fresh >= 0) {
          ExpectValidPath(grid, path, start, goal);
        } else {
          EXPECT_EQ(path.status, GoalStatus::kNoRoute);
        }
      }
    }
    EXPECT_GT(planner.stats().searches + planner.stats().hits, 0);
    EXPECT_LE(planner.stats().peak_bytes, options.cache_bytes);
  }
}

// Walls across every other row, each with one gap at alternating ends: the
// way from the top-left corner to the bottom-left one runs the whole grid.
Grid Serpentine(int rows, int cols) {
  Grid grid(rows, cols);
  for (int r = 1; r < rows; r += 2) {
    const int gap = (r / 2) % 2 == 0 ? cols - 1 : 0;
    for (int c = 0; c < cols; ++c) {
      if (c != gap) grid.set(r, c, Cell::kObstacle);
    }
  }
  return grid;
}

// A field holds 2 bytes a cell while its distances are at most
// narrow_limit, and is made again 4 bytes a cell when one passes it: at
// its build, and when a repair lengthens the paths.
TEST(GoalPaths, WideFieldsPastTheNarrowLimit) {
  GoalPlannerOptions options;
  options.hot_after = 1;
  options.background_builds = false;
  options.landmarks = 0;
  options.narrow_limit = 20;
  Grid grid = Serpentine(9, 12);  // the way to (8, 0) from (0, 0): 47 moves
  const int goal = grid.Index(8, 0);
  {
    GoalPlanner planner(options);
    planner.Update(Shared(grid), {});
    const GoalPath path = planner.Plan(0, 0, 8, 0);
    EXPECT_EQ(path.source, GoalSource::kField);
    EXPECT_EQ(path.cost, FreshGoalDistance(grid, 0, goal));
    EXPECT_GT(path.cost, 20);
    ExpectValidPath(grid, path, 0, goal);
    EXPECT_EQ(planner.stats().widened, 1);
  }
  // A shortcut through every wall: all distances at most 20, 2 bytes a cell.
  std::vector<int> shortcut;
  for (int r = 1; r < 9; r += 2) {
    grid.set(r, 5, Cell::kFree);
    shortcut.push_back(grid.Index(r, 5));
  }
  GoalPlanner planner(options);
  planner.Update(Shared(grid), {});
  EXPECT_EQ(planner.Plan(0, 0, 8, 0).cost, FreshGoalDistance(grid, 0, goal));
  EXPECT_EQ(planner.stats().widened, 0);
  const size_t narrow_bytes = planner.stats().bytes;
  // Closed again: the repair passes the limit, the field is made wide.
  for (int cell : shortcut) grid.set(cell, Cell::kObstacle);
  planner.Update(Shared(grid), shortcut);
  const GoalPath path = planner.Plan(0, 0, 8, 0);
  EXPECT_EQ(path.source, GoalSource::kField);
  EXPECT_EQ(path.cost, FreshGoalDistance(grid, 0, goal));
  ExpectValidPath(grid, path, 0, goal);
  EXPECT_EQ(planner.stats().widened, 1);
  EXPECT_EQ(planner.stats().rebuilds, 1);
  EXPECT_GT(planner.stats().bytes, narrow_bytes);
  EXPECT_EQ(planner.Plan(2, 3, 8, 0).cost, FreshGoalDistance(grid, grid.Index(2, 3), goal));
}

// The real limit: distances above 65,534 on a 201 x 700 serpentine.
TEST(GoalPaths, DistancesAbove65534) {
  const Grid grid = Serpentine(201, 700);
  GoalPlannerOptions options;
  options.hot_after = 1;
  options.background_builds = false;
  options.landmarks = 0;
  GoalPlanner planner(options);
  planner.Update(Shared(grid), {});
  const int goal = grid.Index(200, 0);
  const GoalPath path = planner.Plan(0, 0, 200, 0);
  EXPECT_EQ(path.source, GoalSource::kField);
  EXPECT_GT(path.cost, 65534);
  EXPECT_EQ(path.cost, FreshGoalDistance(grid, 0, goal));
  EXPECT_EQ(path.cells.size(), static_cast<size_t>(path.cost) + 1);
  EXPECT_EQ(planner.stats().widened, 1);
}

// Cells freed after the grid was loaded get the next index entries: the
// fields grow by them and stay exact.
TEST(GoalPaths, CellsFreedLaterJoinTheIndex) {
  Grid grid = FromText(
      ".....\n"
      ".....\n"
      "#####\n"
      ".....\n"
      ".....\n");
  GoalPlannerOptions options;
  options.hot_after = 1;
  options.background_builds = false;
  options.landmarks = 0;
  GoalPlanner planner(options);
  planner.Update(Shared(grid), {});
  EXPECT_EQ(planner.stats().indexed_cells, 20);
  EXPECT_EQ(planner.Plan(0, 0, 4, 0).status, GoalStatus::kNoRoute);
  const size_t bytes = planner.stats().bytes;
  grid.set(2, 3, Cell::kFree);
  planner.Update(Shared(grid), {grid.Index(2, 3)});
  EXPECT_EQ(planner.stats().indexed_cells, 21);
  GoalPath path = planner.Plan(0, 0, 4, 0);
  EXPECT_EQ(path.source, GoalSource::kField);
  EXPECT_EQ(path.cost, 6);  // through (2,3)
  EXPECT_EQ(path.cost, FreshGoalDistance(grid, 0, grid.Index(4, 0)));
  ExpectValidPath(grid, path, 0, grid.Index(4, 0));
  EXPECT_EQ(planner.stats().bytes, bytes + 2);
  grid.set(2, 3, Cell::kObstacle);
  grid.set(2, 0, Cell::kFree);
  planner.Update(Shared(grid), {grid.Index(2, 3), grid.Index(2, 0)});
  EXPECT_EQ(planner.stats().indexed_cells, 22);  // (2,3) keeps its entry
  path = planner.Plan(0, 0, 4, 0);
  EXPECT_EQ(path.cost, 4);
  ExpectValidPath(grid, path, 0, grid.Index(4, 0));
  EXPECT_EQ(planner.stats().repairs, 2);
}

// With background builds a goal turning hot is searched while the builder
// thread makes its field; the field answers once adopted, and is repaired
// like any other. Every answer is exact whichever answered.
TEST(GoalPaths, FieldsMadeOnTheBuilderThread) {
  std::mt19937 random(11);
  Grid grid = RandomGrid(30, 40, 150, 0, random);
  GoalPlannerOptions options;
  options.hot_after = 1;
  options.landmarks = 2;
  GoalPlanner planner(options);
  planner.Update(Shared(grid), {});
  std::vector<int> free;
  for (int v = 0; v < grid.size(); ++v) {
    if (grid.at(v) != Cell::kObstacle) free.push_back(v);
  }
  const int goal = free[free.size() / 2], start = free[3];
  const auto ask = [&](int from, int to) {
    const GoalPath path =
        planner.Plan(grid.RowOf(from), grid.ColOf(from), grid.RowOf(to), grid.ColOf(to));
    EXPECT_EQ(path.cost, FreshGoalDistance(grid, from, to));
    return path;
  };
  EXPECT_EQ(ask(start, goal).source, GoalSource::kSearch);
  EXPECT_EQ(planner.stats().queued, 1);
  planner.WaitForBuilds();
  EXPECT_EQ(planner.stats().builds, 1);
  EXPECT_EQ(planner.stats().pending, 0);
  EXPECT_EQ(ask(start, goal).source, GoalSource::kField);
  for (int step = 0; step < 20; ++step) {
    std::vector<int> changed;
    for (int k = 0; k < 8; ++k) {
      const int cell = static_cast<int>(random() % grid.size());
      if (cell == goal) continue;
      grid.set(cell, grid.at(cell) == Cell::kObstacle ? Cell::kFree : Cell::kObstacle);
      changed.push_back(cell);
    }
    planner.Update(Shared(grid), changed);
    for (int q = 0; q < 5; ++q) {
      const int from = static_cast<int>(random() % grid.size());
      const int to = free[random() % 6];
      if (grid.at(from) == Cell::kObstacle || grid.at(to) == Cell::kObstacle) continue;
      ask(from, to);
    }
    if (grid.at(start) != Cell::kObstacle) ask(start, goal);
    if (step % 4 == 3) planner.WaitForBuilds();
  }
  EXPECT_GT(planner.stats().queued, 1);
  EXPECT_GT(planner.stats().repairs, 0);
  // A grid of another size drops everything, queued builds included.
  ask(start, goal);
  Grid other(12, 12);
  planner.Update(Shared(other), {});
  EXPECT_EQ(planner.stats().fields, 0);
  EXPECT_EQ(planner.stats().pending, 0);
  grid = other;
  EXPECT_EQ(ask(0, grid.Index(11, 11)).cost, 11);
  planner.WaitForBuilds();
  EXPECT_EQ(ask(0, grid.Index(11, 11)).source, GoalSource::kField);
}

// A field whose repairs write more distances than searches expand cells is
// dropped after its answer, and its goal searched from then on.
TEST(GoalPaths, FieldsDearerThanSearchesAreDropped) {
  Grid grid(40, 40);
  for (int c = 1; c < 40; ++c) grid.set(20, c, Cell::kObstacle);  // a gap at column 0
  for (bool drop : {true, false}) {
    Grid g = grid;
    GoalPlannerOptions options;
    options.background_builds = false;
    options.landmarks = 0;
    options.drop_costly_fields = drop;
    GoalPlanner planner(options);
    planner.Update(Shared(g), {});
    for (int c = 0; c < 20; ++c) {  // short searches: a cell or two each
      EXPECT_EQ(planner.Plan(0, c + 1, 0, c).cost, 1);
    }
    const int goal = g.Index(39, 39);
    EXPECT_EQ(planner.Plan(0, 0, 39, 39).source, GoalSource::kSearch);
    EXPECT_EQ(planner.Plan(0, 0, 39, 39).source, GoalSource::kField);  // the second miss
    for (int step = 0; step < 4; ++step) {  // the gap moves from one end to the other
      const bool left = step % 2 == 1;
      g.set(20, 0, left ? Cell::kFree : Cell::kObstacle);
      g.set(20, 39, left ? Cell::kObstacle : Cell::kFree);
      planner.Update(Shared(g), {g.Index(20, 0), g.Index(20, 39)});
      const GoalPath path = planner.Plan(0, 0, 39, 39);
      EXPECT_EQ(path.cost, FreshGoalDistance(g, 0, goal));
      EXPECT_EQ(path.source, !drop || step == 0 ? GoalSource::kField : GoalSource::kSearch)
          << "step " << step << (drop ? " dropping" : " keeping");
    }
    EXPECT_EQ(planner.stats().dropped_costly, drop ? 1 : 0);
  }
}

TEST(GoalPaths, MapFrameRoundTrips) {
  MapFrame frame{0.05, -10.0, -5.0, 40, 60};
  int row = -1, col = -1;
  ASSERT_TRUE(frame.CellAt(-10.0, -5.0, &row, &col));  // the bottom-left corner
  EXPECT_EQ(row, 39);
  EXPECT_EQ(col, 0);
  ASSERT_TRUE(frame.CellAt(frame.X(17), frame.Y(3), &row, &col));
  EXPECT_EQ(row, 3);
  EXPECT_EQ(col, 17);
  EXPECT_DOUBLE_EQ(frame.X(0), -9.975);
  EXPECT_DOUBLE_EQ(frame.Y(39), -4.975);
  EXPECT_FALSE(frame.CellAt(-10.001, 0, &row, &col));
  EXPECT_FALSE(frame.CellAt(-10 + 60 * 0.05, -4, &row, &col));  // the right border
  EXPECT_FALSE(frame.CellAt(0, -5 + 40 * 0.05 + 1e-9, &row, &col));
  EXPECT_FALSE(frame.CellAt(std::nan(""), 0, &row, &col));
  EXPECT_TRUE(CheckFrame(0.05, -10, -5));
  EXPECT_FALSE(CheckFrame(0, 0, 0));
  EXPECT_FALSE(CheckFrame(-1, 0, 0));
  EXPECT_FALSE(CheckFrame(1, std::numeric_limits<double>::infinity(), 0));
}

TEST(GoalPaths, GoalsFiles) {
  auto goals = ParseGoalsText("# shelves\nshelf-1 4,7\n\ndock 12.5,-3.0   # metres\n");
  ASSERT_TRUE(goals) << goals.error().message;
  ASSERT_EQ(goals->size(), 2u);
  EXPECT_EQ((*goals)[0].name, "shelf-1");
  EXPECT_FALSE((*goals)[0].metres);
  EXPECT_EQ((*goals)[0].row, 4);
  EXPECT_EQ((*goals)[0].col, 7);
  EXPECT_TRUE((*goals)[1].metres);
  EXPECT_DOUBLE_EQ((*goals)[1].x, 12.5);
  EXPECT_DOUBLE_EQ((*goals)[1].y, -3.0);
  for (const char* bad : {"shelf\n", "a 1,2\na 3,4\n", "a 1.5,2\n", "a 1,x\n", "a b 1,2\n",
                          "bad/name 1,2\n", "a 1e400.0,2.0\n", "a 99999999999,1\n"}) {
    EXPECT_FALSE(ParseGoalsText(bad)) << bad;
  }
}

}  // namespace
}  // namespace dynapath
