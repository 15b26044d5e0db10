#include "core/local_trainer.h"

#include <gtest/gtest.h>

#include "core/fedasynq.h"
#include "core/scenario.h"
#include "core/single_agent_learner.h"

namespace dynapath {
namespace {

// The round-synchronous parallel trainer gives exactly the tables of the
// sequential learners, for several nodes at once and any thread count.
TEST(LocalTrainerTest, EqualsSequentialLearners) {
  const Scenario scenario = GenerateScenario(40, 40, Difficulty::kHard, 52, 0);
  const QuadTree tree(scenario.grid.rows(), scenario.grid.cols());
  const std::vector<NodeId> nodes = {tree.leaves()[0], tree.leaves()[1], tree.leaves()[3]};
  const std::vector<uint64_t> seeds = {11, 12, 13};
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
        LocalTrainer trainer(pool);
        RootQTable root(tree.rows(), tree.cols());
        const TrainingStats stats = trainer.Train(nodes, seeds, config, tree, scenario.grid, root);
        EXPECT_EQ(stats.jobs, 3);
        EXPECT_GT(stats.steps, 0);
        ASSERT_EQ(root.table(), expected.table()) << "threads " << threads;
      }
    }
  }
}

}  // namespace
}  // namespace dynapath
