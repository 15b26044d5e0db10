#pragma once
// A learning approach's policy as the planner holds it between time steps:
// exported to save it (runtime/policy_file.h writes the file) and imported
// to continue a run from the step after it or to start another maze of the
// same shape from it. It holds everything the next step reads (the root
// table, every node's training count, which seeds its next job, and the
// strategy's baselines), so a run continued from it is the uninterrupted
// run, bit for bit.

#include <cstdint>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/grid.h"
#include "dynapath/planner.h"
#include "dynapath/q_table.h"
#include "dynapath/result.h"

namespace dynapath {

struct PolicyState {
  Approach approach = Approach::kSingleAgent;
  int rows = 0;  // the maze's shape
  int cols = 0;
  int leaf_limit = 0;  // with the shape, the quadtree's shape
  int node_count = 0;  // QuadTree(rows, cols, leaf_limit).node_count()
  Semantics semantics = Semantics::kOurs;
  QPrecision precision = QPrecision::kFloat;
  // The learner options as the run gave them (the approach sets the
  // averaging, the semantics may set the bootstrap) and the strategy's.
  LearnerOptions learner;
  RetrainingThresholds thresholds;
  uint64_t run_seed = 0;             // the seed the job seeds derive from
  int step = 0;                      // the time step after which it was exported
  uint64_t initial_fingerprint = 0;  // MazeFingerprint (change_sequence.h) of the maze at step 0
  uint64_t fingerprint = 0;          // and at `step`
  std::vector<int64_t> training_counts;  // per node: trainings so far
  // Per node, the strategy's stored success rate (-1: never trained), for
  // strategies that keep one (the tree strategy); empty otherwise.
  std::vector<double> baselines;
  QTable table;  // the root table: rows * cols cells of `precision`
};

// Ok when `state` is consistent in itself (sizes of its vectors against its
// shape, training counts >= 0, baselines -1 or in [0, 1]); otherwise a
// kCorrupt error saying what is wrong.
Status CheckPolicyConsistent(const PolicyState& state);

// Ok when `state` can be loaded by `approach` with `options` on a maze of
// `rows` x `cols`; otherwise an error naming what differs ("the policy is
// for 50x50, the maze is 100x100"; "the policy was trained with
// --leaf-limit 16, this run has 8").
Status CheckPolicyFits(const PolicyState& state, Approach approach, const PlannerOptions& options,
                       int rows, int cols);

}  // namespace dynapath
