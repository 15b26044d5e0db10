#pragma once
// Conversions between core/ values and messages. The encodings are exact
// (floats travel as floats), which is what keeps distributed results equal to
// in-process ones.

#include <optional>
#include <string>
#include <vector>

#include "core/change_sequence.h"
#include "core/fedasynq.h"
#include "core/grid.h"
#include "core/start_statistics.h"
#include "core/trainer.h"
#include "core/training_job.h"
#include "dynapath/changes_t.hpp"
#include "dynapath/grid_t.hpp"
#include "dynapath/job_batch_t.hpp"
#include "dynapath/learner_shard_t.hpp"

namespace dynapath::protocol {

// Where a federated job (re)starts: the shared table and start statistics
// after `round` completed rounds.
struct JobProgress {
  int64_t round = 0;
  QTable table;                               // empty: the job's warm start
  std::vector<uint32_t> attempts, successes;  // empty: fresh statistics
};

// The wire's KIND_* of a learner kind, and back (nullopt: no learner has
// that wire value).
int8_t LearnerKindToWire(LearnerKind kind);
std::optional<LearnerKind> LearnerKindFromWire(int8_t wire);

// Fills the batch header (options) from `config`.
void SetBatchOptions(const LearnerConfig& config, job_batch_t& batch);
// Appends `job` (restarting from `progress`) to the batch.
void AddJob(const TrainingJob& job, const JobProgress& progress, job_batch_t& batch);

// The index-th job of a batch as a TrainingJob (warm start = the table it
// restarts from) and where it restarts. Fails when the job is inconsistent
// (e.g. statistics that do not match the region's start cells).
struct ReceivedJob {
  TrainingJob job;
  int64_t start_round = 0;
  std::vector<uint32_t> attempts, successes;
};
Result<ReceivedJob> JobFromBatch(const job_batch_t& batch, int index);

learner_shard_t ShardToMessage(const LearnerShard& shard, int job, bool with_visits);
// Visits absent (equal averaging does not use them) become 1 each.
LearnerShard ShardFromMessage(const learner_shard_t& message, int64_t round);

grid_t GridToMessage(const Grid& grid);
Grid GridFromMessage(const grid_t& message);  // message validated
changes_t ChangesToMessage(const ChangeStep& step, int time_step, int total_steps);
// Fails when a cell lies outside a rows x cols grid.
Result<ChangeStep> ChangesFromMessage(const changes_t& message, int rows, int cols);

}  // namespace dynapath::protocol
