#include "dynapath/experiment.h"

#include <chrono>

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
  for (size_t t = 1; t < steps.size(); ++t) total += steps[t].adapt_seconds;
  return steps.size() <= 1 ? 0.0 : total / static_cast<double>(steps.size() - 1);
}

Clock SteadyClock() {
  return [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
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
  ApproachRun run;
  run.approach = approach;
  run.size_label = labels.size_label;
  run.difficulty_label = labels.difficulty_label;
  const int total_steps = source.total_steps();
  std::unique_ptr<Planner> planner = MakePlanner(approach, options, trainer);
  // A failed source or trainer ends the run (its status tells the caller).
  auto failed = [&] { return !source.status() || (trainer != nullptr && !trainer->status()); };

  Grid grid = source.Initial(pass);
  if (failed()) return run;
  double start = clock();
  StepDetails details = planner->Initialize(grid);
  run.initial_seconds = clock() - start;
  if (failed()) return run;
  run.steps.push_back(Score(*planner, grid, 0, 0, 0.0, details));
  if (on_step) on_step(StepView{run, pass, total_steps, *planner, grid, details});

  std::vector<int> changed_cells;
  for (int t = 1; t <= total_steps; ++t) {
    const ChangeStep step = source.Changes(pass, t);
    if (failed()) return run;
    ApplyChanges(step, grid);
    changed_cells.clear();
    for (const CellChange& change : step.changes) changed_cells.push_back(change.cell);
    const bool timed = planner->Adapts();
    start = clock();
    details = planner->Adapt(grid, changed_cells);
    const double seconds = timed ? clock() - start : 0.0;
    if (failed()) return run;
    run.steps.push_back(Score(*planner, grid, t, step.requested_moves, seconds, details));
    if (on_step) on_step(StepView{run, pass, total_steps, *planner, grid, details});
  }
  return run;
}

}  // namespace dynapath
