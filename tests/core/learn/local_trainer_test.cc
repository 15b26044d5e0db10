#include "dynapath/local_trainer.h"

#include <gtest/gtest.h>

#include <atomic>

#include "core/learn/single_agent_learner.h"
#include "dynapath/federated_job.h"
#include "dynapath/scenario.h"

namespace dynapath {
namespace {

// The parallel trainer gives exactly the tables of the sequential learners,
// for several nodes at once and any thread count: batches of few jobs
// (round by round, one to three workers per job), of many (whole jobs per
// thread from 4 jobs per thread on), and the root alone.
class LocalTrainerTest : public ::testing::TestWithParam<std::vector<int>> {};

TEST_P(LocalTrainerTest, EqualsSequentialLearners) {
  const Scenario scenario = GenerateScenario(60, 60, Difficulty::kHard, 52, 0);  // 16 leaves
  const QuadTree tree(scenario.grid.rows(), scenario.grid.cols());
  std::vector<NodeId> nodes;
  std::vector<uint64_t> seeds;
  for (int leaf : GetParam()) {
    nodes.push_back(leaf < 0 ? tree.root() : tree.leaves()[leaf]);
    seeds.push_back(11 + seeds.size());
  }
  for (LearnerKind kind : {LearnerKind::kFedAsynQ, LearnerKind::kSingleAgent}) {
    for (Averaging averaging : {Averaging::kEqual, Averaging::kImportance}) {
      LearnerConfig config;
      config.kind = kind;
      config.federated.averaging = averaging;
      config.federated.iterations_per_cell = 20;  // keep the test quick
      config.single_agent.max_episodes = 300;
      RootQTable expected(tree.rows(), tree.cols());
      for (size_t i = 0; i < nodes.size(); ++i) {
        const TrainingJob job =
            MakeTrainingJob(nodes[i], seeds[i], config, tree, scenario.grid, expected);
        const TrainingResult result =
            kind == LearnerKind::kFedAsynQ ? TrainFedAsynQ(job) : TrainSingleAgent(job);
        expected.Commit(job.region, result.table);
      }
      for (int threads : {1, 2, 3}) {
        ThreadPool pool(threads);
        // Progress reporting (what a watcher thread reads) changes nothing
        // and ends complete: every job, or every round, done.
        TrainingProgress progress;
        LocalTrainer trainer(pool, nullptr, &progress);
        RootQTable root(tree.rows(), tree.cols());
        const TrainingStats stats = trainer.Train(nodes, seeds, config, tree, scenario.grid, root);
        EXPECT_EQ(stats.jobs, static_cast<int64_t>(nodes.size()));
        EXPECT_GT(stats.steps, 0);
        ASSERT_EQ(root.table(), expected.table()) << "threads " << threads;
        EXPECT_FALSE(progress.running);
        EXPECT_EQ(progress.batches, 1);
        EXPECT_EQ(progress.jobs_total, static_cast<int64_t>(nodes.size()));
        EXPECT_DOUBLE_EQ(progress.Fraction(), 1.0);
        if (progress.rounds_total > 0) {
          EXPECT_EQ(progress.rounds_done, progress.rounds_total);
          EXPECT_EQ(progress.work_total, 0);
        } else if (kind == LearnerKind::kSingleAgent) {
          // Whole jobs count their episodes: every job's budget.
          EXPECT_EQ(progress.work_kind, TrainingWork::kEpisodes);
          EXPECT_EQ(progress.work_total, static_cast<int64_t>(nodes.size()) * 300);
          EXPECT_EQ(progress.work_done, progress.work_total);
        } else {
          // Whole federated jobs count their rounds.
          int64_t rounds = 0;
          for (NodeId node : nodes) {
            rounds += FederatedRounds(tree.node(node).region, config.federated);
          }
          EXPECT_EQ(progress.work_kind, TrainingWork::kRounds);
          EXPECT_EQ(progress.work_total, rounds);
          EXPECT_EQ(progress.work_done, rounds);
        }
      }
    }
  }
}

// Leaf indices; -1 = the root.
INSTANTIATE_TEST_SUITE_P(Batches, LocalTrainerTest,
                         ::testing::Values(std::vector<int>{0, 1, 3},
                                           std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8},
                                           std::vector<int>{-1}));

// A stop requested before training: the trainer fails with kCancelled at
// once, commits nothing, and stays failed; the learners return early (a
// root of 4096x4096 cells would otherwise train for minutes).
TEST(LocalTrainerStopTest, PresetStopCancelsWithoutCommitting) {
  const Scenario scenario = GenerateScenario(60, 60, Difficulty::kHard, 52, 0);
  const QuadTree tree(scenario.grid.rows(), scenario.grid.cols());
  std::atomic<bool> stop{true};
  for (LearnerKind kind : {LearnerKind::kFedAsynQ, LearnerKind::kSingleAgent}) {
    LearnerConfig config;
    config.kind = kind;
    ThreadPool pool(2);
    LocalTrainer trainer(pool, &stop);
    RootQTable root(tree.rows(), tree.cols());
    const RootQTable untouched = root;
    const TrainingStats stats =
        trainer.Train({tree.root()}, {11}, config, tree, scenario.grid, root);
    EXPECT_EQ(stats.jobs, 0);
    EXPECT_EQ(stats.steps, 0);
    EXPECT_TRUE(trainer.status().error().IsCancelled());
    EXPECT_EQ(root.table(), untouched.table());
    const TrainingJob job = MakeTrainingJob(tree.root(), 11, config, tree, scenario.grid, root);
    const TrainingResult result =
        kind == LearnerKind::kFedAsynQ ? TrainFedAsynQ(job, &stop) : TrainSingleAgent(job, &stop);
    EXPECT_EQ(result.episodes_or_rounds, 0);
    EXPECT_EQ(result.steps, 0);
  }
}

// An unset stop token changes nothing: the same tables as without one.
TEST(LocalTrainerStopTest, UnsetStopGivesTheSameTables) {
  const Scenario scenario = GenerateScenario(60, 60, Difficulty::kHard, 52, 0);
  const QuadTree tree(scenario.grid.rows(), scenario.grid.cols());
  std::atomic<bool> stop{false};
  for (LearnerKind kind : {LearnerKind::kFedAsynQ, LearnerKind::kSingleAgent}) {
    LearnerConfig config;
    config.kind = kind;
    config.federated.iterations_per_cell = 20;
    config.single_agent.max_episodes = 300;
    ThreadPool pool(2);
    LocalTrainer plain(pool);
    LocalTrainer stoppable(pool, &stop);
    RootQTable a(tree.rows(), tree.cols());
    RootQTable b(tree.rows(), tree.cols());
    plain.Train({tree.root()}, {11}, config, tree, scenario.grid, a);
    stoppable.Train({tree.root()}, {11}, config, tree, scenario.grid, b);
    EXPECT_TRUE(stoppable.status().ok());
    EXPECT_EQ(a.table(), b.table());
  }
}

}  // namespace
}  // namespace dynapath
