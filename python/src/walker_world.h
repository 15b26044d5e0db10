#pragma once
// The MDP of SPEC section 2 for walkers in Python (python/dynapath): one
// move of one walker, and the maze as it stands after n environment steps.
// Header-only, included by the module's one translation unit.
//
// The maze's clock: with `steps_per_change` k >= 1 the walker's move number
// n + 1 (n steps since its reset) is decided on the maze at time step
// min(n / k, T), T the change sequence's last step; with k = 0 the maze
// stays as it was at time step 0. An obstacle that moves onto a walker
// leaves the walker where it is: it leaves by any move whose target is not
// an obstacle, and a move that is blocked is a bump as always.

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "dynapath/change_sequence.h"
#include "dynapath/grid.h"
#include "dynapath/mdp.h"
#include "dynapath/scenario.h"

namespace dynapath::python {

inline constexpr uint8_t kObstacleCode = static_cast<uint8_t>(Cell::kObstacle);
inline constexpr uint8_t kFreeCode = static_cast<uint8_t>(Cell::kFree);
inline constexpr uint8_t kStationCode = static_cast<uint8_t>(Cell::kStation);

// Snapshots of all time steps cost (T + 1) x cells bytes; more is refused.
inline constexpr size_t kMaxSnapshotBytes = size_t{1} << 30;

struct MoveOutcome {
  int row, col;
  double reward;
  bool terminated;  // ended on a station
};

// One move on `grid` (row-major cell codes of a rows x cols maze).
// `blocked(row, col)` says whether another walker holds the target.
template <typename Blocked>
inline MoveOutcome Move(const uint8_t* grid, int rows, int cols, int row, int col, int action,
                        Blocked&& blocked) {
  const int target_row = row + kActionRowOffset[action];
  const int target_col = col + kActionColOffset[action];
  bool moved = false;
  if (target_row >= 0 && target_row < rows && target_col >= 0 && target_col < cols &&
      grid[static_cast<size_t>(target_row) * cols + target_col] != kObstacleCode &&
      !blocked(target_row, target_col)) {
    row = target_row;
    col = target_col;
    moved = true;
  }
  const bool station = grid[static_cast<size_t>(row) * cols + col] == kStationCode;
  const double reward = station ? kStationReward : (moved ? kStepReward : kBumpReward);
  return {row, col, reward, station};
}

inline MoveOutcome Move(const uint8_t* grid, int rows, int cols, int row, int col, int action) {
  return Move(grid, rows, cols, row, col, action, [](int, int) { return false; });
}

// The maze of one environment: its codes at every time step it can reach,
// the start cells and the episode length.
class World {
 public:
  World(const Scenario& scenario, int steps_per_change, int max_steps)
      : rows_(scenario.grid.rows()),
        cols_(scenario.grid.cols()),
        steps_per_change_(steps_per_change),
        max_steps_(max_steps) {
    if (steps_per_change < 0) throw std::invalid_argument("steps_per_change must be >= 0");
    if (max_steps < 1) throw std::invalid_argument("max_steps must be >= 1");
    const size_t cells = static_cast<size_t>(scenario.grid.size());
    times_ = steps_per_change == 0 ? 1 : static_cast<int>(scenario.changes.steps.size()) + 1;
    if (static_cast<double>(times_) * static_cast<double>(cells) >
        static_cast<double>(kMaxSnapshotBytes)) {
      throw std::invalid_argument("the maze's " + std::to_string(times_ - 1) + " time steps of " +
                                  std::to_string(cells) +
                                  " cells need more than 1 GiB of snapshots: give fewer steps");
    }
    snapshots_.resize(static_cast<size_t>(times_) * cells);
    Grid grid = scenario.grid;
    std::copy(grid.codes().begin(), grid.codes().end(), snapshots_.begin());
    for (int t = 1; t < times_; ++t) {
      ApplyChanges(scenario.changes.steps[t - 1], grid);
      std::copy(grid.codes().begin(), grid.codes().end(),
                snapshots_.begin() + static_cast<ptrdiff_t>(t * cells));
    }
    for (int cell = 0; cell < scenario.grid.size(); ++cell) {
      if (scenario.grid.at(cell) == Cell::kFree) free_cells_.push_back(cell);
    }
    if (free_cells_.empty()) throw std::invalid_argument("the maze has no free cell to start on");
  }

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  int max_steps() const { return max_steps_; }
  int steps_per_change() const { return steps_per_change_; }
  // The time step in force for the move after `steps` steps since reset.
  int TimeAfter(int64_t steps) const {
    if (steps_per_change_ == 0) return 0;
    return static_cast<int>(std::min<int64_t>(steps / steps_per_change_, times_ - 1));
  }
  const uint8_t* GridAt(int time) const {
    return snapshots_.data() + static_cast<size_t>(time) * rows_ * cols_;
  }
  const std::vector<int>& free_cells() const { return free_cells_; }

 private:
  int rows_, cols_;
  int steps_per_change_;
  int max_steps_;
  int times_ = 1;
  std::vector<uint8_t> snapshots_;  // times_ x cells, row-major per time step
  std::vector<int> free_cells_;     // at time step 0: where episodes start
};

}  // namespace dynapath::python
