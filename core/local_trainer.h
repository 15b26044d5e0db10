#pragma once
// Trains nodes in this process on a thread pool.
//
// Single-agent jobs run one per thread. Federated jobs advance round by round
// together: in every round all (job, learner) pairs run in parallel, then
// each job's shards are averaged. This keeps both cores busy even when one
// small leaf is retrained, and gives exactly TrainFedAsynQ's tables.

#include "core/thread_pool.h"
#include "core/trainer.h"

namespace dynapath {

class LocalTrainer : public Trainer {
 public:
  // `pool` must outlive the trainer.
  explicit LocalTrainer(ThreadPool& pool) : pool_(pool) {}

  TrainingStats Train(const std::vector<NodeId>& nodes, const std::vector<uint64_t>& seeds,
                      const LearnerConfig& config, const QuadTree& tree, const Grid& grid,
                      RootQTable& root) override;

 private:
  TrainingStats TrainFederated(std::vector<TrainingJob>& jobs, RootQTable& root);

  ThreadPool& pool_;
};

}  // namespace dynapath
