#include "core/local_trainer.h"

#include <algorithm>
#include <cassert>
#include <memory>

#include "core/fedasynq.h"
#include "core/region_model.h"
#include "core/single_agent_learner.h"

namespace dynapath {

TrainingJob MakeTrainingJob(NodeId node, uint64_t seed, const LearnerConfig& config,
                            const QuadTree& tree, const Grid& grid, const RootQTable& root) {
  TrainingJob job;
  job.node = node;
  job.region = tree.node(node).region;
  job.codes = RegionCodes(grid, job.region);
  job.grid_rows = grid.rows();
  job.grid_cols = grid.cols();
  job.bootstrap = config.bootstrap;
  job.precision = root.precision();
  job.warm_start = root.Extract(job.region);
  job.seed = seed;
  job.kind = config.kind;
  job.single_agent = config.single_agent;
  job.federated = config.federated;
  return job;
}

TrainingStats LocalTrainer::Train(const std::vector<NodeId>& nodes,
                                  const std::vector<uint64_t>& seeds, const LearnerConfig& config,
                                  const QuadTree& tree, const Grid& grid, RootQTable& root) {
  std::vector<TrainingJob> jobs;
  jobs.reserve(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    jobs.push_back(MakeTrainingJob(nodes[i], seeds[i], config, tree, grid, root));
  }
  switch (config.kind) {
    case LearnerKind::kFedAsynQ:
      return TrainFederated(jobs, root);
    case LearnerKind::kSingleAgent:
      break;  // one job per thread, below
  }

  std::vector<TrainingResult> results(jobs.size());
  pool_.ParallelFor(static_cast<int>(jobs.size()),
                    [&](int i) { results[i] = TrainSingleAgent(jobs[i]); });
  TrainingStats stats;
  for (size_t i = 0; i < jobs.size(); ++i) {
    root.Commit(jobs[i].region, results[i].table);
    ++stats.jobs;
    stats.steps += results[i].steps;
  }
  return stats;
}

namespace {

// One federated job in progress. Its K learners are played by `workers`,
// each a FedAsynQLearner with its own copy of the shared table that plays a
// contiguous range of learners in turn with RunRoundAndRevert: memory is one
// table per worker, not one per learner, and a worker's table stays in the
// caches across the learners it plays.
struct FederatedRun {
  const TrainingJob* job = nullptr;
  std::unique_ptr<RegionModel> model;
  std::vector<std::unique_ptr<FedAsynQLearner>> workers;
  std::vector<int> first_learner;    // worker w plays [first_learner[w], first_learner[w + 1])
  std::vector<int> learner_indices;  // 0, 1, ..., K - 1
  std::unique_ptr<FederatedAverager> averager;
  QTable shared;
  StartStatistics stats;
  int64_t rounds = 0;
  std::vector<LearnerShard> shards;
  std::vector<uint32_t> averaged_entries;
  std::vector<float> averaged_values;        // float tables
  std::vector<double> averaged_wide_values;  // double tables
};

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

// Averages one round of `run` into its shared table and every worker's copy.
void CombineRound(FederatedRun& run) {
  WithValueType(run.shared.precision(), [&run]<typename V>(V*) {
    std::vector<V>& values = OfValueType<V>(run.averaged_values, run.averaged_wide_values);
    // The shards of our own learners on this job's model are well formed.
    [[maybe_unused]] const Status combined =
        run.averager->Combine(run.shards, run.shared, run.stats, run.averaged_entries, values);
    assert(combined.ok());
    for (auto& worker : run.workers) worker->ApplyAverage(run.averaged_entries, values);
  });
}

}  // namespace

TrainingStats LocalTrainer::TrainFederated(std::vector<TrainingJob>& jobs, RootQTable& root) {
  TrainingStats stats;
  if (jobs.size() >= static_cast<size_t>(kWholeJobsPerThread * pool_.threads())) {
    // Enough jobs to keep every thread busy: each runs whole jobs, all
    // rounds of one before the next (TrainFedAsynQ), so a job's tables stay
    // in the thread's caches instead of every round cycling through all the
    // batch's tables.
    std::vector<TrainingResult> results(jobs.size());
    pool_.ParallelFor(static_cast<int>(jobs.size()), [&](int i) {
      results[i] = TrainFedAsynQ(jobs[i]);
      jobs[i].warm_start = QTable();  // not needed any more
    });
    for (size_t i = 0; i < jobs.size(); ++i) {
      root.Commit(jobs[i].region, results[i].table);
      ++stats.jobs;
      stats.steps += results[i].steps;
    }
    return stats;
  }

  std::vector<FederatedRun> runs(jobs.size());
  int64_t max_rounds = 0;
  for (size_t j = 0; j < jobs.size(); ++j) {
    FederatedRun& run = runs[j];
    run.job = &jobs[j];
    run.model = std::make_unique<RegionModel>(jobs[j]);
    run.shared = StartingTable(jobs[j]);
    jobs[j].warm_start = QTable();  // copied into `shared`: not kept twice
    run.stats = StartStatistics(run.model->start_cells());
    run.rounds = FederatedRounds(jobs[j].region, jobs[j].federated);
    const int learners = std::max(1, jobs[j].federated.learners);
    const int workers = WorkersPerJob(jobs.size(), pool_.threads(), learners);
    for (int w = 0; w <= workers; ++w) run.first_learner.push_back(w * learners / workers);
    for (int w = 0; w < workers; ++w) {
      run.workers.push_back(std::make_unique<FedAsynQLearner>(*run.model, 0));
      run.workers.back()->set_count_visits(jobs[j].federated.averaging != Averaging::kEqual);
      run.workers.back()->Reset(run.shared);
    }
    run.averager = std::make_unique<FederatedAverager>(static_cast<int>(run.shared.size()),
                                                       jobs[j].federated.averaging);
    run.shards.resize(static_cast<size_t>(learners));
    for (int k = 0; k < learners; ++k) run.learner_indices.push_back(k);
    max_rounds = std::max(max_rounds, run.rounds);
  }

  // Work items of a round: (job, worker) pairs of the jobs still running.
  std::vector<std::pair<int, int>> items;
  std::vector<int> active_jobs;
  for (int64_t round = 0; round < max_rounds; ++round) {
    items.clear();
    active_jobs.clear();
    for (size_t j = 0; j < runs.size(); ++j) {
      if (round >= runs[j].rounds) continue;
      active_jobs.push_back(static_cast<int>(j));
      for (size_t w = 0; w < runs[j].workers.size(); ++w) {
        items.emplace_back(static_cast<int>(j), static_cast<int>(w));
      }
    }
    pool_.ParallelFor(static_cast<int>(items.size()), [&](int i) {
      FederatedRun& run = runs[items[i].first];
      const int w = items[i].second;
      FedAsynQLearner& worker = *run.workers[w];
      const int first = run.first_learner[w];
      worker.RunRoundsAndRevert(run.learner_indices.data() + first,
                                run.first_learner[w + 1] - first, run.stats, run.job->seed, round,
                                run.job->federated.sync_period, run.shards.data() + first);
    });
    if (active_jobs.size() == 1) {
      CombineRound(runs[active_jobs[0]]);  // not worth waking the pool
    } else {
      pool_.ParallelFor(static_cast<int>(active_jobs.size()),
                        [&](int i) { CombineRound(runs[active_jobs[i]]); });
    }
    for (int j : active_jobs) {
      for (const LearnerShard& shard : runs[j].shards) stats.steps += shard.steps;
    }
  }
  for (FederatedRun& run : runs) {
    root.Commit(run.job->region, run.shared);
    ++stats.jobs;
  }
  return stats;
}

}  // namespace dynapath
