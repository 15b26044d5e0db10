#include "dynapath/scenario.h"

#include <gtest/gtest.h>

#include "dynapath/c_random.h"
#include "dynapath/mdp.h"

namespace dynapath {
namespace {

TEST(ScenarioTest, SameSeedSameScenario) {
  const Scenario a = GenerateScenario(50, 50, Difficulty::kHard, 52);
  const Scenario b = GenerateScenario(50, 50, Difficulty::kHard, 52);
  EXPECT_EQ(a.grid, b.grid);
  EXPECT_EQ(a.changes, b.changes);
  const Scenario c = GenerateScenario(50, 50, Difficulty::kHard, 53);
  EXPECT_NE(a.grid, c.grid);
}

TEST(ScenarioTest, ReportNumberOfStepsAndAtLeastOneRequestedMove) {
  const Scenario scenario = GenerateScenario(100, 100, Difficulty::kMedium, 51);
  ASSERT_EQ(scenario.changes.steps.size(), 200u);
  for (const ChangeStep& step : scenario.changes.steps) {
    EXPECT_GE(step.requested_moves, 1);
    EXPECT_LE(step.requested_moves, 10);
    EXPECT_EQ(step.changes.size() % 2, 0u);
    EXPECT_LE(static_cast<int>(step.changes.size()), 2 * step.requested_moves);
  }
}

// Every move takes an obstacle to a free 8-neighbour; stations never change.
TEST(ScenarioTest, MovesAreToFreeNeighboursAndKeepCounts) {
  const Scenario scenario = GenerateScenario(50, 50, Difficulty::kEasy, 50);
  Grid grid = scenario.grid;
  const int obstacles = grid.Count(Cell::kObstacle);
  const int stations = grid.Count(Cell::kStation);
  for (const ChangeStep& step : scenario.changes.steps) {
    for (size_t i = 0; i < step.changes.size(); i += 2) {
      const CellChange& from = step.changes[i];
      const CellChange& to = step.changes[i + 1];
      ASSERT_EQ(from.code, Cell::kFree);
      ASSERT_EQ(to.code, Cell::kObstacle);
      ASSERT_EQ(grid.at(from.cell), Cell::kObstacle);
      ASSERT_EQ(grid.at(to.cell), Cell::kFree);
      const int dr = grid.RowOf(to.cell) - grid.RowOf(from.cell);
      const int dc = grid.ColOf(to.cell) - grid.ColOf(from.cell);
      ASSERT_LE(std::max(std::abs(dr), std::abs(dc)), 1);
      grid.set(from.cell, Cell::kFree);
      grid.set(to.cell, Cell::kObstacle);
    }
  }
  EXPECT_EQ(grid.Count(Cell::kObstacle), obstacles);
  EXPECT_EQ(grid.Count(Cell::kStation), stations);
}

// The change stream continues the maze's stream: regenerating the changes
// from a fresh stream advanced past the maze gives the same sequence.
TEST(ScenarioTest, ChangesFollowTheMazeOnOneStream) {
  CRandom random(51);
  const Grid grid = GenerateMaze(20, 20, ProbabilitiesOf(Difficulty::kMedium), random);
  const ChangeSequence changes = GenerateChanges(grid, 40, random);
  const Scenario scenario = GenerateScenario(20, 20, Difficulty::kMedium, 51);
  EXPECT_EQ(scenario.grid, grid);
  EXPECT_EQ(scenario.changes, changes);
}

TEST(ScenarioTest, MazeWithoutDrawnStationGetsOne) {
  CRandom random(7);
  const Grid grid = GenerateMaze(3, 3, CellProbabilities{1.0, 0.0, 0.0}, random);
  EXPECT_EQ(grid.Count(Cell::kStation), 1);
  EXPECT_EQ(grid.Count(Cell::kFree), 8);
}

TEST(ScenarioTest, MoveCountDistributionIsSkewed) {
  const Scenario scenario = GenerateScenario(300, 300, Difficulty::kHard, 52, 5000);
  int single = 0;
  for (const ChangeStep& step : scenario.changes.steps) single += step.requested_moves == 1;
  // 90% of steps ask for one move (u < 900 of 1000).
  EXPECT_NEAR(single / 5000.0, 0.9, 0.02);
}

TEST(ScenarioTest, RectangularMazes) {
  const Scenario scenario = GenerateScenario(7, 31, Difficulty::kHard, 3);
  EXPECT_EQ(scenario.grid.rows(), 7);
  EXPECT_EQ(scenario.grid.cols(), 31);
  EXPECT_EQ(scenario.changes.steps.size(), 14u);
}

}  // namespace
}  // namespace dynapath
