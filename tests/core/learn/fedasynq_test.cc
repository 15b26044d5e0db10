#include "core/learn/fedasynq.h"
#include "dynapath/federated_job.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "dynapath/bfs_oracle.h"
#include "dynapath/policy_evaluation.h"
#include "dynapath/scenario.h"
#include "tests/learner_test_support.h"

namespace dynapath {
namespace {

using test_maps::kMap10;
using test_maps::kMap20;
using test_maps::MapFromText;

TrainingJob WholeGridJob(const Grid& grid, Averaging averaging, uint64_t seed) {
  TrainingJob job = test_maps::WholeGridJob(grid, LearnerKind::kFedAsynQ, seed);
  job.federated.averaging = averaging;
  return job;
}

using test_maps::BytesEqual;
using test_maps::LearningCase;
using test_maps::LearningCases;
using test_maps::PolicyQuality;
using test_maps::Quality;

LearnerShard MakeShard(int learner, std::vector<uint32_t> entries, std::vector<float> values,
                       std::vector<uint32_t> visits, int start_cell, bool reached) {
  LearnerShard shard;
  shard.learner = learner;
  shard.entries = std::move(entries);
  shard.values = std::move(values);
  shard.visits = std::move(visits);
  shard.start_cell = start_cell;
  shard.reached_station = reached;
  return shard;
}

// --- Job bookkeeping ---------------------------------------------------------

TEST(FedAsynQTest, FederatedRoundsIsTOverTauAtLeastOne) {
  const FedAsynQOptions options;
  EXPECT_EQ(FederatedRounds(Region{0, 19, 0, 19}, options), 80);
  EXPECT_EQ(FederatedRounds(Region{0, 299, 0, 299}, options), 18000);
  EXPECT_EQ(FederatedRounds(Region{0, 2, 0, 2}, options), 1);  // 1800 / 1000
  EXPECT_EQ(FederatedRounds(Region{0, 1, 0, 1}, options), 1);  // 800 / 1000 -> 0 -> 1
  EXPECT_EQ(FederatedRounds(Region{0, 24, 0, 9}, options), 50);
}

TEST(FedAsynQTest, SeedsDifferPerNodeCountLearnerAndRound) {
  EXPECT_EQ(JobSeed(1, 2, 3), JobSeed(1, 2, 3));
  EXPECT_NE(JobSeed(1, 2, 3), JobSeed(1, 2, 4));
  EXPECT_NE(JobSeed(1, 2, 3), JobSeed(1, 3, 3));
  EXPECT_NE(JobSeed(1, 2, 3), JobSeed(2, 2, 3));
  EXPECT_NE(LearnerRoundSeed(9, 0, 1), LearnerRoundSeed(9, 1, 0));
  EXPECT_NE(LearnerRoundSeed(9, 0, 1), LearnerRoundSeed(9, 0, 2));
}

// --- Averaging ---------------------------------------------------------------

class FederatedAveragerTest : public ::testing::Test {
 protected:
  // Two cells (16 entries), all 1.0; three learners.
  //   learner 0: entry 3 -> 5 (1 visit), entry 7 -> 2 (2 visits)
  //   learner 1: entry 3 -> 9 (3 visits)
  //   learner 2: nothing
  void Combine(Averaging averaging) {
    shared_.values().assign(16, 1.0f);
    const std::vector<LearnerShard> shards = {MakeShard(0, {3, 7}, {5, 2}, {1, 2}, 0, true),
                                              MakeShard(1, {3}, {9}, {3}, 1, false),
                                              MakeShard(2, {}, {}, {}, 0, false)};
    FederatedAverager averager(16, averaging);
    ASSERT_TRUE(averager.Combine(shards, shared_, stats_, entries_, values_).ok());
  }

  QTable shared_{2};
  StartStatistics stats_{std::vector<int>{0, 1}};
  std::vector<uint32_t> entries_;
  std::vector<float> values_;
};

TEST_F(FederatedAveragerTest, EqualAveragingIsTheMeanWithSharedValuesForIdleLearners) {
  Combine(Averaging::kEqual);
  EXPECT_EQ(entries_, (std::vector<uint32_t>{3, 7}));
  ASSERT_EQ(values_.size(), 2u);
  EXPECT_EQ(values_[0], 5.0f);                           // (5 + 9 + 1) / 3
  EXPECT_EQ(values_[1], static_cast<float>(4.0 / 3.0));  // (2 + 1 + 1) / 3
  for (int e = 0; e < 16; ++e) {
    const float expected = e == 3 ? values_[0] : e == 7 ? values_[1] : 1.0f;
    EXPECT_EQ(shared_.values()[e], expected) << e;
  }
}

TEST_F(FederatedAveragerTest, ImportanceAveragingWeighsByPowersOfOneMinusEta) {
  Combine(Averaging::kImportance);
  EXPECT_EQ(entries_, (std::vector<uint32_t>{3, 7}));
  // weight_k proportional to 0.6^-N_k.
  const double w1 = std::pow(0.6, -1), w3 = std::pow(0.6, -3), w2 = std::pow(0.6, -2);
  const double expected3 = (5 * w1 + 9 * w3 + 1 * 1.0) / (w1 + w3 + 1.0);
  const double expected7 = (2 * w2 + 1 * 1.0 + 1 * 1.0) / (w2 + 2.0);
  EXPECT_FLOAT_EQ(values_[0], static_cast<float>(expected3));
  EXPECT_FLOAT_EQ(values_[1], static_cast<float>(expected7));
  EXPECT_EQ(shared_.values()[3], values_[0]);
  EXPECT_EQ(shared_.values()[7], values_[1]);
  EXPECT_EQ(shared_.values()[0], 1.0f);
}

// The report's double tables: shards and averages in double, the mean in
// double with no rounding to float; a float shard on a double table is
// malformed.
TEST(FederatedAveragerDoubleTest, AveragesDoubleShardsInDouble) {
  QTable shared(2, QPrecision::kDouble);
  shared.wide_values().assign(16, 0.1);
  StartStatistics stats(std::vector<int>{0, 1});
  std::vector<LearnerShard> shards(3);
  for (int k = 0; k < 3; ++k) {
    shards[k].learner = k;
    shards[k].start_cell = -1;
  }
  shards[0].entries = {5};
  shards[0].wide_values = {0.2};
  shards[0].visits = {1};
  shards[1].entries = {5};
  shards[1].wide_values = {0.7};
  shards[1].visits = {1};
  FederatedAverager averager(16, Averaging::kEqual);
  std::vector<uint32_t> entries;
  std::vector<double> values;
  ASSERT_TRUE(averager.Combine(shards, shared, stats, entries, values).ok());
  EXPECT_EQ(entries, (std::vector<uint32_t>{5}));
  const double mean = (0.2 + 0.7 + 0.1) / 3.0;
  ASSERT_EQ(values.size(), 1u);
  EXPECT_EQ(values[0], mean);
  EXPECT_NE(values[0], static_cast<double>(static_cast<float>(mean)));
  EXPECT_EQ(shared.wide_values()[5], mean);
  // A float shard on a double table, and a double table averaged as float.
  shards[0].values = {0.2f};
  shards[0].wide_values.clear();
  EXPECT_FALSE(averager.Combine(shards, shared, stats, entries, values).ok());
  std::vector<float> narrow;
  EXPECT_FALSE(averager.Combine(shards, shared, stats, entries, narrow).ok());
}

TEST_F(FederatedAveragerTest, RecordsEveryStartOutcome) {
  Combine(Averaging::kEqual);
  EXPECT_EQ(stats_.attempts(), (std::vector<uint32_t>{2, 1}));
  EXPECT_EQ(stats_.successes(), (std::vector<uint32_t>{1, 0}));
  EXPECT_EQ(stats_.total_attempts(), 3);
}

TEST(FederatedAveragerLargeVisitsTest, ImportanceWeightsStayFinite) {
  constexpr int kLearners = 12;
  std::vector<LearnerShard> shards;
  for (int k = 0; k < kLearners; ++k) shards.push_back(MakeShard(k, {}, {}, {}, -1, false));
  // One learner with 2,000 visits, the others none: 0.6^-2000 overflows a
  // double, the log-space weights do not, and that learner takes all.
  shards[5] = MakeShard(5, {4}, {42.5f}, {2000}, -1, false);
  // Two learners with 2,000 and 2,001 visits of one entry: weights 0.6 : 1.
  shards[0] = MakeShard(0, {2}, {10.0f}, {2000}, -1, false);
  shards[1] = MakeShard(1, {2}, {20.0f}, {2001}, -1, false);
  QTable shared(1);
  shared.values().assign(8, 7.0f);
  StartStatistics stats(std::vector<int>{0});
  std::vector<uint32_t> entries;
  std::vector<float> values;
  FederatedAverager averager(8, Averaging::kImportance);
  ASSERT_TRUE(averager.Combine(shards, shared, stats, entries, values).ok());
  EXPECT_EQ(entries, (std::vector<uint32_t>{2, 4}));
  for (float v : shared.values()) EXPECT_TRUE(std::isfinite(v));
  EXPECT_EQ(shared.values()[4], 42.5f);
  EXPECT_NEAR(shared.values()[2], (10.0 * 0.6 + 20.0) / 1.6, 1e-4);
  EXPECT_EQ(shared.values()[0], 7.0f);
  EXPECT_EQ(stats.total_attempts(), 0);
}

TEST(FederatedAveragerLargeVisitsTest, RejectsMalformedShards) {
  QTable shared(1);
  StartStatistics stats(std::vector<int>{0});
  std::vector<uint32_t> entries;
  std::vector<float> values;
  FederatedAverager averager(8, Averaging::kEqual);
  const std::vector<LearnerShard> out_of_range = {MakeShard(0, {8}, {1.0f}, {1}, -1, false)};
  EXPECT_FALSE(averager.Combine(out_of_range, shared, stats, entries, values).ok());
  const std::vector<LearnerShard> wrong_order = {MakeShard(1, {}, {}, {}, -1, false)};
  EXPECT_FALSE(averager.Combine(wrong_order, shared, stats, entries, values).ok());
  const std::vector<LearnerShard> bad_start = {MakeShard(0, {}, {}, {}, 3, false)};
  EXPECT_FALSE(averager.Combine(bad_start, shared, stats, entries, values).ok());
  const std::vector<LearnerShard> not_finite = {MakeShard(0, {1}, {std::nanf("")}, {1}, -1, false)};
  EXPECT_FALSE(averager.Combine(not_finite, shared, stats, entries, values).ok());
  EXPECT_EQ(shared.values(), QTable(1).values());
}

// --- One learner -------------------------------------------------------------

TEST(FedAsynQLearnerTest, TwoCellCorridorFollowsTheUpdateRuleExactly) {
  // Free cell 0, station cell 1: the only moves are E from 0 (+100) and W
  // from 1 (-1), so a round alternates between them.
  const Grid grid = MapFromText(".C\n");
  const RegionModel model(grid, Region{0, 0, 0, 1});
  FedAsynQLearner learner(model, 3);
  // Out-of-region actions hold large values that must never be bootstrapped.
  QTable start(2);
  start.values().assign(16, 500.0f);
  start.row(0)[2] = 0.0f;
  start.row(1)[6] = 0.0f;
  learner.Reset(start);
  const StartStatistics stats(model.start_cells());
  const LearnerShard shard = learner.RunRound(stats, 77, 4, 1000);
  EXPECT_EQ(shard.learner, 3);
  EXPECT_EQ(shard.round, 4);
  EXPECT_EQ(shard.steps, 1000);
  EXPECT_TRUE(shard.reached_station);
  float east = 0.0f, west = 0.0f;
  int s = shard.start_cell;
  ASSERT_TRUE(s == 0 || s == 1);
  for (int t = 0; t < 1000; ++t) {
    if (s == 0) {
      east += 0.4f * (100.0f + 0.9f * west - east);
    } else {
      west += 0.4f * (-1.0f + 0.9f * east - west);
    }
    s = 1 - s;
  }
  EXPECT_EQ(shard.entries, (std::vector<uint32_t>{0 * 8 + 2, 1 * 8 + 6}));
  EXPECT_EQ(shard.visits, (std::vector<uint32_t>{500, 500}));
  ASSERT_EQ(shard.values.size(), 2u);
  EXPECT_FLOAT_EQ(shard.values[0], east);
  EXPECT_FLOAT_EQ(shard.values[1], west);
  EXPECT_EQ(learner.table().row(0)[2], shard.values[0]);
}

// The same corridor on a double table (--semantics report): every update in
// double with the double constants 0.4 and 0.9, exactly.
TEST(FedAsynQLearnerTest, DoubleTablesFollowTheUpdateRuleInDouble) {
  const Grid grid = MapFromText(".C\n");
  const RegionModel model(grid, Region{0, 0, 0, 1});
  FedAsynQLearner learner(model, 3);
  learner.Reset(QTable(2, QPrecision::kDouble));
  const StartStatistics stats(model.start_cells());
  const LearnerShard shard = learner.RunRound(stats, 77, 4, 1000);
  double east = 0.0, west = 0.0;
  int s = shard.start_cell;
  ASSERT_TRUE(s == 0 || s == 1);
  for (int t = 0; t < 1000; ++t) {
    if (s == 0) {
      east += 0.4 * (100.0 + 0.9 * west - east);
    } else {
      west += 0.4 * (-1.0 + 0.9 * east - west);
    }
    s = 1 - s;
  }
  EXPECT_EQ(shard.entries, (std::vector<uint32_t>{0 * 8 + 2, 1 * 8 + 6}));
  EXPECT_TRUE(shard.values.empty());
  ASSERT_EQ(shard.wide_values.size(), 2u);
  EXPECT_EQ(shard.wide_values[0], east);
  EXPECT_EQ(shard.wide_values[1], west);
  EXPECT_EQ(learner.table().wide_values()[2], east);
}

TEST(FedAsynQLearnerTest, ShardListsExactlyTheChangedEntries) {
  const Grid grid = MapFromText(kMap20);
  const RegionModel model(grid, Region{0, 19, 0, 19});
  QTable start(model.cells());
  for (size_t i = 0; i < start.values().size(); ++i) {
    start.values()[i] = static_cast<float>(i % 13) - 6.0f;
  }
  FedAsynQLearner learner(model, 0);
  learner.Reset(start);
  const StartStatistics stats(model.start_cells());
  for (int round = 0; round < 3; ++round) {
    const LearnerShard shard = learner.RunRound(stats, 5, round, 1000);
    EXPECT_EQ(shard.steps, 1000);
    uint64_t visits = 0;
    for (size_t i = 0; i < shard.entries.size(); ++i) {
      if (i > 0) {
        EXPECT_LT(shard.entries[i - 1], shard.entries[i]);
      }
      EXPECT_GE(shard.visits[i], 1u);
      visits += shard.visits[i];
      EXPECT_EQ(learner.table().values()[shard.entries[i]], shard.values[i]);
    }
    EXPECT_EQ(visits, 1000u);
    // Everything else is as the round started.
    std::vector<bool> listed(start.values().size(), false);
    for (uint32_t entry : shard.entries) listed[entry] = true;
    for (size_t i = 0; i < listed.size(); ++i) {
      if (!listed[i]) {
        ASSERT_EQ(learner.table().values()[i], start.values()[i]) << i;
      }
    }
    // Back to the round's start for the next round.
    learner.ApplyAverage(shard.entries, std::vector<float>(shard.entries.size(), 0.0f));
    for (uint32_t entry : shard.entries) start.values()[entry] = 0.0f;
    ASSERT_TRUE(learner.table() == start);
  }
}

TEST(FedAsynQLearnerTest, RunRoundAndRevertPlaysAnyLearnerAndKeepsTheTable) {
  const Grid grid = GenerateScenario(20, 20, Difficulty::kHard, 52, 0).grid;
  const RegionModel model(grid, Region{0, 19, 0, 19});
  QTable start(model.cells());
  for (size_t i = 0; i < start.values().size(); ++i) {
    start.values()[i] = static_cast<float>(i % 7) * 0.5f;
  }
  StartStatistics stats(model.start_cells());
  for (int i = 0; i < 30; ++i) stats.Record(i % 50, i % 3 == 0);
  FedAsynQLearner own(model, 4), player(model, 0);
  own.Reset(start);
  player.Reset(start);
  const LearnerShard expected = own.RunRound(stats, 5, 2, 1000);
  const LearnerShard played = player.RunRoundAndRevert(4, stats, 5, 2, 1000);
  EXPECT_EQ(played.learner, 4);
  EXPECT_EQ(played.round, 2);
  EXPECT_EQ(played.entries, expected.entries);
  EXPECT_EQ(played.values, expected.values);
  EXPECT_EQ(played.visits, expected.visits);
  EXPECT_EQ(played.start_cell, expected.start_cell);
  EXPECT_EQ(played.reached_station, expected.reached_station);
  EXPECT_EQ(played.steps, expected.steps);
  EXPECT_TRUE(player.table() == start);
  EXPECT_FALSE(own.table() == start);
}

// Equal averaging's rounds skip the visit counts: the same entries, values,
// start and table afterwards (reverted or not) as a counting round, with
// every visit count 1. Both table sizes: a 20x20 region's 3,200 entries
// outnumber the 2,048 count slots (hashed counts), a 12x12's do not (direct).
TEST(FedAsynQLearnerTest, RoundsWithoutVisitCountsMatchCountingRounds) {
  const Grid grid = GenerateScenario(20, 20, Difficulty::kHard, 52, 0).grid;
  for (const Region& region : {Region{0, 19, 0, 19}, Region{4, 15, 2, 13}}) {
    const RegionModel model(grid, region);
    QTable start(model.cells());
    for (size_t i = 0; i < start.values().size(); ++i) {
      start.values()[i] = static_cast<float>(i % 5) * 0.25f - 0.5f;
    }
    StartStatistics stats(model.start_cells());
    for (int round = 0; round < 6; ++round) {
      FedAsynQLearner counting(model, 3), plain(model, 3);
      plain.set_count_visits(false);
      counting.Reset(start);
      plain.Reset(start);
      const bool revert = round % 2 == 0;
      const LearnerShard expected = revert ? counting.RunRoundAndRevert(3, stats, 9, round, 1000)
                                           : counting.RunRound(stats, 9, round, 1000);
      const LearnerShard shard = revert ? plain.RunRoundAndRevert(3, stats, 9, round, 1000)
                                        : plain.RunRound(stats, 9, round, 1000);
      ASSERT_FALSE(shard.entries.empty());
      EXPECT_EQ(shard.entries, expected.entries);
      EXPECT_EQ(shard.values, expected.values);
      EXPECT_EQ(shard.visits, std::vector<uint32_t>(shard.entries.size(), 1u));
      EXPECT_EQ(shard.start_cell, expected.start_cell);
      EXPECT_EQ(shard.reached_station, expected.reached_station);
      EXPECT_EQ(shard.steps, expected.steps);
      EXPECT_TRUE(plain.table() == counting.table());
      EXPECT_EQ(plain.table() == start, revert);
    }
  }
}

// Without visit counts, RunRoundsAndRevert walks learners two at a time on
// a twin table: every shard, and the table after each round's average, are
// those of one-at-a-time counting rounds; an odd count and a start-less
// region take the one-at-a-time path for what is left.
TEST(FedAsynQLearnerTest, PairedUncountedRoundsMatchOneAtATime) {
  const Grid grid = GenerateScenario(20, 20, Difficulty::kHard, 52, 0).grid;
  for (const int learners : {12, 5}) {
    const RegionModel model(grid, Region{2, 17, 0, 15});
    FedAsynQLearner counting(model, 0), paired(model, 0);
    paired.set_count_visits(false);
    QTable start(model.cells());
    counting.Reset(start);
    paired.Reset(start);
    StartStatistics stats(model.start_cells());
    std::vector<int> ids(static_cast<size_t>(learners));
    for (int k = 0; k < learners; ++k) ids[k] = k;
    std::vector<LearnerShard> expected(ids.size()), got(ids.size());
    for (int round = 0; round < 4; ++round) {
      counting.RunRoundsAndRevert(ids.data(), learners, stats, 21, round, 500, expected.data());
      paired.RunRoundsAndRevert(ids.data(), learners, stats, 21, round, 500, got.data());
      for (int k = 0; k < learners; ++k) {
        ASSERT_EQ(got[k].learner, k);
        ASSERT_EQ(got[k].entries, expected[k].entries) << "round " << round << " learner " << k;
        ASSERT_EQ(got[k].values, expected[k].values) << "round " << round << " learner " << k;
        ASSERT_EQ(got[k].start_cell, expected[k].start_cell);
        ASSERT_EQ(got[k].reached_station, expected[k].reached_station);
        ASSERT_EQ(got[k].steps, expected[k].steps);
      }
      ASSERT_TRUE(paired.table() == counting.table());
      // A made-up average applied to both: the twin table must follow.
      std::vector<uint32_t> entries = expected[0].entries;
      std::vector<float> values(entries.size(), static_cast<float>(round) + 0.5f);
      counting.ApplyAverage(entries, values);
      paired.ApplyAverage(entries, values);
    }
  }
}

TEST(FedAsynQLearnerTest, RegionsWithoutStartsOrMovesGiveTrivialShards) {
  const Grid walls = MapFromText("##\n##\n");
  const RegionModel empty(walls, Region{0, 1, 0, 1});
  FedAsynQLearner idle(empty, 0);
  idle.Reset(QTable(4));
  const LearnerShard none = idle.RunRound(StartStatistics(empty.start_cells()), 1, 0, 1000);
  EXPECT_EQ(none.start_cell, -1);
  EXPECT_EQ(none.steps, 0);
  EXPECT_TRUE(none.entries.empty());
  EXPECT_FALSE(none.reached_station);

  const Grid station = MapFromText("C\n");
  const RegionModel single(station, Region{0, 0, 0, 0});
  FedAsynQLearner stuck(single, 0);
  stuck.Reset(QTable(1));
  const LearnerShard on_station = stuck.RunRound(StartStatistics(single.start_cells()), 1, 0, 1000);
  EXPECT_EQ(on_station.start_cell, 0);
  EXPECT_EQ(on_station.steps, 0);
  EXPECT_TRUE(on_station.reached_station);  // started on it
}

TEST(FedAsynQLearnerTest, ReachedStationOnlyWhenOneIsVisited) {
  const Grid grid = MapFromText("......\n......\n.....C\n");
  const RegionModel no_station(grid, Region{0, 1, 0, 5});
  FedAsynQLearner learner(no_station, 0);
  learner.Reset(QTable(no_station.cells()));
  EXPECT_FALSE(
      learner.RunRound(StartStatistics(no_station.start_cells()), 1, 0, 1000).reached_station);
  const RegionModel with_station(grid, Region{0, 2, 0, 5});
  FedAsynQLearner walker(with_station, 0);
  walker.Reset(QTable(with_station.cells()));
  EXPECT_TRUE(
      walker.RunRound(StartStatistics(with_station.start_cells()), 1, 0, 1000).reached_station);
}

// --- Whole jobs --------------------------------------------------------------

TEST(FedAsynQTest, BothAveragingsLearnToReachAStationFromReachableStarts) {
  for (const Averaging averaging : {Averaging::kEqual, Averaging::kImportance}) {
    for (const LearningCase& c : LearningCases()) {
      const std::string label = c.name + (averaging == Averaging::kEqual ? " EqAvg" : " ImAvg");
      const TrainingResult result = TrainFedAsynQ(WholeGridJob(c.grid, averaging, 23));
      const PolicyQuality trained = Quality(c.grid, result.table);
      const PolicyQuality untrained = Quality(c.grid, QTable(c.grid.size()));
      // Seen: 1.0 and a length ratio <= 1.08 over 20 seeds; the zero table
      // scores 0.10-0.62.
      EXPECT_GE(trained.reachable_success, 0.97) << label;
      EXPECT_LE(trained.length_ratio, 1.2) << label;
      EXPECT_LT(untrained.reachable_success, trained.reachable_success - 0.3) << label;
      EXPECT_EQ(result.episodes_or_rounds,
                FederatedRounds(Region{0, c.grid.rows() - 1, 0, c.grid.cols() - 1}, {}))
          << label;
      EXPECT_EQ(result.steps, result.episodes_or_rounds * 12 * 1000) << label;
    }
  }
}

TEST(FedAsynQTest, SameJobGivesTheSameTable) {
  const Grid grid = MapFromText(kMap20);
  for (const Averaging averaging : {Averaging::kEqual, Averaging::kImportance}) {
    const TrainingResult first = TrainFedAsynQ(WholeGridJob(grid, averaging, 5));
    const TrainingResult second = TrainFedAsynQ(WholeGridJob(grid, averaging, 5));
    EXPECT_TRUE(BytesEqual(first.table, second.table));
    EXPECT_FALSE(BytesEqual(first.table, TrainFedAsynQ(WholeGridJob(grid, averaging, 6)).table));
  }
}

// Runs `job` as a distributed trainer would: the learners of each round in a
// different order (or on two threads), each against start statistics rebuilt
// from their counts, then the averager in learner order.
QTable RunByHand(const TrainingJob& job, bool threaded) {
  const RegionModel model(job);
  const int learner_count = job.federated.learners;
  std::vector<FedAsynQLearner> learners;
  for (int k = 0; k < learner_count; ++k) {
    learners.emplace_back(model, k);
    learners.back().Reset(job.warm_start);
  }
  QTable shared = job.warm_start;
  StartStatistics stats(model.start_cells());
  FederatedAverager averager(model.cells() * kNumActions, job.federated.averaging);
  std::vector<LearnerShard> shards(static_cast<size_t>(learner_count));
  std::vector<uint32_t> entries;
  std::vector<float> values;
  const int64_t rounds = FederatedRounds(job.region, job.federated);
  for (int64_t round = 0; round < rounds; ++round) {
    const StartStatistics received(stats.start_cells(), stats.attempts(), stats.successes());
    const auto run = [&](int k) {
      shards[k] = learners[k].RunRound(received, job.seed, round, job.federated.sync_period);
    };
    if (threaded) {
      std::thread odd([&] {
        for (int k = 1; k < learner_count; k += 2) run(k);
      });
      for (int k = 0; k < learner_count; k += 2) run(k);
      odd.join();
    } else {
      // Reverse order on even rounds, rotated by the round on odd ones.
      for (int i = 0; i < learner_count; ++i) {
        run(round % 2 == 0 ? learner_count - 1 - i : static_cast<int>((i + round) % learner_count));
      }
    }
    EXPECT_TRUE(averager.Combine(shards, shared, stats, entries, values).ok());
    for (FedAsynQLearner& learner : learners) learner.ApplyAverage(entries, values);
  }
  return shared;
}

TEST(FedAsynQTest, ExecutionOrderAndThreadsDoNotChangeTheTable) {
  const Grid grid = GenerateScenario(20, 20, Difficulty::kHard, 52, 0).grid;
  for (const Averaging averaging : {Averaging::kEqual, Averaging::kImportance}) {
    const TrainingJob job = WholeGridJob(grid, averaging, 41);
    const QTable expected = TrainFedAsynQ(job).table;
    EXPECT_TRUE(BytesEqual(RunByHand(job, false), expected));
    EXPECT_TRUE(BytesEqual(RunByHand(job, true), expected));
  }
}

TEST(FedAsynQTest, NeverWritesOutOfRegionEntries) {
  const Grid grid = MapFromText(kMap20);
  TrainingJob job = WholeGridJob(grid, Averaging::kImportance, 9);
  job.region = Region{5, 14, 3, 12};
  job.codes = RegionCodes(grid, job.region);
  job.warm_start = QTable(job.region.cells());
  job.warm_start.values().assign(job.warm_start.values().size(), 7.25f);
  const TrainingResult result = TrainFedAsynQ(job);
  const RegionModel model(job);
  int changed = 0;
  for (int cell = 0; cell < model.cells(); ++cell) {
    for (int a = 0; a < kNumActions; ++a) {
      if (model.action_mask(cell)[a] != 0.0f) {
        EXPECT_EQ(result.table.row(cell)[a], 7.25f);
      } else if (result.table.row(cell)[a] != 7.25f) {
        ++changed;
      }
    }
  }
  EXPECT_GT(changed, 100);
}

TEST(FedAsynQTest, RegionWithoutStartCellKeepsTheWarmStart) {
  const Grid grid = MapFromText("###\n###\n###\n");
  TrainingJob job = WholeGridJob(grid, Averaging::kEqual, 3);
  job.warm_start.values().assign(job.warm_start.values().size(), -2.0f);
  const TrainingResult result = TrainFedAsynQ(job);
  EXPECT_EQ(result.steps, 0);
  EXPECT_EQ(result.episodes_or_rounds, 1);
  EXPECT_TRUE(BytesEqual(result.table, job.warm_start));
}

// The marks list what was marked, ascending and without repeats, rank each
// marked entry by its position in that list, and are all clear after Clear,
// across words, summary words and repeated use.
TEST(SortedMarksTest, ListsRanksAndClears) {
  const size_t entries = 3 * 4096 + 100;  // several summary words, a partial one
  SortedMarks marks(entries);
  Rng rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<uint32_t> marked;
    const int count = 1 + static_cast<int>(rng.Below(trial % 2 == 0 ? 30 : 3000));
    for (int i = 0; i < count; ++i) {
      const uint32_t entry = rng.Below(static_cast<uint32_t>(entries));
      marked.push_back(entry);
      marks.Mark(entry);
    }
    marks.Mark(static_cast<uint32_t>(entries - 1));  // the last entry
    marked.push_back(static_cast<uint32_t>(entries - 1));
    std::sort(marked.begin(), marked.end());
    marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
    std::vector<uint32_t> listed = {12345};  // replaced, not appended to
    marks.List(listed);
    ASSERT_EQ(listed, marked);
    for (size_t i = 0; i < listed.size(); ++i) ASSERT_EQ(marks.Position(listed[i]), i);
    marks.Clear(listed);
    marks.List(listed);
    ASSERT_TRUE(listed.empty());
  }
}

}  // namespace
}  // namespace dynapath
