#include "protocol/resend_gate.h"

#include <gtest/gtest.h>

namespace dynapath::protocol {
namespace {

TEST(ResendGateTest, AnswersARoundOncePerInterval) {
  ResendGate gate;
  EXPECT_TRUE(gate.Allow(/*round=*/7, /*oldest_kept=*/0, /*now_ms=*/100, /*interval_ms=*/20));
  // A backlog of requests for round 7 within the interval: one answer only.
  for (int64_t now = 100; now < 120; ++now) EXPECT_FALSE(gate.Allow(7, 0, now, 20)) << now;
  EXPECT_TRUE(gate.Allow(7, 0, 120, 20));
  EXPECT_FALSE(gate.Allow(7, 0, 121, 20));
}

TEST(ResendGateTest, RoundsAreGatedApart) {
  ResendGate gate;
  EXPECT_TRUE(gate.Allow(3, 0, 0, 50));
  EXPECT_TRUE(gate.Allow(4, 0, 1, 50));
  EXPECT_FALSE(gate.Allow(3, 0, 2, 50));
  EXPECT_FALSE(gate.Allow(4, 0, 2, 50));
}

TEST(ResendGateTest, ForgetsRoundsNoLongerKeptAndResets) {
  ResendGate gate;
  EXPECT_TRUE(gate.Allow(3, 0, 0, 50));
  // Round 3 dropped out of what is kept, then (a new epoch) is kept again.
  EXPECT_TRUE(gate.Allow(9, 4, 1, 50));
  EXPECT_TRUE(gate.Allow(3, 3, 2, 50));
  EXPECT_FALSE(gate.Allow(3, 3, 3, 50));
  gate.Reset();
  EXPECT_TRUE(gate.Allow(3, 3, 4, 50));
}

}  // namespace
}  // namespace dynapath::protocol

namespace dynapath::protocol {
namespace {

TEST(RepeatIntervalTest, TwoRoundTripsAndFiveMsWithinItsBounds) {
  EXPECT_EQ(RepeatIntervalMs(-1, 200), 20);  // no round trip measured yet
  EXPECT_EQ(RepeatIntervalMs(0, 200), 5);
  EXPECT_EQ(RepeatIntervalMs(1.6, 200), 8);
  EXPECT_EQ(RepeatIntervalMs(7.4, 20), 19);
  EXPECT_EQ(RepeatIntervalMs(50, 20), 20);
  EXPECT_EQ(RepeatIntervalMs(500, 200), 200);
}

}  // namespace
}  // namespace dynapath::protocol
