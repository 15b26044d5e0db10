#include "dynapath/latency_histogram.h"

#include <gtest/gtest.h>

namespace dynapath {
namespace {

TEST(LatencyHistogram, ExactBelowAMillisecondCloseAbove) {
  LatencyHistogram h;
  EXPECT_EQ(h.Quantile(0.5), 0);
  for (int i = 1; i <= 100; ++i) h.Add(i);
  EXPECT_EQ(h.Quantile(0.5), 50);
  EXPECT_EQ(h.Quantile(0.99), 99);
  EXPECT_EQ(h.Quantile(1.0), 100);
  EXPECT_EQ(h.max(), 100);
  LatencyHistogram big;
  big.Add(123456);
  big.Add(5000000);
  EXPECT_GE(big.Quantile(0.5), 123456);
  EXPECT_LE(big.Quantile(0.5), 123456 * 1.016 + 1);
  EXPECT_EQ(big.Quantile(1.0), 5000000);
  h.Merge(big);
  EXPECT_EQ(h.count(), 102);
  EXPECT_EQ(h.max(), 5000000);
}

}  // namespace
}  // namespace dynapath
