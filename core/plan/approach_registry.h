#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/approach.h"
#endif
// What each approach is made of, from its one line in core/include/dynapath/approach_list.h:
// the planner factory, and for learning approaches the learner (kind and
// averaging) and the retraining strategy. The only place that maps an
// approach to its parts; everything else asks here.

#include <memory>
#include <optional>
#include <vector>

#include "core/plan/retraining_strategy.h"
#include "dynapath/approach.h"
#include "dynapath/planner.h"
#include "dynapath/training_job.h"

namespace dynapath {

struct ApproachSpec;

// Builds an approach's planner. `trainer` is used by learning approaches
// (must outlive the planner), ignored (may be null) by the others.
using PlannerFactory = std::unique_ptr<Planner> (*)(const ApproachSpec& spec,
                                                    const PlannerOptions& options,
                                                    Trainer* trainer);
// Builds a learning approach's retraining strategy over `tree` (which must
// outlive it).
using StrategyFactory = std::unique_ptr<RetrainingStrategy> (*)(
    const QuadTree& tree, const RetrainingThresholds& thresholds);

struct ApproachSpec {
  Approach approach;
  const char* name;  // the result-file name
  PlannerFactory make_planner;
  std::optional<LearnerKind> learner;  // none: the approach does not learn
  Averaging averaging;                 // the federated learner's averaging
  StrategyFactory make_strategy;       // null exactly when there is no learner
};

// Every approach, in the order of core/include/dynapath/approach_list.h.
const std::vector<ApproachSpec>& ApproachRegistry();

const ApproachSpec& GetApproachSpec(Approach approach);

}  // namespace dynapath
