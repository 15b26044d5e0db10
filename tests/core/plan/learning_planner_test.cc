#include "core/plan/learning_planner.h"

#include <gtest/gtest.h>

#include <vector>

#include "dynapath/change_sequence.h"
#include "dynapath/experiment.h"
#include "dynapath/local_trainer.h"
#include "dynapath/policy_evaluation.h"
#include "dynapath/scenario.h"
#include "dynapath/thread_pool.h"

namespace dynapath {
namespace {

// PlannerOptions::before_retraining: called once in every step that trains,
// before any value changes, with the step's grid; never in a step that
// trains nothing nor in the initial training; and the run's results are
// those of a run without it.
TEST(LearningPlanner, AnnouncesEachRetrainingBeforeItChangesTheTable) {
  const Scenario scenario = GenerateScenario(24, 24, Difficulty::kHard, 52, 30);
  ThreadPool pool(2);
  LocalTrainer trainer(pool);
  PlannerOptions plain;
  plain.run_seed = 9;
  plain.leaf_limit = 6;
  const ApproachRun reference =
      RunApproach(scenario, Approach::kFedAsynQEqAvg, plain, &trainer, {"24", "Hard"});

  PlannerOptions options = plain;
  std::vector<int> announced;  // per call: the step it came in
  std::vector<float> table_after_last_step;
  int step = 0;
  options.before_retraining = [&](Planner& planner, const Grid& grid) {
    auto& learning = dynamic_cast<LearningPlanner&>(planner);
    announced.push_back(step);
    // Nothing retrained yet: the table is the previous step's.
    const QTable& table = learning.root().table();
    ASSERT_EQ(table.precision(), QPrecision::kFloat);
    const std::vector<float> now(table.row(0), table.row(0) + 8 * static_cast<size_t>(grid.size()));
    EXPECT_EQ(now, table_after_last_step) << "step " << step;
    // The grid is the step's (its changes applied) and the picture is the
    // previous policy evaluated on it.
    Grid expected = scenario.grid;
    for (int t = 1; t <= step; ++t) ApplyChanges(scenario.changes.steps[t - 1], expected);
    EXPECT_EQ(grid.codes(), expected.codes()) << "step " << step;
    PolicyEvaluator evaluator;
    PolicyDepths full;
    evaluator.Evaluate(grid, table, full);
    PolicyPicture picture;
    ASSERT_TRUE(planner.Picture(grid, picture));
    EXPECT_EQ(picture.depth, full.depth) << "step " << step;
  };
  const ApproachRun run = RunApproach(
      scenario, Approach::kFedAsynQEqAvg, options, &trainer, {"24", "Hard"}, SteadyClock(),
      [&](const StepView& view) {
        const QTable& table = dynamic_cast<LearningPlanner&>(view.planner).root().table();
        table_after_last_step.assign(table.row(0),
                                     table.row(0) + 8 * static_cast<size_t>(view.grid.size()));
        step = static_cast<int>(view.run.steps.size());
      });
  std::vector<int> retraining_steps;
  ASSERT_EQ(run.steps.size(), reference.steps.size());
  for (size_t t = 0; t < run.steps.size(); ++t) {
    EXPECT_EQ(run.steps[t].success_rate, reference.steps[t].success_rate) << "step " << t;
    EXPECT_EQ(run.steps[t].nodes_trained, reference.steps[t].nodes_trained) << "step " << t;
    if (t > 0 && run.steps[t].nodes_trained > 0) retraining_steps.push_back(static_cast<int>(t));
  }
  ASSERT_FALSE(retraining_steps.empty());
  EXPECT_EQ(announced, retraining_steps);
}

}  // namespace
}  // namespace dynapath
