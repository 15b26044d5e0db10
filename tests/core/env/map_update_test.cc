#include "dynapath/map_update.h"

#include <gtest/gtest.h>

#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

MapUpdate Update(const std::string& source, int64_t sequence, std::vector<CellChange> changes) {
  MapUpdate update;
  update.source = source;
  update.sequence = sequence;
  update.changes = std::move(changes);
  return update;
}

TEST(UpdateQueue, MergesAcceptedUpdatesIntoOneStep) {
  UpdateQueue queue(test_grids::FromText("C...\n....\n"));
  EXPECT_FALSE(queue.Submit(Update("a", 1, {{1, Cell::kObstacle}})));
  EXPECT_FALSE(queue.Submit(Update("b", 1, {{5, Cell::kObstacle}, {1, Cell::kFree}})));
  // Reported as it already is: accepted, changes nothing.
  EXPECT_FALSE(queue.Submit(Update("a", 2, {{2, Cell::kFree}})));
  ASSERT_TRUE(queue.pending());
  const ChangeStep step = queue.Take();
  // In the order accepted, an intermediate state kept (as a run's step
  // keeps it).
  ASSERT_EQ(step.changes.size(), 3u);
  EXPECT_EQ(step.changes[0], (CellChange{1, Cell::kObstacle}));
  EXPECT_EQ(step.changes[2], (CellChange{1, Cell::kFree}));
  EXPECT_FALSE(queue.pending());
  EXPECT_TRUE(queue.Take().changes.empty());
  EXPECT_EQ(queue.latest().at(5), Cell::kObstacle);
  EXPECT_EQ(queue.counts().accepted, 3);
  EXPECT_EQ(queue.counts().cells_changed, 3);
  EXPECT_EQ(queue.counts().cells_unchanged, 1);
  EXPECT_EQ(queue.counts().steps, 1);
}

TEST(UpdateQueue, RefusesAndCountsBadUpdatesWhole) {
  UpdateQueue queue(test_grids::FromText("C...\n....\n"));
  EXPECT_FALSE(queue.Submit(Update("a", 5, {{1, Cell::kObstacle}})));
  EXPECT_EQ(queue.Submit(Update("a", 5, {{2, Cell::kObstacle}})), UpdateRefusal::kStale);
  EXPECT_EQ(queue.Submit(Update("a", 4, {{2, Cell::kObstacle}})), UpdateRefusal::kStale);
  EXPECT_EQ(queue.Submit(Update("a", 6, {{2, Cell::kObstacle}, {0, Cell::kObstacle}})),
            UpdateRefusal::kStationToObstacle);
  // The refused update's number is used up.
  EXPECT_EQ(queue.Submit(Update("a", 6, {{2, Cell::kObstacle}})), UpdateRefusal::kStale);
  EXPECT_EQ(queue.Submit(Update("b", 1, {{8, Cell::kObstacle}})), UpdateRefusal::kOutsideGrid);
  EXPECT_EQ(queue.Submit(Update("c", 1, {{3, Cell::kStation}})), UpdateRefusal::kUnknownState);
  queue.Refuse(UpdateRefusal::kGridShape);
  const UpdateCounts& counts = queue.counts();
  EXPECT_EQ(counts.received, 8);
  EXPECT_EQ(counts.accepted, 1);
  EXPECT_EQ(counts.refused_total(), 7);
  EXPECT_EQ(counts.refused[static_cast<size_t>(UpdateRefusal::kStale)], 3);
  // Nothing of a refused update was applied.
  EXPECT_EQ(queue.latest().at(2), Cell::kFree);
  EXPECT_EQ(queue.Take().changes.size(), 1u);
  EXPECT_STREQ(UpdateRefusalName(UpdateRefusal::kStationToObstacle), "station_to_obstacle");
}

TEST(UpdateQueue, ForgetsTheLeastRecentSourceBeyondItsLimit) {
  UpdateQueue queue(Grid(4, 4));
  for (size_t i = 0; i <= UpdateQueue::kMaxSources; ++i) {
    std::string source = "s";  // not "s" + ...: GCC 12's -Wrestrict misfires on it
    source += std::to_string(i);
    ASSERT_FALSE(queue.Submit(Update(source, 1, {})));
  }
  EXPECT_EQ(queue.sources(), UpdateQueue::kMaxSources);
  // s0 was forgotten: its number 1 is accepted again; s2 is remembered.
  EXPECT_FALSE(queue.Submit(Update("s0", 1, {})));
  EXPECT_EQ(queue.Submit(Update("s2", 1, {})), UpdateRefusal::kStale);
}

}  // namespace
}  // namespace dynapath
