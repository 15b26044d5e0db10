#include "dynapath/training_progress.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "core/learn/single_agent_learner.h"
#include "dynapath/federated_job.h"
#include "tests/learner_test_support.h"

namespace dynapath {
namespace {

using test_maps::BytesEqual;
using test_maps::kMap20;
using test_maps::MapFromText;

using test_maps::WholeGridJob;

// A single-agent job counts exactly its budget (max_episodes) once it
// returns, whether it ran all its episodes or converged early, and the
// counting changes nothing of its result.
TEST(TrainingProgressTest, SingleAgentJobCountsItsWholeBudget) {
  // The two-cell corridor converges at episode 1550 of 10000; the 20x20
  // map with 300 episodes runs them all (the first check is at 500).
  for (const char* map : {".C\n", kMap20}) {
    TrainingJob job = WholeGridJob(MapFromText(map), LearnerKind::kSingleAgent, 3);
    if (map == kMap20) job.single_agent.max_episodes = 300;
    std::atomic<int64_t> work{5};  // what other jobs counted before
    const TrainingResult counted = TrainSingleAgent(job, nullptr, &work);
    const TrainingResult plain = TrainSingleAgent(job);
    EXPECT_EQ(work, 5 + job.single_agent.max_episodes) << map;
    EXPECT_EQ(SingleAgentBudget(job), job.single_agent.max_episodes);
    EXPECT_TRUE(BytesEqual(counted.table, plain.table)) << map;
    EXPECT_EQ(counted.steps, plain.steps) << map;
    EXPECT_EQ(counted.episodes_or_rounds, plain.episodes_or_rounds) << map;
    EXPECT_EQ(counted.episodes_or_rounds, map == kMap20 ? 300 : 1550);
  }
}

// Mid-job the count is between 0 and the budget, a multiple of the 64
// episodes between stop checks; a job stopped then still ends having counted
// its whole budget. The job (10 million episodes, no convergence check) can
// only end by the stop the watcher requests once it has seen progress, so
// the test does not depend on timing (on a loaded machine too).
TEST(TrainingProgressTest, SingleAgentCountIsSeenInsideTheJob) {
  TrainingJob job = WholeGridJob(MapFromText(kMap20), LearnerKind::kSingleAgent, 3);
  job.single_agent.max_episodes = 10000000;
  job.single_agent.convergence_start_episode = 10000000;
  std::atomic<int64_t> work{0};
  std::atomic<bool> stop{false};
  int64_t seen = 0;
  std::thread watcher([&] {
    // Bounded: with no count at all the test fails instead of hanging.
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while ((seen = work.load()) == 0 && std::chrono::steady_clock::now() < give_up) {
      std::this_thread::yield();
    }
    stop = true;
  });
  const TrainingResult result = TrainSingleAgent(job, &stop, &work);
  watcher.join();
  EXPECT_GT(seen, 0);
  EXPECT_LT(seen, job.single_agent.max_episodes);
  EXPECT_EQ(seen % 64, 0);
  EXPECT_GE(result.episodes_or_rounds, seen);
  EXPECT_LT(result.episodes_or_rounds, job.single_agent.max_episodes);
  EXPECT_EQ(work, job.single_agent.max_episodes);
}

// A whole federated job counts its rounds, one at each round's stop check,
// and its whole FederatedRounds once it returns, stopped before it started
// or not; the counting changes nothing of its result.
TEST(TrainingProgressTest, FederatedJobCountsItsRounds) {
  TrainingJob job = WholeGridJob(MapFromText(kMap20), LearnerKind::kFedAsynQ, 7);
  job.federated.iterations_per_cell = 20;
  const int64_t rounds = FederatedRounds(job.region, job.federated);
  ASSERT_GT(rounds, 1);
  std::atomic<int64_t> work{0};
  const TrainingResult counted = TrainFedAsynQ(job, nullptr, &work);
  const TrainingResult plain = TrainFedAsynQ(job);
  EXPECT_EQ(work, rounds);
  EXPECT_EQ(counted.episodes_or_rounds, rounds);
  EXPECT_TRUE(BytesEqual(counted.table, plain.table));
  EXPECT_EQ(counted.steps, plain.steps);

  std::atomic<bool> stop{true};
  work = 0;
  const TrainingResult stopped = TrainFedAsynQ(job, &stop, &work);
  EXPECT_EQ(stopped.episodes_or_rounds, 0);
  EXPECT_EQ(work, rounds);
}

// The fraction done: rounds for a batch in rounds, else the work inside the
// jobs where counted, else jobs; in [0, 1].
TEST(TrainingProgressTest, FractionCountsRoundsThenWorkThenJobs) {
  TrainingProgress progress;
  EXPECT_EQ(progress.Fraction(), 0.0);
  progress.Start(4, 0);
  progress.jobs_done = 1;
  EXPECT_EQ(progress.Fraction(), 0.25);
  progress.Start(1, 0, 10000, TrainingWork::kEpisodes);
  EXPECT_EQ(progress.batches, 2);
  EXPECT_EQ(progress.jobs_done, 0);
  EXPECT_EQ(progress.work_done, 0);
  progress.work_done = 2500;
  EXPECT_EQ(progress.Fraction(), 0.25);
  progress.work_done = 20000;  // never above 1
  EXPECT_EQ(progress.Fraction(), 1.0);
  progress.Start(4, 200);
  EXPECT_EQ(progress.work_total, 0);
  EXPECT_EQ(progress.work_kind, TrainingWork::kNone);
  progress.rounds_done = 50;
  EXPECT_EQ(progress.Fraction(), 0.25);
}

// One text for the run's log and the study's progress line, for the three
// kinds of batch.
TEST(TrainingProgressTest, DescribesTheThreeKindsOfBatch) {
  TrainingProgress progress;
  progress.Start(4, 225);
  progress.rounds_done = 40;
  EXPECT_EQ(DescribeTraining(progress), "training round 40/225 of 4 jobs");
  progress.Start(1, 300);
  EXPECT_EQ(DescribeTraining(progress), "training round 0/300 of 1 job");

  progress.Start(1, 0, 10000, TrainingWork::kEpisodes);
  progress.work_done = 3840;
  EXPECT_EQ(DescribeTraining(progress), "training 0/1 jobs, 38% of episodes");
  progress.work_done = 9999;  // rounded down: 100% only when done
  EXPECT_EQ(DescribeTraining(progress), "training 0/1 jobs, 99% of episodes");
  progress.Start(4096, 0, 40960, TrainingWork::kRounds);
  progress.jobs_done = 1689;
  progress.work_done = 16896;
  EXPECT_EQ(DescribeTraining(progress), "training 1689/4096 jobs, 41% of rounds");

  progress.Start(12, 0);  // jobs only (work not counted)
  progress.jobs_done = 3;
  EXPECT_EQ(DescribeTraining(progress), "training 3/12 jobs");
}

}  // namespace
}  // namespace dynapath
