#pragma once
// Repeated runs: how many, and each repeat's learner seed (run --repeats,
// a study's repeats).

#include <cstdint>
#include <optional>

namespace dynapath::app {

// Repeat k's learner seed: base + (k - 1) x kRepeatSeedStride, base being
// --learner-seed when given, else the maze seed `maze_seed`. Unset for
// repeat 1 without --learner-seed (the run's default stream, which is the
// maze seed).
inline constexpr uint64_t kRepeatSeedStride = 1000003;
inline constexpr int kMaxRepeats = 1000;
std::optional<uint64_t> RepeatLearnerSeed(std::optional<long long> learner_seed, uint64_t maze_seed,
                                          int repeat);

}  // namespace dynapath::app
