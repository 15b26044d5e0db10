#pragma once
// Exact shortest paths to any goal cell on a changing grid: the moves of
// SPEC section 2 (8 neighbours, each move costs 1, a diagonal move needs
// only its target free: no corner-cutting rule), stations counting as free.
//
// GoalPlanner answers (start, goal) on its current grid two ways:
//  * hot goals: a goal-rooted distance field (one breadth-first search from
//    the goal), kept exact across grid updates by repairing it from the
//    changed cells only (DynamicDistances, the Incremental Oracle's method).
//    A field is repaired when its goal is next asked (the batches of changed
//    cells since its version are kept in a bounded log; a field behind the
//    log is rebuilt). Fields live in an LRU cache bounded in bytes; a goal
//    gets a field on its `hot_after`-th miss, so a goal asked once never
//    pays a whole-grid search.
//  * cold goals: A* from the start, ties to the larger g, with the larger of
//    the Chebyshev distance (the octile distance when a diagonal costs 1)
//    and the ALT bound max |d_L(v) - d_L(goal)| over a few landmark fields
//    (exact fields of cells spread over the map by farthest-point
//    selection, repaired like the others, held within half the cache). A
//    landmark that reaches one of start and goal but not the other proves
//    there is no path without any search.
// A path is walked down the field (or back along A*'s parents), neighbours
// in action order N, NE, E, SE, S, SW, W, NW: the same inputs give the same
// cells. Not thread-safe: one caller at a time.
//
// MapFrame converts metres (ROS map_server's frame: the origin is the
// bottom-left corner of the map's bottom-left cell, x to the right along
// columns, y up along rows; the origin's yaw is not applied, as Nav2's
// costmap does not) to cells and back.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "dynapath/grid.h"
#include "dynapath/result.h"

namespace dynapath {

struct MapFrame {
  double resolution = 1.0;  // metres per cell
  double origin_x = 0.0;    // the bottom-left corner of cell (rows - 1, 0)
  double origin_y = 0.0;
  int rows = 0;
  int cols = 0;

  // The centre of a cell, in metres.
  double X(int col) const { return origin_x + (col + 0.5) * resolution; }
  double Y(int row) const { return origin_y + (rows - 1 - row + 0.5) * resolution; }
  // The cell holding the point (x, y); false (and nothing set) outside the
  // map or for a non-finite coordinate. A point on a border between cells
  // belongs to the cell right of it / above it.
  bool CellAt(double x, double y, int* row, int* col) const;
};

// Ok when a resolution and origin can be used: finite, resolution > 0 and
// at most 1000 m, |origin| at most 1e9 m.
Status CheckFrame(double resolution, double origin_x, double origin_y);

enum class GoalStatus : int8_t {
  kReached = 0,
  kNoRoute = 1,  // "unreachable": no path from the start to the goal
  kStartObstacle = 2,
  kStartOutsideGrid = 3,
  kStartOutsideMap = 4,  // a start pose outside the map (runtime only)
  kOverBudget = 5,       // the path has more cells than the budget left
};
inline constexpr int kGoalStatusCount = 6;
const char* GoalStatusName(GoalStatus status);

// What a whole request's goal is.
enum class GoalCheck : int8_t {
  kOk = 0,
  kOutsideGrid = 1,
  kObstacle = 2,
  kOutsideMap = 3,   // a goal pose outside the map
  kUnknownName = 4,  // a named goal the service does not have
};
inline constexpr int kGoalCheckCount = 5;
const char* GoalCheckName(GoalCheck check);

enum class GoalSource : int8_t { kNone = 0, kField = 1, kSearch = 2 };

struct GoalPath {
  GoalStatus status = GoalStatus::kNoRoute;
  GoalSource source = GoalSource::kNone;
  int32_t cost = -1;           // moves; -1 unless reached
  std::vector<int32_t> cells;  // start to goal, both included; empty unless reached
};

struct GoalPlannerOptions {
  // The fields' bytes at most (their distances and repair stamps: 8 bytes a
  // cell each). 0: no fields, every goal searched.
  size_t cache_bytes = size_t{256} << 20;
  // A goal gets a field on this miss (1: at once).
  int hot_after = 2;
  // Batches of changed cells kept for fields that were not asked for a while.
  size_t log_batches = 256;
  // Landmark fields for A*'s heuristic (fewer when half the cache cannot
  // hold them).
  int landmarks = 8;
};

struct GoalCacheStats {
  int64_t hits = 0;       // answered from a field already in the cache
  int64_t misses = 0;     // the goal had no field
  int64_t builds = 0;     // fields made (a miss that made the goal hot)
  int64_t evictions = 0;  // fields dropped for room
  int64_t repairs = 0;    // fields repaired from changed cells
  int64_t rebuilds = 0;   // fields behind the log, searched again
  int64_t searches = 0;   // A* searches (cold goals)
  int64_t expanded = 0;   // their expanded cells
  size_t bytes = 0;       // the fields' bytes now
  size_t peak_bytes = 0;
  size_t cap_bytes = 0;
  int64_t fields = 0;
  int64_t landmarks = 0;
  int64_t proved_unreachable = 0;  // no path, told by a landmark without a search
};

class GoalPlanner {
 public:
  explicit GoalPlanner(GoalPlannerOptions options = {});
  ~GoalPlanner();
  GoalPlanner(const GoalPlanner&) = delete;
  GoalPlanner& operator=(const GoalPlanner&) = delete;

  // The grid from now on, `changed` the cells that differ from the previous
  // one (any superset; duplicates allowed); the first call's `changed` is
  // ignored. A grid of another size drops every field.
  void Update(std::shared_ptr<const Grid> grid, const std::vector<int>& changed);
  const Grid* grid() const { return grid_.get(); }
  // Updates so far (0 before the first).
  int64_t updates() const { return updates_; }

  // Validity of a goal cell on the current grid.
  GoalCheck CheckGoal(int row, int col) const;
  // The shortest path from start to goal (both (row, col)); a goal that is
  // not kOk answers kNoRoute. At most `budget` cells.
  GoalPath Plan(int start_row, int start_col, int goal_row, int goal_col,
                size_t budget = size_t{1} << 20);

  const GoalCacheStats& stats() const { return stats_; }

 private:
  struct Field;
  struct Batch {
    int64_t update;
    std::vector<int> cells;
  };
  Field* HotField(int goal);  // the goal's field, repaired; null when cold
  void Bring(Field& field);   // repairs or rebuilds it to the current grid
  void Evict(size_t need);
  GoalPath FromField(const Field& field, int start, size_t budget) const;
  GoalPath Search(int start, int goal, size_t budget);
  void PlaceLandmarks();

  GoalPlannerOptions options_;
  std::shared_ptr<const Grid> grid_;
  int64_t updates_ = 0;
  std::vector<Batch> log_;  // oldest first, at most options_.log_batches
  int64_t log_floor_ = 0;   // a field at this update or later can be repaired
  std::unordered_map<int, std::unique_ptr<Field>> fields_;
  std::vector<std::unique_ptr<Field>> landmarks_;  // never evicted
  std::vector<int32_t> landmark_goal_;             // A* scratch: d_L(goal)
  std::unordered_map<int, int> misses_;            // per cold goal (bounded: cleared when large)
  uint64_t clock_ = 0;
  GoalCacheStats stats_;
  // A* scratch, reused: g and parent per cell, valid where stamp == epoch.
  std::vector<int32_t> g_, parent_;
  std::vector<uint32_t> stamp_;
  uint32_t epoch_ = 0;
};

// The number of moves of a shortest path (breadth-first search on `grid`),
// -1 when there is none or either cell is an obstacle. For tests and
// benchmarks: a fresh search from scratch.
int32_t FreshGoalDistance(const Grid& grid, int start, int goal);

// Named goals, one per line: `NAME ROW,COL` (integers: a cell) or
// `NAME X,Y` (numbers with a decimal point: metres). Names are 1-64
// characters of [A-Za-z0-9_.-]; '#' starts a comment; blank lines are
// skipped. At most 65,536 goals; each name once.
struct NamedGoal {
  std::string name;
  bool metres = false;
  int row = 0, col = 0;
  double x = 0, y = 0;
};
Result<std::vector<NamedGoal>> ParseGoalsText(const std::string& text);

}  // namespace dynapath
