#include "core/learn/rng_skip.h"

#include <gtest/gtest.h>

namespace dynapath {
namespace {

TEST(RngSkipTest, EqualsDrawingOneByOne) {
  for (const int draws : {0, 1, 2, 63, 64, 65, 1000}) {
    const RngSkip& skip = RngSkip::For(draws);
    EXPECT_EQ(skip.draws(), draws);
    for (uint64_t seed = 1; seed <= 50; ++seed) {
      Rng stepped(seed * 0x9E3779B97F4A7C15ull), skipped = stepped;
      for (int i = 0; i < 17; ++i) stepped.Next();  // an arbitrary state
      for (int i = 0; i < 17; ++i) skipped.Next();
      for (int i = 0; i < draws; ++i) stepped.Next();
      skip.Apply(skipped);
      ASSERT_EQ(skipped.state(), stepped.state()) << draws << " " << seed;
      EXPECT_EQ(skipped.Next(), stepped.Next());
    }
  }
}

TEST(RngSkipTest, SharedTablesAreBuiltOnce) {
  EXPECT_EQ(&RngSkip::For(64), &RngSkip::For(64));
  EXPECT_NE(&RngSkip::For(64), &RngSkip::For(32));
}

}  // namespace
}  // namespace dynapath
