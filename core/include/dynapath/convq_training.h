#pragma once
// Training convQ's model (dynapath/convq_model.h) by reinforcement
// learning: fitted Q-iteration on TD targets of SPEC's MDP. Every round
// settles the current model's values on freshly generated mazes (the
// report's generator, every difficulty, a random point of their change
// sequences), samples transitions (s, a, r, s') of the MDP from them and
// fits the weights to the TD targets r + 0.9 max_a' Q(s', a') by least
// squares, the values of the round held fixed (semi-gradient). No path
// of any oracle is used.
//
// Deterministic: a model is a function of the options' seed, rounds and
// sizes; the threads only share out the mazes of a round, whose sums are
// added in maze order, so the result is the same for every thread count.
//
// Federated (learners > 0): K learners each fit a copy of the round's model
// on their own share of the round's mazes (maze i goes to learner i mod K),
// and the round's model is the average of their fits, taken in learner
// order, as FedAsynQ averages its learners' tables: equal (the plain mean)
// or importance (each fit weighted by the transitions it was fitted on, as
// FedAsynQ weights table entries by visits). A learner's shard is a
// function of (options, round, learner, the round's model) alone, so the
// result is the same whichever process or thread computes which learner
// (agents over LCM: coordinator/convq_trainer.h).

#include <cstdint>
#include <functional>
#include <vector>

#include "dynapath/convq_model.h"
#include "dynapath/result.h"
#include "dynapath/stop_token.h"

namespace dynapath {

enum class ConvQAveraging { kEqual, kImportance };

// Learners of a federated training at most (the wire's bound too).
inline constexpr int kMaxConvQLearners = 256;

struct ConvQTrainingOptions {
  uint64_t seed = 1;
  int threads = 1;
  int rounds = 12;
  int mazes_per_round = 8;
  int samples_per_maze = 512;
  int min_side = 16;  // maze sides are drawn from [min_side, max_side]
  int max_side = 48;
  // Federated training: the number of learners (0: not federated, the
  // round's sums are pooled into one fit) and how their fits are averaged.
  int learners = 0;
  ConvQAveraging averaging = ConvQAveraging::kEqual;
};

// Maze seeds of training are at least this (2^31); every evaluation seed
// of the repository's studies and tests is far below it.
inline constexpr uint64_t kConvQTrainingSeedBase = uint64_t{1} << 31;

// The generator seed of maze `index` of round `round`.
unsigned ConvQTrainingMazeSeed(uint64_t seed, int round, int index);

struct ConvQTrainingRound {
  int round = 0;      // 1-based
  double td_rms = 0;  // TD error of the samples under the round's model
  int samples = 0;
  ConvQModel model;  // after the round's fit
};

// The trained model, or kCancelled once `stop` is set (checked between
// mazes). `progress` (may be empty) is called after every round.
Result<ConvQModel> TrainConvQModel(const ConvQTrainingOptions& options, StopToken stop,
                                   const std::function<void(const ConvQTrainingRound&)>& progress);

// One learner's part of a federated round: its fit and what it was fitted on.
struct ConvQShard {
  int learner = 0;
  ConvQModel model;          // its least-squares fit (the round's model if samples == 0)
  int samples = 0;           // transitions sampled from its mazes
  double squared_error = 0;  // their squared TD errors under the round's model
  bool operator==(const ConvQShard&) const = default;
};

// Learner `learner` (0-based, < options.learners) of round `round`
// (1-based) from the round's model: a pure function of its arguments.
ConvQShard TrainConvQLearner(const ConvQTrainingOptions& options, const ConvQModel& model,
                             int round, int learner);

// The next round's model from all learners' shards, shards[k] being
// learner k's: equal, the mean of their weights; importance, the mean
// weighted by their samples (the round's model when none has a sample).
// Summed in learner order, then kept inside the model's bounds.
ConvQModel AverageConvQShards(const std::vector<ConvQShard>& shards, ConvQAveraging averaging,
                              const ConvQModel& round_model);

// Computes every learner's shard of a round (in learner order) from the
// round's model: in this process (LocalConvQShards) or on agents.
using ConvQShardSource =
    std::function<Result<std::vector<ConvQShard>>(int round, const ConvQModel& model)>;

// The learners' shards computed on `options.threads` threads of this
// process (learner k on thread k mod threads); kCancelled once `stop` is set.
ConvQShardSource LocalConvQShards(const ConvQTrainingOptions& options, StopToken stop);

// Federated training (options.learners > 0) with the shards of every round
// from `source`; fails with the source's error. TrainConvQModel calls it
// with LocalConvQShards when options.learners > 0.
Result<ConvQModel> TrainConvQFederated(
    const ConvQTrainingOptions& options, const ConvQShardSource& source,
    const std::function<void(const ConvQTrainingRound&)>& progress);

// The start of every training: no reward known, half discounts.
ConvQModel InitialConvQModel();

}  // namespace dynapath
