#pragma once
// The --save-policy file of a run (docs/howto/POLICIES.md, Save): which
// sections it holds and writing it each time a learning approach saves.
//
// A file already at the path keeps the sections the run does not rewrite
// (a run of fedAsynQ_EqAvg saving into a file of four replaces one). A
// resumed run (runtime/checkpoint_file.h) takes up the file only when it
// holds what its checkpoint recorded of it: the sections saved before the
// checkpoint, unchanged, and no section the run neither saved nor found
// there; otherwise it refuses, so the file it finishes is never missing a
// section nor mixed with another run's.

#include <string>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/policy_state.h"
#include "dynapath/result.h"
#include "runtime/checkpoint_file.h"
#include "runtime/policy_file.h"
#include "runtime/policy_options.h"

namespace dynapath::runtime {

class PolicySaver {
 public:
  // The file of `policy.save_path` for a run of `approaches` with
  // `total_steps` steps, continuing from `resume` (null for a new run).
  // Fails (option --save-policy, nothing written) when a file there is not
  // a policy file, or does not hold what `resume` recorded of it.
  static Result<PolicySaver> Open(const PolicyPlan& policy, const std::vector<Approach>& approaches,
                                  int total_steps, const RunCheckpoint* resume);

  // Puts `state`'s section in place of its approach's (or adds it) and
  // rewrites the file atomically.
  Status Save(const PolicyState& state);
  // What the file holds now, for the run's checkpoints.
  std::vector<SavedSection> Record() const;

 private:
  // The section of `approach`, or sections_.end().
  std::vector<PolicySection>::iterator Find(Approach approach);

  std::string path_;
  std::vector<PolicySection> sections_;
};

}  // namespace dynapath::runtime
