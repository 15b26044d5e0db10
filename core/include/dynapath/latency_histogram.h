#pragma once
// Latency percentiles in constant memory: microsecond values counted in
// log-linear buckets (exact below 1024 us, 1/64 of an octave above, up to
// about 70 minutes), so a service answering millions of queries keeps a few
// kilobytes for them.

#include <array>
#include <cstdint>

namespace dynapath {

class LatencyHistogram {
 public:
  void Add(int64_t micros);
  void Merge(const LatencyHistogram& other);
  int64_t count() const { return count_; }
  int64_t max() const { return max_; }
  // The value at quantile q (0..1): the upper edge of its bucket (within
  // 1.6% above 1 ms), 0 when empty.
  int64_t Quantile(double q) const;

 private:
  static constexpr int kLinear = 1024;
  static constexpr int kSub = 64;
  static constexpr int kOctaves = 22;  // 2^10 .. 2^32 us
  static int Bucket(int64_t micros);
  static int64_t UpperEdge(int bucket);
  std::array<int64_t, kLinear + kSub * kOctaves> counts_{};
  int64_t count_ = 0;
  int64_t max_ = 0;
};

}  // namespace dynapath
