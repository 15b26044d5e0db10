#include "dynapath/approach.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "core/plan/approach_registry.h"
#include "dynapath/local_trainer.h"
#include "dynapath/thread_pool.h"

namespace dynapath {
namespace {

TEST(ApproachTest, NamesRoundTripCaseInsensitively) {
  for (Approach approach : RegisteredApproaches()) {
    EXPECT_EQ(ParseApproach(ApproachName(approach)), approach);
  }
  EXPECT_EQ(ParseApproach("fedasynq_eqavg"), Approach::kFedAsynQEqAvg);
  EXPECT_EQ(ParseApproach(" a* oracle "), Approach::kAStarOracle);
  EXPECT_FALSE(ParseApproach("fedAsynQ").has_value());
  EXPECT_EQ(ParseApproach("incremental oracle"), Approach::kIncrementalOracle);
  EXPECT_EQ(ParseApproach("convq"), Approach::kConvQ);
}

TEST(ApproachTest, AllLeavesOutConvQ) {
  const std::vector<Approach>& all = AllApproaches();
  EXPECT_EQ(all.size() + 1, RegisteredApproaches().size());
  EXPECT_EQ(std::find(all.begin(), all.end(), Approach::kConvQ), all.end());
  EXPECT_FALSE(IsLearningApproach(Approach::kConvQ));
}

TEST(ApproachTest, SpecsSevenComeFirstInOrder) {
  const std::vector<std::string> spec = {"A* Static",          "A* Oracle",   "BFS Oracle",
                                         "onlyTrainLeafNodes", "singleAgent", "fedAsynQ_EqAvg",
                                         "fedAsynQ_ImAvg"};
  ASSERT_GE(AllApproaches().size(), spec.size());
  for (size_t i = 0; i < spec.size(); ++i) EXPECT_EQ(ApproachName(AllApproaches()[i]), spec[i]);
}

TEST(ApproachRegistryTest, OneConsistentLinePerApproach) {
  const std::vector<ApproachSpec>& registry = ApproachRegistry();
  ASSERT_EQ(registry.size(), RegisteredApproaches().size());
  for (size_t i = 0; i < registry.size(); ++i) {
    const ApproachSpec& spec = registry[i];
    EXPECT_EQ(spec.approach, RegisteredApproaches()[i]);
    EXPECT_EQ(&GetApproachSpec(spec.approach), &spec);
    ASSERT_NE(spec.make_planner, nullptr) << spec.name;
    // A learner comes with a retraining strategy, and only then.
    EXPECT_EQ(spec.learner.has_value(), spec.make_strategy != nullptr) << spec.name;
    EXPECT_EQ(IsLearningApproach(spec.approach), spec.learner.has_value()) << spec.name;
  }
  for (size_t i = 0; i < registry.size(); ++i) {
    for (size_t j = 0; j < i; ++j) EXPECT_STRNE(registry[i].name, registry[j].name);
  }
}

TEST(ApproachRegistryTest, LinesSayWhatEachApproachIs) {
  EXPECT_FALSE(GetApproachSpec(Approach::kBfsOracle).learner.has_value());
  EXPECT_FALSE(GetApproachSpec(Approach::kIncrementalOracle).learner.has_value());
  EXPECT_EQ(GetApproachSpec(Approach::kOnlyTrainLeafNodes).learner, LearnerKind::kSingleAgent);
  EXPECT_EQ(GetApproachSpec(Approach::kSingleAgent).learner, LearnerKind::kSingleAgent);
  EXPECT_EQ(GetApproachSpec(Approach::kFedAsynQEqAvg).learner, LearnerKind::kFedAsynQ);
  EXPECT_EQ(GetApproachSpec(Approach::kFedAsynQEqAvg).averaging, Averaging::kEqual);
  EXPECT_EQ(GetApproachSpec(Approach::kFedAsynQImAvg).averaging, Averaging::kImportance);
  EXPECT_EQ(GetApproachSpec(Approach::kOnlyTrainLeafNodes).make_strategy, &MakeLeavesOnlyStrategy);
  EXPECT_EQ(GetApproachSpec(Approach::kSingleAgent).make_strategy, &MakeTreeStrategy);
}

TEST(ApproachRegistryTest, EveryPlannerIsBuiltAndOnlyAStarStaticNeverAdapts) {
  ThreadPool pool(1);
  LocalTrainer trainer(pool);
  for (Approach approach : RegisteredApproaches()) {
    std::unique_ptr<Planner> planner = MakePlanner(approach, PlannerOptions{}, &trainer);
    ASSERT_NE(planner, nullptr);
    EXPECT_EQ(planner->Adapts(), approach != Approach::kAStarStatic) << ApproachName(approach);
  }
}

TEST(ApproachTest, NamesTextListsEveryApproach) {
  const std::string text = ApproachNamesText();
  for (Approach approach : RegisteredApproaches()) {
    EXPECT_NE(text.find(ApproachName(approach)), std::string::npos);
  }
  EXPECT_EQ(text.rfind("A* Static, A* Oracle, BFS Oracle", 0), 0u);
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
