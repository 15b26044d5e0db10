#include "core/learn/settled_updates.h"

namespace dynapath {

SettledUpdates::SettledUpdates(const RegionModel& model)
    : settled_(static_cast<size_t>(model.cells()) * kNumActions, 0),
      in_buffer_(settled_.size(), 0),
      first_(static_cast<size_t>(model.cells()) + 1, 0) {
  const int cells = model.cells();
  // Counting sort of the in-region entries by target cell.
  for (int s = 0; s < cells; ++s) {
    for (int i = 0; i < model.action_count(s); ++i) {
      ++first_[static_cast<size_t>(model.target(s, model.actions(s)[i])) + 1];
    }
  }
  for (int c = 0; c < cells; ++c) first_[c + 1] += first_[c];
  predecessors_.resize(static_cast<size_t>(first_[cells]));
  std::vector<int32_t> fill(first_.begin(), first_.end() - 1);
  for (int s = 0; s < cells; ++s) {
    for (int i = 0; i < model.action_count(s); ++i) {
      const int a = model.actions(s)[i];
      predecessors_[static_cast<size_t>(fill[model.target(s, a)]++)] =
          static_cast<uint32_t>(s * kNumActions + a);
    }
  }
}

}  // namespace dynapath
