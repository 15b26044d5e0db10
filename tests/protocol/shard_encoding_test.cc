// Shards on the wire: conversions both ways and the Bus-level validation of
// their compact encodings.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "protocol/convert.h"
#include "protocol/validate.h"
#include "tests/protocol/validation_problem.h"

namespace dynapath::protocol {
namespace {

LearnerShard Shard() {
  LearnerShard shard;
  shard.learner = 4;
  shard.round = 9;
  shard.entries = {0, 1, 2, 3, 40, 41, 5000};
  shard.values = {0.5f, -1.25f, 3.0f, 1e-7f, 2.0f, 0.0f, -0.0f};
  shard.visits = {1, 2, 3, 1, 200, 1, 7};
  shard.start_cell = 12;
  shard.reached_station = true;
  shard.steps = 1000;
  return shard;
}

shards_t Wrap(const learner_shard_t& shard) {
  shards_t m{};
  m.run_id = "r";
  m.num_shards = 1;
  m.shards = {shard};
  return m;
}

TEST(ShardEncodingTest, RoundTripsWithVisits) {
  const LearnerShard shard = Shard();
  const learner_shard_t m = ShardToMessage(shard, 3, true);
  EXPECT_EQ(m.job, 3);
  EXPECT_EQ(ValidationProblem(Wrap(m)), "");
  const LearnerShard back = ShardFromMessage(m, 9);
  EXPECT_EQ(back.learner, shard.learner);
  EXPECT_EQ(back.round, 9);
  EXPECT_EQ(back.entries, shard.entries);
  EXPECT_EQ(back.values, shard.values);
  EXPECT_EQ(back.visits, shard.visits);
  EXPECT_EQ(back.start_cell, shard.start_cell);
  EXPECT_EQ(back.reached_station, shard.reached_station);
  EXPECT_EQ(back.steps, shard.steps);
}

TEST(ShardEncodingTest, DoubleValuesRoundTripBitForBit) {
  LearnerShard shard = Shard();
  shard.wide_values = {0.1, -1.0 / 3.0, 3.0, 1e-300, 2.0, 0.0, -0.0};
  shard.values.clear();
  const learner_shard_t m = ShardToMessage(shard, 3, true);
  EXPECT_EQ(m.num_values, 0);
  EXPECT_EQ(m.num_wide_values, 7);
  EXPECT_EQ(ValidationProblem(Wrap(m)), "");
  const LearnerShard back = ShardFromMessage(m, 9);
  EXPECT_TRUE(back.values.empty());
  ASSERT_EQ(back.wide_values.size(), 7u);
  EXPECT_EQ(0, std::memcmp(back.wide_values.data(), shard.wide_values.data(), 7 * sizeof(double)));
  // Values in both types, or too few of one, are malformed.
  learner_shard_t both = m;
  both.values = {1.0f};
  both.num_values = 1;
  EXPECT_NE(ValidationProblem(Wrap(both)), "");
  learner_shard_t short_of_one = m;
  short_of_one.wide_values.pop_back();
  short_of_one.num_wide_values = 6;
  EXPECT_NE(ValidationProblem(Wrap(short_of_one)), "");
  learner_shard_t nan = m;
  nan.wide_values[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(ValidationProblem(Wrap(nan)), "");
}

TEST(ShardEncodingTest, EqualAveragingOmitsVisits) {
  const learner_shard_t m = ShardToMessage(Shard(), 0, false);
  EXPECT_EQ(m.visit_bytes, 0);
  // 7 entries: 0,1,2,3 one byte each, 40 one, 41 one, 5000 two.
  EXPECT_EQ(m.entry_bytes, 8);
  const LearnerShard back = ShardFromMessage(m, 0);
  EXPECT_EQ(back.visits, std::vector<uint32_t>(7, 1u));
}

TEST(ShardEncodingTest, ValidateRejectsBrokenEncodings) {
  const learner_shard_t good = ShardToMessage(Shard(), 0, true);
  learner_shard_t m = good;
  m.num_entries = 6;  // values say 7
  EXPECT_NE(ValidationProblem(Wrap(m)), "");
  m = good;
  m.entry_gaps.push_back(0);  // entry_bytes no longer matches
  EXPECT_NE(ValidationProblem(Wrap(m)), "");
  m = good;
  m.entry_gaps.back() |= 0x80;  // truncated varint
  EXPECT_NE(ValidationProblem(Wrap(m)), "");
  m = good;
  m.visits.pop_back();
  m.visit_bytes = static_cast<int32_t>(m.visits.size());
  EXPECT_NE(ValidationProblem(Wrap(m)), "");
  m = good;
  m.values[2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(ValidationProblem(Wrap(m)), "");
  m = good;
  m.start_cell = -2;
  EXPECT_NE(ValidationProblem(Wrap(m)), "");
  shards_t wrapped = Wrap(good);
  wrapped.needs_round = -1;
  EXPECT_NE(ValidationProblem(wrapped), "");
}

}  // namespace
}  // namespace dynapath::protocol
