#include "dynapath/local_trainer.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <memory>

#include "core/learn/single_agent_learner.h"
#include "dynapath/federated_job.h"

namespace dynapath {

TrainingJob MakeTrainingJob(NodeId node, uint64_t seed, const LearnerConfig& config,
                            const QuadTree& tree, const Grid& grid, const RootQTable& root) {
  TrainingJob job;
  static_cast<LearnerOptions&>(job) = config;
  job.node = node;
  job.region = tree.node(node).region;
  job.codes = RegionCodes(grid, job.region);
  job.grid_rows = grid.rows();
  job.grid_cols = grid.cols();
  job.precision = root.precision();
  job.warm_start = root.Extract(job.region);
  job.seed = seed;
  job.kind = config.kind;
  return job;
}

bool LocalTrainer::Stopped() {
  if (status_.ok() && StopRequested(stop_)) status_ = Error::Cancelled();
  return !status_.ok();
}

TrainingStats LocalTrainer::Train(const std::vector<NodeId>& nodes,
                                  const std::vector<uint64_t>& seeds, const LearnerConfig& config,
                                  const QuadTree& tree, const Grid& grid, RootQTable& root) {
  if (Stopped()) return {};
  std::vector<TrainingJob> jobs;
  jobs.reserve(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    jobs.push_back(MakeTrainingJob(nodes[i], seeds[i], config, tree, grid, root));
  }
  struct Finish {
    TrainingProgress* progress;
    ~Finish() {
      if (progress != nullptr) progress->Finish();
    }
  } finish{progress_};
  switch (config.kind) {
    case LearnerKind::kFedAsynQ:
      return TrainFederated(jobs, root);
    case LearnerKind::kSingleAgent:
      break;  // one job per thread, below
  }

  std::atomic<int64_t>* work = nullptr;
  if (progress_ != nullptr) {
    int64_t episodes = 0;
    for (const TrainingJob& job : jobs) episodes += SingleAgentBudget(job);
    progress_->Start(static_cast<int64_t>(jobs.size()), 0, episodes, TrainingWork::kEpisodes);
    work = &progress_->work_done;
  }
  std::vector<TrainingResult> results(jobs.size());
  pool_.ParallelFor(static_cast<int>(jobs.size()), [&](int i) {
    results[i] = TrainSingleAgent(jobs[i], stop_, work);
    if (progress_ != nullptr) progress_->jobs_done.fetch_add(1, std::memory_order_relaxed);
  });
  if (Stopped()) return {};  // some jobs may have ended early
  TrainingStats stats;
  for (size_t i = 0; i < jobs.size(); ++i) {
    root.Commit(jobs[i].region, results[i].table);
    ++stats.jobs;
    stats.steps += results[i].steps;
  }
  return stats;
}

namespace {

// From this many jobs per thread on, the jobs of a batch run whole, one per
// thread (below, the threads would finish at different times: e.g. 5 jobs
// on 4 threads); fewer advance round by round together, their learners
// spread over the threads.
constexpr int kWholeJobsPerThread = 4;

// Workers per job: enough (job, worker) items for every thread to have about
// four, so that the threads finish a round together; at most one per thread
// and one per learner. A batch of many jobs then holds one table per job, a
// lone root one per thread.
int WorkersPerJob(size_t jobs, int threads, int learners) {
  const int wanted = static_cast<int>((4 * static_cast<size_t>(threads) + jobs - 1) / jobs);
  return std::max(1, std::min({wanted, threads, learners}));
}

}  // namespace

TrainingStats LocalTrainer::TrainFederated(std::vector<TrainingJob>& jobs, RootQTable& root) {
  TrainingStats stats;
  if (jobs.size() >= static_cast<size_t>(kWholeJobsPerThread * pool_.threads())) {
    // Enough jobs to keep every thread busy: each runs whole jobs, all
    // rounds of one before the next (TrainFedAsynQ), so a job's tables stay
    // in the thread's caches instead of every round cycling through all the
    // batch's tables.
    std::atomic<int64_t>* work = nullptr;
    if (progress_ != nullptr) {
      int64_t rounds = 0;
      for (const TrainingJob& job : jobs) rounds += FederatedRounds(job.region, job.federated);
      progress_->Start(static_cast<int64_t>(jobs.size()), 0, rounds, TrainingWork::kRounds);
      work = &progress_->work_done;
    }
    std::vector<TrainingResult> results(jobs.size());
    pool_.ParallelFor(static_cast<int>(jobs.size()), [&](int i) {
      results[i] = TrainFedAsynQ(jobs[i], stop_, work);
      jobs[i].warm_start = QTable();  // not needed any more
      if (progress_ != nullptr) progress_->jobs_done.fetch_add(1, std::memory_order_relaxed);
    });
    if (Stopped()) return {};  // some jobs may have ended early
    for (size_t i = 0; i < jobs.size(); ++i) {
      root.Commit(jobs[i].region, results[i].table);
      ++stats.jobs;
      stats.steps += results[i].steps;
    }
    return stats;
  }

  std::vector<std::unique_ptr<FederatedRun>> runs;
  int64_t max_rounds = 0;
  for (TrainingJob& job : jobs) {
    const int learners = std::max(1, job.federated.learners);
    runs.push_back(std::make_unique<FederatedRun>(
        job, WorkersPerJob(jobs.size(), pool_.threads(), learners)));
    job.warm_start = QTable();  // copied into the run's shared table: not kept twice
    max_rounds = std::max(max_rounds, runs.back()->rounds());
  }

  if (progress_ != nullptr) progress_->Start(static_cast<int64_t>(jobs.size()), max_rounds);
  // Work items of a round: (job, worker) pairs of the jobs still running.
  std::vector<std::pair<int, int>> items;
  std::vector<int> active_jobs;
  for (int64_t round = 0; round < max_rounds; ++round) {
    if (progress_ != nullptr) progress_->rounds_done.store(round, std::memory_order_relaxed);
    if (Stopped()) return {};
    items.clear();
    active_jobs.clear();
    for (size_t j = 0; j < runs.size(); ++j) {
      if (round >= runs[j]->rounds()) continue;
      active_jobs.push_back(static_cast<int>(j));
      for (int w = 0; w < runs[j]->workers(); ++w) items.emplace_back(static_cast<int>(j), w);
    }
    pool_.ParallelFor(static_cast<int>(items.size()),
                      [&](int i) { runs[items[i].first]->RunRound(items[i].second, round); });
    if (active_jobs.size() == 1) {
      runs[active_jobs[0]]->FinishRound();  // not worth waking the pool
    } else {
      pool_.ParallelFor(static_cast<int>(active_jobs.size()),
                        [&](int i) { runs[active_jobs[i]]->FinishRound(); });
    }
  }
  if (progress_ != nullptr) progress_->rounds_done.store(max_rounds, std::memory_order_relaxed);
  for (auto& run : runs) {
    root.Commit(run->job().region, run->shared());
    ++stats.jobs;
    stats.steps += run->steps();
  }
  return stats;
}

}  // namespace dynapath
