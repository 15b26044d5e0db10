#include "dynapath/map_update.h"

#include <utility>

namespace dynapath {

const char* UpdateRefusalName(UpdateRefusal why) {
  switch (why) {
    case UpdateRefusal::kStale:
      return "stale";
    case UpdateRefusal::kOutsideGrid:
      return "outside_grid";
    case UpdateRefusal::kUnknownState:
      return "unknown_state";
    case UpdateRefusal::kStationToObstacle:
      return "station_to_obstacle";
    case UpdateRefusal::kGridShape:
      return "grid_shape";
    case UpdateRefusal::kOtherMaze:
      return "other_maze";
    case UpdateRefusal::kResolution:
      return "resolution";
    case UpdateRefusal::kOffLattice:
      return "off_lattice";
  }
  return "unknown";
}

int64_t UpdateCounts::refused_total() const {
  int64_t total = 0;
  for (int64_t n : refused) total += n;
  return total;
}

UpdateQueue::UpdateQueue(Grid latest) : latest_(std::move(latest)) {}

void UpdateQueue::Refuse(UpdateRefusal why) {
  ++counts_.received;
  ++counts_.refused[static_cast<size_t>(why)];
}

std::optional<UpdateRefusal> UpdateQueue::Submit(const MapUpdate& update) {
  ++counts_.received;
  auto refuse = [&](UpdateRefusal why) {
    ++counts_.refused[static_cast<size_t>(why)];
    return why;
  };
  auto it = sources_.find(update.source);
  if (it == sources_.end()) {
    if (sources_.size() >= kMaxSources) {
      auto oldest = sources_.begin();
      for (auto s = sources_.begin(); s != sources_.end(); ++s) {
        if (s->second.last_use < oldest->second.last_use) oldest = s;
      }
      sources_.erase(oldest);
    }
    it = sources_.emplace(update.source, Source{}).first;
  }
  it->second.last_use = ++uses_;
  // The number is used up even when the content is refused below: a
  // repeat of a refused update is a repeat.
  if (update.sequence <= it->second.last_sequence) return refuse(UpdateRefusal::kStale);
  it->second.last_sequence = update.sequence;
  for (const CellChange& change : update.changes) {
    if (change.cell < 0 || change.cell >= latest_.size())
      return refuse(UpdateRefusal::kOutsideGrid);
    if (change.code != Cell::kFree && change.code != Cell::kObstacle) {
      return refuse(UpdateRefusal::kUnknownState);
    }
    // Stations never change: a station is where robots go, not something a
    // sensor may wall in.
    if (latest_.at(change.cell) == Cell::kStation && change.code == Cell::kObstacle) {
      return refuse(UpdateRefusal::kStationToObstacle);
    }
  }
  ++counts_.accepted;
  for (const CellChange& change : update.changes) {
    if (latest_.at(change.cell) == change.code || latest_.at(change.cell) == Cell::kStation) {
      ++counts_.cells_unchanged;
      continue;
    }
    latest_.set(change.cell, change.code);
    pending_.changes.push_back(change);
    ++counts_.cells_changed;
  }
  return std::nullopt;
}

ChangeStep UpdateQueue::Take() {
  ChangeStep step;
  std::swap(step, pending_);
  step.requested_moves = static_cast<int>(step.changes.size());
  if (!step.changes.empty()) ++counts_.steps;
  return step;
}

}  // namespace dynapath
