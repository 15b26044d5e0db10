#include "study/repeat_statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

namespace dynapath::study {
namespace {

TEST(RepeatStatistics, HandComputedValues) {
  const std::vector<double> a = {1, 2, 4, 10};
  EXPECT_DOUBLE_EQ(Mean(a), 4.25);
  // Deviations -3.25, -2.25, -0.25, 5.75: squares 48.75, / 3 = 16.25.
  EXPECT_DOUBLE_EQ(StandardDeviation(a), std::sqrt(16.25));
  EXPECT_DOUBLE_EQ(Median(a), 3.0);
  EXPECT_DOUBLE_EQ(InterquartileMean(a), 3.0);  // {2, 4}

  const std::vector<double> b = {5, 1, 9, 3, 7, 2, 8, 4};  // sorted 1 2 3 4 5 7 8 9
  EXPECT_DOUBLE_EQ(Mean(b), 39.0 / 8);
  EXPECT_DOUBLE_EQ(Median(b), 4.5);
  EXPECT_DOUBLE_EQ(InterquartileMean(b), 4.75);  // {3, 4, 5, 7}

  // Ten repeats with an outlier: the IQM drops 2 at each end.
  const std::vector<double> c = {100, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  EXPECT_DOUBLE_EQ(Median(c), 5.5);
  EXPECT_DOUBLE_EQ(InterquartileMean(c), 5.5);  // {3..8}
  EXPECT_DOUBLE_EQ(Mean(c), 14.5);

  const std::vector<double> odd = {3, 1, 2};  // fewer than 4: nothing trimmed
  EXPECT_DOUBLE_EQ(Median(odd), 2.0);
  EXPECT_DOUBLE_EQ(InterquartileMean(odd), 2.0);
  EXPECT_DOUBLE_EQ(StandardDeviation({7.5}), 0.0);
}

TEST(RepeatStatistics, QuantileInterpolatesLinearly) {
  const std::vector<double> sorted = {0, 10, 20, 30};
  EXPECT_DOUBLE_EQ(SortedQuantile(sorted, 0.5), 15.0);
  EXPECT_DOUBLE_EQ(SortedQuantile(sorted, 0.025), 0.75);  // position 0.075
  EXPECT_DOUBLE_EQ(SortedQuantile(sorted, 0.975), 29.25);
  EXPECT_DOUBLE_EQ(SortedQuantile(sorted, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(SortedQuantile(sorted, 1.0), 30.0);
}

TEST(RepeatStatistics, NoValuesOrNonFiniteGiveNaN) {
  EXPECT_TRUE(std::isnan(Mean({})));
  EXPECT_TRUE(std::isnan(Median({})));
  EXPECT_TRUE(std::isnan(InterquartileMean({1, NAN, 3, 4})));
  const Interval none = StratifiedBootstrap({}, Mean);
  EXPECT_TRUE(std::isnan(none.low) && std::isnan(none.high));
  const Interval nan = StratifiedBootstrap({{1, 2, INFINITY}}, Mean);
  EXPECT_TRUE(std::isnan(nan.low) && std::isnan(nan.high));
}

TEST(RepeatStatistics, OneValueOrEqualValuesGiveAPointInterval) {
  const Interval one = StratifiedBootstrap({{0.25}}, Mean);
  EXPECT_DOUBLE_EQ(one.low, 0.25);
  EXPECT_DOUBLE_EQ(one.high, 0.25);
  const Interval same = StratifiedBootstrap({{2, 2, 2}, {2}}, Mean);
  EXPECT_DOUBLE_EQ(same.low, 2.0);
  EXPECT_DOUBLE_EQ(same.high, 2.0);
}

// The exact bootstrap distribution of the pooled mean, by enumerating every
// equally likely resample (each stratum's draws independently): the
// reference the Monte Carlo interval is checked against, sharing no code
// with it.
std::map<double, double> ExactBootstrapDistribution(
    const std::vector<std::vector<double>>& strata) {
  std::map<double, double> distribution{{0.0, 1.0}};  // sum -> probability
  size_t total = 0;
  for (const std::vector<double>& stratum : strata) {
    total += stratum.size();
    for (size_t draw = 0; draw < stratum.size(); ++draw) {
      std::map<double, double> next;
      for (const auto& [sum, p] : distribution) {
        for (const double value : stratum) {
          next[sum + value] += p / static_cast<double>(stratum.size());
        }
      }
      distribution = std::move(next);
    }
  }
  std::map<double, double> means;
  for (const auto& [sum, p] : distribution) means[sum / static_cast<double>(total)] += p;
  return means;
}

// P(X < x) and P(X <= x) under `distribution`.
std::pair<double, double> Cdf(const std::map<double, double>& distribution, double x) {
  double below = 0, at_most = 0;
  for (const auto& [value, p] : distribution) {
    if (value < x - 1e-12) below += p;
    if (value <= x + 1e-12) at_most += p;
  }
  return {below, at_most};
}

// `x` is a q-quantile of the distribution up to `slack` in probability.
void ExpectQuantile(const std::map<double, double>& distribution, double x, double q,
                    double slack) {
  const auto [below, at_most] = Cdf(distribution, x);
  EXPECT_LE(below, q + slack) << "x " << x;
  EXPECT_GE(at_most, q - slack) << "x " << x;
}

TEST(RepeatStatistics, BootstrapMatchesTheExactBootstrapDistribution) {
  // 10 000 resamples: the empirical 2.5% point's probability has a standard
  // error of 0.0016; 0.006 is almost four of them.
  for (const std::vector<std::vector<double>>& strata :
       std::vector<std::vector<std::vector<double>>>{
           {{0, 1, 2, 4, 8}},                    // one stratum: 3125 resamples
           {{0.9, 0.95, 0.97, 1.0, 1.0, 0.99}},  // success rates
           {{0, 10}, {100, 200, 300}},           // two strata of different size
       }) {
    const std::map<double, double> exact = ExactBootstrapDistribution(strata);
    const Interval ci = StratifiedBootstrap(strata, Mean);
    ExpectQuantile(exact, ci.low, 0.025, 0.006);
    ExpectQuantile(exact, ci.high, 0.975, 0.006);
    EXPECT_LE(ci.low, ci.high);
  }
}

TEST(RepeatStatistics, BootstrapKeepsEachStratumsSize) {
  // Stratified: every resample holds two values of {0, 10} and three of
  // {100, 200, 300}, so the pooled mean stays within [60, 184]; a bootstrap
  // over the five values pooled would reach below 60 (all zeros: 1/3125).
  const Interval ci =
      StratifiedBootstrap({{0, 10}, {100, 200, 300}}, Mean, 20000, kBootstrapSeed, 0.9999);
  EXPECT_GE(ci.low, 60.0);
  EXPECT_LE(ci.high, 184.0);
}

TEST(RepeatStatistics, BootstrapIsFixedBySeed) {
  const std::vector<std::vector<double>> strata = {{1, 5, 2, 8, 3, 9, 4, 4, 7, 6}};
  const Interval a = StratifiedBootstrap(strata, Mean);
  const Interval b = StratifiedBootstrap(strata, Mean);
  EXPECT_EQ(a.low, b.low);
  EXPECT_EQ(a.high, b.high);
  // Another seed draws other resamples (values whose means rarely tie).
  const std::vector<std::vector<double>> irregular = {
      {1.1, 5.37, 2.718, 8.2, 3.1416, 9.9, 4.05, 4.6, 7.77, 6.01}};
  const Interval x = StratifiedBootstrap(irregular, Mean);
  const Interval y = StratifiedBootstrap(irregular, Mean, kBootstrapResamples, 1);
  EXPECT_TRUE(x.low != y.low || x.high != y.high);
  // The interval of the IQM lies within the sample's range and holds its IQM.
  const Interval iqm = StratifiedBootstrap(
      strata, [](const std::vector<double>& v) { return InterquartileMean(v); });
  EXPECT_GE(iqm.low, 1.0);
  EXPECT_LE(iqm.high, 9.0);
  EXPECT_LE(iqm.low, InterquartileMean(strata[0]));
  EXPECT_GE(iqm.high, InterquartileMean(strata[0]));
}

TEST(RepeatStatistics, SummarizePoolsTheStrata) {
  const SampleSummary s = Summarize({{1, 2}, {4, 10}});
  EXPECT_EQ(s.count, 4);
  EXPECT_DOUBLE_EQ(s.mean, 4.25);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(16.25));
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  EXPECT_DOUBLE_EQ(s.iqm, 3.0);
  const Interval mean_ci = StratifiedBootstrap({{1, 2}, {4, 10}}, Mean);
  EXPECT_EQ(s.mean_ci.low, mean_ci.low);
  EXPECT_EQ(s.mean_ci.high, mean_ci.high);
}

}  // namespace
}  // namespace dynapath::study
