#pragma once
// One approach's plan over a run: built at time step 0, adapted after each
// step's changes, scored on the current grid. The runner times Initialize and
// Adapt; everything that counts as adaptation happens inside them.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/convq_model.h"
#include "dynapath/grid.h"
#include "dynapath/learner_options.h"
#include "dynapath/policy_evaluation.h"
#include "dynapath/quadtree.h"
#include "dynapath/result.h"
#include "dynapath/stop_token.h"
#include "dynapath/trainer.h"

namespace dynapath {

struct PolicyState;  // dynapath/policy_state.h

// Whose learning semantics the learning approaches follow (docs/concepts/DECISIONS.md,
// "The report code's semantics"). kReport reproduces the report's public
// code: the update's bootstrap max over all 8 stored values
// (Bootstrap::kAllStored), a node other than the root trained for the first
// time with no trained ancestor starts from zeros instead of the root table
// cut to its region, the report code's single-agent learner
// (SingleAgentRules, core/learn/single_agent_learner.h), and the Q-tables hold
// doubles instead of floats.
enum class Semantics { kOurs, kReport };

// The learner options (the base: bootstrap, single_agent, federated) are
// the learning approaches'; the approach sets the averaging, --semantics
// report the bootstrap.
class Planner;

struct PlannerOptions : LearnerOptions {
  uint64_t run_seed = 0;                         // learners' seeds derive from it
  int leaf_limit = QuadTree::kDefaultLeafLimit;  // largest leaf side
  RetrainingThresholds thresholds;
  Semantics semantics = Semantics::kOurs;
  // The tables' value type when not the semantics' own (float for kOurs,
  // double for kReport): only for experiments that separate the report
  // code's rules from its precision (bench/semantics_spread report-float).
  std::optional<QPrecision> table_precision;
  // Ctrl-C: planners whose one step can take long (A* Oracle's per-start
  // searches) end it early once set; the run is then cancelled. Not a
  // parameter of the results.
  StopToken stop = nullptr;
  // convQ's model (--model FILE); null: the shipped one (ShippedConvQModel).
  std::shared_ptr<const ConvQModel> convq_model;
};

// What an initialisation or adaptation did (extra result columns).
struct StepDetails {
  int nodes_trained = 0;
  int highest_level = -1;               // smallest quadtree level trained, -1 if none
  std::vector<Region> trained_regions;  // regions of the trained nodes (for viewers)
};

// The policy as a picture (for viewers): per cell, the greedy action (-1 for
// obstacles and stations) and whether following the policy from the cell
// reaches a station (1), fails (0) or the cell is no start (-1). `second`
// (the second-best action, -1 where `actions` is) and `depth` (the policy
// evaluation's path length to a station, kNoPath for failing starts and
// obstacles) are what a path query needs to walk the path that evaluation
// counted (dynapath/routes.h).
struct PolicyPicture {
  std::vector<int8_t> actions;
  std::vector<int8_t> reaches;
  std::vector<int8_t> second;
  std::vector<int32_t> depth;
};

class Planner {
 public:
  virtual ~Planner() = default;
  virtual StepDetails Initialize(const Grid& grid) = 0;
  // `grid` already holds the step's changes; `changed_cells` their positions.
  virtual StepDetails Adapt(const Grid& grid, const std::vector<int>& changed_cells) = 0;
  // Adapt in two calls, for a caller that acts between them (the service
  // commits the step's grid under the previous policy while the retraining
  // runs): TakeChanges takes in the step's changes (same arguments as
  // Adapt; `grid` must outlive Retrain) and decides what to retrain, true
  // when Retrain will train something (until then Picture shows `grid`
  // under the previous step's policy); Retrain then adapts. The two in a
  // row are Adapt. The defaults: TakeChanges keeps its arguments and
  // returns false, Retrain calls Adapt with them.
  virtual bool TakeChanges(const Grid& grid, const std::vector<int>& changed_cells);
  virtual StepDetails Retrain();
  virtual PolicyScore Evaluate(const Grid& grid) = 0;
  // Fills `picture` for the current policy on `grid` (after Evaluate);
  // false for approaches without a table (the baselines).
  virtual bool Picture(const Grid& /*grid*/, PolicyPicture& /*picture*/) { return false; }
  // False for a plan that never adapts (A* Static): its adaptation time is 0
  // by definition, not the time of a call that does nothing.
  virtual bool Adapts() const { return true; }
  // The learning approaches' state (dynapath/policy_state.h): ExportPolicy
  // fills `state` but its step and fingerprints (the runner's) and returns
  // true; false for approaches without one. ImportPolicy replaces
  // Initialize: it checks that `state` fits (CheckPolicyFits) and takes it
  // over on `grid`, which the next Adapt call changes.
  virtual bool ExportPolicy(PolicyState& /*state*/) const { return false; }
  virtual Status ImportPolicy(const PolicyState& state, const Grid& grid);
  // The exact distance of every cell to its nearest station on the current
  // grid (kUnreachable where none), for planners that keep them up to date
  // (Incremental Oracle); null for the others.
  virtual const std::vector<int32_t>* ExactDistances() const { return nullptr; }

 private:
  // The default TakeChanges' arguments, for the default Retrain.
  const Grid* taken_grid_ = nullptr;
  std::vector<int> taken_cells_;
};

// The approach's planner (its factory in core/plan/approach_registry.h).
// `trainer` is used by the learning approaches and must outlive the planner
// (ignored, may be null, for the baselines).
std::unique_ptr<Planner> MakePlanner(Approach approach, const PlannerOptions& options,
                                     Trainer* trainer);

}  // namespace dynapath
