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

namespace {

// One pass of `planner` over the source (RunApproach's body), filling `run`
// whose approach and labels are set.
Result<ApproachRun> RunPlanner(StepSource& source, int pass, Planner& planner, ApproachRun run,
                               const PlannerOptions& options, Trainer* trainer,
                               const PolicyHooks& hooks, const Clock& clock,
                               const StepCallback& on_step) {
  const int total_steps = source.total_steps();
  // A failed source or trainer ends the run (its status tells the caller).
  auto failed = [&] { return !source.status() || (trainer != nullptr && !trainer->status()); };
  uint64_t initial_fingerprint = 0;
  const int save_at = hooks.save_at == kSaveAtEnd ? total_steps : hooks.save_at;
  auto export_at = [&](int t, const Grid& grid, PolicyState& state) {
    if (!planner.ExportPolicy(state)) return false;
    state.step = t;
    state.initial_fingerprint = initial_fingerprint;
    state.fingerprint = MazeFingerprint(grid);
    return true;
  };
  auto maybe_save = [&](int t, const Grid& grid) {
    if (t != save_at || !hooks.save) return;
    PolicyState state;
    if (export_at(t, grid, state)) hooks.save(std::move(state));
  };
  auto maybe_checkpoint = [&](int t, const Grid& grid) {
    if (hooks.checkpoint_every <= 0 || !hooks.checkpoint || t % hooks.checkpoint_every != 0 ||
        (hooks.checkpoint_due && !hooks.checkpoint_due())) {
      return;
    }
    PolicyState state;
    if (export_at(t, grid, state)) hooks.checkpoint(std::move(state), run);
  };

  Grid grid = source.Initial(pass);
  if (failed()) return run;
  initial_fingerprint = MazeFingerprint(grid);
  int first_step = 1;
  const PolicyState* loaded = hooks.load;
  const bool same_run = loaded != nullptr && loaded->initial_fingerprint == initial_fingerprint &&
                        loaded->run_seed == options.run_seed;
  if (loaded != nullptr && hooks.must_continue && !same_run) {
    return Error(loaded->run_seed != options.run_seed
                     ? "the checkpoint is of a run with seed " + std::to_string(loaded->run_seed) +
                           ", this run has " + std::to_string(options.run_seed)
                     : "the maze at step 0 differs from the checkpointed run's (was the map or "
                       "change file edited?)");
  }
  if (same_run) {
    // The maze it was saved from: catch up with the saved step, then go on.
    const int saved = loaded->step;
    if (saved > total_steps) {
      return Error("the policy was saved after step " + std::to_string(saved) + ", this run has " +
                   std::to_string(total_steps) + " steps");
    }
    for (int t = 1; t <= saved; ++t) {
      const ChangeStep step = source.Changes(pass, t);
      if (failed()) return run;
      ApplyChanges(step, grid);
    }
    if (MazeFingerprint(grid) != loaded->fingerprint) {
      return Error("the maze at step " + std::to_string(saved) +
                   " differs from the one the policy was saved on "
                   "(another change sequence?)");
    }
    const double start = clock();
    if (Status imported = planner.ImportPolicy(*loaded, grid); !imported) {
      return imported.error();
    }
    run.load_seconds = clock() - start;
    first_step = saved + 1;
    maybe_save(saved, grid);
    if (hooks.on_loaded) {
      const StepDetails none;
      hooks.on_loaded(StepView{run, pass, total_steps, planner, grid, none});
    }
  } else {
    StepDetails details;
    double start = clock();
    if (loaded != nullptr) {
      // Another maze of the same shape: the strategy decides node by node
      // from the loaded baselines, as after a step that changed every cell.
      if (Status imported = planner.ImportPolicy(*loaded, grid); !imported) {
        return imported.error();
      }
      run.load_seconds = clock() - start;
      std::vector<int> every_cell(static_cast<size_t>(grid.size()));
      for (int cell = 0; cell < grid.size(); ++cell) every_cell[cell] = cell;
      details = planner.Adapt(grid, every_cell);
    } else {
      details = planner.Initialize(grid);
    }
    run.initial_seconds = clock() - start;
    if (failed()) return run;
    run.steps.push_back(Score(planner, grid, 0, 0, 0.0, details));
    maybe_save(0, grid);
    maybe_checkpoint(0, grid);
    if (on_step) on_step(StepView{run, pass, total_steps, planner, grid, details});
  }

  std::vector<int> changed_cells;
  for (int t = first_step; t <= total_steps; ++t) {
    const ChangeStep step = source.Changes(pass, t);
    if (failed()) return run;
    ApplyChanges(step, grid);
    changed_cells.clear();
    for (const CellChange& change : step.changes) changed_cells.push_back(change.cell);
    const bool timed = planner.Adapts();
    const double start = clock();
    const StepDetails details = planner.Adapt(grid, changed_cells);
    const double seconds = timed ? clock() - start : 0.0;
    if (failed()) return run;
    run.steps.push_back(Score(planner, grid, t, step.requested_moves, seconds, details));
    maybe_save(t, grid);
    maybe_checkpoint(t, grid);
    if (on_step) on_step(StepView{run, pass, total_steps, planner, grid, details});
  }
  return run;
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
