#pragma once
// Prioritised start positions (SPEC section 6): per start cell, how often an
// episode (or federated round) started there and how often it reached a
// station. Starts are drawn uniformly during a warm-up, then with weight
// `1 - successes/attempts + 0.1` (a never-tried start counts as rate 0).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "dynapath/rng.h"

namespace dynapath {

class StartStatistics {
 public:
  // 10: the report's number of uniformly drawn first starts.
  static constexpr int kUniformStarts = 10;
  // 0.1: keeps a start that always succeeds drawable.
  static constexpr double kWeightFloor = 0.1;

  StartStatistics() = default;
  // `start_cells`: the candidate cells (region-local indices), fixed order.
  explicit StartStatistics(std::vector<int> start_cells);
  // Restores statistics from their counts (e.g. received in a message):
  // `attempts` and `successes` are per slot, the same size as `start_cells`.
  // Draws are a function of the counts only, not of the order of the Record
  // calls that produced them, so a restored copy draws exactly as the
  // original.
  StartStatistics(std::vector<int> start_cells, std::vector<uint32_t> attempts,
                  std::vector<uint32_t> successes);

  const std::vector<int>& start_cells() const { return start_cells_; }
  // Total attempts recorded so far (all starts).
  int64_t total_attempts() const { return total_attempts_; }
  const std::vector<uint32_t>& attempts() const { return attempts_; }
  const std::vector<uint32_t>& successes() const { return successes_; }

  // Draws a start cell: uniform while total_attempts() < kUniformStarts,
  // weighted afterwards. Returns -1 when there is no start cell.
  int Draw(Rng& rng) const;
  // Records an attempt from the start with index `slot` in start_cells().
  void Record(int slot, bool success);
  // Index of `cell` in start_cells(), -1 if absent.
  int SlotOf(int cell) const;

 private:
  std::vector<int> start_cells_;
  std::vector<int> slot_of_cell_;  // indexed by region cell, -1 = not a start
  std::vector<uint32_t> attempts_;
  std::vector<uint32_t> successes_;
  int64_t total_attempts_ = 0;
  // Sum tree of the draw weights: leaf `leaves_ + slot` holds the slot's
  // weight (padding leaves 0), every inner node the sum of its two children,
  // recomputed from them on each update. Each node is then a function of the
  // current weights alone (no drift from incremental deltas), and a draw
  // descends it in O(log n).
  std::vector<double> tree_;
  size_t leaves_ = 1;

  void Init();
  void SetWeight(int slot);
};

}  // namespace dynapath
