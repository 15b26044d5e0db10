#include "dynapath/planner.h"

#include "core/plan/approach_registry.h"

namespace dynapath {

std::unique_ptr<Planner> MakePlanner(Approach approach, const PlannerOptions& options,
                                     Trainer* trainer) {
  const ApproachSpec& spec = GetApproachSpec(approach);
  return spec.make_planner(spec, options, trainer);
}

Status Planner::ImportPolicy(const PolicyState& /*state*/, const Grid& /*grid*/) {
  return Error("this approach learns no policy");
}

}  // namespace dynapath
