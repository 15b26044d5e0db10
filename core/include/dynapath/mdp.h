#pragma once
// The MDP every learner solves (SPEC section 2).

#include <array>

namespace dynapath {

inline constexpr int kNumActions = 8;
// Actions 0..7 = N, NE, E, SE, S, SW, W, NW.
inline constexpr std::array<int, kNumActions> kActionRowOffset = {-1, -1, 0, 1, 1, 1, 0, -1};
inline constexpr std::array<int, kNumActions> kActionColOffset = {0, 1, 1, 1, 0, -1, -1, -1};

inline constexpr float kStationReward = 100.0f;  // the cell the agent ends on is a station
inline constexpr float kBumpReward = -10.0f;     // the move was blocked, the agent stayed
inline constexpr float kStepReward = -1.0f;      // any other move

inline constexpr float kDiscount = 0.9f;      // gamma
inline constexpr float kLearningRate = 0.4f;  // alpha (= eta of the federated learner)

// The same constants in a table's value type (q_table.h): float tables
// learn with the float constants above, double tables (the report code's)
// with 0.9 and 0.4 in double.
template <typename V>
inline constexpr V kDiscountOf = static_cast<V>(0.9);
template <typename V>
inline constexpr V kLearningRateOf = static_cast<V>(0.4);
static_assert(kDiscountOf<float> == kDiscount && kLearningRateOf<float> == kLearningRate);

}  // namespace dynapath
