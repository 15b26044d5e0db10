#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/learner_options.h"
#endif
// When to (re)train which quadtree node (SPEC section 5). The strategies see
// the world only through TrainingContext, so the decisions can be tested with
// scripted success rates and a fake trainer, and run unchanged over a local
// or a distributed trainer. Private to core: the planner's options carry
// their thresholds (RetrainingThresholds, dynapath/learner_options.h).

#include <memory>
#include <vector>

#include "dynapath/learner_options.h"
#include "dynapath/quadtree.h"

namespace dynapath {

// What a strategy needs from the world.
class TrainingContext {
 public:
  virtual ~TrainingContext() = default;
  // Success rate of `node`'s region under the policy now in force.
  virtual double SuccessRate(NodeId node) = 0;
  // Trains `nodes` (ascending ids, pairwise disjoint) and puts the result in force.
  virtual void Train(const std::vector<NodeId>& nodes) = 0;
};

struct AdaptationReport {
  std::vector<NodeId> trained;  // every trained node, in training order
  int highest_level = -1;       // smallest level trained (0 = root), -1 if none
};

class RetrainingStrategy {
 public:
  virtual ~RetrainingStrategy() = default;
  // One time step: `changed_leaves` are the leaves (ascending ids) holding a
  // changed cell; empty means initial training. It is FirstToTrain then
  // TrainFrom, the two calls a planner makes separately when its caller acts
  // between deciding and training (Planner::TakeChanges and Retrain).
  AdaptationReport Adapt(const std::vector<NodeId>& changed_leaves, TrainingContext& context) {
    return TrainFrom(FirstToTrain(changed_leaves, context), context);
  }
  // The nodes the step trains first (ascending ids), decided without
  // training anything: empty when the step trains nothing.
  virtual std::vector<NodeId> FirstToTrain(const std::vector<NodeId>& changed_leaves,
                                           TrainingContext& context) = 0;
  // Trains `first` (FirstToTrain's answer) and whatever follows from it.
  virtual AdaptationReport TrainFrom(const std::vector<NodeId>& first,
                                     TrainingContext& context) = 0;
  // The per-node success rates the strategy keeps between steps (-1: never
  // trained), for saving a policy; empty for a strategy that keeps none.
  // RestoreBaselines takes back what Baselines returned (same size).
  virtual std::vector<double> Baselines() const { return {}; }
  virtual void RestoreBaselines(const std::vector<double>& /*baselines*/) {}
};

// The report's tree strategy: success-rate condition on changed leaves, then
// escalation to parents whose child is still below the minimum rate.
class TreeStrategy : public RetrainingStrategy {
 public:
  // `tree` must outlive the strategy.
  TreeStrategy(const QuadTree& tree, RetrainingThresholds thresholds = {});

  std::vector<NodeId> FirstToTrain(const std::vector<NodeId>& changed_leaves,
                                   TrainingContext& context) override;
  AdaptationReport TrainFrom(const std::vector<NodeId>& first, TrainingContext& context) override;

  // Stored baseline success rate of a node; negative when never trained.
  double baseline(NodeId node) const { return baseline_[node]; }
  bool trained(NodeId node) const { return baseline_[node] >= 0.0; }
  std::vector<double> Baselines() const override { return baseline_; }
  void RestoreBaselines(const std::vector<double>& baselines) override;

 private:
  // The retraining condition of SPEC 5.1: true = retrain. Otherwise raises
  // the stored baseline when the rate went up.
  bool NeedsTraining(NodeId node, TrainingContext& context);
  // Trains `nodes`, stores baselines of them and their descendants, and
  // returns the sorted parents of trained nodes still below the minimum.
  std::vector<NodeId> TrainAndCollectParents(const std::vector<NodeId>& nodes,
                                             TrainingContext& context, AdaptationReport& report);
  void StoreBaselines(NodeId node, TrainingContext& context);

  const QuadTree& tree_;
  RetrainingThresholds thresholds_;
  std::vector<double> baseline_;
};

// onlyTrainLeafNodes: all leaves at first, then every changed leaf, with no
// condition and no escalation.
class LeavesOnlyStrategy : public RetrainingStrategy {
 public:
  explicit LeavesOnlyStrategy(const QuadTree& tree) : tree_(tree) {}
  std::vector<NodeId> FirstToTrain(const std::vector<NodeId>& changed_leaves,
                                   TrainingContext& context) override;
  AdaptationReport TrainFrom(const std::vector<NodeId>& first, TrainingContext& context) override;

 private:
  const QuadTree& tree_;
};

// The strategy factories named in core/include/dynapath/approach_list.h.
std::unique_ptr<RetrainingStrategy> MakeTreeStrategy(const QuadTree& tree,
                                                     const RetrainingThresholds& thresholds);
std::unique_ptr<RetrainingStrategy> MakeLeavesOnlyStrategy(const QuadTree& tree,
                                                           const RetrainingThresholds& thresholds);

}  // namespace dynapath
