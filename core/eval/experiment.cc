#include "dynapath/experiment.h"

#include <chrono>

#include "dynapath/change_sequence.h"

namespace dynapath {

double ApproachRun::AverageSuccessRate() const {
  double total = 0.0;
  for (const StepRecord& step : steps) total += step.success_rate;
  return steps.empty() ? 0.0 : total / static_cast<double>(steps.size());
}

double ApproachRun::AveragePathLength() const {
  double total = 0.0;
  for (const StepRecord& step : steps) total += step.average_path_length;
  return steps.empty() ? 0.0 : total / static_cast<double>(steps.size());
}

double ApproachRun::AdaptSecondsPerStep() const {
  double total = 0.0;
  int counted = 0;
  for (const StepRecord& step : steps) {
    if (step.time_step == 0) continue;
    total += step.adapt_seconds;
    ++counted;
  }
  return counted == 0 ? 0.0 : total / static_cast<double>(counted);
}

Clock SteadyClock() {
  return [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
}

std::string ApproachRun::Label() const {
  return external_label.empty() ? ApproachName(approach) : external_label;
}

std::string SizeLabel(int rows, int cols) {
  return rows == cols ? std::to_string(rows) : std::to_string(rows) + "x" + std::to_string(cols);
}

namespace {

StepRecord Score(Planner& planner, const Grid& grid, int time_step, int num_changes,
                 double adapt_seconds, const StepDetails& details) {
  const PolicyScore score = planner.Evaluate(grid);
  return StepRecord{time_step,
                    num_changes,
                    adapt_seconds,
                    score.success_rate(),
                    score.average_path_length(),
                    details.nodes_trained,
                    details.highest_level};
}

}  // namespace

ApproachRun RunApproach(const Scenario& scenario, Approach approach, const PlannerOptions& options,
                        Trainer* trainer, const RunLabels& labels, const Clock& clock,
                        const StepCallback& on_step) {
  ScenarioStepSource source(scenario);
  return RunApproach(source, 0, approach, options, trainer, labels, clock, on_step);
}

ApproachRun RunApproach(StepSource& source, int pass, Approach approach,
                        const PlannerOptions& options, Trainer* trainer, const RunLabels& labels,
                        const Clock& clock, const StepCallback& on_step) {
  // Without a policy to load nothing can fail but the source or trainer,
  // whose status the caller checks.
  Result<ApproachRun> run =
      RunApproach(source, pass, approach, options, trainer, labels, PolicyHooks{}, clock, on_step);
  return run ? std::move(*run) : ApproachRun{};
}

ApproachStepper::ApproachStepper(StepSource& source, int pass, Planner& planner, ApproachRun run,
                                 const PlannerOptions& options, Trainer* trainer,
                                 const PolicyHooks& hooks, Clock clock)
    : source_(source),
      pass_(pass),
      planner_(planner),
      run_(std::move(run)),
      run_seed_(options.run_seed),
      trainer_(trainer),
      hooks_(hooks),
      clock_(std::move(clock)),
      total_steps_(source.total_steps()),
      save_at_(hooks.save_at == kSaveAtEnd ? total_steps_ : hooks.save_at) {}

bool ApproachStepper::failed() const {
  return !source_.status() || (trainer_ != nullptr && !trainer_->status());
}

bool ApproachStepper::Export(int time_step, PolicyState& state) const {
  if (!planner_.ExportPolicy(state)) return false;
  state.step = time_step;
  state.initial_fingerprint = initial_fingerprint_;
  state.fingerprint = MazeFingerprint(grid_);
  return true;
}

void ApproachStepper::SaveAndCheckpoint(int t, bool checkpoint) {
  if (t == save_at_ && hooks_.save) {
    PolicyState state;
    if (Export(t, state)) hooks_.save(std::move(state));
  }
  if (!checkpoint || hooks_.checkpoint_every <= 0 || !hooks_.checkpoint ||
      t % hooks_.checkpoint_every != 0 || (hooks_.checkpoint_due && !hooks_.checkpoint_due())) {
    return;
  }
  PolicyState state;
  if (Export(t, state)) hooks_.checkpoint(std::move(state), run_);
}

Status ApproachStepper::Begin() {
  grid_ = source_.Initial(pass_);
  if (failed()) return Ok{};
  initial_fingerprint_ = MazeFingerprint(grid_);
  const PolicyState* loaded = hooks_.load;
  const bool same_run = loaded != nullptr && loaded->initial_fingerprint == initial_fingerprint_ &&
                        loaded->run_seed == run_seed_;
  if (loaded != nullptr && hooks_.must_continue && !same_run) {
    return Error(loaded->run_seed != run_seed_
                     ? "the checkpoint is of a run with seed " + std::to_string(loaded->run_seed) +
                           ", this run has " + std::to_string(run_seed_)
                     : "the maze at step 0 differs from the checkpointed run's (was the map or "
                       "change file edited?)");
  }
  if (same_run) {
    // The maze it was saved from: catch up with the saved step, then go on.
    const int saved = loaded->step;
    if (saved > total_steps_) {
      return Error("the policy was saved after step " + std::to_string(saved) + ", this run has " +
                   std::to_string(total_steps_) + " steps");
    }
    for (int t = 1; t <= saved; ++t) {
      const ChangeStep step = source_.Changes(pass_, t);
      if (failed()) return Ok{};
      ApplyChanges(step, grid_);
    }
    if (MazeFingerprint(grid_) != loaded->fingerprint) {
      return Error("the maze at step " + std::to_string(saved) +
                   " differs from the one the policy was saved on "
                   "(another change sequence?)");
    }
    const double start = clock_();
    if (Status imported = planner_.ImportPolicy(*loaded, grid_); !imported) {
      return imported.error();
    }
    run_.load_seconds = clock_() - start;
    time_step_ = saved;
    loaded_ = true;
    SaveAndCheckpoint(saved, false);
    return Ok{};
  }
  double start = clock_();
  if (loaded != nullptr) {
    // Another maze of the same shape: the strategy decides node by node
    // from the loaded baselines, as after a step that changed every cell.
    if (Status imported = planner_.ImportPolicy(*loaded, grid_); !imported) {
      return imported.error();
    }
    run_.load_seconds = clock_() - start;
    std::vector<int> every_cell(static_cast<size_t>(grid_.size()));
    for (int cell = 0; cell < grid_.size(); ++cell) every_cell[cell] = cell;
    details_ = planner_.Adapt(grid_, every_cell);
  } else {
    details_ = planner_.Initialize(grid_);
  }
  run_.initial_seconds = clock_() - start;
  if (failed()) return Ok{};
  run_.steps.push_back(Score(planner_, grid_, 0, 0, 0.0, details_));
  SaveAndCheckpoint(0, true);
  return Ok{};
}

bool ApproachStepper::NextStep() {
  if (time_step_ >= total_steps_) return false;
  const int t = time_step_ + 1;
  const ChangeStep step = source_.Changes(pass_, t);
  if (failed()) return false;
  time_step_ = t;
  requested_moves_ = step.requested_moves;
  ApplyChanges(step, grid_);
  changed_cells_.clear();
  for (const CellChange& change : step.changes) changed_cells_.push_back(change.cell);
  adapt_start_ = clock_();
  retrains_ = planner_.TakeChanges(grid_, changed_cells_);
  return true;
}

bool ApproachStepper::Retrain() {
  details_ = planner_.Retrain();
  retrains_ = false;
  const double seconds = planner_.Adapts() ? clock_() - adapt_start_ : 0.0;
  if (failed()) return false;
  run_.steps.push_back(Score(planner_, grid_, time_step_, requested_moves_, seconds, details_));
  SaveAndCheckpoint(time_step_, true);
  return true;
}

namespace {

// One pass of `planner` over the source (RunApproach's body), filling `run`
// whose approach and labels are set.
Result<ApproachRun> RunPlanner(StepSource& source, int pass, Planner& planner, ApproachRun run,
                               const PlannerOptions& options, Trainer* trainer,
                               const PolicyHooks& hooks, const Clock& clock,
                               const StepCallback& on_step) {
  ApproachStepper stepper(source, pass, planner, std::move(run), options, trainer, hooks, clock);
  if (Status begun = stepper.Begin(); !begun) return begun.error();
  if (stepper.failed()) return stepper.Take();
  if (!stepper.loaded() && on_step) on_step(stepper.view());
  while (stepper.NextStep()) {
    if (!stepper.Retrain()) break;
    if (on_step) on_step(stepper.view());
  }
  return stepper.Take();
}

}  // namespace

Result<ApproachRun> RunApproach(StepSource& source, int pass, Approach approach,
                                const PlannerOptions& options, Trainer* trainer,
                                const RunLabels& labels, const PolicyHooks& hooks,
                                const Clock& clock, const StepCallback& on_step) {
  ApproachRun run;
  run.approach = approach;
  run.size_label = labels.size_label;
  run.difficulty_label = labels.difficulty_label;
  std::unique_ptr<Planner> planner = MakePlanner(approach, options, trainer);
  return RunPlanner(source, pass, *planner, std::move(run), options, trainer, hooks, clock,
                    on_step);
}

ApproachRun RunExternalPlanner(StepSource& source, int pass, Planner& planner,
                               const std::string& label, const RunLabels& labels,
                               const Clock& clock, const StepCallback& on_step) {
  ApproachRun run;
  run.external_label = label;
  run.size_label = labels.size_label;
  run.difficulty_label = labels.difficulty_label;
  // Without a policy to load nothing can fail but the source, whose status
  // the caller checks.
  Result<ApproachRun> done = RunPlanner(source, pass, planner, std::move(run), PlannerOptions{},
                                        nullptr, PolicyHooks{}, clock, on_step);
  return done ? std::move(*done) : ApproachRun{};
}

}  // namespace dynapath
