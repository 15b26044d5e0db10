#pragma once
// --save-policy, --save-at and --load-policy of `dynapath run` (and the
// coordinator, which gets them from the launcher): what a run saves and
// starts from (runtime/policy_file.h is the file, docs/howto/POLICIES.md the
// guide).
//
// A policy file holds one section per learning approach of the run that
// saved it (with --approach all: onlyTrainLeafNodes, singleAgent and both
// fedAsynQ variants). Loading gives each learning approach of the run its
// own section and fails when one is missing; the baselines run as usual.

#include <memory>
#include <string>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/experiment.h"
#include "dynapath/policy_state.h"
#include "runtime/option_group.h"

namespace dynapath::runtime {

// The options as given (declared by DeclareRunOptions).
struct PolicyOptions {
  std::string save_policy;    // FILE, "" none
  std::string save_at = "0";  // STEP or end
  std::string load_policy;    // FILE, "" none
};

// What a run saves and loads, resolved.
struct PolicyPlan {
  std::string save_path;  // "" saves nothing
  int save_at = 0;        // a time step, or kSaveAtEnd
  std::string load_path;
  // The loaded file's sections (shared: run plans are copied).
  std::shared_ptr<const std::vector<PolicyState>> loaded;

  // The loaded section of `approach`, or null.
  const PolicyState* Find(Approach approach) const;
};

void DeclarePolicyOptions(OptionGroup& group, PolicyOptions& options);

// Checks the options against the run's approaches and reads --load-policy's
// file (every error names the option or the file).
Result<PolicyPlan> ResolvePolicyOptions(const PolicyOptions& options,
                                        const std::vector<Approach>& approaches);

// Ok when the loaded policy can start every learning approach of the run
// on the maze `initial` (step 0) with `options` and learner seed
// `run_seed`, and --save-at is a step each learning approach will run in a
// run of `total_steps` steps (a section loaded on the maze it was saved on
// continues after its step: an earlier --save-at is never reached);
// otherwise an error naming the option.
Status CheckPolicyPlan(const PolicyPlan& plan, const std::vector<Approach>& approaches,
                       const PlannerOptions& options, const Grid& initial, int total_steps,
                       uint64_t run_seed);

}  // namespace dynapath::runtime
