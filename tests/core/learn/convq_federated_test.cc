// Federated training of convQ's model: the averaging by hand, and a
// K-learner training independent of how its learners are grouped (threads
// here; agent processes in tests/convq_federated_test.sh).

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <vector>

#include "dynapath/convq_training.h"

namespace dynapath {
namespace {

ConvQTrainingOptions Small(int learners) {
  ConvQTrainingOptions options;
  options.seed = 5;
  options.rounds = 3;
  options.mazes_per_round = 5;
  options.samples_per_maze = 64;
  options.min_side = 8;
  options.max_side = 14;
  options.learners = learners;
  return options;
}

ConvQShard Shard(int learner, ConvQModel model, int samples) {
  ConvQShard shard;
  shard.learner = learner;
  shard.model = model;
  shard.samples = samples;
  return shard;
}

TEST(ConvQFederatedTest, EqualAveragingIsTheMeanOfTheLearnersWeights) {
  const std::vector<ConvQShard> shards = {Shard(0, {90, -1, -12, 0.8, 0.6}, 100),
                                          Shard(1, {96, -3, -6, 0.9, 0.9}, 300)};
  const ConvQModel mean = AverageConvQShards(shards, ConvQAveraging::kEqual, InitialConvQModel());
  EXPECT_EQ(mean, (ConvQModel{93, -2, -9, (0.8 + 0.9) / 2, (0.6 + 0.9) / 2}));
}

TEST(ConvQFederatedTest, ImportanceAveragingWeightsEachFitByItsSamples) {
  const std::vector<ConvQShard> shards = {Shard(0, {90, -1, -12, 0.8, 0.6}, 100),
                                          Shard(1, {94, -3, -4, 0.4, 0.2}, 300)};
  const ConvQModel weighted =
      AverageConvQShards(shards, ConvQAveraging::kImportance, InitialConvQModel());
  EXPECT_DOUBLE_EQ(weighted.station_reward, (100 * 90.0 + 300 * 94.0) / 400);
  EXPECT_DOUBLE_EQ(weighted.free_reward, (100 * -1.0 + 300 * -3.0) / 400);
  EXPECT_DOUBLE_EQ(weighted.blocked_reward, (100 * -12.0 + 300 * -4.0) / 400);
  EXPECT_DOUBLE_EQ(weighted.move_discount, (100 * 0.8 + 300 * 0.4) / 400);
  EXPECT_DOUBLE_EQ(weighted.bump_discount, (100 * 0.6 + 300 * 0.2) / 400);
  // No learner with a sample: the round's model stays.
  const ConvQModel round_model{1, 2, 3, 0.25, 0.5};
  EXPECT_EQ(AverageConvQShards({Shard(0, {90, -1, -12, 0.8, 0.6}, 0)}, ConvQAveraging::kImportance,
                               round_model),
            round_model);
}

TEST(ConvQFederatedTest, ALearnersShardIsAFunctionOfItsInputsAlone) {
  const ConvQTrainingOptions options = Small(3);
  const ConvQModel model{80, -2, -8, 0.7, 0.6};
  const ConvQShard first = TrainConvQLearner(options, model, 2, 1);
  // Another learner computed in between changes nothing.
  (void)TrainConvQLearner(options, model, 2, 0);
  EXPECT_EQ(TrainConvQLearner(options, model, 2, 1), first);
  EXPECT_EQ(first.learner, 1);
  // Mazes 1 and 4 of the five are learner 1's.
  EXPECT_EQ(first.samples, 2 * options.samples_per_maze);
  EXPECT_EQ(TrainConvQLearner(options, model, 2, 2).samples, options.samples_per_maze);
  EXPECT_NE(TrainConvQLearner(options, model, 3, 1), first);
}

TEST(ConvQFederatedTest, TheModelIsTheSameHoweverLearnersAreGrouped) {
  ConvQTrainingOptions options = Small(4);
  options.threads = 1;
  Result<ConvQModel> one = TrainConvQModel(options, nullptr, {});
  ASSERT_TRUE(one.ok());
  for (int threads : {2, 3, 4}) {
    options.threads = threads;
    Result<ConvQModel> more = TrainConvQModel(options, nullptr, {});
    ASSERT_TRUE(more.ok());
    EXPECT_EQ(*more, *one) << threads << " threads";
  }
  // Learners grouped as agents would host them ({3, 0}, {2}, {1}), each
  // group computed apart, the shards put back in learner order.
  const ConvQShardSource grouped = [&](int round, const ConvQModel& model) {
    std::vector<ConvQShard> shards(4);
    for (const std::vector<int>& group : {std::vector<int>{3, 0}, {2}, {1}}) {
      for (int k : group)
        shards[static_cast<size_t>(k)] = TrainConvQLearner(options, model, round, k);
    }
    return Result<std::vector<ConvQShard>>(shards);
  };
  std::vector<ConvQTrainingRound> rounds;
  Result<ConvQModel> by_groups = TrainConvQFederated(
      options, grouped, [&](const ConvQTrainingRound& round) { rounds.push_back(round); });
  ASSERT_TRUE(by_groups.ok());
  EXPECT_EQ(*by_groups, *one);
  ASSERT_EQ(rounds.size(), 3u);
  EXPECT_EQ(rounds[0].samples, options.mazes_per_round * options.samples_per_maze);
  EXPECT_GT(rounds[0].td_rms, rounds[2].td_rms);
}

TEST(ConvQFederatedTest, EqualAndImportanceDifferAndBothDifferFromThePooledFit) {
  ConvQTrainingOptions options = Small(3);  // 5 mazes: learners of 2, 2 and 1
  Result<ConvQModel> equal = TrainConvQModel(options, nullptr, {});
  options.averaging = ConvQAveraging::kImportance;
  Result<ConvQModel> importance = TrainConvQModel(options, nullptr, {});
  options.learners = 0;
  Result<ConvQModel> pooled = TrainConvQModel(options, nullptr, {});
  ASSERT_TRUE(equal.ok() && importance.ok() && pooled.ok());
  EXPECT_NE(*equal, *importance);
  EXPECT_NE(*equal, *pooled);
  EXPECT_TRUE(CheckConvQModel(*equal).ok());
  EXPECT_TRUE(CheckConvQModel(*importance).ok());
}

TEST(ConvQFederatedTest, ASourcesErrorEndsTheTraining) {
  const ConvQShardSource failing = [](int round, const ConvQModel&) {
    if (round == 2) return Result<std::vector<ConvQShard>>(Error::Unavailable("no agent left"));
    return Result<std::vector<ConvQShard>>(std::vector<ConvQShard>{Shard(0, {}, 0)});
  };
  Result<ConvQModel> model = TrainConvQFederated(Small(1), failing, {});
  ASSERT_FALSE(model.ok());
  EXPECT_EQ(model.error().message, "no agent left");
  // Shards out of learner order are refused, not averaged.
  const ConvQShardSource shuffled = [](int, const ConvQModel&) {
    return Result<std::vector<ConvQShard>>(
        std::vector<ConvQShard>{Shard(1, {}, 0), Shard(0, {}, 0)});
  };
  EXPECT_FALSE(TrainConvQFederated(Small(2), shuffled, {}).ok());
  std::atomic<bool> stop{true};
  Result<ConvQModel> stopped = TrainConvQModel(Small(2), &stop, {});
  ASSERT_FALSE(stopped.ok());
  EXPECT_TRUE(stopped.error().IsCancelled());
}

}  // namespace
}  // namespace dynapath
