#include "dynapath/policy_state.h"

#include <gtest/gtest.h>

#include <memory>

#include "dynapath/change_sequence.h"
#include "dynapath/experiment.h"
#include "dynapath/local_trainer.h"
#include "dynapath/thread_pool.h"

namespace dynapath {
namespace {

Clock FakeClock() {
  auto now = std::make_shared<double>(0.0);
  return [now] { return *now += 1.0; };
}

const Approach kLearning[] = {Approach::kOnlyTrainLeafNodes, Approach::kSingleAgent,
                              Approach::kFedAsynQEqAvg, Approach::kFedAsynQImAvg};

struct Saved {
  ApproachRun run;
  PolicyState state;
};

Saved RunSaving(const Scenario& scenario, Approach approach, const PlannerOptions& options,
                int save_at) {
  ThreadPool pool(2);
  LocalTrainer trainer(pool);
  ScenarioStepSource source(scenario);
  Saved saved;
  PolicyHooks hooks;
  hooks.save_at = save_at;
  hooks.save = [&](PolicyState&& state) { saved.state = std::move(state); };
  Result<ApproachRun> run =
      RunApproach(source, 0, approach, options, &trainer, {"30", "Hard"}, hooks, FakeClock());
  EXPECT_TRUE(run.ok());
  saved.run = std::move(*run);
  return saved;
}

Result<ApproachRun> RunLoading(const Scenario& scenario, Approach approach,
                               const PlannerOptions& options, const PolicyState& state) {
  ThreadPool pool(2);
  LocalTrainer trainer(pool);
  ScenarioStepSource source(scenario);
  PolicyHooks hooks;
  hooks.load = &state;
  return RunApproach(source, 0, approach, options, &trainer, {"30", "Hard"}, hooks, FakeClock());
}

void ExpectSameFrom(const ApproachRun& whole, const ApproachRun& continued, int first) {
  ASSERT_EQ(continued.steps.size(), whole.steps.size() - static_cast<size_t>(first));
  for (size_t i = 0; i < continued.steps.size(); ++i) {
    const StepRecord& a = whole.steps[static_cast<size_t>(first) + i];
    const StepRecord& b = continued.steps[i];
    EXPECT_EQ(a.time_step, b.time_step);
    EXPECT_EQ(a.success_rate, b.success_rate) << "step " << a.time_step;
    EXPECT_EQ(a.average_path_length, b.average_path_length) << "step " << a.time_step;
    EXPECT_EQ(a.nodes_trained, b.nodes_trained) << "step " << a.time_step;
    EXPECT_EQ(a.highest_level, b.highest_level) << "step " << a.time_step;
  }
}

// Saved after step 4 and loaded on the same scenario, every learning
// approach continues at step 5 exactly as the uninterrupted run, in both
// semantics (float and double tables).
TEST(PolicyStateTest, ContinuesExactlyAfterTheSavedStep) {
  const Scenario scenario = GenerateScenario(30, 30, Difficulty::kHard, 52, 10);
  for (Semantics semantics : {Semantics::kOurs, Semantics::kReport}) {
    PlannerOptions options;
    options.run_seed = 52;
    options.leaf_limit = 8;
    options.semantics = semantics;
    for (Approach approach : kLearning) {
      SCOPED_TRACE(ApproachName(approach));
      const Saved saved = RunSaving(scenario, approach, options, 4);
      EXPECT_EQ(saved.state.step, 4);
      EXPECT_EQ(saved.state.approach, approach);
      EXPECT_EQ(saved.state.table.precision(),
                semantics == Semantics::kReport ? QPrecision::kDouble : QPrecision::kFloat);
      EXPECT_EQ(saved.state.baselines.empty(), approach == Approach::kOnlyTrainLeafNodes);
      Result<ApproachRun> continued = RunLoading(scenario, approach, options, saved.state);
      ASSERT_TRUE(continued.ok()) << continued.error().message;
      EXPECT_EQ(continued->initial_seconds, 0.0);
      ExpectSameFrom(saved.run, *continued, 5);
    }
  }
}

// Saved at the end: loading continues with no step left.
TEST(PolicyStateTest, SavedAtTheEndContinuesWithNoSteps) {
  const Scenario scenario = GenerateScenario(30, 30, Difficulty::kHard, 52, 3);
  PlannerOptions options;
  options.run_seed = 52;
  const Saved saved = RunSaving(scenario, Approach::kSingleAgent, options, kSaveAtEnd);
  EXPECT_EQ(saved.state.step, 3);
  Result<ApproachRun> continued =
      RunLoading(scenario, Approach::kSingleAgent, options, saved.state);
  ASSERT_TRUE(continued.ok());
  EXPECT_TRUE(continued->steps.empty());
}

// On another maze of the same shape, step 0 adapts from the loaded tables
// (timed as the initial training) and every step follows.
TEST(PolicyStateTest, AnotherMazeStartsFromTheLoadedTables) {
  const Scenario trained = GenerateScenario(30, 30, Difficulty::kHard, 52, 4);
  const Scenario other = GenerateScenario(30, 30, Difficulty::kHard, 53, 4);
  PlannerOptions options;
  options.run_seed = 52;
  options.leaf_limit = 8;
  for (Approach approach : kLearning) {
    SCOPED_TRACE(ApproachName(approach));
    const Saved saved = RunSaving(trained, approach, options, 0);
    PlannerOptions on_other = options;
    on_other.run_seed = 53;
    Result<ApproachRun> run = RunLoading(other, approach, on_other, saved.state);
    ASSERT_TRUE(run.ok()) << run.error().message;
    ASSERT_EQ(run->steps.size(), 5u);
    EXPECT_EQ(run->steps[0].time_step, 0);
    EXPECT_GT(run->initial_seconds, 0.0);
    EXPECT_GE(run->steps[0].success_rate, 0.0);
  }
}

// A policy whose step-0 maze is the run's but whose step-S maze is not
// (another change sequence) is refused, not continued from a wrong state.
TEST(PolicyStateTest, RefusesAnotherChangeSequence) {
  const Scenario scenario = GenerateScenario(30, 30, Difficulty::kHard, 52, 6);
  PlannerOptions options;
  options.run_seed = 52;
  Saved saved = RunSaving(scenario, Approach::kSingleAgent, options, 3);
  saved.state.fingerprint ^= 1;
  Result<ApproachRun> run = RunLoading(scenario, Approach::kSingleAgent, options, saved.state);
  ASSERT_FALSE(run.ok());
  EXPECT_NE(run.error().message.find("maze at step 3 differs"), std::string::npos);
}

TEST(PolicyStateTest, FitNamesWhatDiffers) {
  const Scenario scenario = GenerateScenario(30, 30, Difficulty::kHard, 52, 1);
  PlannerOptions options;
  options.run_seed = 52;
  const PolicyState state = RunSaving(scenario, Approach::kSingleAgent, options, 0).state;
  EXPECT_TRUE(CheckPolicyFits(state, Approach::kSingleAgent, options, 30, 30).ok());
  EXPECT_EQ(CheckPolicyFits(state, Approach::kSingleAgent, options, 40, 50).error().message,
            "the policy is for a 30x30 maze, this maze is 40x50");
  EXPECT_EQ(CheckPolicyFits(state, Approach::kFedAsynQEqAvg, options, 30, 30).error().message,
            "the policy was saved with approach singleAgent, this run has fedAsynQ_EqAvg");
  PlannerOptions other = options;
  other.single_agent.max_episodes = 5000;
  EXPECT_EQ(CheckPolicyFits(state, Approach::kSingleAgent, other, 30, 30).error().message,
            "the policy was saved with learner option max_episodes 10000, this run has 5000");
  other = options;
  other.semantics = Semantics::kReport;
  EXPECT_FALSE(CheckPolicyFits(state, Approach::kSingleAgent, other, 30, 30).ok());
}

TEST(PolicyStateTest, ConsistencyChecksSizesAndValues) {
  const Scenario scenario = GenerateScenario(30, 30, Difficulty::kHard, 52, 1);
  PlannerOptions options;
  options.run_seed = 52;
  PolicyState state = RunSaving(scenario, Approach::kSingleAgent, options, 0).state;
  EXPECT_TRUE(CheckPolicyConsistent(state).ok());
  PolicyState bad = state;
  bad.baselines[0] = 1.5;
  EXPECT_TRUE(CheckPolicyConsistent(bad).error().IsCorrupt());
  bad = state;
  bad.training_counts.pop_back();
  EXPECT_TRUE(CheckPolicyConsistent(bad).error().IsCorrupt());
  bad = state;
  bad.training_counts[0] = -1;
  EXPECT_TRUE(CheckPolicyConsistent(bad).error().IsCorrupt());
  bad = state;
  bad.table = QTable(10);
  EXPECT_TRUE(CheckPolicyConsistent(bad).error().IsCorrupt());
}

TEST(PolicyStateTest, FingerprintSeesEveryCell) {
  Grid grid(3, 4);
  const uint64_t empty = MazeFingerprint(grid);
  EXPECT_EQ(empty, MazeFingerprint(Grid(3, 4)));
  EXPECT_NE(empty, MazeFingerprint(Grid(4, 3)));
  grid.set(11, Cell::kStation);
  EXPECT_NE(empty, MazeFingerprint(grid));
}

}  // namespace
}  // namespace dynapath
