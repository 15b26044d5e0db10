#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/policy_evaluation.h"
#endif
// The policy evaluation of SPEC section 4 kept up to date incrementally, with
// the success figures of every quadtree node, for the retraining decisions.
//
// The depths are those of PolicyEvaluator (the reverse breadth-first search
// over the top-2 policy graph, depth bound rows + cols) but maintained by a
// DynamicDistances repair: a step's changed cells and the cells whose top-2
// actions changed in a retrained region are repaired, nothing else is
// visited. Each node's PolicyScore is kept by adding what changed along the
// leaf-to-root path of each changed cell. The figures are exactly the full
// evaluation's (integers, same definition), only cheaper.

#include <cstdint>
#include <vector>

#include "core/plan/dynamic_distances.h"
#include "dynapath/grid.h"
#include "dynapath/policy_evaluation.h"
#include "dynapath/q_table.h"
#include "dynapath/quadtree.h"
#include "dynapath/region.h"

namespace dynapath {

// The top-2 policy graph as a DynamicDistances graph. Successors are the
// in-grid targets of a cell's two best actions whatever the targets hold (an
// obstacle target is blocked, so its edge carries nothing, as in
// PolicyEvaluator); predecessors of a cell are the neighbours whose
// successors include it.
class PolicyGraph {
 public:
  PolicyGraph(const Grid& grid, const std::vector<int32_t>& successors)
      : grid_(grid), successors_(successors) {}
  int size() const { return grid_.size(); }
  bool IsBlocked(int v) const { return grid_.at(v) == Cell::kObstacle; }
  bool IsSource(int v) const { return grid_.at(v) == Cell::kStation; }
  template <class F>
  void ForEachSuccessor(int v, F f) const {
    for (int k = 0; k < 2; ++k) {
      if (successors_[2 * v + k] >= 0) f(successors_[2 * v + k]);
    }
  }
  template <class F>
  void ForEachPredecessor(int u, F f) const {
    const int rows = grid_.rows(), cols = grid_.cols();
    const int row = u / cols, col = u % cols;
    for (int dr = -1; dr <= 1; ++dr) {
      const int r = row + dr;
      if (r < 0 || r >= rows) continue;
      for (int dc = -1; dc <= 1; ++dc) {
        const int c = col + dc;
        if ((dr == 0 && dc == 0) || c < 0 || c >= cols) continue;
        const int v = r * cols + c;
        if (successors_[2 * v] == u || successors_[2 * v + 1] == u) f(v);
      }
    }
  }

 private:
  const Grid& grid_;
  const std::vector<int32_t>& successors_;
};

class IncrementalPolicyEvaluation {
 public:
  // Starts over for a new run on `tree` (which must outlive this object);
  // the first query evaluates in full.
  void Reset(const QuadTree& tree);
  // The cells whose codes changed since the last query.
  void GridChanged(const std::vector<int>& cells);
  // The table's values changed over `region` (a retrained node).
  void TableChanged(const Region& region);

  // Per-cell depths (PolicyEvaluator's), up to date for `grid` and `table`.
  const std::vector<int32_t>& Depths(const Grid& grid, const QTable& table);
  // Per cell, the targets of its two best actions (TopTwoActions: 2 per
  // cell, best first, -1 none), up to date like Depths.
  const std::vector<int32_t>& Successors(const Grid& grid, const QTable& table);
  // The score of `node`'s region (ScoreRegion of the full evaluation).
  const PolicyScore& Score(const Grid& grid, const QTable& table, NodeId node);

 private:
  void Update(const Grid& grid, const QTable& table);
  void Build(const Grid& grid, const QTable& table);
  // Adds (sign +1) or removes (-1) one cell's part of its nodes' scores.
  void Count(int cell, Cell code, int32_t depth, int sign);
  void Successors(const Grid& grid, const QTable& table, int cell, int32_t& first,
                  int32_t& second) const;

  const QuadTree* tree_ = nullptr;
  bool built_ = false;
  DynamicDistances depths_;
  std::vector<int32_t> successors_;  // 2 per cell, -1 = none
  std::vector<uint8_t> codes_;       // the grid as last seen, for the old codes
  std::vector<PolicyScore> scores_;  // per node
  std::vector<int> pending_cells_;   // changed cells not yet repaired
  std::vector<Region> pending_regions_;
  std::vector<int> changed_;  // scratch: nodes of the graph to repair
  std::vector<uint8_t> marked_;
  std::vector<int> touched_;
};

}  // namespace dynapath
