#pragma once
// Runs a list of approaches over one maze and change sequence and writes the
// result files: the part of a run shared by `dynapath run --local` and the
// coordinator process, so both produce the same files the same way.

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dynapath/experiment.h"
#include "dynapath/quadtree.h"
#include "dynapath/results_csv.h"
#include "dynapath/training_progress.h"
#include "runtime/checkpoint_file.h"
#include "runtime/option_group.h"
#include "runtime/parameter_options.h"
#include "runtime/policy_options.h"
#include "runtime/scenario_options.h"
#include "runtime/word_table.h"

namespace dynapath::runtime {

// How a distributed run spreads a training batch over the agent processes
// (coordinator/distributed_trainer.h); --local ignores it.
enum class Placement {
  kAuto,   // split a batch's learners only when its rounds are long enough to pay
  kWhole,  // always whole jobs per agent
  kSplit,  // split learners whenever the batch has fewer jobs than agents
};

// --checkpoint, --checkpoint-every and the resumed checkpoint, resolved.
struct CheckpointPlan {
  std::string dir;         // "" writes none
  int every = 1;           // time steps between checkpoints
  double min_seconds = 0;  // and at least this long between them
  // The checkpoint the run continues from (--resume-checkpoint found one).
  std::shared_ptr<const RunCheckpoint> resume;
  // A test hook (DYNAPATH_TEST_HOLD=run:STEP, runtime/test_hold.h): the
  // process stops itself once the first approach's first checkpoint at or
  // after this time step is on disk. -1: never.
  int hold_after_step = -1;
};

// An approach from outside core (the Python module's): its planner and the
// label of its rows, run before approaches[before] (after them all when
// `before` is their count), over the same source and scored the same way.
// Only for a run in one process (RunLocal): no policy file, no checkpoint.
struct ExternalApproach {
  std::string label;
  std::shared_ptr<Planner> planner;
  size_t before = 0;
};

struct RunPlan {
  std::vector<Approach> approaches;
  std::vector<ExternalApproach> external;  // none from the command line
  PlannerOptions options;                  // run_seed is set from the scenario
  std::string out_dir = "results";
  Placement placement = Placement::kAuto;
  PolicyPlan policy;  // --save-policy, --save-at, --load-policy
  CheckpointPlan checkpoint;
  // --learner-seed: the seed every learner's stream derives from. Unset: the
  // maze's seed (the scenario's --seed), the stream of runs without it.
  std::optional<uint64_t> learner_seed;
  // --model: the model file options.convq_model was read from ("" the
  // shipped model), for params.toml.
  std::string model_path;
  // The run seed the learners' seeds derive from on a maze of seed
  // `maze_seed`: learner_seed when set, else maze_seed.
  uint64_t RunSeed(uint64_t maze_seed) const { return learner_seed.value_or(maze_seed); }
};

// --learner-seed takes 0 to 2^53 - 1 (exact in JSON and in every TOML reader).
inline constexpr long long kMaxLearnerSeed = (1LL << 53) - 1;

// The words of --bootstrap, --semantics and --placement (also a study
// file's keys), each written once: help texts, checks and parses read them.
const WordTable<Bootstrap>& BootstrapWords();
const WordTable<Semantics>& SemanticsWords();
const WordTable<Placement>& PlacementWords();

// The options of a run plan as given; ResolveRunOptions checks them. Their
// defaults are the run plan's and the planner's own, as words.
struct RunOptions {
  std::string approach = "all";
  std::string out = RunPlan{}.out_dir;
  long long leaf_limit = PlannerOptions{}.leaf_limit;
  std::string bootstrap = BootstrapWords().Name(PlannerOptions{}.bootstrap);
  std::string semantics = SemanticsWords().Name(PlannerOptions{}.semantics);
  std::string placement = PlacementWords().Name(RunPlan{}.placement);
  PolicyOptions policy;
  ParameterOptions parameters;                // the learner and strategy parameters given
  std::string checkpoint;                     // DIR, "" none
  std::optional<long long> checkpoint_every;  // K, 1 when unset (needs --checkpoint)
  std::optional<double> checkpoint_interval;  // SECONDS, 0 when unset (needs --checkpoint)
  bool resume_checkpoint = false;         // continue from DIR's checkpoint (run --resume sets it)
  std::optional<long long> learner_seed;  // --learner-seed
  std::string model;                      // --model FILE, "" the shipped model
};
// The values the run plan's options accept, checked without naming the
// option (callers add "option --NAME" or a config file's origin), so that
// `run` and `experiment` check them the same way.
inline constexpr long long kMaxLeafLimit = 10000;
Status CheckBootstrap(const std::string& text);  // "must be in-grid or in-region, got 'x'"
Status CheckSemantics(const std::string& text);
Status CheckPlacement(const std::string& text);

// --leaf-limit alone (dynapath maze), checked.
void DeclareLeafLimitOption(OptionGroup& group, long long& leaf_limit);
Result<int> ResolveLeafLimit(long long leaf_limit);
// --leaf-limit, --bootstrap, --semantics and every learner and strategy
// parameter (also `dynapath experiment`'s).
void DeclareLearnerOptions(OptionGroup& group, RunOptions& options);
// --placement (also `dynapath experiment`'s).
void DeclarePlacementOption(OptionGroup& group, RunOptions& options);
// Declares --approach, --out, the learner options, --placement, the
// policy options (runtime/policy_options.h) and the checkpoint options.
void DeclareRunOptions(OptionGroup& group, RunOptions& options);
Result<RunPlan> ResolveRunOptions(const RunOptions& options);
// --checkpoint DIR ("" none), --checkpoint-every, --checkpoint-interval and
// --resume-checkpoint into plan.checkpoint, checked; with `resume`, DIR's
// checkpoint is read and must be of plan.approaches' run. ResolveRunOptions
// uses it; a study sets its configurations' checkpoints with it directly.
Status ResolveCheckpointOptions(const std::string& dir, std::optional<long long> every,
                                std::optional<double> interval, bool resume, RunPlan& plan);

// DIR/params.toml of a run: what determines its results besides the maze,
// as `--config` lines: the approaches, --leaf-limit, --bootstrap (with
// semantics ours), --semantics, every parameter's value and the
// --learner-seed when given. Its comment says what it leaves out (the maze).
std::string RunPlanToml(const RunPlan& plan);

// Runs `plan.approaches` in order over `source` (pass i for the i-th
// approach), logging progress, and (re)writes DIR/results.csv,
// DIR/results_detailed.csv and DIR/params.toml (RunPlanToml)
// atomically after every approach, so an interrupted run keeps what
// finished. `extra` is called after every step. With plan.policy, each
// learning approach starts from its loaded section, and the saved file
// (runtime/policy_saver.h) is rewritten when one saves its section; a
// failed write ends the run after that approach's rows are written. With
// plan.checkpoint.dir,
// a checkpoint is written after every `every` time steps of a learning
// approach and after every approach; with plan.checkpoint.resume, the
// finished approaches' rows are taken from it and the approach in progress
// continues from its policy (a baseline runs again from step 0): the
// result files are the uninterrupted run's, time columns aside.
// Fails when the files cannot be written, with the source's or the
// trainer's status() when one of them fails, and with kCancelled when
// `stop` (may be null; checked before every time step and after every
// approach) is set: the approaches before it were written.
Result<std::vector<ApproachRun>> RunApproaches(StepSource& source, Trainer& trainer,
                                               const RunPlan& plan, const RunLabels& labels,
                                               const StepCallback& extra = {},
                                               const std::atomic<bool>* stop = nullptr);

// Warnings for the approaches of `plan` whose cost model predicts more than
// an hour for `steps` time steps on `grid` (empty when none): A* Oracle's
// per-start searches cost about (free cells) x (cells) per step, calibrated
// at 17 s per step on a free 1024x1024 map on the 2-core reference machine.
std::vector<std::string> LongRunWarnings(const RunPlan& plan, const Grid& grid, int steps);

// The end of a run's step progress line: ", ~12 s left in this approach (2
// approaches after it)" at time step `step` of `total_steps`, the steps
// after step 0 having taken `seconds_since_step0`; "" at the last step.
std::string StepTimeLeft(int step, int total_steps, double seconds_since_step0,
                         int approaches_after);

// `dynapath run --local`: RunApproaches over `setup`'s scenario (the run
// seed set from it) with a LocalTrainer on a pool of `threads` threads.
// An exception thrown by `extra` ends the run and comes back as a kInternal
// error, after the approaches before it were written. `progress` (may be
// null): where the training batch in hand is counted, for a watcher such as
// a study's progress line; the run's own log lines read it too.
Result<std::vector<ApproachRun>> RunLocal(const RunPlan& plan, const ScenarioSetup& setup,
                                          int threads, const StepCallback& extra = {},
                                          const std::atomic<bool>* stop = nullptr,
                                          TrainingProgress* progress = nullptr);

}  // namespace dynapath::runtime
