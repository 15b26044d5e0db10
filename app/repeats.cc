#include "app/repeats.h"

namespace dynapath::app {

std::optional<uint64_t> RepeatLearnerSeed(std::optional<long long> learner_seed, uint64_t maze_seed,
                                          int repeat) {
  if (repeat <= 1 && !learner_seed) return std::nullopt;
  const uint64_t base = learner_seed ? static_cast<uint64_t>(*learner_seed) : maze_seed;
  return base + static_cast<uint64_t>(repeat - 1) * kRepeatSeedStride;
}

}  // namespace dynapath::app
