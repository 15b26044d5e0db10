#include "dynapath/map_scenario.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "dynapath/mdp.h"

namespace dynapath {
namespace {

Grid Walled(int rows, int cols) {
  Grid grid(rows, cols);
  for (int c = 0; c < cols; c += 3) grid.set(rows / 2, c, Cell::kObstacle);  // static walls
  return grid;
}

TEST(MapScenarioTest, CellCounts) {
  EXPECT_EQ(ParseCellCount("12")->Resolve(1000), 12);
  EXPECT_EQ(ParseCellCount("0.5%")->Resolve(1000), 5);
  EXPECT_EQ(ParseCellCount("0.01%")->Resolve(1000), 1);  // at least one
  EXPECT_EQ(ParseCellCount("0%")->Resolve(1000), 0);
  for (const char* bad : {"", "-1", "x", "5%%", "101%", "1e3", "%", "nan%"}) {
    EXPECT_FALSE(ParseCellCount(bad).ok()) << bad;
  }
}

TEST(MapScenarioTest, PlacementIsSeededAndOnFreeCells) {
  Grid a = Walled(10, 17), b = Walled(10, 17);
  CRandom ra(7), rb(7);
  Result<std::vector<int>> pa = PlaceOnFreeCells(a, 9, Cell::kStation, ra);
  Result<std::vector<int>> pb = PlaceOnFreeCells(b, 9, Cell::kStation, rb);
  ASSERT_TRUE(pa.ok() && pb.ok());
  EXPECT_EQ(*pa, *pb);
  EXPECT_EQ(a, b);
  EXPECT_EQ(std::set<int>(pa->begin(), pa->end()).size(), 9u);
  EXPECT_EQ(a.Count(Cell::kStation), 9);
  for (int cell : *pa) EXPECT_NE(Walled(10, 17).at(cell), Cell::kObstacle);
  Grid c = Walled(10, 17);
  CRandom rc(7);
  EXPECT_FALSE(PlaceOnFreeCells(c, 1000, Cell::kStation, rc).ok());
}

TEST(MapScenarioTest, StationsFile) {
  const Grid grid = Walled(4, 6);  // row 2 has walls at columns 0 and 3
  Result<std::vector<int>> ok = ParseStationsFile("# stations\n0 0\r\n\n3 5\n", grid);
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_EQ(*ok, (std::vector<int>{0, 23}));
  // Any spaces and tabs around and between the numbers; indented comments.
  Result<std::vector<int>> spaced =
      ParseStationsFile("  # indented\n\t0\t 0  \n3   5\t\r\n \t\n", grid);
  ASSERT_TRUE(spaced.ok()) << spaced.error().message;
  EXPECT_EQ(*spaced, (std::vector<int>{0, 23}));
  const struct {
    const char* text;
    const char* error;
  } cases[] = {{"", "no station"},
               {"0\n", "line 1: expected 'row col'"},
               {"0 0 0\n", "line 1: expected 'row col'"},
               {"0\t\n", "line 1: expected 'row col'"},
               {"0,1\n", "line 1: expected 'row col'"},
               {"1 x\n", "line 1: expected 'row col'"},
               {"\n4 0\n", "line 2: (4, 0) is outside the 4x6 map"},
               {"2 3\n", "line 1: (2, 3) is an obstacle"},
               {"1 1\n1 1\n", "line 2: station given twice"},
               {"99999999999999 1\n", "line 1: expected 'row col'"}};
  for (const auto& c : cases) {
    Result<std::vector<int>> stations = ParseStationsFile(c.text, grid);
    ASSERT_FALSE(stations.ok()) << c.text;
    EXPECT_NE(stations.error().message.find(c.error), std::string::npos)
        << stations.error().message;
  }
}

TEST(MapScenarioTest, OnlyMoversMoveByTheReportsRule) {
  Grid grid = Walled(30, 41);
  CRandom random(3);
  ASSERT_TRUE(PlaceOnFreeCells(grid, 4, Cell::kStation, random).ok());
  Result<std::vector<int>> movers = PlaceOnFreeCells(grid, 60, Cell::kObstacle, random);
  ASSERT_TRUE(movers.ok());
  const Grid initial = grid;
  const ChangeSequence changes = GenerateMoverChanges(initial, *movers, 400, random);
  std::set<int> positions(movers->begin(), movers->end());
  int one_move_steps = 0;
  for (const ChangeStep& step : changes.steps) {
    ASSERT_GE(step.requested_moves, 1);
    ASSERT_LE(step.requested_moves, 10);
    one_move_steps += step.requested_moves == 1;
    ASSERT_EQ(step.changes.size() % 2, 0u);
    for (size_t k = 0; k < step.changes.size(); k += 2) {
      const CellChange from = step.changes[k], to = step.changes[k + 1];
      // A mover leaves a cell for a free 8-neighbour.
      ASSERT_EQ(positions.count(from.cell), 1u);
      ASSERT_EQ(from.code, Cell::kFree);
      ASSERT_EQ(to.code, Cell::kObstacle);
      ASSERT_EQ(grid.at(to.cell), Cell::kFree);
      ASSERT_LE(std::abs(grid.RowOf(from.cell) - grid.RowOf(to.cell)), 1);
      ASSERT_LE(std::abs(grid.ColOf(from.cell) - grid.ColOf(to.cell)), 1);
      positions.erase(from.cell);
      positions.insert(to.cell);
      grid.set(from.cell, Cell::kFree);
      grid.set(to.cell, Cell::kObstacle);
    }
  }
  // Walls and stations never move.
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (initial.at(cell) == Cell::kStation) {
      EXPECT_EQ(grid.at(cell), Cell::kStation);
    }
    if (initial.at(cell) == Cell::kObstacle &&
        std::find(movers->begin(), movers->end(), cell) == movers->end()) {
      EXPECT_EQ(grid.at(cell), Cell::kObstacle);
    }
  }
  // The report's skew: 90% of steps move one obstacle.
  EXPECT_GT(one_move_steps, 320);
  EXPECT_LT(one_move_steps, 390);
  // No movers: nothing is drawn, nothing moves.
  const ChangeSequence none = GenerateMoverChanges(initial, {}, 5, random);
  ASSERT_EQ(none.steps.size(), 5u);
  for (const ChangeStep& step : none.steps) EXPECT_TRUE(step.changes.empty());
}

}  // namespace
}  // namespace dynapath
