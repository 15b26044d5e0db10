#include "core/planner.h"

#include "core/baseline_planners.h"
#include "core/incremental_oracle.h"
#include "core/learning_planner.h"

namespace dynapath {

std::unique_ptr<Planner> MakePlanner(Approach approach, const PlannerOptions& options,
                                     Trainer* trainer) {
  switch (approach) {
    case Approach::kAStarStatic:
      return std::make_unique<AStarStaticPlanner>();
    case Approach::kAStarOracle:
      return std::make_unique<AStarOraclePlanner>();
    case Approach::kBfsOracle:
      return std::make_unique<BfsOraclePlanner>();
    case Approach::kIncrementalOracle:
      return std::make_unique<IncrementalOraclePlanner>();
    default:
      return std::make_unique<LearningPlanner>(approach, options, *trainer);
  }
}

}  // namespace dynapath
