#pragma once
// Runs one approach over a scenario (SPEC section 9): initial training at
// time step 0, then for every step apply the changes, adapt (timed), evaluate.

#include <functional>
#include <string>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/planner.h"
#include "dynapath/policy_state.h"
#include "dynapath/scenario.h"

namespace dynapath {

// Where a run's maze and change sequence come from, one time step at a time:
// a Scenario in memory, or the environment simulator over LCM. Every
// approach is one pass over the same sequence. A source that fails (the
// simulator is gone, the run is stopped) says so in status(), as leveldb's
// iterators do, and returns empty values from then on.
class StepSource {
 public:
  virtual ~StepSource() = default;
  virtual int total_steps() const = 0;
  // The maze at time step 0 of pass `pass`.
  virtual Grid Initial(int pass) = 0;
  // The changes of time step `t` (1..total_steps()) of pass `pass`.
  virtual ChangeStep Changes(int pass, int t) = 0;
  // Ok, or why the source failed (kCancelled when the run was stopped).
  virtual Status status() const { return Ok{}; }
};

class ScenarioStepSource : public StepSource {
 public:
  explicit ScenarioStepSource(const Scenario& scenario) : scenario_(scenario) {}
  int total_steps() const override { return static_cast<int>(scenario_.changes.steps.size()); }
  Grid Initial(int /*pass*/) override { return scenario_.grid; }
  ChangeStep Changes(int /*pass*/, int t) override {
    return scenario_.changes.steps[static_cast<size_t>(t - 1)];
  }

 private:
  const Scenario& scenario_;
};

struct StepRecord {
  int time_step = 0;
  int num_changes = 0;         // obstacle moves requested (the report's NumChanges)
  double adapt_seconds = 0.0;  // 0 at time step 0 and for A* Static
  double success_rate = 0.0;
  double average_path_length = 0.0;
  int nodes_trained = 0;
  int highest_level = -1;
};

struct ApproachRun {
  Approach approach = Approach::kBfsOracle;
  // The row label of a planner from outside core (RunExternalPlanner: the
  // Python module's approaches); "" for a built-in approach.
  std::string external_label;
  std::string size_label;        // "50" for square mazes, "40x60" otherwise
  std::string difficulty_label;  // "Easy", "Medium", "Hard", "Custom", or a map's name
  double initial_seconds = 0.0;
  double load_seconds = 0.0;      // taking over a loaded policy (PolicyHooks), else 0
  std::vector<StepRecord> steps;  // time steps 0..T (S+1..T continuing a loaded policy)

  // SPEC 9 summary: success and length averaged over the steps, adaptation
  // time over those after step 0.
  double AverageSuccessRate() const;
  double AveragePathLength() const;
  double AdaptSecondsPerStep() const;
  // The result files' Approach column: ApproachName(approach) or the
  // external label.
  std::string Label() const;
};

struct RunLabels {
  std::string size_label;
  std::string difficulty_label;
};

// Seconds on a monotonic clock; injectable so tests need no real time.
using Clock = std::function<double()>;
Clock SteadyClock();

// Called after each time step (progress display, policy publishing) with
// the planner and the grid of that step.
struct StepView {
  const ApproachRun& run;
  int pass;
  int total_steps;
  Planner& planner;
  const Grid& grid;
  const StepDetails& details;
};
using StepCallback = std::function<void(const StepView& view)>;

ApproachRun RunApproach(const Scenario& scenario, Approach approach, const PlannerOptions& options,
                        Trainer* trainer, const RunLabels& labels,
                        const Clock& clock = SteadyClock(), const StepCallback& on_step = {});
// The same over any source; `pass` tells the source which pass this is.
// When the source's or the trainer's status() fails, the run ends early
// with the steps so far: the caller checks them (runtime::RunApproaches).
ApproachRun RunApproach(StepSource& source, int pass, Approach approach,
                        const PlannerOptions& options, Trainer* trainer, const RunLabels& labels,
                        const Clock& clock = SteadyClock(), const StepCallback& on_step = {});

// Loading and saving a learning approach's policy (dynapath/policy_state.h).
inline constexpr int kSaveAtEnd = -2;
struct PolicyHooks {
  // Start from this policy instead of the initial training: on the maze it
  // was saved from (same step-0 maze and run seed) the run continues at the
  // step after the saved one, its changes up to that step applied without
  // adapting (its steps then start there; initial_seconds is 0); on another
  // maze of the same shape step 0 adapts from it as after a change of every
  // cell (timed as the initial training).
  const PolicyState* load = nullptr;
  // After which time step `save` gets the policy: -1 never, kSaveAtEnd the
  // last. Called only for planners that export one.
  int save_at = -1;
  std::function<void(PolicyState&&)> save;
  // Every `checkpoint_every` time steps (0: never; step 0 included),
  // `checkpoint` gets the policy after the step and the run's rows so far
  // (a checkpoint of the run: runtime/checkpoint_file.h). Not called for
  // the step a loaded policy continues from.
  int checkpoint_every = 0;
  std::function<void(PolicyState&&, const ApproachRun&)> checkpoint;
  // When set, a checkpoint step is skipped (nothing exported) unless this
  // says one is due (the previous checkpoint's write is done, and the
  // minimum time between checkpoints has passed).
  std::function<bool()> checkpoint_due;
  // The loaded policy must continue this run (a checkpoint of it): when the
  // maze or run seed differ, fail instead of starting from it as on
  // another maze.
  bool must_continue = false;
};
// RunApproach with `hooks`; fails when the loaded policy does not fit the
// run (CheckPolicyFits) or continuing it finds another change sequence.
Result<ApproachRun> RunApproach(StepSource& source, int pass, Approach approach,
                                const PlannerOptions& options, Trainer* trainer,
                                const RunLabels& labels, const PolicyHooks& hooks,
                                const Clock& clock = SteadyClock(),
                                const StepCallback& on_step = {});

// RunApproach's pass a time step at a time, for a caller that acts inside
// a step: the service commits the step's grid under the previous policy
// between taking in a step's changes and retraining. RunApproach is
// Begin, then NextStep and Retrain until NextStep says the run is over.
class ApproachStepper {
 public:
  // `source`, `planner` and `trainer` (may be null) must outlive the
  // stepper; `run` has its approach and labels set.
  ApproachStepper(StepSource& source, int pass, Planner& planner, ApproachRun run,
                  const PlannerOptions& options, Trainer* trainer, const PolicyHooks& hooks,
                  Clock clock = SteadyClock());
  // Time step 0: the initial training, scored, or taking over hooks.load
  // (on the maze it was saved from, its steps caught up without adapting
  // and nothing scored: loaded() is then true). Fails when the loaded
  // policy does not fit the run. When the source or trainer fails, Begin
  // is Ok and failed() says so: the run ends with the steps so far.
  Status Begin();
  // Reads the next time step's changes from the source, applies them to
  // the grid and gives them to the planner (Planner::TakeChanges); false
  // when the run is over (its last step done, or the source failed).
  bool NextStep();
  // After NextStep: whether Retrain will train (until then the planner's
  // Picture shows the step's grid under the previous policy).
  bool retrains() const { return retrains_; }
  // Adapts to the step NextStep took (Planner::Retrain; timed from
  // NextStep's TakeChanges on), scores it and saves or checkpoints as the
  // hooks ask; false when the source or trainer failed.
  bool Retrain();

  bool loaded() const { return loaded_; }
  bool failed() const;
  int total_steps() const { return total_steps_; }
  // The step NextStep took last (the loaded policy's or 0 before).
  int time_step() const { return time_step_; }
  const std::vector<int>& changed_cells() const { return changed_cells_; }
  Planner& planner() { return planner_; }
  const Grid& grid() const { return grid_; }
  const ApproachRun& run() const { return run_; }
  // The last step scored, or taken over when loaded() and none was.
  StepView view() { return StepView{run_, pass_, total_steps_, planner_, grid_, details_}; }
  ApproachRun Take() { return std::move(run_); }

 private:
  bool Export(int time_step, PolicyState& state) const;
  void SaveAndCheckpoint(int time_step, bool checkpoint);

  StepSource& source_;
  const int pass_;
  Planner& planner_;
  ApproachRun run_;
  const uint64_t run_seed_;
  Trainer* const trainer_;
  const PolicyHooks hooks_;
  const Clock clock_;
  const int total_steps_;
  const int save_at_;
  Grid grid_;
  uint64_t initial_fingerprint_ = 0;
  bool loaded_ = false;
  int time_step_ = 0;
  int requested_moves_ = 0;
  std::vector<int> changed_cells_;
  bool retrains_ = false;
  double adapt_start_ = 0.0;
  StepDetails details_;
};

// RunApproach for a planner made outside core (no policy to load or save),
// its rows labelled `label`: the same steps, timing and scoring.
ApproachRun RunExternalPlanner(StepSource& source, int pass, Planner& planner,
                               const std::string& label, const RunLabels& labels,
                               const Clock& clock = SteadyClock(),
                               const StepCallback& on_step = {});

// "50" for a 50x50 maze, "40x60" for 40 rows and 60 columns.
std::string SizeLabel(int rows, int cols);

}  // namespace dynapath
