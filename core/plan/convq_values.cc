#include "core/plan/convq_values.h"

#include <algorithm>

namespace dynapath {
namespace {

bool IsConvQFree(const Grid& grid, int cell) { return grid.at(cell) == Cell::kFree; }

// Calls f(neighbour) for the in-grid neighbours of `cell`, in action order.
template <class F>
void ForEachConvQNeighbour(const Grid& grid, int cell, F f) {
  const int row = grid.RowOf(cell), col = grid.ColOf(cell);
  for (int a = 0; a < kNumActions; ++a) {
    const int r = row + kActionRowOffset[a], c = col + kActionColOffset[a];
    if (grid.InBounds(r, c)) f(grid.Index(r, c));
  }
}

}  // namespace

ConvQValues::ConvQValues(const ConvQModel& model) : model_(model) {
  shift_ = model.free_reward / (1.0 - model.move_discount);
  station_ = model.station_reward - shift_;
  blocked_base_ = model.blocked_reward - shift_ + model.bump_discount * shift_;
  blocked_fixed_ = blocked_base_ / (1.0 - model.bump_discount);
  move_ = model.move_discount;
}

double ConvQValues::Initial(const Grid& grid, int cell) const {
  const int row = grid.RowOf(cell), col = grid.ColOf(cell);
  bool any = false;
  double best = 0;
  const auto take = [&](double value) {
    if (!any || value > best) best = value;
    any = true;
  };
  for (int a = 0; a < kNumActions; ++a) {
    const int r = row + kActionRowOffset[a], c = col + kActionColOffset[a];
    if (!grid.InBounds(r, c)) {
      take(blocked_fixed_);
      continue;
    }
    switch (grid.at(r, c)) {
      case Cell::kObstacle:
        take(blocked_fixed_);
        break;
      case Cell::kStation:
        take(station_);
        break;
      case Cell::kFree:
        // A free neighbour: the wandering loop's value, 0 after the shift.
        take(0.0);
        break;
    }
  }
  return best;
}

void ConvQValues::Push(int cell) {
  // Only values above 0 can raise a neighbour (move_ * U > U' >= 0).
  if (shifted_[static_cast<size_t>(cell)] > 0) queue_.emplace(shifted_[cell], cell);
}

void ConvQValues::Propagate(const Grid& grid) {
  while (!queue_.empty()) {
    // Named copies, not a structured binding: clang 14 (the fuzz build)
    // cannot capture a binding in the lambda below.
    const double value = queue_.top().first;
    const int cell = queue_.top().second;
    queue_.pop();
    if (value != shifted_[static_cast<size_t>(cell)]) continue;  // stale
    const double offer = move_ * value;
    ForEachConvQNeighbour(grid, cell, [&](int next) {
      if (!IsConvQFree(grid, next) || !(offer > shifted_[static_cast<size_t>(next)])) return;
      shifted_[static_cast<size_t>(next)] = offer;
      source_[static_cast<size_t>(next)] = cell;
      touched_.push_back(next);
      Push(next);
    });
  }
}

void ConvQValues::Solve(const Grid& grid) {
  const size_t n = static_cast<size_t>(grid.size());
  shifted_.assign(n, 0.0);
  source_.assign(n, -1);
  marked_.assign(n, 0);
  touched_.clear();
  queue_ = {};
  for (int cell = 0; cell < grid.size(); ++cell) {
    touched_.push_back(cell);
    if (!IsConvQFree(grid, cell)) continue;
    shifted_[static_cast<size_t>(cell)] = Initial(grid, cell);
    Push(cell);
  }
  Propagate(grid);
}

void ConvQValues::Repair(const Grid& grid, const std::vector<int>& changed) {
  touched_.clear();
  reset_.clear();
  const auto add = [&](int cell) {
    if (marked_[static_cast<size_t>(cell)]) return;
    marked_[static_cast<size_t>(cell)] = 1;
    reset_.push_back(cell);
  };
  // The changed cells and their neighbours (whose own terms changed), then
  // every cell whose value was derived through one of them.
  for (int cell : changed) {
    add(cell);
    ForEachConvQNeighbour(grid, cell, add);
  }
  for (size_t i = 0; i < reset_.size(); ++i) {
    const int cell = reset_[i];
    ForEachConvQNeighbour(grid, cell, [&](int next) {
      if (source_[static_cast<size_t>(next)] == cell) add(next);
    });
  }
  // Reset them to what their neighbourhood alone gives: a lower bound of
  // the new fixed point, as every other value is (its derivation avoids
  // the changed cells), so settling upwards reaches it.
  for (int cell : reset_) {
    source_[static_cast<size_t>(cell)] = -1;
    shifted_[static_cast<size_t>(cell)] = IsConvQFree(grid, cell) ? Initial(grid, cell) : 0.0;
    touched_.push_back(cell);
  }
  for (int cell : reset_) {
    marked_[static_cast<size_t>(cell)] = 0;
    if (!IsConvQFree(grid, cell)) continue;
    double& value = shifted_[static_cast<size_t>(cell)];
    ForEachConvQNeighbour(grid, cell, [&](int next) {
      if (!IsConvQFree(grid, next)) return;
      const double offer = move_ * shifted_[static_cast<size_t>(next)];
      if (offer > value) {
        value = offer;
        source_[static_cast<size_t>(cell)] = next;
      }
    });
  }
  for (int cell : reset_) {
    if (IsConvQFree(grid, cell)) Push(cell);
  }
  Propagate(grid);
}

double ConvQValues::Value(const Grid& grid, int cell) const {
  if (!IsConvQFree(grid, cell)) return 0.0;
  return shifted_[static_cast<size_t>(cell)] + shift_;
}

void ConvQValues::ActionValues(const Grid& grid, int cell, double* q) const {
  std::fill(q, q + kNumActions, 0.0);
  if (!IsConvQFree(grid, cell)) return;
  const double stay = blocked_base_ + model_.bump_discount * shifted_[static_cast<size_t>(cell)];
  const int row = grid.RowOf(cell), col = grid.ColOf(cell);
  for (int a = 0; a < kNumActions; ++a) {
    const int r = row + kActionRowOffset[a], c = col + kActionColOffset[a];
    if (!grid.InBounds(r, c)) {
      q[a] = stay;
      continue;
    }
    switch (grid.at(r, c)) {
      case Cell::kObstacle:
        q[a] = stay;
        break;
      case Cell::kStation:
        q[a] = station_;
        break;
      case Cell::kFree:
        q[a] = move_ * shifted_[static_cast<size_t>(grid.Index(r, c))];
        break;
    }
  }
}

std::vector<double> IterateConvQ(const ConvQModel& model, const Grid& grid, int iterations) {
  const size_t n = static_cast<size_t>(grid.size());
  std::vector<double> value(n, 0.0), next(n, 0.0);
  for (int k = 0; k < iterations; ++k) {
    for (int cell = 0; cell < grid.size(); ++cell) {
      next[static_cast<size_t>(cell)] = 0.0;
      if (!IsConvQFree(grid, cell)) continue;
      const int row = grid.RowOf(cell), col = grid.ColOf(cell);
      double best = 0;
      for (int a = 0; a < kNumActions; ++a) {
        const int r = row + kActionRowOffset[a], c = col + kActionColOffset[a];
        double q = 0;
        if (!grid.InBounds(r, c) || grid.at(r, c) == Cell::kObstacle) {
          q = model.blocked_reward + model.bump_discount * value[static_cast<size_t>(cell)];
        } else if (grid.at(r, c) == Cell::kStation) {
          q = model.station_reward;
        } else {
          q = model.free_reward +
              model.move_discount * value[static_cast<size_t>(grid.Index(r, c))];
        }
        if (a == 0 || q > best) best = q;
      }
      next[static_cast<size_t>(cell)] = best;
    }
    value.swap(next);
  }
  return value;
}

}  // namespace dynapath
