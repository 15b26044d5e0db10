#include "dynapath/routes.h"

#include <gtest/gtest.h>

#include "dynapath/experiment.h"
#include "dynapath/local_trainer.h"
#include "dynapath/mdp.h"
#include "dynapath/scenario.h"
#include "dynapath/thread_pool.h"
#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

// Every move to one of the 8 neighbours, never onto an obstacle, the last
// cell a station, `length` moves.
void ExpectValidPath(const Grid& grid, const Route& route) {
  ASSERT_EQ(route.status, RouteStatus::kReached);
  ASSERT_EQ(route.cells.size(), static_cast<size_t>(route.length) + 1);
  for (size_t i = 0; i < route.cells.size(); ++i) {
    const int cell = route.cells[i];
    ASSERT_NE(grid.at(cell), Cell::kObstacle);
    if (i > 0) {
      const int prev = route.cells[i - 1];
      const int dr = grid.RowOf(cell) - grid.RowOf(prev), dc = grid.ColOf(cell) - grid.ColOf(prev);
      ASSERT_TRUE(std::abs(dr) <= 1 && std::abs(dc) <= 1 && (dr != 0 || dc != 0));
    }
  }
  EXPECT_EQ(grid.at(route.cells.back()), Cell::kStation);
}

TEST(Routes, ExactRoutesAreShortestAndValid) {
  const Grid grid = test_grids::FromText(
      "....#...\n"
      ".##.#.#.\n"
      ".#..#.#.\n"
      ".#.##.#C\n"
      "...#...#\n");
  RouteSnapshot s;
  s.grid = grid;
  s.distance = test_grids::Distances(grid);
  for (int cell = 0; cell < grid.size(); ++cell) {
    const Route route = AnswerRoute(s, grid.RowOf(cell), grid.ColOf(cell), AnswerMode::kExact, 100);
    if (grid.at(cell) == Cell::kObstacle) {
      EXPECT_EQ(route.status, RouteStatus::kStartObstacle);
    } else if (s.distance[cell] == kUnreachable) {
      EXPECT_EQ(route.status, RouteStatus::kNoRoute);
    } else {
      ExpectValidPath(grid, route);
      EXPECT_EQ(route.length, ExactDistanceFrom(grid, cell));
      EXPECT_EQ(route.answered_by, AnsweredBy::kExact);
    }
  }
  EXPECT_EQ(AnswerRoute(s, -1, 0, AnswerMode::kExact, 100).status, RouteStatus::kOutsideGrid);
  EXPECT_EQ(AnswerRoute(s, 0, 8, AnswerMode::kExact, 100).status, RouteStatus::kOutsideGrid);
  // A path longer than the budget is not cut: it is refused.
  int far = 0;
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (s.distance[cell] > s.distance[far]) far = cell;
  }
  ASSERT_GE(s.distance[far], 3);
  const size_t cells = static_cast<size_t>(s.distance[far]) + 1;
  EXPECT_EQ(AnswerRoute(s, grid.RowOf(far), grid.ColOf(far), AnswerMode::kExact, cells - 1).status,
            RouteStatus::kOverBudget);
  EXPECT_EQ(AnswerRoute(s, grid.RowOf(far), grid.ColOf(far), AnswerMode::kExact, cells).status,
            RouteStatus::kReached);
}

// A hand-made policy on one row: "C . . ." with the best actions pointing
// west, except a loop, a wall and a walk off.
TEST(Routes, LearnedFailuresSayWhy) {
  const Grid grid = test_grids::FromText("C...#.\n");
  RouteSnapshot s;
  s.grid = grid;
  constexpr int8_t kWest = 6, kEast = 2;
  s.best = {-1, kWest, kEast, kWest, -1, kWest};
  s.second = {-1, kEast, kEast, kEast, -1, kEast};
  // Depths as the evaluation computes them over the two best actions.
  s.depth = {0, 1, kNoPath, kNoPath, kNoPath, kNoPath};
  s.distance = test_grids::Distances(grid);
  Route reached = AnswerRoute(s, 0, 1, AnswerMode::kLearned, 100);
  ExpectValidPath(grid, reached);
  EXPECT_EQ(reached.length, 1);
  EXPECT_EQ(AnswerRoute(s, 0, 2, AnswerMode::kLearned, 100).status, RouteStatus::kLoops);
  EXPECT_EQ(AnswerRoute(s, 0, 5, AnswerMode::kLearned, 100).status, RouteStatus::kHitsObstacle);
  EXPECT_EQ(AnswerRoute(s, 0, 4, AnswerMode::kLearned, 100).status, RouteStatus::kStartObstacle);
  // learned-else-exact: the exact path where the policy fails, unreachable
  // behind the wall.
  const Route exact = AnswerRoute(s, 0, 2, AnswerMode::kLearnedElseExact, 100);
  ExpectValidPath(grid, exact);
  EXPECT_EQ(exact.answered_by, AnsweredBy::kExact);
  EXPECT_EQ(AnswerRoute(s, 0, 5, AnswerMode::kLearnedElseExact, 100).status, RouteStatus::kNoRoute);
}

// A trained policy: the starts the evaluation counts as successes are
// exactly those answered `reached`, with the evaluation's lengths, every
// path valid and no shorter than the optimum.
TEST(Routes, TrainedPolicyAnswersAsItsEvaluationCounts) {
  const Scenario scenario = GenerateScenario(24, 24, Difficulty::kHard, 7, 0);
  ThreadPool pool(1);
  LocalTrainer trainer(pool);
  PlannerOptions options;
  options.run_seed = 7;
  std::unique_ptr<Planner> planner = MakePlanner(Approach::kFedAsynQEqAvg, options, &trainer);
  std::unique_ptr<Planner> oracle = MakePlanner(Approach::kIncrementalOracle, options, nullptr);
  const Grid& grid = scenario.grid;
  planner->Initialize(grid);
  oracle->Initialize(grid);
  const PolicyScore score = planner->Evaluate(grid);
  const RouteSnapshot s = MakeRouteSnapshot(*planner, grid, oracle.get(), 3, 0);
  ASSERT_TRUE(s.has_learned());
  ASSERT_TRUE(s.has_exact());
  EXPECT_EQ(s.version, 3);
  int reached = 0;
  int64_t total = 0;
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (grid.at(cell) == Cell::kObstacle) continue;
    const Route learned =
        AnswerRoute(s, grid.RowOf(cell), grid.ColOf(cell), AnswerMode::kLearned, size_t{1} << 20);
    if (learned.status == RouteStatus::kReached) {
      ExpectValidPath(grid, learned);
      EXPECT_GE(learned.length, ExactDistanceFrom(grid, cell));
      ++reached;
      total += learned.length;
    }
    const Route either = AnswerRoute(s, grid.RowOf(cell), grid.ColOf(cell),
                                     AnswerMode::kLearnedElseExact, size_t{1} << 20);
    if (ExactDistanceFrom(grid, cell) != kUnreachable) ExpectValidPath(grid, either);
  }
  EXPECT_EQ(reached, score.successes);
  EXPECT_EQ(total, score.total_length);
  // The snapshot alone gives back the planner's picture.
  PolicyPicture from_planner, from_snapshot;
  ASSERT_TRUE(planner->Picture(grid, from_planner));
  ASSERT_TRUE(PictureOf(s, from_snapshot));
  EXPECT_EQ(from_snapshot.actions, from_planner.actions);
  EXPECT_EQ(from_snapshot.second, from_planner.second);
  EXPECT_EQ(from_snapshot.depth, from_planner.depth);
  EXPECT_EQ(from_snapshot.reaches, from_planner.reaches);
  EXPECT_FALSE(PictureOf(MakeRouteSnapshot(*oracle, grid, nullptr, 1, 0), from_snapshot));
}

TEST(Routes, NamesMatchTheWire) {
  EXPECT_STREQ(RouteStatusName(RouteStatus::kReached), "reached");
  EXPECT_STREQ(RouteStatusName(RouteStatus::kOverBudget), "over_budget");
  EXPECT_STREQ(AnsweredByName(AnsweredBy::kExact), "exact");
}

}  // namespace
}  // namespace dynapath
