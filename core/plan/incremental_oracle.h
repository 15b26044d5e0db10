#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/planner.h"
#endif
// Incremental Oracle: the exact optimum of the BFS Oracle (distance from
// every cell to its nearest station over free 8-connected moves), kept by
// repairing the distances from the changed cells only (DynamicDistances)
// instead of one whole-grid search per step. Its score is kept the same way,
// so a step costs in proportion to the cells whose distance changes.

#include <cstdint>
#include <vector>

#include "core/plan/dynamic_distances.h"
#include "dynapath/grid.h"
#include "dynapath/planner.h"

namespace dynapath {

// The grid's moves as a DynamicDistances graph: 8 in-grid neighbours, both
// ways (a diagonal move ignores the side cells, so moves are symmetric).
class GridMoves {
 public:
  explicit GridMoves(const Grid& grid) : grid_(grid) {}
  int size() const { return grid_.size(); }
  bool IsBlocked(int v) const { return grid_.at(v) == Cell::kObstacle; }
  bool IsSource(int v) const { return grid_.at(v) == Cell::kStation; }
  template <class F>
  void ForEachSuccessor(int v, F f) const {
    const int rows = grid_.rows(), cols = grid_.cols();
    const int row = v / cols, col = v % cols;
    for (int dr = -1; dr <= 1; ++dr) {
      const int r = row + dr;
      if (r < 0 || r >= rows) continue;
      for (int dc = -1; dc <= 1; ++dc) {
        const int c = col + dc;
        if ((dr == 0 && dc == 0) || c < 0 || c >= cols) continue;
        f(r * cols + c);
      }
    }
  }
  template <class F>
  void ForEachPredecessor(int u, F f) const {
    ForEachSuccessor(u, f);
  }

 private:
  const Grid& grid_;
};

// The grid's moves with one cell, a goal, as the only source: the moves of
// goal-rooted distance fields (the fleet's and the goal service's).
class GoalMoves {
 public:
  GoalMoves(const Grid& grid, int goal) : moves_(grid), grid_(grid), goal_(goal) {}
  int size() const { return grid_.size(); }
  bool IsBlocked(int v) const { return grid_.at(v) == Cell::kObstacle; }
  bool IsSource(int v) const { return v == goal_; }
  template <class F>
  void ForEachSuccessor(int v, F f) const {
    moves_.ForEachSuccessor(v, f);
  }
  template <class F>
  void ForEachPredecessor(int u, F f) const {
    moves_.ForEachSuccessor(u, f);
  }

 private:
  GridMoves moves_;
  const Grid& grid_;
  int goal_;
};

class IncrementalOraclePlanner : public Planner {
 public:
  StepDetails Initialize(const Grid& grid) override;
  StepDetails Adapt(const Grid& grid, const std::vector<int>& changed_cells) override;
  PolicyScore Evaluate(const Grid& grid) override;

  // Current distances (kUnreachable = -1 where no station is reachable).
  const std::vector<int32_t>& distances() const { return distances_.values(); }
  const std::vector<int32_t>* ExactDistances() const override { return &distances_.values(); }

 private:
  // Adds (sign +1) or removes (-1) one cell's part of the score.
  void Count(Cell code, int32_t distance, int sign);

  DynamicDistances distances_;
  std::vector<uint8_t> codes_;  // the grid as last seen, for the old codes
  std::vector<uint8_t> marked_;
  std::vector<int> touched_;
  PolicyScore score_;
};

}  // namespace dynapath
