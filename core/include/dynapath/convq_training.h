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

#include <cstdint>
#include <functional>

#include "dynapath/convq_model.h"
#include "dynapath/result.h"
#include "dynapath/stop_token.h"

namespace dynapath {

struct ConvQTrainingOptions {
  uint64_t seed = 1;
  int threads = 1;
  int rounds = 12;
  int mazes_per_round = 8;
  int samples_per_maze = 512;
  int min_side = 16;  // maze sides are drawn from [min_side, max_side]
  int max_side = 48;
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

}  // namespace dynapath
