#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/planner.h"
#endif
// The four Q-learning approaches: a quadtree, the root table, a retraining
// strategy and a trainer.

#include <memory>
#include <optional>

#include "core/eval/incremental_policy_evaluation.h"
#include "core/plan/approach_registry.h"
#include "dynapath/planner.h"

namespace dynapath {

// A policy's picture from the incremental evaluation of its table: each
// cell's depth, and its two best actions read back from the successors the
// evaluation keeps (two a cell), which is the table's TopTwoActions without
// its values. Shared by every planner whose policy is a Q-table.
void PictureFromSuccessors(const Grid& grid, const std::vector<int32_t>& depth,
                           const std::vector<int32_t>& successors, PolicyPicture& picture);

class LearningPlanner : public Planner, private TrainingContext {
 public:
  // `approach` must be registered with a learner (IsLearningApproach).
  LearningPlanner(Approach approach, const PlannerOptions& options, Trainer& trainer);

  StepDetails Initialize(const Grid& grid) override;
  StepDetails Adapt(const Grid& grid, const std::vector<int>& changed_cells) override;
  bool TakeChanges(const Grid& grid, const std::vector<int>& changed_cells) override;
  StepDetails Retrain() override;
  PolicyScore Evaluate(const Grid& grid) override;
  bool Picture(const Grid& grid, PolicyPicture& picture) override;
  bool ExportPolicy(PolicyState& state) const override;
  Status ImportPolicy(const PolicyState& state, const Grid& grid) override;

  const QuadTree& tree() const { return *tree_; }
  const RootQTable& root() const { return *root_; }

 private:
  // TrainingContext: success rates of the current policy on the current grid.
  double SuccessRate(NodeId node) override;
  void Train(const std::vector<NodeId>& nodes) override;

  StepDetails Details(const AdaptationReport& report) const;
  // Initialize's part before training: a fresh tree, table, counts, strategy.
  void Reset(const Grid& grid);
  // Whether some ancestor of `node` has been trained (--semantics report's
  // first-training rule).
  bool AncestorTrained(NodeId node) const;

  const ApproachSpec& spec_;  // its learner and strategy
  PlannerOptions options_;
  LearnerConfig learner_;
  Trainer& trainer_;
  const Grid* grid_ = nullptr;  // the grid of the step being adapted
  // TakeChanges' decision: the nodes Retrain trains first.
  std::vector<NodeId> first_to_train_;
  std::unique_ptr<QuadTree> tree_;
  std::unique_ptr<RootQTable> root_;
  std::unique_ptr<RetrainingStrategy> strategy_;
  std::vector<int64_t> training_count_;  // per node, for job seeds
  // The evaluation behind the success rates, repaired where cells changed
  // or regions were retrained instead of redone every query.
  IncrementalPolicyEvaluation evaluation_;
};

}  // namespace dynapath
