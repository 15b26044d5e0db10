#include "core/plan/approach_registry.h"

#include <cassert>

namespace dynapath {

// The factories named in core/include/dynapath/approach_list.h, each defined in its
// approach's module; declared here from the list so that a registry line is
// all an approach needs (a missing or mistyped factory fails to link).
#define DYNAPATH_DECLARE_FACTORIES(id, name, planner, learner, averaging, strategy) \
  std::unique_ptr<Planner> planner(const ApproachSpec&, const PlannerOptions&, Trainer*);
DYNAPATH_APPROACHES(DYNAPATH_DECLARE_FACTORIES)
#undef DYNAPATH_DECLARE_FACTORIES

namespace {

// The "learner" column: no learner, or a LearnerKind enumerator (one
// constant per kind of core/include/dynapath/training_job.h's list).
constexpr std::optional<LearnerKind> kNoLearner = std::nullopt;
#define DYNAPATH_LEARNER_COLUMN(kind) constexpr std::optional<LearnerKind> kind = LearnerKind::kind;
DYNAPATH_LEARNER_KINDS(DYNAPATH_LEARNER_COLUMN)
#undef DYNAPATH_LEARNER_COLUMN
constexpr Averaging kEqual = Averaging::kEqual;
constexpr Averaging kImportance = Averaging::kImportance;

}  // namespace

const std::vector<ApproachSpec>& ApproachRegistry() {
#define DYNAPATH_APPROACH_SPEC(id, name, planner, learner, averaging, strategy) \
  ApproachSpec{Approach::id, name, &planner, learner, averaging, strategy},
  static const std::vector<ApproachSpec> registry = {DYNAPATH_APPROACHES(DYNAPATH_APPROACH_SPEC)};
#undef DYNAPATH_APPROACH_SPEC
  return registry;
}

const ApproachSpec& GetApproachSpec(Approach approach) {
  // The enum is generated from the same list in the same order, so every
  // value of the enum indexes its own line.
  const std::vector<ApproachSpec>& registry = ApproachRegistry();
  const auto index = static_cast<size_t>(approach);
  assert(index < registry.size() && registry[index].approach == approach);
  return registry[index];
}

}  // namespace dynapath
