#include "dynapath/policy_evaluation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "dynapath/bfs_oracle.h"
#include "dynapath/grid.h"
#include "dynapath/mdp.h"
#include "dynapath/q_table.h"
#include "dynapath/region.h"
#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

using test_grids::RandomGrid;

Grid FromText(const std::string& text) {
  Result<Grid> grid = GridFromText(text);
  EXPECT_TRUE(grid.ok());
  return grid.value();
}

// The top-2 successors of SPEC section 4, written independently of
// TopTwoActions: rank the in-grid actions by value, ties to the higher index,
// keep the first two, drop obstacle targets.
std::vector<int> ReferenceSuccessors(const Grid& grid, const QTable& q, int cell) {
  const int row = grid.RowOf(cell), col = grid.ColOf(cell);
  std::vector<std::pair<float, int>> ranked;  // (value, action)
  for (int a = 0; a < kNumActions; ++a) {
    if (grid.InBounds(row + kActionRowOffset[a], col + kActionColOffset[a])) {
      ranked.push_back({q.row(cell)[a], a});
    }
  }
  std::sort(ranked.begin(), ranked.end(), [](const auto& x, const auto& y) {
    return x.first != y.first ? x.first > y.first : x.second > y.second;
  });
  std::vector<int> successors;
  for (size_t k = 0; k < ranked.size() && k < 2; ++k) {
    const int a = ranked[k].second;
    const int target = grid.Index(row + kActionRowOffset[a], col + kActionColOffset[a]);
    if (grid.at(target) != Cell::kObstacle) successors.push_back(target);
  }
  return successors;
}

// One forward breadth-first search per start over the top-2 policy graph,
// stopping at the first station; success iff its depth is < rows + cols.
// `too_deep` counts starts that reach a station only at depth >= rows + cols.
std::vector<int32_t> ReferenceDepths(const Grid& grid, const QTable& q, int* too_deep) {
  const int n = grid.size();
  const int32_t limit = grid.rows() + grid.cols();
  std::vector<int32_t> depth(static_cast<size_t>(n), kNoPath);
  std::vector<int32_t> seen(static_cast<size_t>(n));
  std::vector<int> queue;
  for (int start = 0; start < n; ++start) {
    if (grid.at(start) == Cell::kObstacle) continue;
    std::fill(seen.begin(), seen.end(), -1);
    queue.assign(1, start);
    seen[start] = 0;
    int32_t found = kNoPath;
    for (size_t head = 0; head < queue.size(); ++head) {
      const int cell = queue[head];
      if (grid.at(cell) == Cell::kStation) {
        found = seen[cell];
        break;
      }
      for (int target : ReferenceSuccessors(grid, q, cell)) {
        if (seen[target] >= 0) continue;
        seen[target] = seen[cell] + 1;
        queue.push_back(target);
      }
    }
    if (found != kNoPath && found < limit) {
      depth[start] = found;
    } else if (found != kNoPath && too_deep != nullptr) {
      ++*too_deep;
    }
  }
  return depth;
}

enum class TableKind {
  kSmallIntegers,  // values in {0, 1, 2}: many exact ties
  kUniform,        // floats in [-1, 1): ties are rare
  kGuided,         // minus the target's station distance, plus {0, 1} noise:
                   // long, near-optimal policy paths that hit the depth limit
};

QTable RandomTable(const Grid& grid, TableKind kind, std::mt19937& random) {
  QTable q(grid.size());
  std::vector<int32_t> distance, queue;
  if (kind == TableKind::kGuided) NearestStationDistances(grid, distance, queue);
  for (int cell = 0; cell < grid.size(); ++cell) {
    for (int a = 0; a < kNumActions; ++a) {
      float& value = q.row(cell)[a];
      switch (kind) {
        case TableKind::kSmallIntegers:
          value = static_cast<float>(random() % 3);
          break;
        case TableKind::kUniform:
          value = static_cast<float>(random() % 2000) / 1000.0f - 1.0f;
          break;
        case TableKind::kGuided: {
          const int r = grid.RowOf(cell) + kActionRowOffset[a];
          const int c = grid.ColOf(cell) + kActionColOffset[a];
          const int32_t d = grid.InBounds(r, c) ? distance[grid.Index(r, c)] : kUnreachable;
          value =
              static_cast<float>(d == kUnreachable ? -1000 : -d) + static_cast<float>(random() % 2);
          break;
        }
      }
    }
  }
  return q;
}

TEST(PolicyEvaluationTest, EqualsPerStartForwardSearchOnRandomInstances) {
  std::mt19937 random(2024);
  PolicyEvaluator evaluator;  // reused across sizes on purpose
  PolicyDepths depths;
  const int shapes[][2] = {{1, 1}, {1, 23}, {23, 1}, {2, 11}, {9, 14}, {20, 20}, {27, 16}};
  const int densities[][2] = {{0, 10}, {150, 20}, {300, 5}, {450, 15}, {300, 0}};
  int too_deep = 0;
  int cases = 0;
  for (const auto& shape : shapes) {
    for (const auto& density : densities) {
      for (TableKind kind : {TableKind::kSmallIntegers, TableKind::kUniform, TableKind::kGuided}) {
        for (int repeat = 0; repeat < 3; ++repeat) {
          const Grid grid = RandomGrid(shape[0], shape[1], density[0], density[1], random);
          const QTable q = RandomTable(grid, kind, random);
          evaluator.Evaluate(grid, q, depths);
          ASSERT_EQ(depths.depth, ReferenceDepths(grid, q, &too_deep))
              << shape[0] << "x" << shape[1] << " density " << density[0] << "/" << density[1]
              << " kind " << static_cast<int>(kind) << " case " << cases;
          ++cases;
        }
      }
    }
  }
  // The depth limit decided some of these starts, so it was exercised.
  EXPECT_GT(too_deep, 0);
}

TEST(PolicyEvaluationTest, PolicyPointingAwayFromTheStationFails) {
  // A walled corridor; every cell prefers W (best) then NW (an obstacle, so
  // no second successor): nothing but the station itself reaches it.
  const Grid grid = FromText(
      "######\n"
      ".....C\n"
      "######\n");
  QTable q(grid.size());
  for (int cell = 0; cell < grid.size(); ++cell) {
    q.row(cell)[6] = 2.0f;  // W
    q.row(cell)[7] = 1.0f;  // NW
  }
  PolicyEvaluator evaluator;
  PolicyDepths depths;
  evaluator.Evaluate(grid, q, depths);
  EXPECT_EQ(depths.depth, ReferenceDepths(grid, q, nullptr));
  std::vector<int32_t> expected(static_cast<size_t>(grid.size()), kNoPath);
  expected[grid.Index(1, 5)] = 0;  // a station start succeeds with length 0
  EXPECT_EQ(depths.depth, expected);
  const PolicyScore score = ScoreGrid(grid, depths);
  EXPECT_EQ(score.starts, 6);
  EXPECT_EQ(score.successes, 1);
  EXPECT_EQ(score.total_length, 0);

  // Turned around (E best), the whole corridor succeeds.
  for (int cell = 0; cell < grid.size(); ++cell) q.row(cell)[2] = 3.0f;
  evaluator.Evaluate(grid, q, depths);
  for (int c = 0; c <= 5; ++c) EXPECT_EQ(depths.depth[grid.Index(1, c)], 5 - c);
}

// The action whose move goes from `from` to the 8-neighbour `to`.
int ActionBetween(const Grid& grid, int from, int to) {
  for (int a = 0; a < kNumActions; ++a) {
    if (grid.RowOf(from) + kActionRowOffset[a] == grid.RowOf(to) &&
        grid.ColOf(from) + kActionColOffset[a] == grid.ColOf(to)) {
      return a;
    }
  }
  ADD_FAILURE() << "not neighbours: " << from << " " << to;
  return 0;
}

TEST(PolicyEvaluationTest, DepthLimitOfRowsPlusColsIsEnforced) {
  // A 5x5 serpentine policy: along row 0 eastwards, row 1 westwards, ...,
  // ending at the station in the bottom-right corner, 24 moves from (0,0).
  // Each cell's best action is the next serpentine cell, its second the
  // previous one (further from the station, so no shortcut). rows + cols =
  // 10: a start 9 moves away succeeds, one 10 moves away fails.
  Grid grid(5, 5);
  grid.set(4, 4, Cell::kStation);
  std::vector<int> order;  // serpentine position -> cell
  for (int r = 0; r < 5; ++r) {
    for (int k = 0; k < 5; ++k) order.push_back(grid.Index(r, r % 2 == 0 ? k : 4 - k));
  }
  QTable q(grid.size());
  for (size_t p = 0; p + 1 < order.size(); ++p) {
    q.row(order[p])[ActionBetween(grid, order[p], order[p + 1])] = 2.0f;
    if (p > 0) q.row(order[p])[ActionBetween(grid, order[p], order[p - 1])] = 1.0f;
  }
  PolicyEvaluator evaluator;
  PolicyDepths depths;
  evaluator.Evaluate(grid, q, depths);
  int too_deep = 0;
  EXPECT_EQ(depths.depth, ReferenceDepths(grid, q, &too_deep));
  for (size_t p = 0; p < order.size(); ++p) {
    const int32_t moves = static_cast<int32_t>(order.size() - 1 - p);
    EXPECT_EQ(depths.depth[order[p]], moves < 10 ? moves : kNoPath) << "position " << p;
  }
  EXPECT_EQ(depths.depth[grid.Index(3, 4)], 9);
  EXPECT_EQ(depths.depth[grid.Index(2, 4)], kNoPath);
  EXPECT_EQ(too_deep, 15);  // every cell of rows 0..2 reaches the station, too late
}

TEST(PolicyEvaluationTest, TopTwoActionsBreaksTiesToTheHigherIndex) {
  const Grid grid(3, 3);
  const int centre = grid.Index(1, 1), corner = grid.Index(0, 0);
  struct Case {
    int cell;
    std::array<float, kNumActions> q;
    int best, second;
  };
  const Case cases[] = {
      {centre, {0, 0, 0, 0, 0, 0, 0, 0}, 7, 6},
      {centre, {5, 1, 5, 0, 0, 0, 0, 0}, 2, 0},
      {centre, {1, 3, 2, 3, 0, 0, 0, 3}, 7, 3},
      {centre, {9, 1, 1, 1, 1, 1, 1, 1}, 0, 7},
      {centre, {-1, -2, -3, -4, -5, -6, -7, -8}, 0, 1},
      // Corner (0,0): only E, SE, S are in the grid; out-of-grid values are
      // ignored however large.
      {corner, {0, 0, 0, 0, 0, 0, 0, 0}, 4, 3},
      {corner, {100, 100, 1, 2, 1, 100, 100, 100}, 3, 4},
      {corner, {100, 100, 3, 2, 1, 100, 100, 100}, 2, 3},
  };
  for (const Case& c : cases) {
    int best = -2, second = -2;
    TopTwoActions(grid, c.cell, c.q.data(), best, second);
    EXPECT_EQ(best, c.best) << "case with q[0]=" << c.q[0];
    EXPECT_EQ(second, c.second) << "case with q[0]=" << c.q[0];
  }
  // A 1x1 grid has no in-grid action; a 1x3 middle cell has E and W only.
  const std::array<float, kNumActions> zeros{};
  int best = -2, second = -2;
  TopTwoActions(Grid(1, 1), 0, zeros.data(), best, second);
  EXPECT_EQ(best, -1);
  EXPECT_EQ(second, -1);
  TopTwoActions(Grid(1, 3), 1, zeros.data(), best, second);
  EXPECT_EQ(best, 6);
  EXPECT_EQ(second, 2);
}

TEST(PolicyEvaluationTest, ScoreRegionCountsOnlyNonObstacleCells) {
  const Grid grid = FromText(
      "C.#.\n"
      "..##\n"
      "..##\n");
  // Depths set by hand: ScoreRegion only reads them.
  constexpr int32_t X = kNoPath;
  PolicyDepths depths;
  depths.depth = {0, 1, X, X,  //
                  1, 1, X, X,  //
                  2, X, X, X};
  const PolicyScore left = ScoreRegion(grid, depths, Region{0, 2, 0, 1});
  EXPECT_EQ(left.starts, 6);
  EXPECT_EQ(left.successes, 5);
  EXPECT_EQ(left.total_length, 5);
  EXPECT_DOUBLE_EQ(left.success_rate(), 5.0 / 6.0);
  EXPECT_DOUBLE_EQ(left.average_path_length(), 1.0);

  const PolicyScore right = ScoreRegion(grid, depths, Region{0, 2, 2, 3});
  EXPECT_EQ(right.starts, 1);  // (0,3) only; the obstacles are no starts
  EXPECT_EQ(right.successes, 0);
  EXPECT_DOUBLE_EQ(right.success_rate(), 0.0);

  const PolicyScore walls = ScoreRegion(grid, depths, Region{1, 2, 2, 3});
  EXPECT_EQ(walls.starts, 0);
  EXPECT_DOUBLE_EQ(walls.success_rate(), 1.0);  // nothing to fail
  EXPECT_DOUBLE_EQ(walls.average_path_length(), 0.0);

  const PolicyScore whole = ScoreGrid(grid, depths);
  EXPECT_EQ(whole.starts, 7);
  EXPECT_EQ(whole.successes, 5);
}

// A deterministic policy (one action per cell, the Python module's
// approaches): the walk from every start that follows the actions, written
// independently, succeeds iff it reaches a station in < rows + cols moves.
TEST(PolicyEvaluationTest, ActionArrayEqualsFollowingTheActionsOnRandomInstances) {
  std::mt19937 random(7);
  PolicyEvaluator evaluator;
  PolicyDepths depths;
  const int shapes[][2] = {{1, 1}, {1, 23}, {23, 1}, {9, 14}, {20, 20}, {27, 16}};
  int successes = 0, failures = 0;
  for (const auto& shape : shapes) {
    for (int repeat = 0; repeat < 20; ++repeat) {
      const Grid grid = RandomGrid(shape[0], shape[1], 200, 15, random);
      std::vector<int8_t> actions(static_cast<size_t>(grid.size()));
      for (int8_t& a : actions) a = static_cast<int8_t>(static_cast<int>(random() % 9) - 1);
      evaluator.Evaluate(grid, actions.data(), depths);
      const int32_t limit = grid.rows() + grid.cols();
      for (int start = 0; start < grid.size(); ++start) {
        int32_t want = kNoPath;
        if (grid.at(start) == Cell::kStation) want = 0;
        if (grid.at(start) == Cell::kFree) {
          int cell = start;
          for (int32_t moves = 1; moves < limit; ++moves) {
            const int a = actions[cell];
            if (a < 0) break;
            const int row = grid.RowOf(cell) + kActionRowOffset[a];
            const int col = grid.ColOf(cell) + kActionColOffset[a];
            if (!grid.InBounds(row, col) || grid.at(grid.Index(row, col)) == Cell::kObstacle) {
              break;
            }
            cell = grid.Index(row, col);
            if (grid.at(cell) == Cell::kStation) {
              want = moves;
              break;
            }
          }
          (want == kNoPath ? failures : successes) += 1;
        }
        ASSERT_EQ(depths.depth[start], want) << shape[0] << "x" << shape[1] << " cell " << start;
      }
    }
  }
  EXPECT_GT(successes, 0);
  EXPECT_GT(failures, 0);
}

}  // namespace
}  // namespace dynapath
