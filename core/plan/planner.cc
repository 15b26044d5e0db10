#include "dynapath/planner.h"

#include <cassert>

#include "core/plan/approach_registry.h"

namespace dynapath {

std::unique_ptr<Planner> MakePlanner(Approach approach, const PlannerOptions& options,
                                     Trainer* trainer) {
  const ApproachSpec& spec = GetApproachSpec(approach);
  return spec.make_planner(spec, options, trainer);
}

bool Planner::TakeChanges(const Grid& grid, const std::vector<int>& changed_cells) {
  taken_grid_ = &grid;
  taken_cells_ = changed_cells;
  return false;
}

StepDetails Planner::Retrain() {
  assert(taken_grid_ != nullptr);  // TakeChanges came first
  const Grid& grid = *taken_grid_;
  taken_grid_ = nullptr;
  return Adapt(grid, taken_cells_);
}

Status Planner::ImportPolicy(const PolicyState& /*state*/, const Grid& /*grid*/) {
  return Error("this approach learns no policy");
}

}  // namespace dynapath
