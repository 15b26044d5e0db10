#include "core/eval/incremental_policy_evaluation.h"

#include "dynapath/mdp.h"

namespace dynapath {

void IncrementalPolicyEvaluation::Reset(const QuadTree& tree) {
  tree_ = &tree;
  built_ = false;
  pending_cells_.clear();
  pending_regions_.clear();
}

void IncrementalPolicyEvaluation::GridChanged(const std::vector<int>& cells) {
  if (built_) pending_cells_.insert(pending_cells_.end(), cells.begin(), cells.end());
}

void IncrementalPolicyEvaluation::TableChanged(const Region& region) {
  if (built_) pending_regions_.push_back(region);
}

const std::vector<int32_t>& IncrementalPolicyEvaluation::Depths(const Grid& grid,
                                                                const QTable& table) {
  Update(grid, table);
  return depths_.values();
}

const std::vector<int32_t>& IncrementalPolicyEvaluation::Successors(const Grid& grid,
                                                                    const QTable& table) {
  Update(grid, table);
  return successors_;
}

const PolicyScore& IncrementalPolicyEvaluation::Score(const Grid& grid, const QTable& table,
                                                      NodeId node) {
  Update(grid, table);
  return scores_[node];
}

void IncrementalPolicyEvaluation::Successors(const Grid& grid, const QTable& table, int cell,
                                             int32_t& first, int32_t& second) const {
  int best, next;
  TopTwoActions(grid, cell, table, best, next);
  const int cols = grid.cols();
  first = best < 0 ? -1 : cell + kActionRowOffset[best] * cols + kActionColOffset[best];
  second = next < 0 ? -1 : cell + kActionRowOffset[next] * cols + kActionColOffset[next];
}

void IncrementalPolicyEvaluation::Count(int cell, Cell code, int32_t depth, int sign) {
  if (code == Cell::kObstacle) return;
  const bool success = depth != kNoPath;
  for (NodeId node = tree_->LeafOf(cell); node != kNoNode; node = tree_->node(node).parent) {
    PolicyScore& score = scores_[node];
    score.starts += sign;
    if (success) {
      score.successes += sign;
      score.total_length += sign * static_cast<int64_t>(depth);
    }
  }
}

void IncrementalPolicyEvaluation::Build(const Grid& grid, const QTable& table) {
  const int n = grid.size();
  successors_.resize(static_cast<size_t>(n) * 2);
  for (int cell = 0; cell < n; ++cell) {
    Successors(grid, table, cell, successors_[2 * cell], successors_[2 * cell + 1]);
  }
  depths_.Build(PolicyGraph(grid, successors_), grid.rows() + grid.cols());
  codes_ = grid.codes();
  marked_.assign(static_cast<size_t>(n), 0);
  scores_.assign(static_cast<size_t>(tree_->node_count()), PolicyScore{});
  // Leaves first, then each node from its children: linear in the cells.
  for (int cell = 0; cell < n; ++cell) {
    if (grid.at(cell) == Cell::kObstacle) continue;
    PolicyScore& score = scores_[tree_->LeafOf(cell)];
    ++score.starts;
    if (depths_.value(cell) != kNoPath) {
      ++score.successes;
      score.total_length += depths_.value(cell);
    }
  }
  for (NodeId node = tree_->node_count() - 1; node >= 0; --node) {
    const QuadNode& q = tree_->node(node);
    if (q.is_leaf()) continue;
    PolicyScore sum;
    for (NodeId child : q.children) {
      if (child == kNoNode) continue;
      sum.starts += scores_[child].starts;
      sum.successes += scores_[child].successes;
      sum.total_length += scores_[child].total_length;
    }
    scores_[node] = sum;
  }
  built_ = true;
}

void IncrementalPolicyEvaluation::Update(const Grid& grid, const QTable& table) {
  if (!built_) {
    Build(grid, table);
    return;
  }
  if (pending_cells_.empty() && pending_regions_.empty()) return;
  // The graph nodes whose own definition changed: cells whose code changed,
  // cells of retrained regions whose top-2 successors changed.
  changed_.assign(pending_cells_.begin(), pending_cells_.end());
  for (const Region& region : pending_regions_) {
    for (int r = region.r0; r <= region.r1; ++r) {
      for (int c = region.c0; c <= region.c1; ++c) {
        const int cell = grid.Index(r, c);
        int32_t first, second;
        Successors(grid, table, cell, first, second);
        if (first == successors_[2 * cell] && second == successors_[2 * cell + 1]) continue;
        successors_[2 * cell] = first;
        successors_[2 * cell + 1] = second;
        changed_.push_back(cell);
      }
    }
  }
  pending_cells_.clear();
  pending_regions_.clear();
  // Take out the old part of every cell whose code or depth changes, repair,
  // put back the new part.
  touched_.clear();
  for (int cell : changed_) {
    if (marked_[cell]) continue;
    marked_[cell] = 1;
    touched_.push_back(cell);
    Count(cell, static_cast<Cell>(codes_[cell]), depths_.value(cell), -1);
  }
  depths_.Repair(PolicyGraph(grid, successors_), changed_);
  for (const DynamicDistances::ValueChange& change : depths_.changes()) {
    if (marked_[change.node]) continue;
    marked_[change.node] = 1;
    touched_.push_back(change.node);
    Count(change.node, static_cast<Cell>(codes_[change.node]), change.old_value, -1);
  }
  for (int cell : touched_) {
    marked_[cell] = 0;
    codes_[cell] = static_cast<uint8_t>(grid.at(cell));
    Count(cell, grid.at(cell), depths_.value(cell), +1);
  }
}

}  // namespace dynapath
