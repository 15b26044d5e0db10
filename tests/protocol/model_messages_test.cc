// The messages of a federated training of convQ's model: conversions are
// exact, and validation refuses counts that do not match, sizes beyond the
// training command's bounds, repeated learners and weights that are not
// finite or out of the model's bounds.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "protocol/convert.h"
#include "protocol/validate.h"
#include "tests/protocol/validation_problem.h"

namespace dynapath::protocol {
namespace {

ConvQTrainingOptions Training() {
  ConvQTrainingOptions training;
  training.seed = 9;
  training.rounds = 4;
  training.mazes_per_round = 3;
  training.samples_per_maze = 16;
  training.min_side = 8;
  training.max_side = 10;
  training.learners = 3;
  return training;
}

model_round_t Round() {
  model_round_t round = ModelRoundToMessage(Training(), 2, ConvQModel{99, -1, -10, 0.875, 0.5});
  round.run_id = "r1";
  round.num_items = 3;
  round.item_learner = {2, 0, 1};
  round.item_agent = {1, 1, 5};
  return round;
}

model_shards_t Shards() {
  const ConvQTrainingOptions training = Training();
  model_shards_t shards =
      ConvQShardsToMessage({TrainConvQLearner(training, InitialConvQModel(), 1, 0),
                            TrainConvQLearner(training, InitialConvQModel(), 1, 2)});
  shards.run_id = "r1";
  shards.round = 1;
  shards.agent = 5;
  return shards;
}

TEST(ModelMessages, ConversionsAreExact) {
  const model_round_t round = Round();
  EXPECT_EQ(ValidationProblem(round), "");
  const ConvQTrainingOptions back = ConvQOptionsFromRound(round);
  EXPECT_EQ(back.seed, 9u);
  EXPECT_EQ(back.rounds, 4);
  EXPECT_EQ(back.mazes_per_round, 3);
  EXPECT_EQ(back.samples_per_maze, 16);
  EXPECT_EQ(back.min_side, 8);
  EXPECT_EQ(back.max_side, 10);
  EXPECT_EQ(back.learners, 3);
  EXPECT_EQ(ConvQModelFromRound(round), (ConvQModel{99, -1, -10, 0.875, 0.5}));
  const ConvQTrainingOptions training = Training();
  const std::vector<ConvQShard> sent = {TrainConvQLearner(training, InitialConvQModel(), 1, 0),
                                        TrainConvQLearner(training, InitialConvQModel(), 1, 2)};
  const model_shards_t shards = Shards();
  EXPECT_EQ(ValidationProblem(shards), "");
  EXPECT_EQ(ConvQShardsFromMessage(shards), sent);
}

TEST(ModelMessages, BadRoundsAreRefused) {
  const auto refused = [](auto change) {
    model_round_t round = Round();
    change(round);
    return !ValidationProblem(round).empty();
  };
  EXPECT_TRUE(refused([](model_round_t& m) { m.round = 0; }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.round = m.rounds + 1; }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.mazes = 4097; }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.samples = 0; }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.max_side = kMaxModelMazeSide + 1; }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.min_side = m.max_side + 1; }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.learners = kMaxModelLearners + 1; }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.num_weights = 4; }));
  EXPECT_TRUE(refused([](model_round_t& m) {
    m.weights.pop_back();
    m.num_weights = 4;
  }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.weights[0] = std::nan(""); }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.weights[1] = 1e7; }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.weights[3] = 1.0; }));  // would not settle
  EXPECT_TRUE(refused([](model_round_t& m) { m.num_items = 2; }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.item_learner[1] = 2; }));  // repeated
  EXPECT_TRUE(refused([](model_round_t& m) { m.item_learner[1] = 3; }));
  EXPECT_TRUE(refused([](model_round_t& m) { m.item_agent[0] = -1; }));
}

TEST(ModelMessages, BadShardsAreRefused) {
  const auto refused = [](auto change) {
    model_shards_t shards = Shards();
    change(shards);
    return !ValidationProblem(shards).empty();
  };
  EXPECT_TRUE(refused([](model_shards_t& m) { m.round = 0; }));
  EXPECT_TRUE(refused([](model_shards_t& m) { m.num_shards = 3; }));
  EXPECT_TRUE(refused([](model_shards_t& m) {
    m.num_shards = 0;
    m.learner.clear();
    m.samples.clear();
    m.squared_error.clear();
    m.weights.clear();
    m.num_weights = 0;
  }));
  EXPECT_TRUE(refused([](model_shards_t& m) { m.num_weights = 5; }));
  EXPECT_TRUE(refused([](model_shards_t& m) { m.learner[0] = kMaxModelLearners; }));
  EXPECT_TRUE(refused([](model_shards_t& m) { m.samples[1] = -1; }));
  EXPECT_TRUE(refused([](model_shards_t& m) { m.squared_error[0] = -1; }));
  EXPECT_TRUE(refused(
      [](model_shards_t& m) { m.squared_error[0] = std::numeric_limits<double>::infinity(); }));
  EXPECT_TRUE(refused([](model_shards_t& m) { m.weights[7] = std::nan(""); }));
  EXPECT_TRUE(refused([](model_shards_t& m) { m.weights[9] = -0.5; }));  // a negative discount
}

}  // namespace
}  // namespace dynapath::protocol
