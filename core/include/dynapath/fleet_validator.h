#pragma once
// An independent check of a fleet's joint moves (it shares no code with
// the planner of fleet.h): given the grid of the tick, where each robot was
// and where it is after the tick, and which robots' moves were drawn to
// fail, it counts every rule broken:
//   * out_of_bounds: a cell outside the grid;
//   * onto_obstacle: a robot moved onto an obstacle;
//   * not_adjacent: a move that is not a stay or one of the 8 king moves;
//   * vertex: two robots on one cell after the tick (each extra robot);
//   * swap: two robots exchanged their cells;
//   * crossing: two diagonal moves crossed inside one 2x2 square;
//   * delay: a robot whose move was drawn to fail moved.
// A robot that stays on a cell an obstacle appeared on (an overrun) is not
// a conflict: it is counted apart.

#include <cstdint>
#include <vector>

#include "dynapath/grid.h"

namespace dynapath {

struct JointMoveReport {
  int64_t out_of_bounds = 0;
  int64_t onto_obstacle = 0;
  int64_t not_adjacent = 0;
  int64_t vertex = 0;
  int64_t swap = 0;
  int64_t crossing = 0;
  int64_t delay = 0;
  int64_t overrun = 0;  // not a conflict
  int64_t conflicts() const {
    return out_of_bounds + onto_obstacle + not_adjacent + vertex + swap + crossing + delay;
  }
  void Add(const JointMoveReport& other);
};

// `before`, `after` (same length) and `delayed` (empty: no delays, or the
// same length) per robot, cells as row-major indices.
JointMoveReport CheckJointMove(const Grid& grid, const std::vector<int>& before,
                               const std::vector<int>& after, const std::vector<uint8_t>& delayed);

}  // namespace dynapath
