#include "protocol/round_combiner.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/learn/fedasynq.h"
#include "protocol/convert.h"
#include "tests/learner_test_support.h"

namespace dynapath::protocol {
namespace {

TrainingJob SmallJob(Averaging averaging, int learners) {
  const Grid grid = test_maps::MapFromText(test_maps::kMap10);
  TrainingJob job;
  job.node = 0;
  job.region = Region{0, grid.rows() - 1, 0, grid.cols() - 1};
  job.codes = RegionCodes(grid, job.region);
  job.warm_start = QTable(job.region.cells());
  job.seed = 17;
  job.kind = LearnerKind::kFedAsynQ;
  job.federated.averaging = averaging;
  job.federated.learners = learners;
  return job;
}

// One agent of the simulation: hosts some learners of the job and keeps its
// own combiner, as agent processes do.
struct SimAgent {
  int id;
  std::vector<std::unique_ptr<FedAsynQLearner>> learners;
  std::unique_ptr<RoundCombiner> combiner;
};

shards_t RoundMessage(SimAgent& agent, const TrainingJob& job, bool importance) {
  shards_t message{};
  message.batch_id = 0;
  message.round = agent.combiner->round();
  message.agent = agent.id;
  message.needs_round = message.round;
  for (auto& learner : agent.learners) {
    const LearnerShard shard = learner->RunRound(agent.combiner->job(0).stats, job.seed,
                                                 message.round, job.federated.sync_period);
    message.shards.push_back(ShardToMessage(shard, 0, importance));
  }
  message.num_shards = static_cast<int32_t>(message.shards.size());
  return message;
}

// Two agents (learners 0-2 and 3-5) and a coordinator, each combining every
// round from the same messages arriving in different orders, end with the
// table in-process training computes, bit for bit.
void CheckMatchesInProcess(Averaging averaging) {
  const TrainingJob job = SmallJob(averaging, 6);
  const RegionModel model(job);
  const bool importance = averaging == Averaging::kImportance;
  RoundCombiner::Items items = {{1, {{0, 0}, {0, 1}, {0, 2}}}, {2, {{0, 3}, {0, 4}, {0, 5}}}};
  RoundCombiner coordinator({RoundCombiner::Job::From(0, job)}, items, 0);
  std::vector<SimAgent> agents(2);
  for (int a = 0; a < 2; ++a) {
    agents[a].id = a + 1;
    agents[a].combiner = std::make_unique<RoundCombiner>(
        std::vector<RoundCombiner::Job>{RoundCombiner::Job::From(0, job)}, items, 0);
    for (int k = 3 * a; k < 3 * a + 3; ++k) {
      agents[a].learners.push_back(std::make_unique<FedAsynQLearner>(model, k));
      agents[a].learners.back()->Reset(StartingTable(job));
    }
  }
  int64_t rounds = 0;
  while (!coordinator.Finished()) {
    const shards_t first = RoundMessage(agents[0], job, importance);
    const shards_t second = RoundMessage(agents[1], job, importance);
    ASSERT_EQ(coordinator.Add(second), RoundCombiner::Added::kStored);
    EXPECT_EQ(coordinator.Missing(), std::vector<int>{1});
    EXPECT_FALSE(coordinator.RoundComplete());
    ASSERT_EQ(coordinator.Add(first), RoundCombiner::Added::kStored);
    ASSERT_TRUE(coordinator.RoundComplete());
    const auto expected = coordinator.Combine();
    for (int a = 0; a < 2; ++a) {
      RoundCombiner& combiner = *agents[a].combiner;
      ASSERT_EQ(combiner.Add(a == 0 ? first : second), RoundCombiner::Added::kStored);
      ASSERT_EQ(combiner.Add(a == 0 ? second : first), RoundCombiner::Added::kStored);
      const auto got = combiner.Combine();
      ASSERT_EQ(got.size(), 1u);
      EXPECT_EQ(got[0].entries, expected[0].entries);
      EXPECT_EQ(0, std::memcmp(got[0].values.data(), expected[0].values.data(),
                               got[0].values.size() * sizeof(float)));
      for (auto& learner : agents[a].learners) {
        learner->ApplyAverage(got[0].entries, got[0].values);
      }
    }
    ++rounds;
  }
  EXPECT_EQ(rounds, FederatedRounds(job.region, job.federated));
  const QTable reference = TrainFedAsynQ(job).table;
  const QTable& ours = coordinator.job(0).shared;
  ASSERT_EQ(ours.values().size(), reference.values().size());
  EXPECT_EQ(0, std::memcmp(ours.values().data(), reference.values().data(),
                           ours.values().size() * sizeof(float)));
  for (const SimAgent& agent : agents) {
    EXPECT_EQ(0, std::memcmp(agent.combiner->job(0).shared.values().data(),
                             reference.values().data(), ours.values().size() * sizeof(float)));
    EXPECT_EQ(agent.combiner->job(0).stats.attempts(), coordinator.job(0).stats.attempts());
    EXPECT_EQ(agent.combiner->job(0).stats.successes(), coordinator.job(0).stats.successes());
  }
}

TEST(RoundCombinerTest, EqualAveragingMatchesInProcessTraining) {
  CheckMatchesInProcess(Averaging::kEqual);
}

TEST(RoundCombinerTest, ImportanceAveragingMatchesInProcessTraining) {
  CheckMatchesInProcess(Averaging::kImportance);
}

// A hand-made message of `agent` for `round` with shards of `learners`.
shards_t Message(int agent, int64_t round, std::vector<int> learners) {
  shards_t message{};
  message.round = round;
  message.agent = agent;
  for (int learner : learners) {
    LearnerShard shard;
    shard.learner = learner;
    shard.entries = {1, 2};
    shard.values = {0.5f, 0.25f};
    shard.visits = {1, 1};
    message.shards.push_back(ShardToMessage(shard, 0, false));
  }
  message.num_shards = static_cast<int32_t>(message.shards.size());
  return message;
}

class RoundCombinerAddTest : public ::testing::Test {
 protected:
  RoundCombinerAddTest()
      : job_(SmallJob(Averaging::kEqual, 2)),
        model_(job_),
        combiner_({RoundCombiner::Job::From(0, job_)}, {{1, {{0, 0}}}, {2, {{0, 1}}}}, 3) {}
  TrainingJob job_;
  RegionModel model_;
  RoundCombiner combiner_;
};

TEST_F(RoundCombinerAddTest, KeepsThisRoundAndTheNextOnly) {
  EXPECT_EQ(combiner_.round(), 3);
  EXPECT_EQ(combiner_.Missing(), (std::vector<int>{1, 2}));
  EXPECT_EQ(combiner_.Add(Message(1, 2, {0})), RoundCombiner::Added::kPast);
  EXPECT_EQ(combiner_.Add(Message(1, 5, {0})), RoundCombiner::Added::kFuture);
  EXPECT_EQ(combiner_.Add(Message(1, 4, {0})), RoundCombiner::Added::kStored);  // ahead
  EXPECT_EQ(combiner_.Add(Message(1, 3, {0})), RoundCombiner::Added::kStored);
  EXPECT_EQ(combiner_.Add(Message(1, 3, {0})), RoundCombiner::Added::kDuplicate);
  EXPECT_EQ(combiner_.Missing(), std::vector<int>{2});
  EXPECT_EQ(combiner_.Add(Message(2, 3, {1})), RoundCombiner::Added::kStored);
  ASSERT_TRUE(combiner_.RoundComplete());
  const auto rounds = combiner_.Combine();
  ASSERT_EQ(rounds.size(), 1u);
  EXPECT_EQ(rounds[0].entries, (std::vector<uint32_t>{1, 2}));
  EXPECT_EQ(rounds[0].values, (std::vector<float>{0.5f, 0.25f}));
  // Round 4: agent 1's early message was kept.
  EXPECT_EQ(combiner_.round(), 4);
  EXPECT_EQ(combiner_.Missing(), std::vector<int>{2});
}

// The coordinator's combiner keeps rounds further ahead (rounds_ahead),
// within a byte cap, and combines them in turn once the lost round arrives.
TEST_F(RoundCombinerAddTest, KeepsRoundsFurtherAheadWithinTheByteCap) {
  const int64_t bytes = Message(1, 5, {0}).getEncodedSize();
  // Room for three messages past round 4 (rounds 5 and 6 here).
  RoundCombiner ahead({RoundCombiner::Job::From(0, job_)}, {{1, {{0, 0}}}, {2, {{0, 1}}}}, 3, 4,
                      3 * bytes);
  EXPECT_EQ(ahead.Add(Message(1, 8, {0})), RoundCombiner::Added::kFuture);  // beyond 3 + 4
  for (int64_t round = 4; round <= 6; ++round) {
    EXPECT_EQ(ahead.Add(Message(1, round, {0})), RoundCombiner::Added::kStored) << round;
    EXPECT_EQ(ahead.Add(Message(2, round, {1})),
              round == 6 ? RoundCombiner::Added::kFuture : RoundCombiner::Added::kStored)
        << round;  // the fourth message past round 4 is over the cap
  }
  // Round 3, lost at first, arrives: rounds 3 to 5 combine at once.
  EXPECT_EQ(ahead.Add(Message(1, 3, {0})), RoundCombiner::Added::kStored);
  EXPECT_EQ(ahead.Add(Message(2, 3, {1})), RoundCombiner::Added::kStored);
  int combined = 0;
  while (ahead.RoundComplete()) {
    ahead.Combine();
    ++combined;
  }
  EXPECT_EQ(combined, 3);
  EXPECT_EQ(ahead.round(), 6);
  EXPECT_EQ(ahead.Missing(), std::vector<int>{2});
  // Its cap freed, the round that did not fit is taken now.
  EXPECT_EQ(ahead.Add(Message(2, 6, {1})), RoundCombiner::Added::kStored);
  EXPECT_TRUE(ahead.RoundComplete());
}

TEST_F(RoundCombinerAddTest, RejectsMessagesThatDoNotFit) {
  std::string why;
  EXPECT_EQ(combiner_.Add(Message(1, 3, {1}), &why), RoundCombiner::Added::kInvalid);
  EXPECT_NE(why.find("learners"), std::string::npos);
  EXPECT_EQ(combiner_.Add(Message(1, 3, {0, 1}), &why), RoundCombiner::Added::kInvalid);
  EXPECT_EQ(combiner_.Add(Message(3, 3, {0}), &why), RoundCombiner::Added::kInvalid);

  shards_t outside = Message(1, 3, {0});
  LearnerShard shard;
  shard.entries = {static_cast<uint32_t>(job_.region.cells() * kNumActions)};
  shard.values = {1.0f};
  shard.visits = {1};
  outside.shards[0] = ShardToMessage(shard, 0, false);
  EXPECT_EQ(combiner_.Add(outside, &why), RoundCombiner::Added::kInvalid);
  EXPECT_NE(why.find("outside"), std::string::npos);

  shards_t with_visits = Message(1, 3, {0});
  shard.entries = {0};
  with_visits.shards[0] = ShardToMessage(shard, 0, true);  // equal averaging sends none
  EXPECT_EQ(combiner_.Add(with_visits, &why), RoundCombiner::Added::kInvalid);

  shards_t bad_start = Message(1, 3, {0});
  bad_start.shards[0].start_cell = 12;  // row 1, column 2 of kMap10: an obstacle
  ASSERT_LT(combiner_.job(0).stats.SlotOf(12), 0);
  EXPECT_EQ(combiner_.Add(bad_start, &why), RoundCombiner::Added::kInvalid);
  EXPECT_NE(why.find("start"), std::string::npos);
  EXPECT_EQ(combiner_.Missing(), (std::vector<int>{1, 2}));  // nothing was kept
}

TEST(RoundCombinerTest, EveryLearnerMustBeHostedOnce) {
  const TrainingJob job = SmallJob(Averaging::kEqual, 2);
  const std::vector<RoundCombiner::Job> jobs = {RoundCombiner::Job::From(0, job)};
  auto check = [&](const RoundCombiner::Items& items) {
    return RoundCombiner::CheckItems(jobs, items).ok();
  };
  EXPECT_TRUE(check({{1, {{0, 0}, {0, 1}}}}));
  EXPECT_TRUE(check({{1, {{0, 1}}}, {2, {{0, 0}}}}));
  EXPECT_FALSE(check({{1, {{0, 0}}}}));                         // learner 1 missing
  EXPECT_FALSE(check({{1, {{0, 0}, {0, 1}}}, {2, {{0, 1}}}}));  // twice
  EXPECT_FALSE(check({{1, {{0, 0}, {0, 2}}}}));                 // no learner 2
  EXPECT_FALSE(check({{1, {{1, 0}, {0, 1}}}}));                 // no job 1
}

TEST(RoundCombinerTest, JobsEndAtTheirOwnRound) {
  const TrainingJob job = SmallJob(Averaging::kEqual, 1);
  RoundCombiner::Job short_job = RoundCombiner::Job::From(0, job);
  short_job.rounds = 1;
  RoundCombiner::Job long_job = RoundCombiner::Job::From(0, job);
  long_job.index = 1;
  long_job.rounds = 2;
  RoundCombiner combiner({short_job, long_job}, {{1, {{0, 0}}}, {2, {{1, 0}}}}, 0);
  shards_t both = Message(1, 0, {0});
  ASSERT_EQ(combiner.Add(both), RoundCombiner::Added::kStored);
  shards_t other = Message(2, 0, {0});
  other.shards[0].job = 1;
  ASSERT_EQ(combiner.Add(other), RoundCombiner::Added::kStored);
  EXPECT_EQ(combiner.Combine().size(), 2u);
  // Round 1: only job 1 runs, so agent 1 owes nothing.
  EXPECT_EQ(combiner.Missing(), std::vector<int>{2});
  EXPECT_EQ(combiner.Add(Message(1, 1, {0})), RoundCombiner::Added::kInvalid);
  other.round = 1;
  ASSERT_EQ(combiner.Add(other), RoundCombiner::Added::kStored);
  EXPECT_EQ(combiner.Combine().size(), 1u);
  EXPECT_TRUE(combiner.Finished());
  EXPECT_FALSE(combiner.RoundComplete());
}

}  // namespace
}  // namespace dynapath::protocol
