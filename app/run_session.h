#pragma once
// `dynapath run` below its command line: the options it was given, typed
// (RunOptions), the run they describe, checked once (RunPlan), and the
// session that runs it (RunSession): in this process on a thread pool (with
// repeats), or envsim, coordinator and agents as threads over memq:// or as
// processes.

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "runtime/option_group.h"
#include "runtime/output_lock.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"

namespace dynapath::app {

// What run was given (the command line fills it).
struct RunOptions {
  runtime::ModeOptions mode;
  runtime::ScenarioOptions scenario;
  runtime::RunOptions run;
  runtime::ProcessOptions process;
  runtime::ThreadOptions threads;
  runtime::LogOptions log;
  std::optional<std::string> log_file;  // --log
  bool force = false;
  std::optional<long long> restarts;  // --restart-coordinator
  std::optional<long long> repeats;
  // Options only told apart by being given at all.
  bool fault_drop_given = false;
  bool fault_dup_given = false;
};

// The options a checkpointed run records in its DIR/run.toml, which
// `dynapath run --resume DIR` runs again: every option of the run but the
// process and log ones (a new run id and secret are fine).
void DeclareRecordedOptions(runtime::OptionGroup& group, RunOptions& options);

// A run, checked: what RunSession starts.
struct RunPlan {
  RunOptions options;  // as given (the launcher hands them to the processes)
  runtime::RunMode mode;
  int threads = 1;
  runtime::ProcessSetup process;
  runtime::ScenarioSetup setup;
  runtime::RunPlan run;
  int repeats = 1;
  int coordinator_restarts = 0;
  bool distributed() const { return mode.kind != runtime::RunMode::kLocal; }
  bool checkpointing() const { return !run.checkpoint.dir.empty(); }
};

// Checks `options` once, before any work: an error names the option it is
// about (Error::subject) and says what is wrong, as run prints it.
Result<RunPlan> PlanRun(RunOptions options);

// One finished repeat of run --repeats: its directory (results.csv), its
// number, maze seed and learner seed.
struct RepeatDone {
  std::string directory;
  int repeat = 1;
  uint64_t seed = 0;
  uint64_t learner_seed = 0;
};

class RunSession {
 public:
  explicit RunSession(RunPlan plan);

  // Takes the outputs (--out and --checkpoint locked, a new run's options
  // recorded in the checkpoint directory) and, for processes, enters their
  // network (a private one without --lcm-url; the process must still be
  // single-threaded). An error here is of the options (kInvalidArgument).
  Status Prepare();
  // Runs the plan; `stop` (Ctrl-C) ends it early (kCancelled). A run that
  // does not fit a checkpoint or loaded policy is kInvalidArgument; an
  // empty message was logged already.
  Status Run(const std::atomic<bool>& stop);
  // After Run with repeats: the repeats, in order (their files' writer,
  // study code, is the caller's).
  const std::vector<RepeatDone>& repeats() const { return repeats_; }

  const RunPlan& plan() const { return plan_; }

 private:
  Status RunRepeats(const std::atomic<bool>& stop);
  Status RecordOptions();

  RunPlan plan_;
  std::optional<runtime::OutputLock> out_lock_;
  std::optional<runtime::OutputLock> checkpoint_lock_;
  bool embedded_ = false;
  std::vector<RepeatDone> repeats_;
};

}  // namespace dynapath::app
