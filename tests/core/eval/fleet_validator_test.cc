// The fleet validator catches every kind of bad joint move and accepts the
// legal ones (stays, following, rotations, diagonal moves past a robot).
#include "dynapath/fleet_validator.h"

#include <gtest/gtest.h>

#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

// 4x4, an obstacle at (3,3).
Grid Open() {
  return test_grids::FromText(
      "....\n"
      "....\n"
      "....\n"
      "...#\n");
}

int At(const Grid& grid, int row, int col) { return grid.Index(row, col); }

TEST(FleetValidator, AcceptsStaysFollowingAndRotations) {
  const Grid grid = Open();
  // Robot 0 follows robot 1 along row 0; robot 2 stays.
  JointMoveReport r = CheckJointMove(grid, {At(grid, 0, 0), At(grid, 0, 1), At(grid, 2, 2)},
                                     {At(grid, 0, 1), At(grid, 0, 2), At(grid, 2, 2)}, {});
  EXPECT_EQ(r.conflicts(), 0);
  // A rotation of four around a 2x2 square.
  r = CheckJointMove(grid, {At(grid, 0, 0), At(grid, 0, 1), At(grid, 1, 1), At(grid, 1, 0)},
                     {At(grid, 0, 1), At(grid, 1, 1), At(grid, 1, 0), At(grid, 0, 0)}, {});
  EXPECT_EQ(r.conflicts(), 0);
  // A rotation of three with a diagonal.
  r = CheckJointMove(grid, {At(grid, 0, 0), At(grid, 0, 1), At(grid, 1, 1)},
                     {At(grid, 0, 1), At(grid, 1, 1), At(grid, 0, 0)}, {});
  EXPECT_EQ(r.conflicts(), 0);
  // A diagonal move past a robot standing on a side cell.
  r = CheckJointMove(grid, {At(grid, 0, 0), At(grid, 0, 1)}, {At(grid, 1, 1), At(grid, 0, 1)}, {});
  EXPECT_EQ(r.conflicts(), 0);
}

TEST(FleetValidator, CatchesEachBadMove) {
  const Grid grid = Open();
  const int a = At(grid, 1, 1), b = At(grid, 1, 2);
  JointMoveReport r = CheckJointMove(grid, {a, b}, {b, b}, {});
  EXPECT_EQ(r.vertex, 1);
  EXPECT_EQ(r.conflicts(), 1);
  r = CheckJointMove(grid, {a, b}, {b, a}, {});
  EXPECT_EQ(r.swap, 1);
  EXPECT_EQ(r.conflicts(), 1);
  // Diagonal swap.
  r = CheckJointMove(grid, {At(grid, 0, 0), At(grid, 1, 1)}, {At(grid, 1, 1), At(grid, 0, 0)}, {});
  EXPECT_EQ(r.swap, 1);
  // Crossing diagonals, both directions of the second.
  r = CheckJointMove(grid, {At(grid, 0, 0), At(grid, 0, 1)}, {At(grid, 1, 1), At(grid, 1, 0)}, {});
  EXPECT_EQ(r.crossing, 1);
  EXPECT_EQ(r.conflicts(), 1);
  r = CheckJointMove(grid, {At(grid, 0, 0), At(grid, 1, 0)}, {At(grid, 1, 1), At(grid, 0, 1)}, {});
  EXPECT_EQ(r.crossing, 1);
  r = CheckJointMove(grid, {At(grid, 2, 2)}, {At(grid, 3, 3)}, {});
  EXPECT_EQ(r.onto_obstacle, 1);
  r = CheckJointMove(grid, {At(grid, 0, 0)}, {At(grid, 0, 2)}, {});
  EXPECT_EQ(r.not_adjacent, 1);
  // Row wrap: (0,3) -> (1,0) is one index apart but not adjacent.
  r = CheckJointMove(grid, {At(grid, 0, 3)}, {At(grid, 1, 0)}, {});
  EXPECT_EQ(r.not_adjacent, 1);
  r = CheckJointMove(grid, {At(grid, 0, 0)}, {-1}, {});
  EXPECT_EQ(r.out_of_bounds, 1);
  r = CheckJointMove(grid, {At(grid, 0, 0)}, {grid.size()}, {});
  EXPECT_EQ(r.out_of_bounds, 1);
  r = CheckJointMove(grid, {a}, {b}, {1});
  EXPECT_EQ(r.delay, 1);
  // A delayed robot that stays is fine; one on an obstacle that stays is an
  // overrun, not a conflict.
  r = CheckJointMove(grid, {a, At(grid, 3, 3)}, {a, At(grid, 3, 3)}, {1, 0});
  EXPECT_EQ(r.conflicts(), 0);
  EXPECT_EQ(r.overrun, 1);
}

}  // namespace
}  // namespace dynapath
