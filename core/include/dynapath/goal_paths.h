#pragma once
// Exact shortest paths to any goal cell on a changing grid: the moves of
// SPEC section 2 (8 neighbours, each move costs 1, a diagonal move needs
// only its target free: no corner-cutting rule), stations counting as free.
//
// GoalPlanner answers (start, goal) on its current grid two ways:
//  * hot goals: a goal-rooted distance field (one breadth-first search from
//    the goal), kept exact across grid updates by repairing it from the
//    changed cells only (the Incremental Oracle's method: withdraw the
//    values that lost their support, then relax outwards). A field is
//    repaired when its goal is next asked (the batches of changed cells
//    since its version are kept in a bounded log; a field behind the log is
//    dropped and made again). A field holds 2 bytes per indexed cell (4 when
//    a distance exceeds 65,534: it is then made again that wide), indexed
//    by a free-cell index: every cell free at some update since the grid
//    was loaded gets the next index, so the fields cover the free cells and
//    grow only by the cells that became free. Fields live in an LRU cache
//    bounded in bytes (fields being made count); a goal gets a field on its
//    `hot_after`-th miss, so a goal asked once never pays a whole-grid
//    search. With `background_builds` a field is made by a builder thread
//    on the grid of the update it was asked on, and adopted (then repaired
//    to the current grid) at a later call; its goal is searched meanwhile.
//    The answer's cost is exact either way; which of field and search
//    answered depends on the builder's progress (GoalPath::source).
//    A field whose repairs write more distances than a search expands
//    cells (on average) is dropped after its answer: where the map changes
//    much between asks, hot goals are searched (drop_costly_fields).
//  * cold goals: A* from the start (open list bucketed by f, ties to the
//    last pushed, the deepest), with the larger of the Chebyshev distance
//    (the octile distance when a diagonal costs 1) and the ALT bound
//    max |d_L(v) - d_L(goal)| over the landmark fields that bound the
//    start best (`active_landmarks` of `landmarks`: exact fields of cells
//    spread over the map by farthest-point selection, repaired like the
//    others at the first search after an update, held within half the
//    cache). A
//    landmark that reaches one of start and goal but not the other proves
//    there is no path without any search.
// A path is walked down the field (or back along A*'s parents), neighbours
// in action order N, NE, E, SE, S, SW, W, NW: the same inputs give the same
// cells. One caller at a time (the builder thread is internal).
//
// MapFrame converts metres (ROS map_server's frame: the origin is the
// bottom-left corner of the map's bottom-left cell, x to the right along
// columns, y up along rows; the origin's yaw is not applied, as Nav2's
// costmap does not) to cells and back.

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>
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
  // The fields' bytes at most (landmarks and fields being made included): a
  // field takes 2 bytes per indexed cell (the cells free at some update
  // since the grid was loaded), 4 when its distances exceed 65,534, plus
  // about 100 bytes. 0: no fields, every goal searched.
  size_t cache_bytes = size_t{256} << 20;
  // A goal gets a field on this miss (1: at once).
  int hot_after = 2;
  // Batches of changed cells kept for fields that were not asked for a while.
  size_t log_batches = 256;
  // Landmark fields for A*'s heuristic (fewer when half the cache cannot
  // hold them).
  int landmarks = 8;
  // A search's heuristic uses the landmarks that bound its start's distance
  // best, at most this many (0: all).
  int active_landmarks = 4;
  // Make hot goals' fields on a builder thread (their goals searched
  // meanwhile); false: on the caller's thread, at the miss that made the
  // goal hot (deterministic sources).
  bool background_builds = true;
  // The largest distance a 2-byte field holds (a field with a larger one
  // is made 4 bytes a cell); below 65,534 only to test the wide fields.
  int32_t narrow_limit = 65534;
  // Drop a hot goal's field whose repairs write more distances, on average,
  // than a search expands cells (the map changes too much for it to pay);
  // its goal is searched and needs 1,024 more misses before a field again.
  // While the fields' repairs on average cost more than searches, a goal
  // that turns hot gets no field either (but one in 64, to measure again).
  bool drop_costly_fields = true;
};

struct GoalCacheStats {
  int64_t hits = 0;       // answered from a field already in the cache
  int64_t misses = 0;     // the goal had no field
  int64_t builds = 0;     // fields made (a miss that made the goal hot)
  int64_t queued = 0;     // of those, handed to the builder thread
  int64_t widened = 0;    // fields made 4 bytes a cell (a distance above narrow_limit)
  int64_t evictions = 0;  // fields dropped for room
  int64_t repairs = 0;    // fields repaired from changed cells
  int64_t dropped_costly = 0;   // fields dropped as dearer to repair than to search
  int64_t not_made_costly = 0;  // hot goals given no field for the same reason
  int64_t rebuilds = 0;         // fields behind the log (or widened), made again
  int64_t searches = 0;   // A* searches (cold goals)
  int64_t expanded = 0;   // their expanded cells
  size_t bytes = 0;       // the fields' bytes now (those being made included)
  size_t peak_bytes = 0;
  size_t cap_bytes = 0;
  int64_t fields = 0;
  int64_t pending = 0;        // fields being made now
  int64_t indexed_cells = 0;  // the free-cell index's size (cells free at some update)
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

  // Waits until the builder thread has made every queued field and adopts
  // them (tests and benchmarks).
  void WaitForBuilds();

  const GoalCacheStats& stats() const { return stats_; }

 private:
  struct Field;
  class LevelQueue;
  class OpenList;
  struct Batch {
    int64_t update;
    std::vector<int> cells;
  };
  struct BuildJob {
    int goal;
    int64_t update;
    size_t slots;  // the index's size at `update`
    std::shared_ptr<const Grid> grid;
  };
  Field* HotField(int goal);  // the goal's field, repaired; null when cold
  // Repairs or rebuilds it to the current grid; false when it could not be
  // kept (behind the log or too wide, background builds on): drop it.
  bool Bring(Field& field, bool landmark);
  // Makes room for `need` more bytes by dropping least recently used fields
  // other than `keep`; false when it cannot.
  bool Evict(size_t need, const Field* keep = nullptr);
  void Request(int goal);  // hands a build to the builder thread
  void Adopt();            // takes the builder's finished fields
  void StopBuilder();      // drops queued builds, waits for the current one
  void BuilderLoop();
  void MakeField(Field& field, const Grid& grid, size_t slots) const;
  int32_t Value(const Field& field, int cell) const;
  GoalPath FromField(const Field& field, int start, size_t budget) const;
  GoalPath Search(int start, int goal, size_t budget);
  template <class H>
  GoalPath AStar(int start, int goal, size_t budget, H h);
  void PlaceLandmarks();

  GoalPlannerOptions options_;
  std::shared_ptr<const Grid> grid_;
  int64_t updates_ = 0;
  int64_t grid_since_ = 0;  // the update that loaded a grid of this size
  std::vector<Batch> log_;  // oldest first, at most options_.log_batches
  int64_t log_floor_ = 0;   // a field at this update or later can be repaired
  // The free-cell index: slot_[cell] (-1: never free since the grid was
  // loaded). Entries are only ever set once (from -1), by Update, before a
  // build that reads them is queued: the builder reads settled entries.
  std::vector<int32_t> slot_;
  size_t slots_ = 0;
  std::unordered_map<int, std::unique_ptr<Field>> fields_;
  std::unordered_map<int, size_t> pending_;        // goal -> bytes held for its build
  std::vector<std::unique_ptr<Field>> landmarks_;  // never evicted
  std::vector<int32_t> landmark_goal_;             // A* scratch: d_L(goal)
  std::vector<int32_t> landmark_start_;            // A* scratch: the bound at the start
  std::unordered_map<int, int> misses_;            // per cold goal (bounded: cleared when large)
  uint64_t clock_ = 0;
  GoalCacheStats stats_;
  // A* scratch, reused: g and parent per cell, valid where stamp == epoch.
  std::vector<int32_t> g_, parent_;
  std::vector<uint32_t> stamp_;
  uint32_t epoch_ = 0;
  // Repair scratch.
  std::unique_ptr<LevelQueue> levels_;
  std::unique_ptr<OpenList> open_;  // A*'s
  int64_t searches_ = 0;            // landmark searches, and their cells expanded
  double search_cost_ = 0;          // (a moving average)
  bool drop_after_answer_ = false;  // HotField's field is dropped once it answered
  int64_t field_repairs_ = 0;       // hot fields' repairs, and distances written
  double repair_cost_ = 0;          // (a moving average)
  uint64_t probe_ = 0;
  std::vector<int> withdrawn_;
  mutable std::vector<int32_t> queue_;  // breadth-first search scratch (caller's thread)
  // The builder thread (started at the first queued build).
  std::thread builder_;
  std::mutex build_mutex_;
  std::condition_variable build_cv_, idle_cv_;
  std::deque<BuildJob> jobs_;                  // guarded by build_mutex_
  std::vector<std::unique_ptr<Field>> built_;  // guarded by build_mutex_
  bool building_ = false;                      // guarded by build_mutex_
  bool stop_ = false;                          // guarded by build_mutex_
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
