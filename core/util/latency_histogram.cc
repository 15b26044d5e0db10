#include "dynapath/latency_histogram.h"

#include <algorithm>
#include <cmath>

namespace dynapath {

int LatencyHistogram::Bucket(int64_t micros) {
  if (micros < 0) micros = 0;
  if (micros < kLinear) return static_cast<int>(micros);
  int octave = 0;  // micros in [2^(10 + octave), 2^(11 + octave))
  while (octave + 1 < kOctaves && (micros >> (11 + octave)) != 0) ++octave;
  const int64_t base = int64_t{1} << (10 + octave);
  const int64_t sub = std::min<int64_t>(kSub - 1, (micros - base) * kSub / base);
  return kLinear + octave * kSub + static_cast<int>(sub);
}

int64_t LatencyHistogram::UpperEdge(int bucket) {
  if (bucket < kLinear) return bucket;
  const int octave = (bucket - kLinear) / kSub;
  const int sub = (bucket - kLinear) % kSub;
  const int64_t base = int64_t{1} << (10 + octave);
  return base + (sub + 1) * base / kSub - 1;
}

void LatencyHistogram::Add(int64_t micros) {
  ++counts_[static_cast<size_t>(Bucket(micros))];
  ++count_;
  max_ = std::max(max_, micros);
}

void LatencyHistogram::Merge(const LatencyHistogram& other) {
  for (size_t i = 0; i < counts_.size(); ++i) counts_[i] += other.counts_[i];
  count_ += other.count_;
  max_ = std::max(max_, other.max_);
}

int64_t LatencyHistogram::Quantile(double q) const {
  if (count_ == 0) return 0;
  const int64_t rank = std::clamp<int64_t>(
      static_cast<int64_t>(std::ceil(q * static_cast<double>(count_))), 1, count_);
  int64_t seen = 0;
  for (size_t i = 0; i < counts_.size(); ++i) {
    seen += counts_[i];
    if (seen >= rank) return std::min(UpperEdge(static_cast<int>(i)), max_);
  }
  return max_;
}

}  // namespace dynapath
