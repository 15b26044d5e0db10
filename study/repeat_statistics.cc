#include "study/repeat_statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dynapath/rng.h"

namespace dynapath::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool AllFinite(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

}  // namespace

double Mean(const std::vector<double>& values) {
  if (values.empty()) return kNaN;
  double sum = 0;
  for (const double value : values) sum += value;
  return sum / static_cast<double>(values.size());
}

double StandardDeviation(const std::vector<double>& values) {
  if (values.empty()) return kNaN;
  if (values.size() == 1) return 0;
  const double mean = Mean(values);
  double squares = 0;
  for (const double value : values) squares += (value - mean) * (value - mean);
  return std::sqrt(squares / static_cast<double>(values.size() - 1));
}

double Median(std::vector<double> values) {
  if (values.empty() || !AllFinite(values)) return kNaN;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

double InterquartileMeanInPlace(std::vector<double>& values) {
  if (values.empty() || !AllFinite(values)) return kNaN;
  std::sort(values.begin(), values.end());
  const size_t cut = values.size() / 4;
  double sum = 0;  // in order, as Mean sums
  for (size_t i = cut; i < values.size() - cut; ++i) sum += values[i];
  return sum / static_cast<double>(values.size() - 2 * cut);
}

double InterquartileMean(std::vector<double> values) { return InterquartileMeanInPlace(values); }

double SortedQuantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return kNaN;
  const double position = q * static_cast<double>(sorted.size() - 1);
  const size_t below = static_cast<size_t>(std::floor(position));
  if (below + 1 >= sorted.size()) return sorted.back();
  const double fraction = position - static_cast<double>(below);
  return sorted[below] + fraction * (sorted[below + 1] - sorted[below]);
}

Interval StratifiedBootstrap(const std::vector<std::vector<double>>& strata,
                             const Statistic& statistic, int resamples, uint64_t seed,
                             double confidence) {
  size_t total = 0;
  for (const std::vector<double>& stratum : strata) {
    if (!AllFinite(stratum)) return {kNaN, kNaN};
    total += stratum.size();
  }
  if (total == 0 || resamples < 1) return {kNaN, kNaN};
  Rng rng(seed);
  std::vector<double> estimates;
  estimates.reserve(static_cast<size_t>(resamples));
  std::vector<double> pooled(total);
  for (int r = 0; r < resamples; ++r) {
    size_t k = 0;
    for (const std::vector<double>& stratum : strata) {
      const uint32_t n = static_cast<uint32_t>(stratum.size());
      for (uint32_t i = 0; i < n; ++i) pooled[k++] = stratum[rng.Below(n)];
    }
    estimates.push_back(statistic(pooled));
  }
  std::sort(estimates.begin(), estimates.end());
  const double tail = (1 - confidence) / 2;
  return {SortedQuantile(estimates, tail), SortedQuantile(estimates, 1 - tail)};
}

SampleSummary Summarize(const std::vector<std::vector<double>>& strata) {
  std::vector<double> all;
  for (const std::vector<double>& stratum : strata)
    all.insert(all.end(), stratum.begin(), stratum.end());
  SampleSummary s;
  s.count = static_cast<int>(all.size());
  const bool finite = AllFinite(all);
  s.mean = finite ? Mean(all) : kNaN;
  s.std = finite ? StandardDeviation(all) : kNaN;
  s.median = Median(all);
  s.iqm = InterquartileMean(all);
  s.mean_ci = StratifiedBootstrap(strata, Mean);
  s.iqm_ci = StratifiedBootstrap(strata, InterquartileMeanInPlace);
  return s;
}

}  // namespace dynapath::study
