#pragma once
// Statistics over the repeats of a study (summary.csv, `dynapath compare`):
// mean, sample standard deviation, median, interquartile mean and a
// percentile confidence interval by stratified bootstrap, in the manner of
// Agarwal et al., "Deep Reinforcement Learning at the Edge of the
// Statistical Precipice" (NeurIPS 2021) and its rliable library.

#include <cstdint>
#include <functional>
#include <vector>

namespace dynapath::study {

// The bootstrap's fixed settings: every summary.csv row records them.
inline constexpr int kBootstrapResamples = 10000;
inline constexpr uint64_t kBootstrapSeed = 20211206;  // rliable's paper's first day
inline constexpr double kConfidence = 0.95;

// Arithmetic mean; NaN for no values.
double Mean(const std::vector<double>& values);
// Sample standard deviation (divisor n - 1); 0 for one value, NaN for none.
double StandardDeviation(const std::vector<double>& values);
// The middle value (the mean of the two middle ones for an even count).
double Median(std::vector<double> values);
// Interquartile mean: the mean of the values left after dropping
// floor(n / 4) of the smallest and as many of the largest (scipy's
// trim_mean(x, 0.25), rliable's IQM); the mean for fewer than 4 values.
double InterquartileMean(std::vector<double> values);
// Linear-interpolation quantile of sorted values (numpy's default
// percentile): position q * (n - 1).
double SortedQuantile(const std::vector<double>& sorted, double q);

// A statistic of a pooled sample (Mean, InterquartileMean). The sample is
// the bootstrap's scratch buffer: the statistic may reorder it.
using Statistic = std::function<double(std::vector<double>&)>;
// InterquartileMean without a copy: sorts `values` in place.
double InterquartileMeanInPlace(std::vector<double>& values);

struct Interval {
  double low = 0, high = 0;
};

// The percentile bootstrap interval of `statistic` of all values pooled:
// each of `resamples` resamples draws, in every stratum independently, as
// many values as it holds, uniformly with replacement (stratified
// bootstrap: the strata are the study's configurations, the values their
// repeats), and computes the statistic of the pooled draws; the interval is
// the (1 - confidence) / 2 and (1 + confidence) / 2 quantiles of those.
// Draws come from dynapath::Rng(seed), each index as Below(stratum size), in
// stratum order. Empty strata are skipped; NaN when no value or a value is
// not finite.
Interval StratifiedBootstrap(const std::vector<std::vector<double>>& strata,
                             const Statistic& statistic, int resamples = kBootstrapResamples,
                             uint64_t seed = kBootstrapSeed, double confidence = kConfidence);

// Everything summary.csv holds of one sample (one stratum, or several
// pooled for the rows over all configurations).
struct SampleSummary {
  int count = 0;
  double mean = 0, std = 0, median = 0, iqm = 0;
  Interval mean_ci, iqm_ci;
};
SampleSummary Summarize(const std::vector<std::vector<double>>& strata);

}  // namespace dynapath::study
