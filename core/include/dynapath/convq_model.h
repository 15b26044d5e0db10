#pragma once
// convQ's model: the weights of a recurrent convolution over the grid whose
// settled values are the approach's action values (a value-iteration
// network). Per iteration, for every free cell s and action a with target
// t = s + offset(a):
//
//   Q_a(s) = R(kind of t) + move_discount * V(t)     t free
//          = R(station)                              t a station (terminal, V = 0)
//          = R(blocked) + bump_discount * V(s)       t an obstacle or outside
//   V(s)   = max_a Q_a(s)
//
// R is a 1x1 convolution of the target's obstacle/free/station channels,
// the discounts scale the 3x3 shift kernel of each action. The eight
// actions share the weights (the MDP is the same in every direction), so a
// model is five numbers; they are learned by fitted Q-iteration on TD
// targets of SPEC's MDP (core/learn/convq_training.cc), not given.

#include <array>
#include <string>

#include "dynapath/result.h"

namespace dynapath {

// The weights in file order (docs/reference/MODEL_FORMAT.md).
#define DYNAPATH_CONVQ_WEIGHTS(X) \
  X(station_reward)               \
  X(free_reward)                  \
  X(blocked_reward)               \
  X(move_discount)                \
  X(bump_discount)

struct ConvQModel {
#define DYNAPATH_CONVQ_MEMBER(name) double name = 0.0;
  DYNAPATH_CONVQ_WEIGHTS(DYNAPATH_CONVQ_MEMBER)
#undef DYNAPATH_CONVQ_MEMBER
  bool operator==(const ConvQModel&) const = default;
};

inline constexpr size_t kConvQWeightCount = 5;
// Bounds a model must keep: rewards within +-kMaxConvQReward, discounts in
// [0, kMaxConvQDiscount] (the iteration then contracts, so it settles).
inline constexpr double kMaxConvQReward = 1e6;
inline constexpr double kMaxConvQDiscount = 0.999;

std::array<double, kConvQWeightCount> ConvQWeights(const ConvQModel& model);
ConvQModel ConvQModelFromWeights(const std::array<double, kConvQWeightCount>& weights);
// The weights' names in file order ("station_reward", ...).
const std::array<const char*, kConvQWeightCount>& ConvQWeightNames();

// kCorrupt naming the first weight out of bounds (or not finite).
Status CheckConvQModel(const ConvQModel& model);

// SPEC section 2's MDP written as weights (100, -1, -10, 0.9, 0.9): what
// training should recover; for tests.
ConvQModel SpecConvQModel();

// The weights of the model the repository ships
// (docs/examples/models/convq.model, trained by `dynapath train-model
// --seed 1`): convQ's model when no --model is given. A test checks that
// the file holds exactly these.
const ConvQModel& ShippedConvQModel();

}  // namespace dynapath
