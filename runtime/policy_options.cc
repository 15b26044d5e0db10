#include "runtime/policy_options.h"

#include <spdlog/spdlog.h>

#include <charconv>
#include <chrono>

#include "dynapath/change_sequence.h"
#include "runtime/policy_file.h"

namespace dynapath::runtime {

const PolicyState* PolicyPlan::Find(Approach approach) const {
  if (!loaded) return nullptr;
  for (const PolicyState& state : *loaded) {
    if (state.approach == approach) return &state;
  }
  return nullptr;
}

void DeclarePolicyOptions(OptionGroup& group, PolicyOptions& o) {
  group.Option("--save-policy", o.save_policy, "FILE",
               "save the learning approaches' policies (one section each; docs/howto/POLICIES.md)");
  group.Option("--save-at", o.save_at, "STEP",
               "the time step after which --save-policy saves: 0 (after the initial training), "
               "a later step, or end");
  group.Option("--load-policy", o.load_policy, "FILE",
               "start each learning approach from its section of FILE: on the maze it was saved "
               "on the run continues after the saved step (result rows from there on), on "
               "another maze of the same shape step 0 adapts from it instead of training");
}

Result<PolicyPlan> ResolvePolicyOptions(const PolicyOptions& o,
                                        const std::vector<Approach>& approaches) {
  PolicyPlan plan;
  plan.save_path = o.save_policy;
  plan.load_path = o.load_policy;
  std::vector<Approach> learning;
  for (Approach approach : approaches) {
    if (IsLearningApproach(approach)) learning.push_back(approach);
  }
  if (o.save_at == "end") {
    plan.save_at = kSaveAtEnd;
  } else {
    int step = -1;
    const char* end = o.save_at.data() + o.save_at.size();
    const auto [ptr, ec] = std::from_chars(o.save_at.data(), end, step);
    if (ec != std::errc() || ptr != end || step < 0) {
      return Error::Option("save-at", "must be a time step (0, 1, ...) or end, got '" +
                                          o.save_at.substr(0, 40) + "'");
    }
    plan.save_at = step;
  }
  if (o.save_at != PolicyOptions{}.save_at && plan.save_path.empty()) {
    return Error::Option("save-at", "needs --save-policy FILE");
  }
  if ((!plan.save_path.empty() || !plan.load_path.empty()) && learning.empty()) {
    return Error::Option(plan.save_path.empty() ? "load-policy" : "save-policy",
                         "needs a learning approach (onlyTrainLeafNodes, singleAgent, "
                         "fedAsynQ_EqAvg or fedAsynQ_ImAvg)");
  }
  if (plan.load_path.empty()) return plan;
  const auto start = std::chrono::steady_clock::now();
  Result<std::vector<PolicyState>> states = ReadPolicyFile(plan.load_path);
  if (!states) return states.error();
  spdlog::info("read {} ({} sections) in {:.3f} s", plan.load_path, states->size(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  plan.loaded = std::make_shared<const std::vector<PolicyState>>(std::move(*states));
  for (Approach approach : learning) {
    if (plan.Find(approach) != nullptr) continue;
    std::string held;
    for (const PolicyState& state : *plan.loaded) {
      held += (held.empty() ? "" : ", ") + ApproachName(state.approach);
    }
    return Error::Option("load-policy", plan.load_path + " holds no policy for " +
                                            ApproachName(approach) + " (it holds " + held +
                                            "; choose them with --approach)");
  }
  return plan;
}

Status CheckPolicyPlan(const PolicyPlan& plan, const std::vector<Approach>& approaches,
                       const PlannerOptions& options, const Grid& initial, int total_steps,
                       uint64_t run_seed) {
  const bool saving = !plan.save_path.empty();
  if (saving && plan.save_at != kSaveAtEnd && plan.save_at > total_steps) {
    return Error::Option("save-at", "step " + std::to_string(plan.save_at) +
                                        " is past the run's last step " +
                                        std::to_string(total_steps));
  }
  const uint64_t initial_fingerprint = MazeFingerprint(initial);
  for (Approach approach : approaches) {
    const PolicyState* state = plan.Find(approach);
    if (state == nullptr) continue;
    if (Status fits = CheckPolicyFits(*state, approach, options, initial.rows(), initial.cols());
        !fits) {
      return Error::Option("load-policy", plan.load_path + ": " + fits.error().message);
    }
    // On its own maze the section continues after its step (RunApproach):
    // the steps before it, where an earlier --save-at is, are not run.
    const bool continues =
        state->initial_fingerprint == initial_fingerprint && state->run_seed == run_seed;
    if (saving && continues && plan.save_at != kSaveAtEnd && plan.save_at < state->step) {
      return Error::Option("save-at", "step " + std::to_string(plan.save_at) + " is before step " +
                                          std::to_string(state->step) + " of " + plan.load_path +
                                          "'s " + ApproachName(approach) +
                                          ", after which the run continues: save at " +
                                          std::to_string(state->step) + " or later, or at end");
    }
  }
  return Ok{};
}

}  // namespace dynapath::runtime
