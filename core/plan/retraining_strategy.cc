#include "core/plan/retraining_strategy.h"

#include <algorithm>

namespace dynapath {
namespace {

void RecordTraining(const QuadTree& tree, const std::vector<NodeId>& nodes,
                    AdaptationReport& report) {
  for (NodeId node : nodes) {
    report.trained.push_back(node);
    const int level = tree.node(node).level;
    if (report.highest_level < 0 || level < report.highest_level) report.highest_level = level;
  }
}

}  // namespace

TreeStrategy::TreeStrategy(const QuadTree& tree, RetrainingThresholds thresholds)
    : tree_(tree),
      thresholds_(thresholds),
      baseline_(static_cast<size_t>(tree.node_count()), -1.0) {}

void TreeStrategy::RestoreBaselines(const std::vector<double>& baselines) {
  if (baselines.size() == baseline_.size()) baseline_ = baselines;
}

bool TreeStrategy::NeedsTraining(NodeId node, TrainingContext& context) {
  if (!trained(node)) return true;
  const double old_rate = baseline_[node];
  const double new_rate = context.SuccessRate(node);
  if (old_rate - new_rate > thresholds_.max_drop || new_rate < thresholds_.min_success_rate) {
    return true;
  }
  if (new_rate > old_rate) baseline_[node] = new_rate;
  return false;
}

void TreeStrategy::StoreBaselines(NodeId node, TrainingContext& context) {
  baseline_[node] = context.SuccessRate(node);
  for (NodeId child : tree_.node(node).children) {
    if (child != kNoNode) StoreBaselines(child, context);
  }
}

std::vector<NodeId> TreeStrategy::TrainAndCollectParents(const std::vector<NodeId>& nodes,
                                                         TrainingContext& context,
                                                         AdaptationReport& report) {
  context.Train(nodes);
  RecordTraining(tree_, nodes, report);
  for (NodeId node : nodes) StoreBaselines(node, context);
  std::vector<NodeId> parents;
  for (NodeId node : nodes) {
    const NodeId parent = tree_.node(node).parent;
    if (parent != kNoNode && baseline_[node] < thresholds_.escalate_below) {
      parents.push_back(parent);
    }
  }
  // Node-id order, never hash or pointer order: same inputs, same decisions.
  std::sort(parents.begin(), parents.end());
  parents.erase(std::unique(parents.begin(), parents.end()), parents.end());
  return parents;
}

std::vector<NodeId> TreeStrategy::FirstToTrain(const std::vector<NodeId>& changed_leaves,
                                               TrainingContext& context) {
  if (changed_leaves.empty()) return tree_.leaves();
  std::vector<NodeId> to_train;
  for (NodeId leaf : changed_leaves) {
    if (NeedsTraining(leaf, context)) to_train.push_back(leaf);
  }
  return to_train;
}

AdaptationReport TreeStrategy::TrainFrom(const std::vector<NodeId>& first,
                                         TrainingContext& context) {
  AdaptationReport report;
  std::vector<NodeId> to_train = first;
  while (!to_train.empty()) {
    const std::vector<NodeId> candidates = TrainAndCollectParents(to_train, context, report);
    to_train.clear();
    for (NodeId candidate : candidates) {
      if (NeedsTraining(candidate, context)) to_train.push_back(candidate);
    }
  }
  return report;
}

std::vector<NodeId> LeavesOnlyStrategy::FirstToTrain(const std::vector<NodeId>& changed_leaves,
                                                     TrainingContext& /*context*/) {
  return changed_leaves.empty() ? tree_.leaves() : changed_leaves;
}

AdaptationReport LeavesOnlyStrategy::TrainFrom(const std::vector<NodeId>& first,
                                               TrainingContext& context) {
  AdaptationReport report;
  if (!first.empty()) {
    context.Train(first);
    RecordTraining(tree_, first, report);
  }
  return report;
}

std::unique_ptr<RetrainingStrategy> MakeTreeStrategy(const QuadTree& tree,
                                                     const RetrainingThresholds& thresholds) {
  return std::make_unique<TreeStrategy>(tree, thresholds);
}

std::unique_ptr<RetrainingStrategy> MakeLeavesOnlyStrategy(const QuadTree& tree,
                                                           const RetrainingThresholds&) {
  return std::make_unique<LeavesOnlyStrategy>(tree);
}

}  // namespace dynapath
