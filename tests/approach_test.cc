#include "core/approach.h"

#include <gtest/gtest.h>

namespace dynapath {
namespace {

TEST(ApproachTest, NamesRoundTripCaseInsensitively) {
  for (Approach approach : AllApproaches()) {
    EXPECT_EQ(ParseApproach(ApproachName(approach)), approach);
  }
  EXPECT_EQ(ParseApproach("fedasynq_eqavg"), Approach::kFedAsynQEqAvg);
  EXPECT_EQ(ParseApproach(" a* oracle "), Approach::kAStarOracle);
  EXPECT_FALSE(ParseApproach("fedAsynQ").has_value());
  EXPECT_EQ(ParseApproach("incremental oracle"), Approach::kIncrementalOracle);
  EXPECT_EQ(AllApproaches().size(), 8u);
}

TEST(ApproachTest, Lists) {
  Result<std::vector<Approach>> all = ParseApproachList("ALL");
  ASSERT_TRUE(all.ok());
  EXPECT_EQ(*all, AllApproaches());
  Result<std::vector<Approach>> some = ParseApproachList("BFS Oracle,singleAgent,bfs oracle");
  ASSERT_TRUE(some.ok());
  EXPECT_EQ(*some, (std::vector<Approach>{Approach::kBfsOracle, Approach::kSingleAgent}));
  Result<std::vector<Approach>> bad = ParseApproachList("BFS Oracle,magic");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("'magic'"), std::string::npos);
  EXPECT_FALSE(ParseApproachList("").ok());
}

}  // namespace
}  // namespace dynapath
