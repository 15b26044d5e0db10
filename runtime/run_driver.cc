#include "runtime/run_driver.h"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "dynapath/local_trainer.h"
#include "dynapath/text_file.h"
#include "dynapath/text_util.h"
#include "dynapath/thread_pool.h"
#include "runtime/model_file.h"
#include "runtime/output_check.h"
#include "runtime/policy_saver.h"
#include "runtime/test_hold.h"

namespace dynapath::runtime {
namespace {

// Logs one line per approach every few seconds, and at its start and end;
// each step line with an estimate of the approach's time left (its steps so
// far, after its initial training, set the pace) and how many approaches
// follow it.
class ProgressLog {
 public:
  ProgressLog(Clock clock, int approaches_after)
      : clock_(std::move(clock)), approaches_after_(approaches_after) {}

  void operator()(const StepView& view) {
    const ApproachRun& run = view.run;
    const int step = run.steps.back().time_step;
    const double now = clock_();
    if (step == 0 || !first_step_time_) first_step_time_ = now;  // the steps' pace from here
    const bool finished = step == view.total_steps;
    if (!finished && step != 0 && now - last_ < kIntervalSeconds) return;
    last_ = now;
    const StepRecord& record = run.steps.back();
    if (step == 0) {
      spdlog::info("{} {} {}: initial training {:.3f} s, success rate {:.4f}, path length {:.3f}",
                   run.Label(), run.size_label, run.difficulty_label, run.initial_seconds,
                   record.success_rate, record.average_path_length);
    } else {
      spdlog::info(
          "{} {} {}: step {}/{}, success rate {:.4f}, adaptation {:.4f} s/step{}", run.Label(),
          run.size_label, run.difficulty_label, step, view.total_steps, record.success_rate,
          run.AdaptSecondsPerStep(),
          StepTimeLeft(step, view.total_steps, now - *first_step_time_, approaches_after_));
    }
  }

 private:
  static constexpr double kIntervalSeconds = 2.0;
  Clock clock_;
  int approaches_after_;
  double last_ = 0.0;
  std::optional<double> first_step_time_;  // when step 0 (its training) ended
};

// `source` until `stop` (may be null) is set; from then on it fails with
// kCancelled.
class StoppableSource : public StepSource {
 public:
  StoppableSource(StepSource& source, const std::atomic<bool>* stop)
      : source_(source), stop_(stop) {}

  int total_steps() const override { return source_.total_steps(); }
  Grid Initial(int pass) override { return Stopped() ? Grid() : source_.Initial(pass); }
  ChangeStep Changes(int pass, int t) override {
    return Stopped() ? ChangeStep{} : source_.Changes(pass, t);
  }
  Status status() const override {
    if (stopped_) return Error::Cancelled();
    return source_.status();
  }
  bool Stopped() {
    stopped_ = stopped_ || (stop_ != nullptr && stop_->load());
    return stopped_;
  }

 private:
  StepSource& source_;
  const std::atomic<bool>* stop_;
  bool stopped_ = false;
};

}  // namespace

std::string StepTimeLeft(int step, int total_steps, double seconds_since_step0,
                         int approaches_after) {
  if (step >= total_steps) return "";
  // The steps so far set the pace (step 0, the initial training, excluded).
  const double per_step = seconds_since_step0 / std::max(1, step);
  std::string text =
      ", ~" + FormatDuration(per_step * (total_steps - step)) + " left in this approach";
  if (approaches_after > 0) {
    text += fmt::format(" ({} approach{} after it)", approaches_after,
                        approaches_after == 1 ? "" : "es");
  }
  return text;
}

void DeclareLeafLimitOption(OptionGroup& group, long long& leaf_limit) {
  group.Option("--leaf-limit", leaf_limit, "N", "largest quadtree leaf side");
}

const WordTable<Bootstrap>& BootstrapWords() {
  // kAllStored is the report semantics' own, not an option.
  static const WordTable<Bootstrap> words(
      {{"in-grid", Bootstrap::kInGrid}, {"in-region", Bootstrap::kInRegion}});
  return words;
}

const WordTable<Semantics>& SemanticsWords() {
  static const WordTable<Semantics> words(
      {{"ours", Semantics::kOurs}, {"report", Semantics::kReport}});
  return words;
}

const WordTable<Placement>& PlacementWords() {
  static const WordTable<Placement> words(
      {{"auto", Placement::kAuto}, {"whole", Placement::kWhole}, {"split", Placement::kSplit}});
  return words;
}

Status CheckBootstrap(const std::string& text) { return BootstrapWords().Check(text); }
Status CheckSemantics(const std::string& text) { return SemanticsWords().Check(text); }
Status CheckPlacement(const std::string& text) { return PlacementWords().Check(text); }

Result<int> ResolveLeafLimit(long long leaf_limit) {
  Result<long long> checked = InRange("leaf-limit", leaf_limit, 0, 1, kMaxLeafLimit);
  if (!checked) return checked.error();
  return static_cast<int>(*checked);
}

void DeclareLearnerOptions(OptionGroup& group, RunOptions& o) {
  DeclareLeafLimitOption(group, o.leaf_limit);
  group.Option("--bootstrap", o.bootstrap, "SCOPE",
               "actions the Q-update's max ranges over: " + BootstrapWords().List() +
                   " (docs/concepts/DECISIONS.md)");
  group.Option(
      "--semantics", o.semantics, "WHOSE",
      "learning semantics: " + SemanticsWords().List() +
          " (report: the report code's bootstrap, first training, single-agent "
          "details and double Q-tables, and its parameter values (REPORT of `dynapath params`): " +
          (ReportPresetText().empty() ? std::string("the defaults") : ReportPresetText()) +
          "; a parameter given overrides them; docs/concepts/DECISIONS.md)");
  DeclareParameterOptions(group, o.parameters);
  group.Option("--learner-seed", o.learner_seed, "N",
               "the learners' random stream: every learner's seed derives from N (0 to 2^53-1); "
               "the same N gives the same results in every mode (docs/howto/STUDIES.md, Repeats)",
               "the maze's seed");
  group.Option("--model", o.model, "FILE",
               "convQ's model file, written by `dynapath train-model` (default: the model the "
               "repository ships, docs/examples/models/convq.model; docs/howto/LEARNED_MODEL.md)");
}

void DeclarePlacementOption(OptionGroup& group, RunOptions& o) {
  group.Option("--placement", o.placement, "MODE",
               "distributed runs: " + PlacementWords().List() +
                   " (docs/howto/DISTRIBUTED.md, Placement; results are the same)");
}

void DeclareRunOptions(OptionGroup& group, RunOptions& o) {
  group.Option("--approach", o.approach, "LIST",
               "comma-separated approaches: " + ApproachNamesText() +
                   "; or all; `dynapath run --local` also takes py:MODULE:CLASS, one written "
                   "in Python (docs/howto/PYTHON.md)");
  group.Option("--out", o.out, "DIR", "output directory");
  DeclareLearnerOptions(group, o);
  DeclarePlacementOption(group, o);
  DeclarePolicyOptions(group, o.policy);
  group.Option("--checkpoint", o.checkpoint, "DIR",
               "write the run's state to DIR after every --checkpoint-every time steps, to "
               "finish it with `dynapath run --resume DIR` if it dies (docs/howto/CHECKPOINTS.md)");
  group.Option("--checkpoint-every", o.checkpoint_every, "K",
               "time steps between checkpoints (1..1000000)", "1");
  group.Option("--checkpoint-interval", o.checkpoint_interval, "SECONDS",
               "and at least this long between checkpoints (0..86400; a study uses 2)", "0");
  group.Flag("--resume-checkpoint", o.resume_checkpoint,
             "continue from --checkpoint's last checkpoint, or start when it has none (what "
             "`dynapath run --resume DIR` sets)");
}

Status ResolveCheckpointOptions(const std::string& dir, std::optional<long long> every_given,
                                std::optional<double> interval_given, bool resume, RunPlan& plan) {
  Result<long long> every = InRange("checkpoint-every", every_given, 1, 1, 1'000'000);
  if (!every) return every.error();
  plan.checkpoint.dir = dir;
  plan.checkpoint.every = static_cast<int>(*every);
  const double interval = interval_given.value_or(0);
  if (!(interval >= 0 && interval <= 86400)) {
    return Error::Option("checkpoint-interval", "must be between 0 and 86400 seconds");
  }
  plan.checkpoint.min_seconds = interval;
  if (!dir.empty()) plan.checkpoint.hold_after_step = TestHoldStep("run");
  if (dir.empty() && (every_given || interval_given)) {
    return Error::Option(every_given ? "checkpoint-every" : "checkpoint-interval",
                         "needs --checkpoint DIR");
  }
  if (resume) {
    if (dir.empty()) return Error::Option("resume-checkpoint", "needs --checkpoint DIR");
    Result<RunCheckpoint> found = ReadCheckpoint(dir);
    if (!found && !found.error().IsNotFound()) return found.error();
    if (found) {
      for (size_t i = 0; i < found->runs.size(); ++i) {
        if (i >= plan.approaches.size() || found->runs[i].approach != plan.approaches[i]) {
          return Error::Option("checkpoint", dir + " is of a run of other approaches");
        }
      }
      plan.checkpoint.resume = std::make_shared<const RunCheckpoint>(std::move(*found));
    }
  }
  return Ok{};
}

Result<RunPlan> ResolveRunOptions(const RunOptions& o) {
  RunPlan plan;
  Result<std::vector<Approach>> approaches = ParseApproachList(o.approach);
  if (!approaches) return approaches.error();
  plan.approaches = *approaches;
  Result<int> leaf_limit = ResolveLeafLimit(o.leaf_limit);
  if (!leaf_limit) return leaf_limit.error();
  plan.options.leaf_limit = *leaf_limit;
  if (!o.model.empty()) {
    Result<ModelFile> model = ReadModelFile(o.model);
    if (!model)
      return Error::Option("model", "names a file that is refused: " + model.error().message);
    plan.options.convq_model = std::make_shared<const ConvQModel>(model->model);
    plan.model_path = o.model;
  }
  Result<Bootstrap> bootstrap = BootstrapWords().ParseOption("bootstrap", o.bootstrap);
  if (!bootstrap) return bootstrap.error();
  plan.options.bootstrap = *bootstrap;
  Result<Semantics> semantics = SemanticsWords().ParseOption("semantics", o.semantics);
  if (!semantics) return semantics.error();
  plan.options.semantics = *semantics;
  // The report's semantics bootstrap over all stored values (kAllStored).
  if (*semantics == Semantics::kReport && *bootstrap != PlannerOptions{}.bootstrap) {
    return Error::Option("semantics", "report sets the bootstrap itself; leave --bootstrap out");
  }
  // The report's parameter values, under those given.
  if (*semantics == Semantics::kReport) ApplyReportPreset(plan.options);
  if (Status status = ApplyParameterOptions(o.parameters, plan.options); !status) {
    return status.error();
  }
  if (o.learner_seed) {
    Result<long long> seed = InRange("learner-seed", o.learner_seed, 0, 0, kMaxLearnerSeed);
    if (!seed) return seed.error();
    plan.learner_seed = static_cast<uint64_t>(*seed);
  }
  plan.out_dir = o.out;
  if (plan.out_dir.empty()) return Error::Option("out", "must not be empty");
  Result<Placement> placement = PlacementWords().ParseOption("placement", o.placement);
  if (!placement) return placement.error();
  plan.placement = *placement;
  Result<PolicyPlan> policy = ResolvePolicyOptions(o.policy, plan.approaches);
  if (!policy) return policy.error();
  plan.policy = std::move(*policy);
  if (Status status = ResolveCheckpointOptions(o.checkpoint, o.checkpoint_every,
                                               o.checkpoint_interval, o.resume_checkpoint, plan);
      !status) {
    return status.error();
  }
  return plan;
}

namespace {

// Writes a run's checkpoints (RunApproaches with plan.checkpoint.dir) on a
// thread of its own: encoding and the two fsyncs of a durable write take
// milliseconds, which would otherwise be added to every time step. At most
// one write is pending; a newer checkpoint replaces it unwritten (the
// newest is what a resume needs). Flush() waits for the last one and says
// whether every write so far succeeded.
class CheckpointWriter {
 public:
  CheckpointWriter(const CheckpointPlan& plan, uint64_t run_seed, int total_steps,
                   int approach_count)
      : plan_(plan),
        run_seed_(run_seed),
        total_steps_(total_steps),
        approach_count_(approach_count) {
    if (enabled()) thread_ = std::thread([this] { Loop(); });
  }
  ~CheckpointWriter() {
    if (!thread_.joinable()) return;
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  bool enabled() const { return !plan_.dir.empty(); }
  // What the --save-policy file holds now: in every checkpoint from here on.
  void SetPolicyFile(std::vector<SavedSection> record) { policy_file_ = std::move(record); }

  // After `run`'s rows so far of the approach in progress (the finished
  // ones in `finished`), with its policy after the last row. Fails with the
  // error of an earlier write.
  Status InProgress(const std::vector<ApproachRun>& finished, const ApproachRun& run,
                    PolicyState&& policy) {
    RunCheckpoint checkpoint = Empty();
    checkpoint.pass = static_cast<int>(finished.size());
    checkpoint.runs = finished;
    checkpoint.runs.push_back(run);
    checkpoint.policy = std::move(policy);
    return Submit(std::move(checkpoint));
  }
  // After the approaches in `finished`, written before it returns.
  Status Finished(const std::vector<ApproachRun>& finished) {
    RunCheckpoint checkpoint = Empty();
    checkpoint.pass = static_cast<int>(finished.size());
    checkpoint.runs = finished;
    if (Status submitted = Submit(std::move(checkpoint)); !submitted) return submitted;
    return Flush();
  }
  // A write is in progress or waiting: the policy of a step now would be
  // replaced before it is written, so the step need not export it.
  bool Busy() {
    std::lock_guard lock(mutex_);
    return writing_ || pending_.has_value();
  }
  Status Flush() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [this] { return !pending_ && !writing_; });
    return status_;
  }

 private:
  RunCheckpoint Empty() const {
    RunCheckpoint checkpoint;
    checkpoint.run_seed = run_seed_;
    checkpoint.total_steps = total_steps_;
    checkpoint.approach_count = approach_count_;
    checkpoint.policy_file = policy_file_;
    return checkpoint;
  }
  Status Submit(RunCheckpoint&& checkpoint) {
    {
      std::lock_guard lock(mutex_);
      if (!status_) return status_;
      pending_ = std::move(checkpoint);
    }
    wake_.notify_all();
    return Ok{};
  }
  void Loop() {
    std::unique_lock lock(mutex_);
    while (true) {
      wake_.wait(lock, [this] { return done_ || pending_; });
      if (!pending_) return;  // done, nothing left to write
      RunCheckpoint checkpoint = std::move(*pending_);
      pending_.reset();
      writing_ = true;
      lock.unlock();
      Status written = WriteCheckpoint(plan_.dir, checkpoint);
      lock.lock();
      writing_ = false;
      if (!written && status_) status_ = written.error().Prefixed("checkpoint: ");
      idle_.notify_all();
    }
  }

  const CheckpointPlan& plan_;
  uint64_t run_seed_;
  int total_steps_;
  int approach_count_;
  std::vector<SavedSection> policy_file_;  // the run's thread's alone
  std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::optional<RunCheckpoint> pending_;
  bool writing_ = false;
  bool done_ = false;
  Status status_ = Ok{};
  std::thread thread_;  // last: started once the rest is ready
};

}  // namespace

std::string RunPlanToml(const RunPlan& plan) {
  std::string approaches;
  for (const Approach approach : plan.approaches) {
    approaches += (approaches.empty() ? "" : ",") + ApproachName(approach);
  }
  const PlannerOptions& o = plan.options;
  std::string text =
      "# What gives this run's results besides its maze: approaches, learner options, every\n"
      "# parameter. The maze is not here: `dynapath run --config FILE` with the run's maze\n"
      "# options (--size, --difficulty, --seed, --steps; or --maze, --stations, --movers)\n"
      "# reruns it to the same result files, time columns aside.\n"
      "approach = \"" +
      approaches + "\"\nleaf-limit = " + std::to_string(o.leaf_limit) + "\n";
  // The report's semantics sets its own bootstrap (no word of --bootstrap).
  if (o.semantics != Semantics::kReport) {
    text += "bootstrap = \"" + BootstrapWords().Name(o.bootstrap) + "\"\n";
  }
  text += "semantics = \"" + SemanticsWords().Name(o.semantics) + "\"\n" + ParameterLines(o);
  if (plan.learner_seed) text += "learner-seed = " + std::to_string(*plan.learner_seed) + "\n";
  if (!plan.model_path.empty()) text += "model = \"" + plan.model_path + "\"\n";
  return text;
}

namespace {

// After an approach: its summary line, and the result files and params.toml
// (re)written with every run so far. The rows first: a policy file that
// could not be written afterwards loses none.
Status FinishApproach(const std::vector<ApproachRun>& runs, const RunPlan& plan) {
  const ApproachRun& run = runs.back();
  spdlog::info(
      "{}: initial {:.3f} s, adaptation {:.4f} s/step, success rate {:.4f}, path length {:.3f}",
      run.Label(), run.initial_seconds, run.AdaptSecondsPerStep(), run.AverageSuccessRate(),
      run.AveragePathLength());
  if (Status status = WriteResultFiles(runs, plan.out_dir); !status) return status;
  return WriteTextFileAtomically(plan.out_dir + "/params.toml", RunPlanToml(plan));
}

}  // namespace

Result<std::vector<ApproachRun>> RunApproaches(StepSource& source, Trainer& trainer,
                                               const RunPlan& plan, const RunLabels& labels,
                                               const StepCallback& extra,
                                               const std::atomic<bool>* stop) {
  StoppableSource stoppable(source, stop);
  PlannerOptions options = plan.options;
  options.stop = stop;
  std::vector<ApproachRun> runs;
  CheckpointWriter checkpoints(plan.checkpoint, options.run_seed, source.total_steps(),
                               static_cast<int>(plan.approaches.size()));
  double last_checkpoint = -1e300;  // SteadyClock() of the last one taken
  bool held = false;                // at plan.checkpoint.hold_after_step
  const RunCheckpoint* resume = plan.checkpoint.resume.get();
  if (resume != nullptr &&
      (resume->run_seed != options.run_seed || resume->total_steps != source.total_steps())) {
    return Error::Option("checkpoint",
                         fmt::format("{} is of another run (maze seed {}, {} time steps; this run: "
                                     "seed {}, {} time steps)",
                                     plan.checkpoint.dir, resume->run_seed, resume->total_steps,
                                     options.run_seed, source.total_steps()));
  }
  if (checkpoints.enabled()) {
    if (Status ready = PrepareOutputDirectory(plan.checkpoint.dir, "checkpoint"); !ready) {
      return ready.error();
    }
    // A writer killed mid-write leaves its temporary file; the directory is
    // this run's alone now (its lock, or the launcher's that started us).
    std::error_code ignored;
    const std::string stale = std::string(kCheckpointFileName) + ".tmp.";
    for (const auto& entry : std::filesystem::directory_iterator(plan.checkpoint.dir, ignored)) {
      if (entry.path().filename().string().rfind(stale, 0) == 0) {
        std::filesystem::remove(entry.path(), ignored);
      }
    }
  }
  if (resume != nullptr) {
    runs.assign(resume->runs.begin(), resume->runs.begin() + resume->pass);
    if (!runs.empty()) {
      spdlog::info("resuming: {} approach{} finished before (rows from the checkpoint)",
                   runs.size(), runs.size() == 1 ? "" : "es");
    }
  }
  // The --save-policy file, checked against the checkpoint when resuming.
  std::optional<PolicySaver> saver;
  if (!plan.policy.save_path.empty()) {
    Result<PolicySaver> opened =
        PolicySaver::Open(plan.policy, plan.approaches, source.total_steps(), resume);
    if (!opened) return opened.error();
    saver.emplace(std::move(*opened));
    checkpoints.SetPolicyFile(saver->Record());
  }
  if (!plan.external.empty() && (checkpoints.enabled() || resume != nullptr)) {
    return Error::Internal("approaches from outside core take no checkpoint");
  }
  // The external approaches due before built-in approach `before`.
  auto run_external = [&](size_t before) -> Status {
    for (const ExternalApproach& external : plan.external) {
      if (std::min(external.before, plan.approaches.size()) != before) continue;
      ProgressLog progress(SteadyClock(), static_cast<int>(plan.approaches.size() - before));
      const StepCallback on_step = [&](const StepView& view) {
        progress(view);
        if (extra) extra(view);
      };
      ApproachRun run =
          RunExternalPlanner(stoppable, static_cast<int>(runs.size()), *external.planner,
                             external.label, labels, SteadyClock(), on_step);
      stoppable.Stopped();
      if (Status status = stoppable.status(); !status) return status;
      runs.push_back(std::move(run));
      if (Status status = FinishApproach(runs, plan); !status) return status;
    }
    return Ok{};
  };
  for (size_t pass = runs.size(); pass < plan.approaches.size(); ++pass) {
    if (Status status = run_external(pass); !status) return status.error();
    const Approach approach = plan.approaches[pass];
    ProgressLog progress(SteadyClock(), static_cast<int>(plan.approaches.size() - pass - 1));
    const StepCallback on_step = [&](const StepView& view) {
      progress(view);
      if (extra) extra(view);
    };
    PolicyHooks hooks;
    hooks.load = plan.policy.Find(approach);
    // The approach the checkpoint was taken in: its rows so far, and its
    // policy to continue from.
    const ApproachRun* resumed = nullptr;
    if (resume != nullptr && pass == static_cast<size_t>(resume->pass) &&
        resume->runs.size() > pass && resume->policy) {
      resumed = &resume->runs[pass];
      hooks.load = &*resume->policy;
      hooks.must_continue = true;
      spdlog::info("{}: resuming after step {} from the checkpoint", ApproachName(approach),
                   resume->policy->step);
    }
    // The file is written when the section is saved, so the checkpoints
    // after it record it (a resumed run continuing past --save-at saves it
    // no more). A failed write ends the run after this approach's rows.
    bool saved = false;
    Status save_status = Ok{};
    if (saver) {
      hooks.save_at = plan.policy.save_at;
      hooks.save = [&](PolicyState&& state) {
        saved = true;
        save_status = saver->Save(state);
        if (!save_status) return;
        checkpoints.SetPolicyFile(saver->Record());
        spdlog::info("{}: saved its policy after step {} to {}", ApproachName(approach), state.step,
                     plan.policy.save_path);
      };
    }
    Status checkpoint_status = Ok{};
    if (checkpoints.enabled() && IsLearningApproach(approach)) {
      hooks.checkpoint_every = plan.checkpoint.every;
      // Exporting a policy copies every table: a step that comes while the
      // previous checkpoint is still being written skips it (its checkpoint
      // would be replaced unwritten), so a run with steps faster than the
      // disk pays for one copy per write, not one per step.
      hooks.checkpoint_due = [&] {
        return !checkpoints.Busy() &&
               SteadyClock()() - last_checkpoint >= plan.checkpoint.min_seconds;
      };
      hooks.checkpoint = [&](PolicyState&& state, const ApproachRun& so_far) {
        last_checkpoint = SteadyClock()();
        if (!checkpoint_status) return;
        const int step = state.step;
        if (resumed == nullptr) {
          checkpoint_status = checkpoints.InProgress(runs, so_far, std::move(state));
        } else {
          ApproachRun whole = *resumed;  // the rows before the checkpoint, then these
          whole.steps.insert(whole.steps.end(), so_far.steps.begin(), so_far.steps.end());
          checkpoint_status = checkpoints.InProgress(runs, whole, std::move(state));
        }
        if (!held && pass == 0 && resumed == nullptr && plan.checkpoint.hold_after_step >= 0 &&
            step >= plan.checkpoint.hold_after_step && checkpoint_status) {
          held = true;
          checkpoint_status = checkpoints.Flush();
          if (checkpoint_status) HoldForTest("run", step);
        }
      };
    }
    Result<ApproachRun> result = RunApproach(stoppable, static_cast<int>(pass), approach, options,
                                             &trainer, labels, hooks, SteadyClock(), on_step);
    // A run cut short by its source or trainer is not written.
    stoppable.Stopped();
    if (Status status = stoppable.status(); !status) return status.error();
    if (Status status = trainer.status(); !status) return status.error();
    if (!result) {
      if (resumed != nullptr) {
        return Error::Option("checkpoint", plan.checkpoint.dir + ": " + result.error().message);
      }
      return Error::Option("load-policy", plan.policy.load_path + ": " + result.error().message);
    }
    if (!checkpoint_status) return checkpoint_status.error();
    if (resumed != nullptr) {
      // The rows and times before the checkpoint, then the rest.
      ApproachRun whole = *resumed;
      whole.steps.insert(whole.steps.end(), result->steps.begin(), result->steps.end());
      *result = std::move(whole);
    }
    runs.push_back(std::move(*result));
    if (hooks.load != nullptr && resumed == nullptr) {
      spdlog::info("{}: took over its loaded policy (saved after step {}) in {:.3f} s",
                   ApproachName(approach), hooks.load->step, runs.back().load_seconds);
    }
    if (Status status = FinishApproach(runs, plan); !status) return status.error();
    if (!save_status) return save_status.error();
    if (!saved && hooks.save && IsLearningApproach(approach) && resumed == nullptr) {
      // CheckPolicyPlan refuses this before any work; here for callers without it.
      return Error::Option("save-at", "step " + std::to_string(plan.policy.save_at) +
                                          " is not a step " + ApproachName(approach) +
                                          " ran (a loaded policy continues after its step)");
    }
    if (checkpoints.enabled()) {
      if (Status written = checkpoints.Finished(runs); !written) return written.error();
    }
  }
  if (Status status = run_external(plan.approaches.size()); !status) return status.error();
  return runs;
}

std::vector<std::string> LongRunWarnings(const RunPlan& plan, const Grid& grid, int steps) {
  // Seconds per (start x cell) of one A* Oracle step: 17.4 s for the 1024^2
  // starts x 1024^2 cells of a free map. Smaller maps run faster than this
  // model says (0.41 s at 256^2), so it errs towards warning.
  constexpr double kAStarSecondsPerStartCell = 17.4 / (1048576.0 * 1048576.0);
  std::vector<std::string> warnings;
  for (Approach approach : plan.approaches) {
    if (approach != Approach::kAStarOracle) continue;
    const double starts = grid.Count(Cell::kFree);
    const double seconds =
        kAStarSecondsPerStartCell * starts * grid.size() * (static_cast<double>(steps) + 1);
    if (seconds <= 3600) continue;
    warnings.push_back(fmt::format(
        "A* Oracle: about {:.0f} hours on this {}x{} map ({} time steps; its per-start A* "
        "costs about (free cells) x (cells) per step); BFS Oracle and Incremental Oracle compute "
        "the same optimum in milliseconds per step",
        seconds / 3600, grid.rows(), grid.cols(), steps));
  }
  return warnings;
}

namespace {

// Logs the training batch in hand every few seconds while it lasts longer
// than that (a large map's step-0 training takes minutes): DescribeTraining's
// jobs, rounds or share of the jobs' episodes done, and the time left at the
// pace so far (inside one large job too). Between steps the run's own
// progress lines say the rest.
class TrainingProgressLog {
 public:
  explicit TrainingProgressLog(const TrainingProgress& progress)
      : progress_(progress), thread_([this] { Loop(); }) {}
  ~TrainingProgressLog() {
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }

 private:
  static constexpr auto kInterval = std::chrono::seconds(5);

  void Loop() {
    int64_t batch = -1;
    auto batch_start = std::chrono::steady_clock::now();
    auto next_line = batch_start;
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, std::chrono::milliseconds(250), [this] { return done_; })) {
      const auto now = std::chrono::steady_clock::now();
      if (!progress_.running) continue;
      if (progress_.batches != batch) {  // a new batch: its own clock
        batch = progress_.batches;
        batch_start = now;
        next_line = now + kInterval;
        continue;
      }
      if (now < next_line) continue;
      next_line = now + kInterval;
      const double elapsed = std::chrono::duration<double>(now - batch_start).count();
      const double fraction = progress_.Fraction();
      std::string left = "time left unknown yet";
      if (fraction >= 0.01) {
        left = fmt::format("about {:.0f} s left", elapsed * (1 - fraction) / fraction);
      }
      spdlog::info("{}, {:.0f} s so far; {}", DescribeTraining(progress_), elapsed, left);
    }
  }

  const TrainingProgress& progress_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::thread thread_;  // last: started once the rest is ready
};

}  // namespace

Result<std::vector<ApproachRun>> RunLocal(const RunPlan& plan, const ScenarioSetup& setup,
                                          int threads, const StepCallback& extra,
                                          const std::atomic<bool>* stop,
                                          TrainingProgress* progress) {
  for (const std::string& warning : LongRunWarnings(
           plan, setup.scenario.grid, static_cast<int>(setup.scenario.changes.steps.size()))) {
    spdlog::warn("{}", warning);
  }
  RunPlan seeded = plan;
  seeded.options.run_seed = plan.RunSeed(setup.seed);
  ThreadPool pool(threads);
  TrainingProgress own_progress;
  TrainingProgress& counted = progress != nullptr ? *progress : own_progress;
  const TrainingProgressLog progress_log(counted);
  LocalTrainer trainer(pool, stop, &counted);
  ScenarioStepSource source(setup.scenario);
  try {
    return RunApproaches(source, trainer, seeded, setup.labels, extra, stop);
  } catch (const std::exception& e) {
    return Error::Internal(e.what());
  }
}

}  // namespace dynapath::runtime
