#pragma once
// A re-implementation of the GNU C library's srand()/rand() (the TYPE_3
// additive feedback generator behind random()), so the report's mazes and
// change sequences are reproduced without touching the process-wide rand()
// state. Each object is an independent stream: not thread-safe, but two
// objects never interfere.

#include <array>
#include <cstdint>

namespace dynapath {

class CRandom {
 public:
  // RAND_MAX of glibc.
  static constexpr int32_t kMax = 2147483647;

  explicit CRandom(uint32_t seed) { Seed(seed); }

  // Same effect as srand(seed) on the stream of this object.
  void Seed(uint32_t seed);

  // Next value in [0, kMax], identical to glibc's rand() after srand(seed).
  int32_t Next();

 private:
  // r[i] = r[i-3] + r[i-31]: keep the last 34 outputs in a ring.
  std::array<int32_t, 34> ring_{};
  int pos_ = 0;
};

}  // namespace dynapath
