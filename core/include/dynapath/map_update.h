#pragma once
// Live map updates of a planning service (dynapath serve): cells reported
// free or blocked by any number of sources, checked against the grid as the
// service knows it, and merged into the next time step's changes, one step
// per batch however many updates arrive while a step is being processed.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "dynapath/change_sequence.h"
#include "dynapath/grid.h"
#include "dynapath/result.h"

namespace dynapath {

// One update: cells inside the grid with their new code (kFree or
// kObstacle), in the order observed.
struct MapUpdate {
  std::string source;
  int64_t sequence = 0;  // from 1, increasing per source
  int64_t utime = 0;
  std::vector<CellChange> changes;
};

// Why an update was refused (each counted).
enum class UpdateRefusal {
  kStale,              // its sequence number is not above the source's last
  kOutsideGrid,        // a cell outside the grid
  kUnknownState,       // a state other than free or obstacle
  kStationToObstacle,  // an obstacle on a station
  kGridShape,          // an occupancy grid that covers no cell of the map
  kOtherMaze,          // made for another maze (its maze fingerprint is not the service's)
  kResolution,         // an occupancy grid of another resolution than the map's
  kOffLattice,         // an occupancy grid whose origin is not on the map's cell lattice
};
inline constexpr size_t kUpdateRefusalCount = 8;
const char* UpdateRefusalName(UpdateRefusal why);  // "stale", "outside_grid", ...

// An update refused before it reached the queue (its conversion from a
// message): the reason counted, and what exactly was wrong.
struct UpdateError {
  UpdateRefusal why = UpdateRefusal::kOutsideGrid;
  Error error;
};

struct UpdateCounts {
  int64_t received = 0;
  int64_t accepted = 0;
  int64_t cells_changed = 0;    // changes queued for a step
  int64_t cells_unchanged = 0;  // reported as they already were
  int64_t steps = 0;            // batches taken
  std::array<int64_t, kUpdateRefusalCount> refused{};
  int64_t refused_total() const;
};

// Not thread-safe: the service guards it.
class UpdateQueue {
 public:
  // Sources whose last sequence number is kept; beyond, the least recently
  // heard is forgotten (its next update is then accepted whatever its
  // number), so a flood of names costs bounded memory.
  static constexpr size_t kMaxSources = 4096;

  explicit UpdateQueue(Grid latest);

  // Checks `update` against the source's sequence and the latest grid;
  // accepted updates are applied to the latest grid and queued (a cell
  // reported as it already is changes nothing). An update is taken or
  // refused whole. nullopt: accepted.
  std::optional<UpdateRefusal> Submit(const MapUpdate& update);
  // Counts an update refused before it got here (its conversion).
  void Refuse(UpdateRefusal why);

  bool pending() const { return !pending_.changes.empty(); }
  // The changes queued since the last Take, in the order accepted (empty
  // when none), as one time step.
  ChangeStep Take();

  const Grid& latest() const { return latest_; }
  const UpdateCounts& counts() const { return counts_; }
  size_t sources() const { return sources_.size(); }

 private:
  struct Source {
    int64_t last_sequence = 0;
    uint64_t last_use = 0;
  };
  Grid latest_;
  ChangeStep pending_;
  std::unordered_map<std::string, Source> sources_;
  uint64_t uses_ = 0;
  UpdateCounts counts_;
};

}  // namespace dynapath
