#pragma once
// Answering path queries from one committed policy (dynapath serve): the
// path from a start cell to a station that the policy evaluation counted
// (SPEC section 4: the breadth-first walk over each cell's two best
// actions), or the exact shortest one from the nearest-station distances.
// A RouteSnapshot is built once per committed time step and never changes
// afterwards, so any number of threads may answer from it while the next
// one is being trained.

#include <cstdint>
#include <string>
#include <vector>

#include "dynapath/grid.h"
#include "dynapath/planner.h"

namespace dynapath {

// Values equal path_reply_t's (the wire keeps them; tests check).
enum class RouteStatus : int8_t {
  kReached = 0,
  kLoops = 1,         // the greedy policy cycles without reaching a station
  kHitsObstacle = 2,  // it walks into an obstacle
  kTooLong = 3,       // no station within rows + cols moves
  kStartObstacle = 4,
  kOutsideGrid = 5,
  kNoRoute = 6,     // no station can be reached from the start at all
  kOverBudget = 7,  // the path did not fit the reply's budget
};
enum class AnsweredBy : int8_t { kNone = 0, kLearned = 1, kExact = 2 };
// --answer: the policy's path only, the exact shortest path only, or the
// policy's where it reaches a station and the exact one elsewhere.
enum class AnswerMode { kLearned, kExact, kLearnedElseExact };
const char* RouteStatusName(RouteStatus status);  // "reached", "loops", ...
const char* AnsweredByName(AnsweredBy by);        // "none", "learned", "exact"

struct RouteSnapshot {
  int64_t version = 0;  // commits so far, 1 for the first
  int time_step = 0;
  Grid grid;
  // The learned policy (empty when the approach has none): per cell its two
  // best actions (-1 none) and the evaluation's depth (kNoPath: fails).
  std::vector<int8_t> best, second;
  std::vector<int32_t> depth;
  // Exact distances to the nearest station (empty when not kept).
  std::vector<int32_t> distance;

  bool has_learned() const { return !depth.empty(); }
  bool has_exact() const { return !distance.empty(); }
};

// The snapshot of `planner` on `grid` (after its Evaluate): the policy
// from Picture, the exact distances from `exact` (may be null) or the
// planner's own ExactDistances.
RouteSnapshot MakeRouteSnapshot(Planner& planner, const Grid& grid, const Planner* exact,
                                int64_t version, int time_step);
// The planner's Picture that `s` was made from, rebuilt from the snapshot
// alone (so another thread can publish it while training goes on); false
// when the snapshot has no learned policy.
bool PictureOf(const RouteSnapshot& s, PolicyPicture& picture);

struct Route {
  RouteStatus status = RouteStatus::kOutsideGrid;
  AnsweredBy answered_by = AnsweredBy::kNone;
  int32_t length = -1;     // moves, -1 unless reached
  std::vector<int> cells;  // start .. station (row-major), empty unless reached
};

// The route from (row, col). `budget`: the most cells its path may hold
// (kOverBudget beyond). Paths are valid moves: each step to one of the 8
// neighbours, never onto an obstacle, ending on a station; a learned path
// has exactly the evaluation's depth, an exact one the optimum.
Route AnswerRoute(const RouteSnapshot& snapshot, int row, int col, AnswerMode mode, size_t budget);

// The exact shortest-path length from `cell` by a breadth-first search on
// `grid` (kUnreachable when none): the check of every answer in tests.
int32_t ExactDistanceFrom(const Grid& grid, int cell);

}  // namespace dynapath
