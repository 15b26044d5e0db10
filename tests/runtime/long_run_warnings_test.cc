// A run whose approaches would take more than an hour says so before it
// starts (runtime::LongRunWarnings): A* Oracle on a large map, with the
// estimate and the approaches that compute the same optimum quickly.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dynapath/grid.h"
#include "runtime/run_driver.h"

namespace dynapath::runtime {
namespace {

RunPlan PlanOf(std::vector<Approach> approaches) {
  RunPlan plan;
  plan.approaches = std::move(approaches);
  return plan;
}

TEST(LongRunWarningsTest, AStarOracleOnTheLargestMapIsEstimatedInHours) {
  Grid grid(4096, 4096);
  grid.set(0, Cell::kStation);
  const std::vector<std::string> warnings =
      LongRunWarnings(PlanOf({Approach::kBfsOracle, Approach::kAStarOracle}), grid, 10);
  ASSERT_EQ(warnings.size(), 1u);
  // 17.4 s x 256^2 / 256 ... = 17.4 x 256 s per step (4454 s), 11 steps.
  EXPECT_NE(warnings[0].find("about 14 hours on this 4096x4096 map"), std::string::npos)
      << warnings[0];
  EXPECT_NE(warnings[0].find("BFS Oracle and Incremental Oracle"), std::string::npos);
}

TEST(LongRunWarningsTest, NoWarningForSmallMapsOrFastApproaches) {
  Grid large(4096, 4096);
  large.set(0, Cell::kStation);
  EXPECT_TRUE(
      LongRunWarnings(PlanOf({Approach::kBfsOracle, Approach::kIncrementalOracle}), large, 100)
          .empty());
  Grid report(300, 300);
  report.set(0, Cell::kStation);
  EXPECT_TRUE(LongRunWarnings(PlanOf({Approach::kAStarOracle}), report, 100).empty());
}

// run's step lines say how long the approach in hand has left, at the pace
// of its steps after the initial training, and how many approaches follow.
TEST(StepTimeLeftTest, ThePaceOfTheStepsSoFar) {
  EXPECT_EQ(StepTimeLeft(50, 200, 2.5, 0), ", ~7.5 s left in this approach");
  EXPECT_EQ(StepTimeLeft(10, 100, 20, 1), ", ~3:00 left in this approach (1 approach after it)");
  EXPECT_EQ(StepTimeLeft(1, 3, 0.5, 3), ", ~1.0 s left in this approach (3 approaches after it)");
  EXPECT_EQ(StepTimeLeft(100, 100, 9, 2), "") << "the last step: nothing left";
}

}  // namespace
}  // namespace dynapath::runtime
