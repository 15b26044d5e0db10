#include "protocol/inbox.h"

#include <gtest/gtest.h>

#include <chrono>

namespace dynapath::protocol {
namespace {

using std::chrono::milliseconds;

TEST(InboxTest, DropsMessagesPastItsBoundAndCountsThem) {
  Inbox inbox(/*max_bytes=*/100);
  int ran = 0;
  EXPECT_TRUE(inbox.Post([&] { ++ran; }, 60));
  EXPECT_TRUE(inbox.Post([&] { ++ran; }, 40));  // exactly at the bound
  EXPECT_FALSE(inbox.Post([&] { ++ran; }, 1));  // past it: dropped
  EXPECT_TRUE(inbox.Post([&] { ++ran; }, 0));   // not a message: always taken
  EXPECT_EQ(inbox.dropped(), 1);
  EXPECT_EQ(inbox.RunFor(milliseconds(0)), 3);
  EXPECT_EQ(ran, 3);
  // What ran no longer counts against the bound.
  EXPECT_TRUE(inbox.Post([&] { ++ran; }, 100));
  EXPECT_EQ(inbox.RunFor(milliseconds(0)), 1);
  EXPECT_EQ(inbox.dropped(), 1);
}

TEST(InboxTest, TakesAnyOneMessageWhenNothingWaits) {
  Inbox inbox(/*max_bytes=*/10);
  int ran = 0;
  EXPECT_TRUE(inbox.Post([&] { ++ran; }, 1000));  // larger than the bound, alone
  EXPECT_FALSE(inbox.Post([&] { ++ran; }, 1));
  EXPECT_EQ(inbox.RunFor(milliseconds(0)), 1);
  EXPECT_EQ(ran, 1);
  EXPECT_EQ(inbox.dropped(), 1);
}

}  // namespace
}  // namespace dynapath::protocol
