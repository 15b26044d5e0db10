#include "core/learn/rng_skip.h"

#include <map>
#include <memory>
#include <mutex>

namespace dynapath {

RngSkip::RngSkip(int draws) : draws_(draws), table_(64 * 16) {
  // The image of each of the 256 state bits, advanced `draws` steps.
  std::array<std::array<uint64_t, 4>, 256> basis;
  Rng rng(0);
  for (int bit = 0; bit < 256; ++bit) {
    std::array<uint64_t, 4> state{};
    state[bit / 64] = uint64_t{1} << (bit % 64);
    rng.set_state(state);
    for (int i = 0; i < draws; ++i) rng.Next();
    basis[bit] = rng.state();
  }
  // Each table entry is the XOR of the images of the bits set in its nibble.
  for (int group = 0; group < 64; ++group) {
    for (int value = 0; value < 16; ++value) {
      std::array<uint64_t, 4> image{};
      for (int b = 0; b < 4; ++b) {
        if (((value >> b) & 1) == 0) continue;
        for (int i = 0; i < 4; ++i) image[i] ^= basis[group * 4 + b][i];
      }
      table_[static_cast<size_t>(group) * 16 + value] = image;
    }
  }
}

const RngSkip& RngSkip::For(int draws) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<RngSkip>> tables;
  const std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<RngSkip>& table = tables[draws];
  if (!table) table = std::make_unique<RngSkip>(draws);
  return *table;
}

}  // namespace dynapath
