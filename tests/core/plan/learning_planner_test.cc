#include "core/plan/learning_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "dynapath/change_sequence.h"
#include "dynapath/experiment.h"
#include "dynapath/local_trainer.h"
#include "dynapath/policy_evaluation.h"
#include "dynapath/scenario.h"
#include "dynapath/thread_pool.h"

namespace dynapath {
namespace {

// Planner::TakeChanges and Retrain, as the service calls them through
// ApproachStepper: TakeChanges says a step retrains exactly when Retrain
// then trains a node, and changes no value (the planner's Picture shows the
// step's grid under the previous step's policy); the run's results are
// those of RunApproach, which adapts in one call.
TEST(LearningPlanner, TakesChangesBeforeRetrainingWithoutChangingTheTable) {
  const Scenario scenario = GenerateScenario(24, 24, Difficulty::kHard, 52, 30);
  ThreadPool pool(2);
  LocalTrainer trainer(pool);
  PlannerOptions options;
  options.run_seed = 9;
  options.leaf_limit = 6;
  const ApproachRun reference =
      RunApproach(scenario, Approach::kFedAsynQEqAvg, options, &trainer, {"24", "Hard"});

  std::unique_ptr<Planner> made = MakePlanner(Approach::kFedAsynQEqAvg, options, &trainer);
  auto& learning = dynamic_cast<LearningPlanner&>(*made);
  ScenarioStepSource source(scenario);
  ApproachRun begun;
  begun.approach = Approach::kFedAsynQEqAvg;
  ApproachStepper stepper(source, 0, learning, std::move(begun), options, &trainer, PolicyHooks{});
  ASSERT_TRUE(stepper.Begin());
  ASSERT_FALSE(stepper.loaded());
  auto table_now = [&] {
    const QTable& table = learning.root().table();
    EXPECT_EQ(table.precision(), QPrecision::kFloat);
    return std::vector<float>(table.row(0),
                              table.row(0) + 8 * static_cast<size_t>(stepper.grid().size()));
  };
  std::vector<int> announced;  // the steps TakeChanges said would retrain
  while (stepper.NextStep()) {
    const int step = stepper.time_step();
    // The grid is the step's (its changes applied).
    Grid expected = scenario.grid;
    for (int t = 1; t <= step; ++t) ApplyChanges(scenario.changes.steps[t - 1], expected);
    EXPECT_EQ(stepper.grid().codes(), expected.codes()) << "step " << step;
    if (stepper.retrains()) {
      announced.push_back(step);
      // Nothing retrained yet: the picture is the previous policy on the
      // step's grid.
      PolicyEvaluator evaluator;
      PolicyDepths full;
      evaluator.Evaluate(stepper.grid(), learning.root().table(), full);
      PolicyPicture picture;
      ASSERT_TRUE(learning.Picture(stepper.grid(), picture));
      EXPECT_EQ(picture.depth, full.depth) << "step " << step;
    }
    const std::vector<float> before = table_now();
    ASSERT_TRUE(stepper.Retrain());
    // A step that was not announced trains nothing and keeps the table.
    if (!announced.empty() && announced.back() == step) {
      EXPECT_GT(stepper.run().steps.back().nodes_trained, 0) << "step " << step;
    } else {
      EXPECT_EQ(stepper.run().steps.back().nodes_trained, 0) << "step " << step;
      EXPECT_EQ(table_now(), before) << "step " << step;
    }
  }
  const ApproachRun run = stepper.Take();
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

// The table does not change between TakeChanges and Retrain: what the
// service commits as the interim version is the previous step's policy.
TEST(LearningPlanner, TakeChangesKeepsThePreviousTable) {
  const Scenario scenario = GenerateScenario(24, 24, Difficulty::kHard, 52, 30);
  ThreadPool pool(1);
  LocalTrainer trainer(pool);
  PlannerOptions options;
  options.run_seed = 9;
  options.leaf_limit = 6;
  LearningPlanner planner(Approach::kFedAsynQEqAvg, options, trainer);
  Grid grid = scenario.grid;
  planner.Initialize(grid);
  int retrained = 0;
  for (const ChangeStep& step : scenario.changes.steps) {
    const QTable before = planner.root().table();
    ApplyChanges(step, grid);
    std::vector<int> cells;
    for (const CellChange& change : step.changes) cells.push_back(change.cell);
    const bool retrains = planner.TakeChanges(grid, cells);
    const QTable& now = planner.root().table();
    EXPECT_TRUE(std::equal(before.row(0), before.row(0) + 8 * static_cast<size_t>(grid.size()),
                           now.row(0)));
    const StepDetails details = planner.Retrain();
    EXPECT_EQ(retrains, details.nodes_trained > 0);
    retrained += retrains ? 1 : 0;
  }
  EXPECT_GT(retrained, 0);
}

}  // namespace
}  // namespace dynapath
