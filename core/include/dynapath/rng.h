#pragma once
// Small fast random generators for learners. Every learner owns one, seeded
// from a hash of (run seed, node, training count, learner, round), so no
// random state is shared and results do not depend on scheduling.

#include <array>
#include <cstdint>
#include <initializer_list>

namespace dynapath {

// SplitMix64 step: a bijective 64-bit mixer.
inline uint64_t SplitMix64(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Derives one seed from a list of integers (order matters).
inline uint64_t DeriveSeed(std::initializer_list<uint64_t> parts) {
  uint64_t state = 0x6A09E667F3BCC909ull;
  uint64_t seed = 0;
  for (uint64_t part : parts) {
    state ^= part;
    seed = SplitMix64(state);
    state = seed;
  }
  return seed;
}

// xoshiro256** 1.0 (Blackman & Vigna): fast, 256-bit state.
class Rng {
 public:
  explicit Rng(uint64_t seed) {
    for (uint64_t& word : s_) word = SplitMix64(seed);
  }

  uint64_t Next() {
    const uint64_t result = Rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = Rotl(s_[3], 45);
    return result;
  }

  // Uniform integer in [0, n), n >= 1 (Lemire's multiply-shift; the bias is
  // below 2^-32 for the small n used here).
  uint32_t Below(uint32_t n) {
    return static_cast<uint32_t>(((Next() >> 32) * static_cast<uint64_t>(n)) >> 32);
  }

  // The raw state (for RngSkip).
  std::array<uint64_t, 4> state() const { return {s_[0], s_[1], s_[2], s_[3]}; }
  void set_state(const std::array<uint64_t, 4>& state) {
    for (int i = 0; i < 4; ++i) s_[i] = state[i];
  }

  // Uniform double in [0, 1).
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

 private:
  static uint64_t Rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t s_[4];
};

}  // namespace dynapath
