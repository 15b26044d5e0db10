#include "dynapath/policy_evaluation.h"

#include "dynapath/mdp.h"

namespace dynapath {

void PolicyEvaluator::Evaluate(const Grid& grid, const QTable& root, PolicyDepths& out) {
  const int n = grid.size();
  const int cols = grid.cols();
  ClearEdges(n);
  // Forward edges: a station ends a path, an obstacle is never a start, so
  // only free cells need successors.
  for (int cell = 0; cell < n; ++cell) {
    if (grid.at(cell) != Cell::kFree) continue;
    int best, second;
    TopTwoActions(grid, cell, root, best, second);
    int k = 0;
    for (int a : {best, second}) {
      if (a < 0) continue;
      const int target = cell + kActionRowOffset[a] * cols + kActionColOffset[a];
      if (grid.at(target) == Cell::kObstacle) continue;
      successors_[2 * cell + k++] = target;
      ++in_offsets_[target + 1];
    }
  }
  SearchFromStations(grid, out);
}

void PolicyEvaluator::Evaluate(const Grid& grid, const int8_t* actions, PolicyDepths& out) {
  const int n = grid.size();
  const int cols = grid.cols();
  ClearEdges(n);
  // One successor per free cell: its action's target, when in the grid and
  // not an obstacle (no action, -1, or a bump ends the path).
  for (int cell = 0; cell < n; ++cell) {
    if (grid.at(cell) != Cell::kFree) continue;
    const int a = actions[cell];
    if (a < 0 || a >= kNumActions) continue;
    const int row = grid.RowOf(cell) + kActionRowOffset[a];
    const int col = grid.ColOf(cell) + kActionColOffset[a];
    if (!grid.InBounds(row, col)) continue;
    const int target = row * cols + col;
    if (grid.at(target) == Cell::kObstacle) continue;
    successors_[2 * cell] = target;
    ++in_offsets_[target + 1];
  }
  SearchFromStations(grid, out);
}

void PolicyEvaluator::ClearEdges(int cells) {
  successors_.assign(static_cast<size_t>(cells) * 2, -1);
  in_offsets_.assign(static_cast<size_t>(cells) + 1, 0);
}

void PolicyEvaluator::SearchFromStations(const Grid& grid, PolicyDepths& out) {
  const int n = grid.size();
  for (int cell = 0; cell < n; ++cell) in_offsets_[cell + 1] += in_offsets_[cell];
  in_edges_.resize(static_cast<size_t>(in_offsets_[n]));
  {
    // Fill by a cursor per target; start cells are visited in increasing
    // order, so the edge order is deterministic.
    std::vector<int32_t>& cursor = queue_;
    cursor.assign(in_offsets_.begin(), in_offsets_.end() - 1);
    for (int cell = 0; cell < n; ++cell) {
      for (int k = 0; k < 2; ++k) {
        const int target = successors_[2 * cell + k];
        if (target >= 0) in_edges_[cursor[target]++] = cell;
      }
    }
  }
  // Reverse breadth-first search from all stations.
  out.depth.assign(static_cast<size_t>(n), kNoPath);
  queue_.resize(static_cast<size_t>(n));
  size_t head = 0, tail = 0;
  for (int cell = 0; cell < n; ++cell) {
    if (grid.at(cell) == Cell::kStation) {
      out.depth[cell] = 0;
      queue_[tail++] = cell;
    }
  }
  const int32_t depth_limit = grid.rows() + grid.cols();  // success needs depth < limit
  while (head < tail) {
    const int cell = queue_[head++];
    const int32_t next_depth = out.depth[cell] + 1;
    if (next_depth >= depth_limit) continue;
    for (int32_t e = in_offsets_[cell]; e < in_offsets_[cell + 1]; ++e) {
      const int source = in_edges_[e];
      if (out.depth[source] != kNoPath) continue;
      out.depth[source] = next_depth;
      queue_[tail++] = source;
    }
  }
}

PolicyScore ScoreRegion(const Grid& grid, const PolicyDepths& depths, const Region& region) {
  PolicyScore score;
  for (int r = region.r0; r <= region.r1; ++r) {
    for (int c = region.c0; c <= region.c1; ++c) {
      const int cell = grid.Index(r, c);
      if (grid.at(cell) == Cell::kObstacle) continue;
      ++score.starts;
      if (depths.depth[cell] != kNoPath) {
        ++score.successes;
        score.total_length += depths.depth[cell];
      }
    }
  }
  return score;
}

PolicyScore ScoreGrid(const Grid& grid, const PolicyDepths& depths) {
  return ScoreRegion(grid, depths, Region{0, grid.rows() - 1, 0, grid.cols() - 1});
}

}  // namespace dynapath
