#pragma once
// Policy evaluation of SPEC section 4: from every start cell, the breadth-
// first depth at which the top-2 policy graph of the root table reaches a
// station. Computed for all cells at once by one reverse breadth-first search
// from the stations, linear in the number of cells.

#include <cstdint>
#include <vector>

#include "dynapath/grid.h"
#include "dynapath/mdp.h"
#include "dynapath/q_table.h"
#include "dynapath/region.h"

namespace dynapath {

inline constexpr int32_t kNoPath = -1;

// Per-cell depth (path length) of a successful start, kNoPath for obstacles
// and failing starts. A start succeeds when a station is reached at depth
// < rows + cols.
struct PolicyDepths {
  std::vector<int32_t> depth;
};

// Success rate and mean path length over a set of starts.
struct PolicyScore {
  int starts = 0;     // non-obstacle cells considered
  int successes = 0;  // of which reach a station
  int64_t total_length = 0;
  double success_rate() const {
    return starts == 0 ? 1.0 : static_cast<double>(successes) / starts;
  }
  double average_path_length() const {
    return successes == 0 ? 0.0 : static_cast<double>(total_length) / successes;
  }
};

// Reusable evaluator: keeps its scratch buffers between calls so repeated
// evaluations do not allocate. Not thread-safe; use one per thread.
class PolicyEvaluator {
 public:
  // Fills `out` for `grid` under the policy `root` (a rows*cols table).
  void Evaluate(const Grid& grid, const QTable& root, PolicyDepths& out);
  // The same for a deterministic policy: `actions` holds one action per
  // cell (0..7, -1 for none), the path from a cell follows it alone (an
  // approach outside core that gives actions, not values: the Python
  // module's). A start succeeds as above.
  void Evaluate(const Grid& grid, const int8_t* actions, PolicyDepths& out);

 private:
  // No edges yet, for `cells` cells.
  void ClearEdges(int cells);
  // The reverse breadth-first search over the successors filled in.
  void SearchFromStations(const Grid& grid, PolicyDepths& out);

  std::vector<int32_t> successors_;  // 2 per cell, -1 = none
  std::vector<int32_t> in_offsets_;  // reverse edges, CSR
  std::vector<int32_t> in_edges_;
  std::vector<int32_t> queue_;
};

// Score over the non-obstacle cells of `region` (paths may leave it).
// A region without non-obstacle cells has success rate 1 (nothing fails).
PolicyScore ScoreRegion(const Grid& grid, const PolicyDepths& depths, const Region& region);
// Score over the whole grid.
PolicyScore ScoreGrid(const Grid& grid, const PolicyDepths& depths);

// The two best in-grid actions of a cell by value, ties to the higher index
// (SPEC section 4). Writes -1 for a missing second action (corner cells have
// at least 3 in-grid actions, so never in practice).
// `q`: the cell's 8 values. Inline: the policy evaluations call it per cell.
template <typename V>
inline void TopTwoActions(const Grid& grid, int cell, const V* q, int& best, int& second) {
  const int row = grid.RowOf(cell), col = grid.ColOf(cell);
  best = -1;
  second = -1;
  for (int a = 0; a < kNumActions; ++a) {
    if (!grid.InBounds(row + kActionRowOffset[a], col + kActionColOffset[a])) continue;
    // ">=": a later action with an equal value ranks higher.
    if (best < 0 || q[a] >= q[best]) {
      second = best;
      best = a;
    } else if (second < 0 || q[a] >= q[second]) {
      second = a;
    }
  }
}
// The same for row `cell` of `table`, in the table's precision.
inline void TopTwoActions(const Grid& grid, int cell, const QTable& table, int& best, int& second) {
  WithValueType(table.precision(), [&]<typename V>(V*) {
    TopTwoActions(grid, cell, table.Row<V>(cell), best, second);
  });
}

}  // namespace dynapath
