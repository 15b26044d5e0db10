#include "dynapath/training_job.h"

#include <algorithm>
#include <cassert>

#include "dynapath/rng.h"

namespace dynapath {

Status CheckJob(const TrainingJob& job) {
  if (static_cast<int>(job.codes.size()) != job.region.cells()) {
    return Error::Corrupt("training job: cell codes do not match the region");
  }
  if (job.warm_start.cells() != 0 && job.warm_start.cells() != job.region.cells()) {
    return Error::Corrupt("training job: warm start does not match the region");
  }
  if (job.warm_start.cells() != 0 && job.warm_start.precision() != job.precision) {
    return Error::Corrupt("training job: warm start is not of the job's precision");
  }
  return Ok{};
}

QTable StartingTable(const TrainingJob& job) {
  // Jobs are consistent by construction (MakeTrainingJob) or were checked
  // where they arrived (JobFromBatch calls CheckJob).
  assert(CheckJob(job).ok());
  if (job.warm_start.cells() == 0) return QTable(job.region.cells(), job.precision);
  return job.warm_start;
}

int64_t FederatedRounds(const Region& region, const FedAsynQOptions& options) {
  const int64_t total_iterations =
      static_cast<int64_t>(region.rows()) * region.cols() * options.iterations_per_cell;
  const int64_t sync_period = std::max(1, options.sync_period);
  return std::max<int64_t>(1, total_iterations / sync_period);
}

uint64_t JobSeed(uint64_t run_seed, NodeId node, int64_t count) {
  return DeriveSeed({run_seed, static_cast<uint64_t>(node), static_cast<uint64_t>(count)});
}

}  // namespace dynapath
