#include "dynapath/start_statistics.h"

#include <cassert>
#include <utility>

namespace dynapath {

StartStatistics::StartStatistics(std::vector<int> start_cells)
    : start_cells_(std::move(start_cells)),
      attempts_(start_cells_.size(), 0),
      successes_(start_cells_.size(), 0) {
  Init();
}

StartStatistics::StartStatistics(std::vector<int> start_cells, std::vector<uint32_t> attempts,
                                 std::vector<uint32_t> successes)
    : start_cells_(std::move(start_cells)),
      attempts_(std::move(attempts)),
      successes_(std::move(successes)) {
  assert(attempts_.size() == start_cells_.size() && successes_.size() == start_cells_.size());
  for (uint32_t count : attempts_) total_attempts_ += count;
  Init();
}

void StartStatistics::Init() {
  int max_cell = -1;
  for (int cell : start_cells_) max_cell = cell > max_cell ? cell : max_cell;
  slot_of_cell_.assign(static_cast<size_t>(max_cell + 1), -1);
  for (size_t slot = 0; slot < start_cells_.size(); ++slot) {
    slot_of_cell_[start_cells_[slot]] = static_cast<int>(slot);
  }
  leaves_ = 1;
  while (leaves_ < start_cells_.size()) leaves_ *= 2;
  tree_.assign(2 * leaves_, 0.0);
  for (size_t slot = 0; slot < start_cells_.size(); ++slot) {
    const double rate =
        attempts_[slot] == 0 ? 0.0 : static_cast<double>(successes_[slot]) / attempts_[slot];
    tree_[leaves_ + slot] = 1.0 - rate + kWeightFloor;
  }
  for (size_t node = leaves_ - 1; node >= 1; --node) {
    tree_[node] = tree_[2 * node] + tree_[2 * node + 1];
  }
}

void StartStatistics::SetWeight(int slot) {
  const double rate =
      attempts_[slot] == 0 ? 0.0 : static_cast<double>(successes_[slot]) / attempts_[slot];
  size_t node = leaves_ + static_cast<size_t>(slot);
  tree_[node] = 1.0 - rate + kWeightFloor;
  for (node /= 2; node >= 1; node /= 2) tree_[node] = tree_[2 * node] + tree_[2 * node + 1];
}

int StartStatistics::Draw(Rng& rng) const {
  if (start_cells_.empty()) return -1;
  if (total_attempts_ < kUniformStarts) {
    return start_cells_[rng.Below(static_cast<uint32_t>(start_cells_.size()))];
  }
  double u = rng.Uniform() * tree_[1];
  size_t node = 1;
  while (node < leaves_) {
    const double left = tree_[2 * node];
    // Rounding can leave u at (or just past) the total: fall back left rather
    // than into a subtree of padding leaves.
    if (u < left || tree_[2 * node + 1] <= 0.0) {
      node = 2 * node;
    } else {
      u -= left;
      node = 2 * node + 1;
    }
  }
  return start_cells_[node - leaves_];
}

void StartStatistics::Record(int slot, bool success) {
  assert(slot >= 0 && static_cast<size_t>(slot) < start_cells_.size());
  ++attempts_[slot];
  if (success) ++successes_[slot];
  ++total_attempts_;
  SetWeight(slot);
}

int StartStatistics::SlotOf(int cell) const {
  if (cell < 0 || static_cast<size_t>(cell) >= slot_of_cell_.size()) return -1;
  return slot_of_cell_[cell];
}

}  // namespace dynapath
