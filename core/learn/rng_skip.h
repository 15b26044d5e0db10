#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/rng.h"
#endif
// Advances an Rng by a fixed number of draws at once. xoshiro256**'s state
// transition is linear over GF(2), so n draws are one 256 x 256 bit matrix;
// applied 4 state bits at a time from precomputed tables (64 x 16 entries of
// 256 bits, 32 KiB) it costs 64 loads and XORs instead of n dependent
// generator steps. The single-agent learner uses it to skip a replay batch
// whose entries are all settled (settled_updates.h): the same state as
// drawing them.

#include <array>
#include <cstdint>
#include <vector>

#include "dynapath/rng.h"

namespace dynapath {

class RngSkip {
 public:
  // `draws` >= 0.
  explicit RngSkip(int draws);

  int draws() const { return draws_; }
  // The state of `rng` after draws() calls of Next.
  void Apply(Rng& rng) const {
    const std::array<uint64_t, 4> state = rng.state();
    std::array<uint64_t, 4> out{};
    const std::array<uint64_t, 4>* entry = table_.data();
    for (int word = 0; word < 4; ++word) {
      uint64_t bits = state[word];
      for (int nibble = 0; nibble < 16; ++nibble, entry += 16, bits >>= 4) {
        const std::array<uint64_t, 4>& image = entry[bits & 15];
        for (int i = 0; i < 4; ++i) out[i] ^= image[i];
      }
    }
    rng.set_state(out);
  }

  // The shared table of `draws` (built on first use; thread-safe).
  static const RngSkip& For(int draws);

 private:
  int draws_;
  // [word * 16 + nibble][value]: the image of that nibble's 4 bits set to value.
  std::vector<std::array<uint64_t, 4>> table_;
};

}  // namespace dynapath
