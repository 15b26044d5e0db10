#include "dynapath/c_random.h"

namespace dynapath {

void CRandom::Seed(uint32_t seed) {
  // glibc's srandom_r: a zero seed is replaced by 1, the state is filled with
  // 16807 * r mod (2^31 - 1) (Schrage's method, on signed 32-bit values), and
  // the first 310 outputs are discarded.
  std::array<int32_t, 344> r{};
  r[0] = static_cast<int32_t>(seed == 0 ? 1 : seed);
  for (int i = 1; i < 31; ++i) {
    const int32_t hi = r[i - 1] / 127773;
    const int32_t lo = r[i - 1] % 127773;
    int32_t word = 16807 * lo - 2836 * hi;
    if (word < 0) word += 2147483647;
    r[i] = word;
  }
  for (int i = 31; i < 34; ++i) r[i] = r[i - 31];
  for (int i = 34; i < 344; ++i) {
    r[i] = static_cast<int32_t>(static_cast<uint32_t>(r[i - 31]) + static_cast<uint32_t>(r[i - 3]));
  }
  for (int i = 0; i < 34; ++i) ring_[i] = r[310 + i];
  pos_ = 0;  // ring_[pos_] is the oldest of the last 34 values
}

int32_t CRandom::Next() {
  // New value = r[n-31] + r[n-3]; with 34 values kept, r[n-34] sits at pos_.
  const int32_t a = ring_[(pos_ + 3) % 34];   // r[n-31]
  const int32_t b = ring_[(pos_ + 31) % 34];  // r[n-3]
  const int32_t value = static_cast<int32_t>(static_cast<uint32_t>(a) + static_cast<uint32_t>(b));
  ring_[pos_] = value;
  pos_ = (pos_ + 1) % 34;
  return static_cast<int32_t>(static_cast<uint32_t>(value) >> 1);
}

}  // namespace dynapath
