#pragma once
// A fleet of robots that see each other: lifelong tasks on a changing grid,
// one conflict-free joint move per tick, planned by PIBT (priority
// inheritance with backtracking, Okumura et al.) guided by exact
// distance-to-goal fields that are repaired at every map change.
//
// Moves are SPEC section 2's: a robot stays or steps to one of its 8
// neighbours that is not an obstacle. A joint move has
//   * no vertex conflict: two robots never end a tick on one cell;
//   * no swap conflict: two robots never exchange their cells;
//   * no crossing: two diagonal moves through one 2x2 square never cross
//     ((r,c)->(r+1,c+1) with (r,c+1)->(r+1,c), or the reverse).
// A robot may enter a cell that another leaves in the same tick (following)
// and robots may rotate along a cycle of 3 or more. A diagonal move past a
// robot on a side cell is allowed, as past an obstacle (SPEC has no corner
// rule).
//
// Tasks alternate, from the start: reach any station (the nearest, by the
// stations' field), then a goal cell drawn from the goal pool, then a
// station again, and so on; a robot gets its next task on the tick it
// arrives. One field per pool goal plus one for the stations: memory is
// (goals + 1) x cells x 8 bytes, refused above kMaxFieldBytes.
//
// The map changes (movers, live updates) between ticks: ApplyChanges
// repairs every field from the changed cells only. A robot never moves onto
// an obstacle; a robot whose cell became an obstacle under it (an overrun:
// the world's doing, not a move) leaves it as soon as it can.
//
// Optional delays: each planned move fails with probability
// `delay_probability` (a seeded stream); a robot then stays, and so does
// every robot that planned to enter a cell whose robot stays (followers and
// whole rotations), so a delayed joint move stays conflict-free.
//
// With `ignore_conflicts` every robot steps greedily along its field as if
// alone (the comparison of "robots do not block each other").
//
// Results are a function of the grid, the changes and the options.

#include <cstdint>
#include <memory>
#include <vector>

#include "dynapath/change_sequence.h"
#include "dynapath/grid.h"
#include "dynapath/result.h"
#include "dynapath/rng.h"

namespace dynapath {

// The distance fields' memory: (goals + 1) x cells x 8 bytes, at most this.
inline constexpr long long kMaxFieldBytes = 2LL << 30;
inline constexpr int kFieldBytesPerCell = 8;

struct FleetOptions {
  int robots = 10;
  uint64_t seed = 1;               // starts, goal pool, priorities' tie-breaks, delays
  int goal_count = 16;             // goal pool drawn from the free cells (when `goals` is empty)
  std::vector<int> goals;          // a given goal pool (free cells), used instead of drawing
  std::vector<int> starts;         // given distinct free start cells (else drawn)
  std::vector<int> first_goals;    // per robot: first task's goal index, -1: a station
  double delay_probability = 0.0;  // [0, 1)
  bool ignore_conflicts = false;
  int threads = 1;  // for repairing the fields
};

struct FleetRobot {
  int cell = 0;
  bool to_station = true;    // the current task: any station, or goal `goal`
  int goal = -1;             // index into goals() when !to_station
  int64_t task_started = 0;  // tick the current task began
  int64_t tasks_done = 0;
  int64_t first_done = -1;  // tick the first task ended (-1: not yet)
};

// One tick's joint move, for a validator: before[i] -> after[i];
// delayed[i] = 1 when robot i's move was drawn to fail.
struct JointMove {
  std::vector<int> before;
  std::vector<int> after;
  std::vector<uint8_t> delayed;
};

class Fleet {
 public:
  // Robots on distinct seeded free cells that reach a station (or the
  // given starts). Errors: an option out of range, a goal or start that is
  // not a free cell, two robots on one cell, fewer start cells than robots.
  static Result<std::unique_ptr<Fleet>> Create(const Grid& grid, const FleetOptions& options);
  ~Fleet();
  Fleet(const Fleet&) = delete;
  Fleet& operator=(const Fleet&) = delete;

  // Applies one time step of map changes and repairs every field.
  void ApplyChanges(const ChangeStep& step);

  // Plans and makes one joint move. `preferred` is empty or holds, per
  // robot, a cell to try first (-1: none), such as the next cell of a path
  // from a planning service; it is taken only when it is a legal move.
  const JointMove& Tick(const std::vector<int>& preferred = {});

  const Grid& grid() const { return grid_; }
  const std::vector<FleetRobot>& robots() const { return robots_; }
  const std::vector<int>& goals() const { return goals_; }
  int64_t tick() const { return tick_; }
  int64_t tasks_done() const { return tasks_done_; }
  int64_t overruns() const { return overruns_; }  // robots an obstacle appeared under
  int64_t delays() const { return delays_; }      // moves drawn to fail
  int64_t held() const { return held_; }          // moves held back by a delayed robot
  // Moves from `cell` to the nearest station (-1: none reaches).
  int32_t StationDistance(int cell) const;
  // Moves from `cell` to robot `robot`'s current target (-1: unreachable).
  int32_t TargetDistance(int robot, int cell) const;

 private:
  struct Fields;
  Fleet(const Grid& grid, const FleetOptions& options);
  void PlanPibt(const std::vector<int>& preferred);
  void PlanIgnoringConflicts(const std::vector<int>& preferred);
  bool Pibt(int robot, int parent, const std::vector<int>& preferred);
  bool Crosses(int from, int to) const;
  void ApplyDelays();
  void NextTask(FleetRobot& robot);

  Grid grid_;
  FleetOptions options_;
  std::vector<int> goals_;
  std::unique_ptr<Fields> fields_;
  std::vector<FleetRobot> robots_;
  std::vector<int> next_;      // planned cell per robot (-1: undecided)
  std::vector<int> occupant_;  // per cell: robot on it now (-1)
  std::vector<int> claimed_;   // per cell: robot that will be on it (-1)
  std::vector<int> claimed_cells_;
  std::vector<int> order_;
  std::vector<uint64_t> tie_;  // per robot, a fixed random tie-break
  JointMove move_;
  Rng random_{1};  // delays, then tie-breaks of candidates
  int64_t tick_ = 0;
  int64_t tasks_done_ = 0;
  int64_t overruns_ = 0;
  int64_t delays_ = 0;
  int64_t held_ = 0;
};

}  // namespace dynapath
