#include "dynapath/routes.h"

#include <unordered_set>

#include "dynapath/bfs_oracle.h"
#include "dynapath/mdp.h"

namespace dynapath {
namespace {

// The neighbour of `cell` by action `a`, or -1 off the grid.
int Target(const Grid& grid, int cell, int a) {
  if (a < 0) return -1;
  const int r = grid.RowOf(cell) + kActionRowOffset[a];
  const int c = grid.ColOf(cell) + kActionColOffset[a];
  return grid.InBounds(r, c) ? grid.Index(r, c) : -1;
}

// Why the policy fails from `start` (its depth is kNoPath): the greedy
// walk tells a user what goes wrong (it cycles, walks into a wall, or is
// still under way after rows + cols moves).
RouteStatus WhyLearnedFails(const RouteSnapshot& s, int start) {
  const Grid& grid = s.grid;
  const int limit = grid.rows() + grid.cols();
  std::unordered_set<int> seen;
  int cell = start;
  for (int moves = 0; moves < limit; ++moves) {
    if (grid.at(cell) == Cell::kStation) return RouteStatus::kTooLong;
    if (!seen.insert(cell).second) return RouteStatus::kLoops;
    const int next = Target(grid, cell, s.best[static_cast<size_t>(cell)]);
    if (next < 0 || grid.at(next) == Cell::kObstacle) return RouteStatus::kHitsObstacle;
    cell = next;
  }
  return RouteStatus::kTooLong;
}

Route LearnedRoute(const RouteSnapshot& s, int start, size_t budget) {
  Route route;
  route.answered_by = AnsweredBy::kLearned;
  const int32_t depth = s.depth[static_cast<size_t>(start)];
  if (depth == kNoPath) {
    route.status = WhyLearnedFails(s, start);
    return route;
  }
  if (static_cast<size_t>(depth) + 1 > budget) {
    route.status = RouteStatus::kOverBudget;
    return route;
  }
  // The evaluation's depths come from the same two successors per cell:
  // one of them is always a level closer (the best one preferred).
  int cell = start;
  route.cells.push_back(cell);
  for (int32_t d = depth; d > 0; --d) {
    int next = -1;
    for (int8_t a : {s.best[static_cast<size_t>(cell)], s.second[static_cast<size_t>(cell)]}) {
      const int t = Target(s.grid, cell, a);
      if (t >= 0 && s.grid.at(t) != Cell::kObstacle && s.depth[static_cast<size_t>(t)] == d - 1) {
        next = t;
        break;
      }
    }
    if (next < 0) {  // a snapshot whose depths do not match its actions
      route.cells.clear();
      route.status = RouteStatus::kLoops;
      return route;
    }
    cell = next;
    route.cells.push_back(cell);
  }
  route.status = RouteStatus::kReached;
  route.length = depth;
  return route;
}

Route ExactRoute(const RouteSnapshot& s, int start, size_t budget) {
  Route route;
  route.answered_by = AnsweredBy::kExact;
  const int32_t distance = s.distance[static_cast<size_t>(start)];
  if (distance == kUnreachable) {
    route.status = RouteStatus::kNoRoute;
    return route;
  }
  if (static_cast<size_t>(distance) + 1 > budget) {
    route.status = RouteStatus::kOverBudget;
    return route;
  }
  int cell = start;
  route.cells.push_back(cell);
  for (int32_t d = distance; d > 0; --d) {
    int next = -1;
    for (int a = 0; a < kNumActions && next < 0; ++a) {
      const int t = Target(s.grid, cell, a);
      if (t >= 0 && s.grid.at(t) != Cell::kObstacle &&
          s.distance[static_cast<size_t>(t)] == d - 1) {
        next = t;
      }
    }
    if (next < 0) {
      route.cells.clear();
      route.status = RouteStatus::kNoRoute;
      return route;
    }
    cell = next;
    route.cells.push_back(cell);
  }
  route.status = RouteStatus::kReached;
  route.length = distance;
  return route;
}

}  // namespace

const char* RouteStatusName(RouteStatus status) {
  switch (status) {
    case RouteStatus::kReached:
      return "reached";
    case RouteStatus::kLoops:
      return "loops";
    case RouteStatus::kHitsObstacle:
      return "hits_obstacle";
    case RouteStatus::kTooLong:
      return "too_long";
    case RouteStatus::kStartObstacle:
      return "start_obstacle";
    case RouteStatus::kOutsideGrid:
      return "outside_grid";
    case RouteStatus::kNoRoute:
      return "unreachable";
    case RouteStatus::kOverBudget:
      return "over_budget";
  }
  return "unknown";
}

const char* AnsweredByName(AnsweredBy by) {
  switch (by) {
    case AnsweredBy::kNone:
      return "none";
    case AnsweredBy::kLearned:
      return "learned";
    case AnsweredBy::kExact:
      return "exact";
  }
  return "unknown";
}

RouteSnapshot MakeRouteSnapshot(Planner& planner, const Grid& grid, const Planner* exact,
                                int64_t version, int time_step) {
  RouteSnapshot s;
  s.version = version;
  s.time_step = time_step;
  s.grid = grid;
  PolicyPicture picture;
  if (planner.Picture(grid, picture) && picture.depth.size() == static_cast<size_t>(grid.size())) {
    s.best = std::move(picture.actions);
    s.second = std::move(picture.second);
    s.depth = std::move(picture.depth);
  }
  const std::vector<int32_t>* distances =
      exact != nullptr ? exact->ExactDistances() : planner.ExactDistances();
  if (distances != nullptr && distances->size() == static_cast<size_t>(grid.size())) {
    s.distance = *distances;
  }
  return s;
}

bool PictureOf(const RouteSnapshot& s, PolicyPicture& picture) {
  if (!s.has_learned()) return false;
  picture.actions = s.best;
  picture.second = s.second;
  picture.depth = s.depth;
  picture.reaches.assign(s.depth.size(), -1);
  for (int cell = 0; cell < s.grid.size(); ++cell) {
    if (s.grid.at(cell) == Cell::kObstacle) continue;
    picture.reaches[static_cast<size_t>(cell)] =
        s.depth[static_cast<size_t>(cell)] == kNoPath ? 0 : 1;
  }
  return true;
}

Route AnswerRoute(const RouteSnapshot& s, int row, int col, AnswerMode mode, size_t budget) {
  Route route;
  if (!s.grid.InBounds(row, col)) {
    route.status = RouteStatus::kOutsideGrid;
    return route;
  }
  const int start = s.grid.Index(row, col);
  if (s.grid.at(start) == Cell::kObstacle) {
    route.status = RouteStatus::kStartObstacle;
    return route;
  }
  const bool learned = mode != AnswerMode::kExact && s.has_learned();
  if (learned) {
    route = LearnedRoute(s, start, budget);
    if (route.status == RouteStatus::kReached || route.status == RouteStatus::kOverBudget ||
        mode == AnswerMode::kLearned || !s.has_exact()) {
      return route;
    }
  }
  if (s.has_exact()) return ExactRoute(s, start, budget);
  return route;
}

int32_t ExactDistanceFrom(const Grid& grid, int cell) {
  std::vector<int32_t> distance, queue;
  NearestStationDistances(grid, distance, queue);
  return distance[static_cast<size_t>(cell)];
}

}  // namespace dynapath
