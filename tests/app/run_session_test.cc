#include "app/run_session.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>

#include "app/repeats.h"
#include "app/resources.h"

namespace dynapath::app {
namespace {

// A small run: easy 10x10 maze, two steps, in process.
RunOptions SmallRun(const std::string& out) {
  RunOptions options;
  options.scenario.size = 10;
  options.scenario.difficulty = "easy";
  options.scenario.steps = 2;
  options.run.approach = "BFS Oracle,fedAsynQ_EqAvg";
  options.run.out = out;
  options.threads.threads = 2;
  return options;
}

std::filesystem::path TempOut(const std::string& name) {
  const std::filesystem::path out = std::filesystem::temp_directory_path() /
                                    ("dynapath-app-" + name + "-" + std::to_string(getpid()));
  std::filesystem::remove_all(out);
  return out;
}

TEST(PlanRun, TakesTheOptionsAsTyped) {
  RunOptions options = SmallRun("unused");
  options.repeats = 3;
  Result<RunPlan> plan = PlanRun(options);
  ASSERT_TRUE(plan) << plan.error().message;
  EXPECT_EQ(plan->mode.kind, runtime::RunMode::kLocal);
  EXPECT_EQ(plan->threads, 2);
  EXPECT_EQ(plan->repeats, 3);
  EXPECT_EQ(plan->run.approaches.size(), 2u);
  EXPECT_EQ(plan->setup.scenario.changes.steps.size(), 2u);
  EXPECT_FALSE(plan->distributed());
  EXPECT_FALSE(plan->checkpointing());
}

// Each bad combination: one error, kInvalidArgument, naming the option.
TEST(PlanRun, NamesTheOptionOfEachError) {
  struct Case {
    const char* option;
    void (*spoil)(RunOptions&);
  };
  const Case cases[] = {
      {"restart-coordinator", [](RunOptions& o) { o.restarts = 2; }},
      {"force", [](RunOptions& o) { o.force = true; }},
      {"lcm-url", [](RunOptions& o) { o.process.lcm_url = "udpm://239.255.76.67:7667"; }},
      {"insecure", [](RunOptions& o) { o.process.insecure = true; }},
      {"fault-drop", [](RunOptions& o) { o.fault_drop_given = true; }},
      {"log", [](RunOptions& o) { o.log_file = "run.log"; }},
      {"repeats", [](RunOptions& o) { o.repeats = 0; }},
      {"repeats",
       [](RunOptions& o) {
         o.repeats = 2;
         o.run.checkpoint = "ckpt";
       }},
      {"learner-seed",
       [](RunOptions& o) {
         o.repeats = 3;
         o.run.learner_seed = runtime::kMaxLearnerSeed;
       }},
  };
  for (const Case& c : cases) {
    RunOptions options = SmallRun("unused");
    c.spoil(options);
    Result<RunPlan> plan = PlanRun(options);
    ASSERT_FALSE(plan) << c.option;
    EXPECT_TRUE(plan.error().IsInvalidArgument()) << c.option;
    EXPECT_EQ(plan.error().subject, c.option) << plan.error().message;
  }
}

TEST(PlanRun, EmbeddedRunsTakeNoUrl) {
  RunOptions options = SmallRun("unused");
  options.mode.embedded = true;
  options.process.lcm_url = "memq://";
  Result<RunPlan> plan = PlanRun(options);
  ASSERT_FALSE(plan);
  EXPECT_EQ(plan.error().subject, "lcm-url");
}

// In process: the run's result files, one row per approach and step.
TEST(RunSession, RunsInProcess) {
  const std::filesystem::path out = TempOut("run");
  Result<RunPlan> plan = PlanRun(SmallRun(out.string()));
  ASSERT_TRUE(plan) << plan.error().message;
  RunSession session(std::move(*plan));
  ASSERT_TRUE(session.Prepare());
  std::atomic<bool> stop{false};
  const Status ran = session.Run(stop);
  ASSERT_TRUE(ran) << ran.error().message;
  EXPECT_TRUE(session.repeats().empty());
  EXPECT_TRUE(std::filesystem::exists(out / "results.csv"));
  EXPECT_TRUE(std::filesystem::exists(out / "results_detailed.csv"));
  std::filesystem::remove_all(out);
}

// Repeats: repeat 1 in the output directory, repeat k in DIR/r<k>, each
// with its own learner seed.
TEST(RunSession, RunsRepeatsInProcess) {
  const std::filesystem::path out = TempOut("repeats");
  RunOptions options = SmallRun(out.string());
  options.repeats = 2;
  Result<RunPlan> plan = PlanRun(options);
  ASSERT_TRUE(plan) << plan.error().message;
  RunSession session(std::move(*plan));
  ASSERT_TRUE(session.Prepare());
  std::atomic<bool> stop{false};
  ASSERT_TRUE(session.Run(stop));
  ASSERT_EQ(session.repeats().size(), 2u);
  EXPECT_EQ(session.repeats()[0].directory, out.string());
  EXPECT_EQ(session.repeats()[1].directory, (out / "r2").string());
  EXPECT_EQ(session.repeats()[1].learner_seed,
            session.repeats()[0].learner_seed + kRepeatSeedStride);
  EXPECT_TRUE(std::filesystem::exists(out / "r2" / "results.csv"));
  std::filesystem::remove_all(out);
}

// A run stopped before it starts is cancelled, not failed.
TEST(RunSession, StopCancels) {
  const std::filesystem::path out = TempOut("stop");
  Result<RunPlan> plan = PlanRun(SmallRun(out.string()));
  ASSERT_TRUE(plan);
  RunSession session(std::move(*plan));
  ASSERT_TRUE(session.Prepare());
  std::atomic<bool> stop{true};
  const Status ran = session.Run(stop);
  ASSERT_FALSE(ran);
  EXPECT_TRUE(ran.error().IsCancelled());
  std::filesystem::remove_all(out);
}

TEST(Resources, GridCapAndThreadsSplit) {
  EXPECT_EQ(GridCap(40, 60), 2400);
  EXPECT_EQ(ThreadsPerAgent(8, 3), 2);
  EXPECT_EQ(ThreadsPerAgent(1, 4), 1);
}

}  // namespace
}  // namespace dynapath::app
