#include "core/plan/convq_planner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/plan/convq_values.h"
#include "core/plan/incremental_oracle.h"
#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

using test_grids::FromText;
using test_grids::RandomGrid;

// A model whose weights differ from SPEC's in every place.
ConvQModel OtherModel() { return ConvQModel{50.0, -2.0, -5.0, 0.8, 0.7}; }

void ExpectSettledLikeIteration(const ConvQModel& model, const Grid& grid) {
  ConvQValues values(model);
  values.Solve(grid);
  // The plain iteration contracts by the larger discount per sweep.
  const std::vector<double> iterated = IterateConvQ(model, grid, 3000);
  for (int cell = 0; cell < grid.size(); ++cell) {
    const double want = iterated[static_cast<size_t>(cell)];
    EXPECT_NEAR(values.Value(grid, cell), want, 1e-9 * std::max(1.0, std::fabs(want)))
        << "cell " << cell;
  }
}

TEST(ConvQValuesTest, CorridorHasTheBellmanValuesOfSpecsMdp) {
  // Station, three free cells, an obstacle, a free cell walled in; below a
  // free pocket with no station.
  const Grid grid = FromText(
      "C...#.\n"
      "######\n"
      "....##\n");
  ConvQValues values(SpecConvQModel());
  values.Solve(grid);
  // Entering the station: 100; each step further: -1 + 0.9 V.
  EXPECT_NEAR(values.Value(grid, grid.Index(0, 1)), 100.0, 1e-12);
  EXPECT_NEAR(values.Value(grid, grid.Index(0, 2)), 89.0, 1e-12);
  EXPECT_NEAR(values.Value(grid, grid.Index(0, 3)), 79.1, 1e-12);
  // Walled in: bumping forever, -10 / (1 - 0.9).
  EXPECT_NEAR(values.Value(grid, grid.Index(0, 5)), -100.0, 1e-12);
  // No station reachable but room to move: -1 / (1 - 0.9).
  EXPECT_NEAR(values.Value(grid, grid.Index(2, 0)), -10.0, 1e-12);
  double q[kNumActions];
  values.ActionValues(grid, grid.Index(0, 2), q);
  // W enters the cell worth 100; E the one worth 79.1; N is outside (bump).
  EXPECT_NEAR(q[6] + values.shift(), 89.0, 1e-12);
  EXPECT_NEAR(q[2] + values.shift(), -1.0 + 0.9 * 79.1, 1e-12);
  EXPECT_NEAR(q[0] + values.shift(), -10.0 + 0.9 * 89.0, 1e-12);
}

TEST(ConvQValuesTest, SettledValuesAreTheIterationsFixedPoint) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 6; ++trial) {
    const Grid grid = RandomGrid(9, 11, 300, 20, random);
    ExpectSettledLikeIteration(SpecConvQModel(), grid);
    ExpectSettledLikeIteration(OtherModel(), grid);
  }
}

TEST(ConvQValuesTest, RepairEqualsSolveBitForBit) {
  std::mt19937 random(11);
  for (const ConvQModel& model : {SpecConvQModel(), OtherModel()}) {
    Grid grid = RandomGrid(14, 12, 300, 15, random);
    ConvQValues repaired(model);
    repaired.Solve(grid);
    for (int step = 0; step < 150; ++step) {
      std::vector<int> changed;
      const int count = 1 + static_cast<int>(random() % 4);
      for (int k = 0; k < count; ++k) {
        const int cell = static_cast<int>(random() % grid.size());
        const int v = static_cast<int>(random() % 100);
        grid.set(cell, v < 45 ? Cell::kObstacle : v < 95 ? Cell::kFree : Cell::kStation);
        changed.push_back(cell);
      }
      repaired.Repair(grid, changed);
      ConvQValues solved(model);
      solved.Solve(grid);
      for (int cell = 0; cell < grid.size(); ++cell) {
        ASSERT_EQ(repaired.Value(grid, cell), solved.Value(grid, cell))
            << "step " << step << " cell " << cell;
      }
    }
  }
}

TEST(ConvQPlannerTest, SpecsWeightsGiveTheOraclesPaths) {
  // With SPEC's weights the settled values are the MDP's optimum, so the
  // policy's paths are the shortest ones, before and after changes.
  std::mt19937 random(3);
  Grid grid = RandomGrid(16, 16, 300, 10, random);
  ConvQPlanner planner(SpecConvQModel(), 8);
  IncrementalOraclePlanner oracle;
  planner.Initialize(grid);
  oracle.Initialize(grid);
  for (int step = 0; step < 40; ++step) {
    const PolicyScore got = planner.Evaluate(grid);
    const PolicyScore want = oracle.Evaluate(grid);
    ASSERT_EQ(got.starts, want.starts) << "step " << step;
    ASSERT_EQ(got.successes, want.successes) << "step " << step;
    ASSERT_EQ(got.total_length, want.total_length) << "step " << step;
    std::vector<int> changed;
    for (int k = 0; k < 3; ++k) {
      const int cell = static_cast<int>(random() % grid.size());
      grid.set(cell, random() % 2 == 0 ? Cell::kObstacle : Cell::kFree);
      changed.push_back(cell);
    }
    planner.Adapt(grid, changed);
    oracle.Adapt(grid, changed);
  }
  PolicyPicture picture;
  ASSERT_TRUE(planner.Picture(grid, picture));
  EXPECT_EQ(picture.actions.size(), static_cast<size_t>(grid.size()));
}

TEST(ConvQModelTest, BoundsAreChecked) {
  EXPECT_TRUE(CheckConvQModel(SpecConvQModel()).ok());
  EXPECT_TRUE(CheckConvQModel(ShippedConvQModel()).ok());
  ConvQModel model = SpecConvQModel();
  model.move_discount = 1.0;
  EXPECT_FALSE(CheckConvQModel(model).ok());
  model = SpecConvQModel();
  model.station_reward = std::nan("");
  EXPECT_FALSE(CheckConvQModel(model).ok());
  model = SpecConvQModel();
  model.bump_discount = -0.1;
  EXPECT_FALSE(CheckConvQModel(model).ok());
  EXPECT_EQ(ConvQModelFromWeights(ConvQWeights(OtherModel())), OtherModel());
}

}  // namespace
}  // namespace dynapath
