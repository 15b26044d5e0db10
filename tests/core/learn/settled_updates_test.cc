#include "core/learn/settled_updates.h"

#include <gtest/gtest.h>

#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

// "...": cells 0, 1, 2 in a row. Entries: 0*8+2 (0 -> 1, E), 1*8+2 (1 -> 2),
// 1*8+6 (1 -> 0, W), 2*8+6 (2 -> 1).
TEST(SettledUpdatesTest, ARowChangeUnsettlesTheEntriesThatReadIt) {
  const RegionModel model(test_grids::FromText("...\n"), Region{0, 0, 0, 2});
  SettledUpdates settled(model);
  for (uint32_t entry : {2u, 10u, 14u, 22u}) {
    EXPECT_FALSE(settled.settled(entry));
    settled.MarkSettled(entry);
    EXPECT_TRUE(settled.settled(entry));
  }
  // Row 1 changed: the entries whose target is 1 (0 E and 2 W) may change.
  settled.RowChanged(1);
  EXPECT_FALSE(settled.settled(2));
  EXPECT_FALSE(settled.settled(22));
  EXPECT_TRUE(settled.settled(10));
  EXPECT_TRUE(settled.settled(14));
  settled.RowChanged(0);  // read by 1 W only
  EXPECT_FALSE(settled.settled(14));
  EXPECT_TRUE(settled.settled(10));
}

TEST(SettledUpdatesTest, BlockedMovesReadTheirOwnRow) {
  // "#..": from cell 1, W hits the obstacle and stays on 1.
  const RegionModel model(test_grids::FromText("#..\n"), Region{0, 0, 0, 2});
  SettledUpdates settled(model);
  settled.MarkSettled(1 * kNumActions + 6);
  settled.RowChanged(1);
  EXPECT_FALSE(settled.settled(1 * kNumActions + 6));
}

TEST(SettledUpdatesTest, BufferIsSettledWhenEveryEntryInItIs) {
  const RegionModel model(test_grids::FromText("...\n"), Region{0, 0, 0, 2});
  SettledUpdates settled(model);
  EXPECT_TRUE(settled.BufferSettled());  // empty
  settled.Added(2);
  settled.Added(2);
  settled.Added(10);
  EXPECT_FALSE(settled.BufferSettled());
  settled.MarkSettled(2);
  EXPECT_FALSE(settled.BufferSettled());  // 10 is not
  settled.MarkSettled(10);
  EXPECT_TRUE(settled.BufferSettled());
  settled.MarkSettled(22);  // not in the buffer: no effect on the count
  settled.RowChanged(2);    // unsettles 1 E (10, in the buffer)
  EXPECT_FALSE(settled.BufferSettled());
  settled.Removed(10);
  EXPECT_TRUE(settled.BufferSettled());
  settled.RowChanged(1);  // unsettles 0 E (2, twice in the buffer) and 2 W
  EXPECT_FALSE(settled.BufferSettled());
  settled.Removed(2);
  EXPECT_FALSE(settled.BufferSettled());  // one copy left
  settled.Removed(2);
  EXPECT_TRUE(settled.BufferSettled());
}

}  // namespace
}  // namespace dynapath
