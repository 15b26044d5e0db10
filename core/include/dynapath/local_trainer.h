#pragma once
// Trains nodes in this process on a thread pool.
//
// Single-agent jobs run one per thread. Federated jobs of a batch with at
// least 4 jobs per thread run whole, one per thread (TrainFedAsynQ). Fewer
// advance round by round together (FederatedRun, core/include/dynapath/federated_job.h): in
// every round each job's learners are played by up to one worker per thread,
// then each job's shards are averaged. This keeps both cores busy even when
// one small leaf (or the root alone) is retrained. Either way the tables are
// exactly TrainFedAsynQ's.

#include "dynapath/stop_token.h"
#include "dynapath/thread_pool.h"
#include "dynapath/trainer.h"
#include "dynapath/training_progress.h"

namespace dynapath {

class LocalTrainer : public Trainer {
 public:
  // `pool` must outlive the trainer. Once `stop` is requested (checked every
  // round and every 64 episodes, also inside one large job) the trainer
  // fails with kCancelled and commits nothing (Trainer::status).
  // `progress` (may be null) is kept up to date for a watcher thread: jobs,
  // rounds of a batch run round by round, and the episodes (rounds) inside
  // a batch of whole jobs, counted every 64 episodes (every round).
  explicit LocalTrainer(ThreadPool& pool, StopToken stop = nullptr,
                        TrainingProgress* progress = nullptr)
      : pool_(pool), stop_(stop), progress_(progress) {}

  TrainingStats Train(const std::vector<NodeId>& nodes, const std::vector<uint64_t>& seeds,
                      const LearnerConfig& config, const QuadTree& tree, const Grid& grid,
                      RootQTable& root) override;
  Status status() const override { return status_; }

 private:
  TrainingStats TrainFederated(std::vector<TrainingJob>& jobs, RootQTable& root);

  // Whether the run was stopped; then status_ becomes kCancelled.
  bool Stopped();

  ThreadPool& pool_;
  StopToken stop_;
  TrainingProgress* progress_;
  Status status_ = Ok{};
};

}  // namespace dynapath
