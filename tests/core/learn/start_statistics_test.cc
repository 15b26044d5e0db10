#include "dynapath/start_statistics.h"

#include <gtest/gtest.h>

#include <vector>

namespace dynapath {
namespace {

std::vector<int> DrawCounts(const StartStatistics& stats, uint64_t seed, int draws, int cells) {
  Rng rng(seed);
  std::vector<int> counts(static_cast<size_t>(cells), 0);
  for (int i = 0; i < draws; ++i) ++counts[stats.Draw(rng)];
  return counts;
}

TEST(StartStatisticsTest, EmptySetDrawsMinusOne) {
  StartStatistics stats(std::vector<int>{});
  Rng rng(1);
  EXPECT_EQ(stats.Draw(rng), -1);
  StartStatistics default_constructed;
  EXPECT_EQ(default_constructed.Draw(rng), -1);
}

TEST(StartStatisticsTest, SlotOfMapsCellsToSlots) {
  StartStatistics stats({2, 5, 9});
  EXPECT_EQ(stats.SlotOf(2), 0);
  EXPECT_EQ(stats.SlotOf(5), 1);
  EXPECT_EQ(stats.SlotOf(9), 2);
  EXPECT_EQ(stats.SlotOf(3), -1);
  EXPECT_EQ(stats.SlotOf(10), -1);
  EXPECT_EQ(stats.SlotOf(-1), -1);
}

TEST(StartStatisticsTest, FirstTenStartsAreUniform) {
  // Nine records that would make slot 0 very unlikely once weighted: the
  // warm-up must still draw uniformly.
  StartStatistics stats({10, 11, 12, 13, 14});
  for (int i = 0; i < StartStatistics::kUniformStarts - 1; ++i) stats.Record(0, true);
  constexpr int kDraws = 50000;
  const std::vector<int> counts = DrawCounts(stats, 7, kDraws, 15);
  for (int cell = 10; cell < 15; ++cell) {
    EXPECT_NEAR(counts[cell] / static_cast<double>(kDraws), 0.2, 0.01) << cell;
  }
  // The tenth attempt ends the warm-up: slot 0 now weighs 0.1 against 1.1.
  stats.Record(0, true);
  const std::vector<int> weighted = DrawCounts(stats, 7, kDraws, 15);
  EXPECT_NEAR(weighted[10] / static_cast<double>(kDraws), 0.1 / 4.5, 0.005);
  EXPECT_NEAR(weighted[11] / static_cast<double>(kDraws), 1.1 / 4.5, 0.01);
}

TEST(StartStatisticsTest, WeightedDrawsFavourLowSuccessStarts) {
  StartStatistics stats({0, 1, 2});
  for (int i = 0; i < 10; ++i) stats.Record(0, true);        // rate 1: weight 0.1
  for (int i = 0; i < 10; ++i) stats.Record(1, i % 2 == 0);  // rate 0.5: weight 0.6
  // slot 2 never tried: rate 0, weight 1.1
  constexpr int kDraws = 100000;
  const std::vector<int> counts = DrawCounts(stats, 11, kDraws, 3);
  EXPECT_NEAR(counts[0] / static_cast<double>(kDraws), 0.1 / 1.8, 0.005);
  EXPECT_NEAR(counts[1] / static_cast<double>(kDraws), 0.6 / 1.8, 0.01);
  EXPECT_NEAR(counts[2] / static_cast<double>(kDraws), 1.1 / 1.8, 0.01);
  EXPECT_EQ(stats.total_attempts(), 20);
  EXPECT_EQ(stats.attempts(), (std::vector<uint32_t>{10, 10, 0}));
  EXPECT_EQ(stats.successes(), (std::vector<uint32_t>{10, 5, 0}));
}

TEST(StartStatisticsTest, DrawsAreDeterministicAndDependOnlyOnCounts) {
  std::vector<int> cells;
  for (int i = 0; i < 1000; ++i) cells.push_back(3 * i);
  StartStatistics forward(cells), backward(cells);
  // The same outcomes recorded in opposite orders.
  for (int i = 0; i < 3000; ++i) forward.Record(i % 1000, i % 7 == 0);
  for (int i = 2999; i >= 0; --i) backward.Record(i % 1000, i % 7 == 0);
  const StartStatistics restored(cells, forward.attempts(), forward.successes());
  EXPECT_EQ(restored.total_attempts(), forward.total_attempts());
  Rng a(5), b(5), c(5);
  for (int i = 0; i < 10000; ++i) {
    const int drawn = forward.Draw(a);
    ASSERT_EQ(drawn, backward.Draw(b));
    ASSERT_EQ(drawn, restored.Draw(c));
    ASSERT_EQ(drawn % 3, 0);
  }
}

TEST(StartStatisticsTest, LargeRegionDrawAndRecordAreFast) {
  // A 300 x 300 region: 10,000 episodes of draw + record must be cheap.
  std::vector<int> cells(90000);
  for (int i = 0; i < 90000; ++i) cells[i] = i;
  StartStatistics stats(cells);
  Rng rng(3);
  for (int episode = 0; episode < 10000; ++episode) {
    const int cell = stats.Draw(rng);
    ASSERT_GE(cell, 0);
    stats.Record(stats.SlotOf(cell), cell % 2 == 0);
  }
  EXPECT_EQ(stats.total_attempts(), 10000);
}

}  // namespace
}  // namespace dynapath
