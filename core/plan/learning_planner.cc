#include "core/plan/learning_planner.h"

#include <algorithm>
#include <array>
#include <cassert>

#include "dynapath/mdp.h"
#include "dynapath/policy_state.h"

namespace dynapath {

LearningPlanner::LearningPlanner(Approach approach, const PlannerOptions& options, Trainer& trainer)
    : spec_(GetApproachSpec(approach)), options_(options), trainer_(trainer) {
  // Only approaches registered with a learner and a strategy get here.
  assert(spec_.learner.has_value() && spec_.make_strategy != nullptr);
  learner_.kind = *spec_.learner;
  static_cast<LearnerOptions&>(learner_) = options;
  learner_.federated.averaging = spec_.averaging;
  learner_.bootstrap =
      options.semantics == Semantics::kReport ? Bootstrap::kAllStored : options.bootstrap;
}

std::unique_ptr<Planner> MakeLearningPlanner(const ApproachSpec& spec,
                                             const PlannerOptions& options, Trainer* trainer) {
  assert(trainer != nullptr);  // the runners always pass one
  return std::make_unique<LearningPlanner>(spec.approach, options, *trainer);
}

StepDetails LearningPlanner::Initialize(const Grid& grid) {
  Reset(grid);
  return Details(strategy_->Adapt({}, *this));
}

void LearningPlanner::Reset(const Grid& grid) {
  tree_ = std::make_unique<QuadTree>(grid.rows(), grid.cols(), options_.leaf_limit);
  // The report's code keeps its tables in double (SPEC section 10).
  const QPrecision precision = options_.table_precision.value_or(
      options_.semantics == Semantics::kReport ? QPrecision::kDouble : QPrecision::kFloat);
  root_ = std::make_unique<RootQTable>(grid.rows(), grid.cols(), precision);
  training_count_.assign(static_cast<size_t>(tree_->node_count()), 0);
  strategy_ = spec_.make_strategy(*tree_, options_.thresholds);
  grid_ = &grid;
  evaluation_.Reset(*tree_);
}

bool LearningPlanner::ExportPolicy(PolicyState& state) const {
  state.approach = spec_.approach;
  state.rows = root_->rows();
  state.cols = root_->cols();
  state.leaf_limit = options_.leaf_limit;
  state.node_count = tree_->node_count();
  state.semantics = options_.semantics;
  state.precision = root_->precision();
  state.learner = options_;
  state.thresholds = options_.thresholds;
  state.run_seed = options_.run_seed;
  state.training_counts = training_count_;
  state.baselines = strategy_->Baselines();
  state.table = root_->table();
  return true;
}

Status LearningPlanner::ImportPolicy(const PolicyState& state, const Grid& grid) {
  if (Status fits = CheckPolicyFits(state, spec_.approach, options_, grid.rows(), grid.cols());
      !fits) {
    return fits;
  }
  if (Status consistent = CheckPolicyConsistent(state); !consistent) return consistent;
  Reset(grid);
  if (state.baselines.size() != strategy_->Baselines().size()) {
    return Error::Corrupt("the policy's baselines do not match " + ApproachName(spec_.approach));
  }
  root_->table() = state.table;
  training_count_ = state.training_counts;
  strategy_->RestoreBaselines(state.baselines);
  // Build the evaluation now, as the initial training did: its cost belongs
  // to loading, not to the next step's adaptation time.
  grid_ = &grid;
  evaluation_.Score(grid, root_->table(), tree_->root());
  return Ok{};
}

StepDetails LearningPlanner::Adapt(const Grid& grid, const std::vector<int>& changed_cells) {
  TakeChanges(grid, changed_cells);
  return Retrain();
}

bool LearningPlanner::TakeChanges(const Grid& grid, const std::vector<int>& changed_cells) {
  std::vector<NodeId> changed_leaves;
  for (int cell : changed_cells) changed_leaves.push_back(tree_->LeafOf(cell));
  std::sort(changed_leaves.begin(), changed_leaves.end());
  changed_leaves.erase(std::unique(changed_leaves.begin(), changed_leaves.end()),
                       changed_leaves.end());
  grid_ = &grid;
  evaluation_.GridChanged(changed_cells);
  first_to_train_.clear();
  if (!changed_leaves.empty()) first_to_train_ = strategy_->FirstToTrain(changed_leaves, *this);
  return !first_to_train_.empty();
}

StepDetails LearningPlanner::Retrain() {
  if (first_to_train_.empty()) return {};
  const std::vector<NodeId> first = std::move(first_to_train_);
  first_to_train_.clear();
  return Details(strategy_->TrainFrom(first, *this));
}

StepDetails LearningPlanner::Details(const AdaptationReport& report) const {
  StepDetails details{static_cast<int>(report.trained.size()), report.highest_level, {}};
  for (NodeId node : report.trained) details.trained_regions.push_back(tree_->node(node).region);
  return details;
}

PolicyScore LearningPlanner::Evaluate(const Grid& grid) {
  grid_ = &grid;
  return evaluation_.Score(grid, root_->table(), tree_->root());
}

namespace {

// The action that moves `cell` to its neighbour `target` (-1 for none),
// by a table over the 3x3 neighbourhood.
int8_t ActionTo(int cell, int32_t target, int cols) {
  static constexpr auto kByOffset = [] {
    std::array<int8_t, 9> by{-1, -1, -1, -1, -1, -1, -1, -1, -1};
    for (int a = 0; a < kNumActions; ++a) {
      by[static_cast<size_t>((kActionRowOffset[a] + 1) * 3 + kActionColOffset[a] + 1)] =
          static_cast<int8_t>(a);
    }
    return by;
  }();
  if (target < 0) return -1;
  const int dr = target / cols - cell / cols, dc = target % cols - cell % cols;
  return kByOffset[static_cast<size_t>((dr + 1) * 3 + dc + 1)];
}

}  // namespace

void PictureFromSuccessors(const Grid& grid, const std::vector<int32_t>& depth,
                           const std::vector<int32_t>& successors, PolicyPicture& picture) {
  const int cols = grid.cols();
  picture.actions.assign(static_cast<size_t>(grid.size()), -1);
  picture.reaches.assign(static_cast<size_t>(grid.size()), -1);
  picture.second.assign(static_cast<size_t>(grid.size()), -1);
  picture.depth = depth;
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (grid.at(cell) == Cell::kObstacle) continue;
    picture.reaches[cell] = depth[cell] == kNoPath ? 0 : 1;
    if (grid.at(cell) == Cell::kStation) continue;
    picture.actions[cell] = ActionTo(cell, successors[2 * static_cast<size_t>(cell)], cols);
    picture.second[cell] = ActionTo(cell, successors[2 * static_cast<size_t>(cell) + 1], cols);
  }
}

bool LearningPlanner::Picture(const Grid& grid, PolicyPicture& picture) {
  grid_ = &grid;
  const std::vector<int32_t>& depth = evaluation_.Depths(grid, root_->table());
  PictureFromSuccessors(grid, depth, evaluation_.Successors(grid, root_->table()), picture);
  return true;
}

double LearningPlanner::SuccessRate(NodeId node) {
  return evaluation_.Score(*grid_, root_->table(), node).success_rate();
}

bool LearningPlanner::AncestorTrained(NodeId node) const {
  for (NodeId up = tree_->node(node).parent; up != kNoNode; up = tree_->node(up).parent) {
    if (training_count_[up] > 0) return true;
  }
  return false;
}

void LearningPlanner::Train(const std::vector<NodeId>& nodes) {
  std::vector<uint64_t> seeds;
  seeds.reserve(nodes.size());
  for (NodeId node : nodes) {
    // The report's code keeps a table per node (only the root has one from
    // the start) and, after a node is trained, copies its table into every
    // ancestor and every descendant, creating theirs. A node's first training
    // therefore starts from zeros only when no ancestor of it has been
    // trained (its table is created then, all zeros); otherwise it keeps the
    // copy, which is the root's values over its region (SPEC 11.3).
    // Zeroing the root over the region before the job is built gives the
    // job exactly that warm start, with any trainer (local or distributed);
    // the job then commits its whole table over the region, as the report
    // copies a trained node's table into its ancestors. Nodes of one call are
    // disjoint, so no other job of the batch reads these values.
    if (options_.semantics == Semantics::kReport && training_count_[node] == 0 &&
        node != tree_->root() && !AncestorTrained(node)) {
      const Region& region = tree_->node(node).region;
      root_->Commit(region, QTable(region.cells(), root_->precision()));
    }
    seeds.push_back(JobSeed(options_.run_seed, node, training_count_[node]++));
  }
  trainer_.Train(nodes, seeds, learner_, *tree_, *grid_, *root_);
  for (NodeId node : nodes) evaluation_.TableChanged(tree_->node(node).region);
}

}  // namespace dynapath
