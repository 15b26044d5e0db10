#pragma once
// A training job: everything a learner needs to train one quadtree node,
// self-contained so it can be run in this process or shipped to an agent
// process. Learners never see the quadtree or the root table.

#include <cstdint>
#include <vector>

#include "dynapath/learner_options.h"
#include "dynapath/q_table.h"
#include "dynapath/quadtree.h"
#include "dynapath/region.h"
#include "dynapath/result.h"

namespace dynapath {

// THE list of learner kinds. The enum, kAllLearnerKinds (core/include/dynapath/learners.h)
// and the registry's learner column (core/plan/approach_registry.cc) are expanded
// from it, so none of them can miss a kind; what differs by kind is decided
// by exhaustive switches (core/include/dynapath/learners.h).
#define DYNAPATH_LEARNER_KINDS(X) X(kSingleAgent) X(kFedAsynQ)

#define DYNAPATH_LEARNER_KIND_ENUMERATOR(kind) kind,
enum class LearnerKind { DYNAPATH_LEARNER_KINDS(DYNAPATH_LEARNER_KIND_ENUMERATOR) };
#undef DYNAPATH_LEARNER_KIND_ENUMERATOR
enum class Averaging { kEqual, kImportance };

// Which actions of the next state the update's max_a' Q(s', a') ranges over.
// The learner only *takes* in-region actions either way. kInGrid (default,
// SPEC 2's formula) also bootstraps from the values of actions that leave
// the region, learned when an ancestor was trained: a retrained leaf with no
// station keeps routing towards the exits its parent found. kInRegion treats
// the region as if it were the whole world. kAllStored is the report code's
// rule (`--semantics report`, docs/concepts/DECISIONS.md): all 8 stored values,
// including those of actions that leave the grid, which no learner ever
// updates and so stay 0 (a "phantom exit" at the outer wall).
enum class Bootstrap { kInGrid, kInRegion, kAllStored };

// The members, their defaults and meaning: core/include/dynapath/learner_options.h.
struct SingleAgentOptions {
  DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_DECLARE_LEARNER_OPTION)
};

struct FedAsynQOptions {
  DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_DECLARE_LEARNER_OPTION)
  Averaging averaging = Averaging::kEqual;  // set by the approach (its own wire field)
};

// The learners' options, one struct from the run's options to every job: the
// planner's options, a trainer's LearnerConfig and each TrainingJob hold it
// as their base, so it is passed on whole, never field by field.
struct LearnerOptions {
  Bootstrap bootstrap = Bootstrap::kInGrid;
  SingleAgentOptions single_agent;
  FedAsynQOptions federated;
};

// The job's learner options (its base) are the run's, with the approach's
// averaging and the semantics' bootstrap.
struct TrainingJob : LearnerOptions {
  NodeId node = kNoNode;
  Region region;               // in grid coordinates
  std::vector<uint8_t> codes;  // region cell codes, region-local row-major
  int grid_rows = 0;           // the whole grid's size (0: the region is the grid)
  int grid_cols = 0;
  QPrecision precision = QPrecision::kFloat;  // of the tables (q_table.h)
  QTable warm_start;  // the node's current table (region.cells(), `precision`), or empty: zeros
  uint64_t seed = 0;  // from (run seed, node, training count)
  LearnerKind kind = LearnerKind::kFedAsynQ;
};

struct TrainingResult {
  NodeId node = kNoNode;
  QTable table;                    // the node's new table
  int64_t episodes_or_rounds = 0;  // episodes (single agent) or rounds (federated)
  int64_t steps = 0;               // Q-learning steps taken by all learners
};

// Error when the codes or the warm start do not match the region (a
// malformed job). Jobs from outside (the wire) are checked with it on
// arrival; the learners take checked jobs only.
Status CheckJob(const TrainingJob& job);

// The table a job's training starts from: its warm start, or zeros when the
// warm start is empty (never trained). `job` must pass CheckJob.
QTable StartingTable(const TrainingJob& job);

// Number of federated rounds: floor(T / tau), at least 1.
int64_t FederatedRounds(const Region& region, const FedAsynQOptions& options);

// The seed of the `count`-th training (0-based) of `node` in a run.
uint64_t JobSeed(uint64_t run_seed, NodeId node, int64_t count);

}  // namespace dynapath
