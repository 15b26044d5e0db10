#include "core/plan/baseline_planners.h"

#include <memory>

#include "core/plan/approach_registry.h"
#include "dynapath/bfs_oracle.h"

namespace dynapath {

StepDetails AStarStaticPlanner::Initialize(const Grid& grid) {
  astar_.ComputeAllPaths(grid, paths_);
  return {};
}

PolicyScore AStarStaticPlanner::Evaluate(const Grid& grid) {
  return ScoreStoredPaths(grid, paths_);
}

StepDetails AStarOraclePlanner::Initialize(const Grid& grid) {
  // Stopped early, the paths are partial; the run is cancelled after this
  // step and nothing of it is written.
  astar_.ComputeAllPaths(grid, paths_, stop_);
  return {};
}

PolicyScore AStarOraclePlanner::Evaluate(const Grid& grid) {
  return ScoreStoredPaths(grid, paths_);
}

StepDetails BfsOraclePlanner::Initialize(const Grid& grid) {
  NearestStationDistances(grid, distance_, queue_);
  return {};
}

PolicyScore BfsOraclePlanner::Evaluate(const Grid& grid) { return ScoreDistances(grid, distance_); }

// Factories of core/include/dynapath/approach_list.h.
std::unique_ptr<Planner> MakeAStarStaticPlanner(const ApproachSpec&, const PlannerOptions&,
                                                Trainer*) {
  return std::make_unique<AStarStaticPlanner>();
}

std::unique_ptr<Planner> MakeAStarOraclePlanner(const ApproachSpec&,
                                                const PlannerOptions& options, Trainer*) {
  return std::make_unique<AStarOraclePlanner>(options.stop);
}

std::unique_ptr<Planner> MakeBfsOraclePlanner(const ApproachSpec&, const PlannerOptions&,
                                              Trainer*) {
  return std::make_unique<BfsOraclePlanner>();
}

}  // namespace dynapath
