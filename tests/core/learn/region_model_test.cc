#include "core/learn/region_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "dynapath/scenario.h"

namespace dynapath {
namespace {

// Actions: 0 N, 1 NE, 2 E, 3 SE, 4 S, 5 SW, 6 W, 7 NW.
Grid SmallGrid() {
  Result<Grid> grid = GridFromText(
      "..#.\n"
      ".C..\n"
      "#...\n"
      "...C\n");
  EXPECT_TRUE(grid.ok());
  return *grid;
}

std::vector<int> ActionsOf(const RegionModel& model, int cell) {
  return std::vector<int>(model.actions(cell), model.actions(cell) + model.action_count(cell));
}

TEST(RegionModelTest, CornerCellHasThreeActions) {
  const Grid grid = SmallGrid();
  const RegionModel model(grid, Region{0, 3, 0, 3});
  EXPECT_EQ(ActionsOf(model, 0), (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(model.target(0, 2), 1);
  EXPECT_EQ(model.reward(0, 2), kStepReward);
  EXPECT_EQ(model.target(0, 3), 5);  // SE onto the station at (1,1)
  EXPECT_EQ(model.reward(0, 3), kStationReward);
  EXPECT_EQ(model.target(0, 4), 4);
  EXPECT_EQ(model.reward(0, 4), kStepReward);
  // Bottom-right corner is a station: N, W, NW.
  EXPECT_EQ(ActionsOf(model, 15), (std::vector<int>{0, 6, 7}));
}

TEST(RegionModelTest, EdgeCellNextToObstacleAndStation) {
  const Grid grid = SmallGrid();
  const RegionModel model(grid, Region{0, 3, 0, 3});
  // (0,1): top edge, obstacle to the east, station to the south.
  EXPECT_EQ(ActionsOf(model, 1), (std::vector<int>{2, 3, 4, 5, 6}));
  EXPECT_EQ(model.target(1, 2), 1);  // bumps into (0,2), stays
  EXPECT_EQ(model.reward(1, 2), kBumpReward);
  EXPECT_EQ(model.target(1, 4), 5);
  EXPECT_EQ(model.reward(1, 4), kStationReward);
  EXPECT_EQ(model.target(1, 3), 6);
  EXPECT_EQ(model.reward(1, 3), kStepReward);
  // (1,0): left edge, obstacle to the south.
  EXPECT_EQ(ActionsOf(model, 4), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(model.target(4, 4), 4);
  EXPECT_EQ(model.reward(4, 4), kBumpReward);
}

TEST(RegionModelTest, BumpOnAStationPaysTheStationReward) {
  // SPEC 2: +100 when the cell the agent ends on is a station, even if it
  // stayed.
  const Grid grid = SmallGrid();
  const RegionModel model(grid, Region{0, 3, 0, 3});
  EXPECT_EQ(model.target(5, 1), 5);  // (1,1) NE -> (0,2) obstacle
  EXPECT_EQ(model.reward(5, 1), kStationReward);
}

TEST(RegionModelTest, InteriorCellHasAllActionsAndStartCellsSkipObstacles) {
  const Grid grid = SmallGrid();
  const RegionModel model(grid, Region{0, 3, 0, 3});
  EXPECT_EQ(model.action_count(10), 8);
  EXPECT_EQ(model.start_cells(),
            (std::vector<int>{0, 1, 3, 4, 5, 6, 7, 9, 10, 11, 12, 13, 14, 15}));
  EXPECT_TRUE(model.is_station(5));
  EXPECT_TRUE(model.is_station(15));
  EXPECT_FALSE(model.is_station(0));
}

TEST(RegionModelTest, RegionCutFromLargerGridRestrictsActions) {
  const Grid grid = SmallGrid();
  const Region region{1, 2, 1, 3};  // rows 1..2, cols 1..3: 2 x 3
  EXPECT_EQ(RegionCodes(grid, region), (std::vector<uint8_t>{2, 1, 1, 1, 1, 1}));
  const RegionModel model(grid, region);
  EXPECT_EQ(model.cells(), 6);
  // Local (0,0) = grid (1,1): only E, SE, S stay inside the region.
  EXPECT_EQ(ActionsOf(model, 0), (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(model.target(0, 2), 1);
  EXPECT_EQ(model.reward(0, 2), kStepReward);
  // Local (0,1) = grid (1,2): its W neighbour is the station.
  EXPECT_EQ(ActionsOf(model, 1), (std::vector<int>{2, 3, 4, 5, 6}));
  EXPECT_EQ(model.reward(1, 6), kStationReward);
  // Local (1,2) = grid (2,3): N, W, NW only.
  EXPECT_EQ(ActionsOf(model, 5), (std::vector<int>{0, 6, 7}));
  EXPECT_EQ(model.start_cells(), (std::vector<int>{0, 1, 2, 3, 4, 5}));
}

TEST(RegionModelTest, BootstrapMaxIgnoresOutOfRegionActions) {
  const Grid grid = SmallGrid();
  const RegionModel model(grid, Region{0, 3, 0, 3});
  // Corner 0 has actions E, SE, S; the large values elsewhere must not count.
  const float row[kNumActions] = {50, 40, -3, -7, -2, 60, 70, 80};
  EXPECT_EQ(model.BootstrapMax(0, row), -2.0f);
  const float interior[kNumActions] = {1, 2, 3, 4, 9, 5, 6, 7};
  EXPECT_EQ(model.BootstrapMax(10, interior), 9.0f);
  for (int a = 0; a < kNumActions; ++a) {
    const bool inside = a >= 2 && a <= 4;
    EXPECT_EQ(model.action_mask(0)[a] == 0.0f, inside) << a;
    EXPECT_EQ(std::isinf(model.action_mask(0)[a]), !inside) << a;
  }
}

TEST(RegionModelTest, SingleCellRegionHasNoActions) {
  const Grid grid = SmallGrid();
  const RegionModel model(grid, Region{1, 1, 1, 1});
  EXPECT_EQ(model.action_count(0), 0);
  EXPECT_EQ(model.start_cells(), (std::vector<int>{0}));
}

// The walk's shortcut (count, then the index-th move) agrees with the
// action list and target() everywhere, on square and wide regions, inside
// a larger grid and as the whole grid.
TEST(RegionModelTest, StepTargetsFollowTheActionList) {
  const Grid grid = GenerateScenario(37, 37, Difficulty::kHard, 52, 0).grid;
  for (const Region& region :
       {Region{0, 36, 0, 36}, Region{3, 9, 0, 36}, Region{20, 20, 5, 5}, Region{10, 29, 17, 19}}) {
    const RegionModel model(grid, region);
    for (int cell = 0; cell < model.cells(); ++cell) {
      ASSERT_EQ(model.in_region_count(cell), model.action_count(cell)) << cell;
      for (int i = 0; i < model.action_count(cell); ++i) {
        ASSERT_EQ(model.step_target(cell, i), model.target(cell, model.actions(cell)[i]))
            << "cell " << cell << " move " << i;
      }
    }
  }
}

}  // namespace
}  // namespace dynapath
