#pragma once
// How the retraining strategy gets nodes trained. The in-process trainer
// (LocalTrainer) runs learners on a thread pool; the coordinator's
// distributed trainer spreads the same jobs over agent processes.

#include <cstdint>
#include <vector>

#include "dynapath/grid.h"
#include "dynapath/q_table.h"
#include "dynapath/quadtree.h"
#include "dynapath/result.h"
#include "dynapath/training_job.h"

namespace dynapath {

// Which learner trains the nodes, and its options.
struct LearnerConfig : LearnerOptions {
  LearnerKind kind = LearnerKind::kFedAsynQ;
};

struct TrainingStats {
  int64_t jobs = 0;
  int64_t steps = 0;  // Q-learning steps of all learners
};

class Trainer {
 public:
  virtual ~Trainer() = default;

  // Trains `nodes` (ascending ids, pairwise disjoint regions) on `grid`, each
  // from its current values in `root`, with `config`, and commits every new
  // table into `root`. Blocks until all are done. `seeds[i]` is the job seed
  // of nodes[i].
  virtual TrainingStats Train(const std::vector<NodeId>& nodes, const std::vector<uint64_t>& seeds,
                              const LearnerConfig& config, const QuadTree& tree, const Grid& grid,
                              RootQTable& root) = 0;

  // Ok, or why the trainer has failed (e.g. kCancelled: the run was
  // stopped). Once failed it stays so, and Train commits nothing: the
  // runner ends the approach (RunApproach) and returns this status.
  virtual Status status() const { return Ok{}; }
};

// Builds the self-contained job of one node.
TrainingJob MakeTrainingJob(NodeId node, uint64_t seed, const LearnerConfig& config,
                            const QuadTree& tree, const Grid& grid, const RootQTable& root);

}  // namespace dynapath
