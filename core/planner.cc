#include "core/planner.h"

#include "core/approach_registry.h"

namespace dynapath {

std::unique_ptr<Planner> MakePlanner(Approach approach, const PlannerOptions& options,
                                     Trainer* trainer) {
  const ApproachSpec& spec = GetApproachSpec(approach);
  return spec.make_planner(spec, options, trainer);
}

}  // namespace dynapath
