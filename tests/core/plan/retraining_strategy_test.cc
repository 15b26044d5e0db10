#include "core/plan/retraining_strategy.h"

#include <gtest/gtest.h>

#include <map>

namespace dynapath {
namespace {

// Success rates are scripted per node; training a node replaces its rate by
// the next scripted post-training value. Records every Train call.
class ScriptedContext : public TrainingContext {
 public:
  std::map<NodeId, double> rate;
  std::map<NodeId, std::vector<double>> after_training;
  // Rates of other nodes that change when a node is trained (its region
  // overlaps theirs).
  std::map<NodeId, std::map<NodeId, double>> side_effects;
  std::vector<std::vector<NodeId>> train_calls;

  double SuccessRate(NodeId node) override {
    const auto it = rate.find(node);
    return it == rate.end() ? 1.0 : it->second;
  }
  void Train(const std::vector<NodeId>& nodes) override {
    train_calls.push_back(nodes);
    for (NodeId node : nodes) {
      auto& script = after_training[node];
      if (!script.empty()) {
        rate[node] = script.front();
        script.erase(script.begin());
      }
      for (const auto& [other, value] : side_effects[node]) rate[other] = value;
    }
  }
};

// A 16x16 grid with leaf limit 4: root 0, level-1 nodes 1..4, leaves 5..20.
class TreeStrategyTest : public testing::Test {
 protected:
  TreeStrategyTest() : tree_(16, 16, 4) {}
  QuadTree tree_;
};

TEST_F(TreeStrategyTest, InitialTrainingTrainsAllLeavesAndStoresBaselines) {
  TreeStrategy strategy(tree_);
  ScriptedContext context;
  const AdaptationReport report = strategy.Adapt({}, context);
  ASSERT_EQ(context.train_calls.size(), 1u);
  EXPECT_EQ(context.train_calls[0], tree_.leaves());
  EXPECT_EQ(report.highest_level, 2);
  for (NodeId leaf : tree_.leaves()) EXPECT_DOUBLE_EQ(strategy.baseline(leaf), 1.0);
  EXPECT_FALSE(strategy.trained(tree_.root()));
}

// The report's illustration (section 4.2.4): leaves 1, 2, 3 change with old
// rates 0.98, 0.94, 0.91 and new rates 0.975, 0.91, 0.77. Leaf 1 is kept
// (drop 0.005, still >= 0.9); 2 (drop 0.03) and 3 (below 0.9) are retrained,
// to 0.99 and 0.87. Only 3 is still below 0.9, so its parent (old 0.93, now
// 0.91: drop 0.02) is retrained, to 0.97, and the process stops.
TEST_F(TreeStrategyTest, ReportIllustration) {
  TreeStrategy strategy(tree_);
  ScriptedContext context;
  const QuadNode& first_parent = tree_.node(1);
  const NodeId leaf1 = first_parent.children[0];
  const NodeId leaf2 = first_parent.children[1];
  const NodeId leaf3 = tree_.node(2).children[0];
  const NodeId parent3 = tree_.node(leaf3).parent;
  ASSERT_EQ(parent3, 2);
  // Before the illustrated step: initial training leaves leaf 3 at 0.85, so
  // its parent is trained (to 0.93), which also lifts leaf 3 to 0.91.
  context.rate = {{leaf1, 0.98}, {leaf2, 0.94}, {leaf3, 0.85}, {parent3, 0.5}};
  context.after_training[parent3] = {0.93};
  context.side_effects[parent3] = {{leaf3, 0.91}};
  strategy.Adapt({}, context);
  ASSERT_EQ(context.train_calls.size(), 2u);
  ASSERT_DOUBLE_EQ(strategy.baseline(leaf1), 0.98);
  ASSERT_DOUBLE_EQ(strategy.baseline(leaf2), 0.94);
  ASSERT_DOUBLE_EQ(strategy.baseline(leaf3), 0.91);
  ASSERT_DOUBLE_EQ(strategy.baseline(parent3), 0.93);
  context.side_effects.clear();

  // The time step of the illustration.
  context.train_calls.clear();
  context.rate[leaf1] = 0.975;
  context.rate[leaf2] = 0.91;
  context.rate[leaf3] = 0.77;
  context.rate[parent3] = 0.91;
  context.after_training[leaf2] = {0.99};
  context.after_training[leaf3] = {0.87};
  context.after_training[parent3] = {0.97};
  const AdaptationReport report = strategy.Adapt({leaf1, leaf2, leaf3}, context);

  ASSERT_EQ(context.train_calls.size(), 2u);
  EXPECT_EQ(context.train_calls[0], (std::vector<NodeId>{leaf2, leaf3}));
  EXPECT_EQ(context.train_calls[1], (std::vector<NodeId>{parent3}));
  EXPECT_EQ(report.trained, (std::vector<NodeId>{leaf2, leaf3, parent3}));
  EXPECT_EQ(report.highest_level, 1);
  EXPECT_DOUBLE_EQ(strategy.baseline(leaf1), 0.98);  // kept, not lowered
  EXPECT_DOUBLE_EQ(strategy.baseline(leaf2), 0.99);
  EXPECT_DOUBLE_EQ(strategy.baseline(parent3), 0.97);
  // The parent's training refreshed the baselines of its descendants.
  EXPECT_DOUBLE_EQ(strategy.baseline(leaf3), 0.87);
}

TEST_F(TreeStrategyTest, KeepsPolicyAndRaisesBaselineWhenRateImproves) {
  TreeStrategy strategy(tree_);
  ScriptedContext context;
  const NodeId leaf = tree_.leaves()[3];
  context.rate[leaf] = 0.92;
  strategy.Adapt({}, context);
  context.train_calls.clear();
  context.rate[leaf] = 0.95;
  const AdaptationReport report = strategy.Adapt({leaf}, context);
  EXPECT_TRUE(context.train_calls.empty());
  EXPECT_TRUE(report.trained.empty());
  EXPECT_EQ(report.highest_level, -1);
  EXPECT_DOUBLE_EQ(strategy.baseline(leaf), 0.95);
}

TEST_F(TreeStrategyTest, StillLowLeafEscalatesUpToTheRoot) {
  TreeStrategy strategy(tree_);
  ScriptedContext context;
  const NodeId leaf = tree_.leaves()[0];
  const NodeId parent = tree_.node(leaf).parent;
  // The leaf has no station: it stays at 0.5 whatever is trained below the
  // root; its parent (untrained) is trained, still 0.6; the root is trained.
  context.rate = {{leaf, 0.5}, {parent, 0.6}, {tree_.root(), 0.95}};
  context.after_training[leaf] = {0.5};
  context.after_training[parent] = {0.6};
  context.after_training[tree_.root()] = {0.99};
  const AdaptationReport report = strategy.Adapt({}, context);
  ASSERT_EQ(context.train_calls.size(), 3u);
  EXPECT_EQ(context.train_calls[1], (std::vector<NodeId>{parent}));
  EXPECT_EQ(context.train_calls[2], (std::vector<NodeId>{tree_.root()}));
  EXPECT_EQ(report.highest_level, 0);
  EXPECT_TRUE(strategy.trained(tree_.root()));
}

TEST_F(TreeStrategyTest, SiblingsEscalateToTheirParentOnce) {
  TreeStrategy strategy(tree_);
  ScriptedContext context;
  const QuadNode& parent = tree_.node(3);
  for (NodeId child : parent.children) context.rate[child] = 0.4;
  context.rate[parent.id] = 0.95;
  context.after_training[parent.id] = {0.95};
  strategy.Adapt({}, context);
  ASSERT_EQ(context.train_calls.size(), 2u);
  EXPECT_EQ(context.train_calls[1], (std::vector<NodeId>{parent.id}));
}

TEST(LeavesOnlyStrategyTest, TrainsEveryChangedLeafWithoutCondition) {
  const QuadTree tree(16, 16, 4);
  LeavesOnlyStrategy strategy(tree);
  ScriptedContext context;
  strategy.Adapt({}, context);
  ASSERT_EQ(context.train_calls.size(), 1u);
  EXPECT_EQ(context.train_calls[0], tree.leaves());
  context.train_calls.clear();
  context.rate[tree.leaves()[2]] = 0.1;  // low, but no escalation
  const AdaptationReport report = strategy.Adapt({tree.leaves()[2], tree.leaves()[5]}, context);
  ASSERT_EQ(context.train_calls.size(), 1u);
  EXPECT_EQ(context.train_calls[0], (std::vector<NodeId>{tree.leaves()[2], tree.leaves()[5]}));
  EXPECT_EQ(report.highest_level, 2);
}

}  // namespace
}  // namespace dynapath
