#include "core/local_trainer.h"

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
  if (config.kind == LearnerKind::kFedAsynQ) return TrainFederated(jobs, root);

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

// One federated job in progress.
struct FederatedRun {
  const TrainingJob* job = nullptr;
  std::unique_ptr<RegionModel> model;
  std::vector<std::unique_ptr<FedAsynQLearner>> learners;
  std::unique_ptr<FederatedAverager> averager;
  QTable shared;
  StartStatistics stats;
  int64_t rounds = 0;
  std::vector<LearnerShard> shards;
  std::vector<uint32_t> averaged_entries;
  std::vector<float> averaged_values;
};

}  // namespace

TrainingStats LocalTrainer::TrainFederated(std::vector<TrainingJob>& jobs, RootQTable& root) {
  std::vector<FederatedRun> runs(jobs.size());
  int64_t max_rounds = 0;
  for (size_t j = 0; j < jobs.size(); ++j) {
    FederatedRun& run = runs[j];
    run.job = &jobs[j];
    run.model = std::make_unique<RegionModel>(jobs[j]);
    run.shared = jobs[j].warm_start;
    run.stats = StartStatistics(run.model->start_cells());
    run.rounds = FederatedRounds(jobs[j].region, jobs[j].federated);
    const int learners = jobs[j].federated.learners;
    for (int k = 0; k < learners; ++k) {
      run.learners.push_back(std::make_unique<FedAsynQLearner>(*run.model, k));
      run.learners.back()->Reset(run.shared);
    }
    run.averager = std::make_unique<FederatedAverager>(static_cast<int>(run.shared.values().size()),
                                                       jobs[j].federated.averaging);
    run.shards.resize(static_cast<size_t>(learners));
    max_rounds = std::max(max_rounds, run.rounds);
  }

  // Work items of a round: (job, learner) pairs of the jobs still running.
  std::vector<std::pair<int, int>> items;
  std::vector<int> active_jobs;
  TrainingStats stats;
  for (int64_t round = 0; round < max_rounds; ++round) {
    items.clear();
    active_jobs.clear();
    for (size_t j = 0; j < runs.size(); ++j) {
      if (round >= runs[j].rounds) continue;
      active_jobs.push_back(static_cast<int>(j));
      for (size_t k = 0; k < runs[j].learners.size(); ++k) {
        items.emplace_back(static_cast<int>(j), static_cast<int>(k));
      }
    }
    pool_.ParallelFor(static_cast<int>(items.size()), [&](int i) {
      FederatedRun& run = runs[items[i].first];
      const int k = items[i].second;
      run.shards[k] = run.learners[k]->RunRound(run.stats, run.job->seed, round,
                                                run.job->federated.sync_period);
    });
    pool_.ParallelFor(static_cast<int>(active_jobs.size()), [&](int i) {
      FederatedRun& run = runs[active_jobs[i]];
      run.averager->Combine(run.shards, run.shared, run.stats, run.averaged_entries,
                            run.averaged_values);
      for (auto& learner : run.learners) {
        learner->ApplyAverage(run.averaged_entries, run.averaged_values);
      }
    });
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
