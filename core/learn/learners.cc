#include "dynapath/learners.h"

#include <cstdlib>

#include "core/learn/single_agent_learner.h"
#include "dynapath/federated_job.h"

namespace dynapath {

TrainingResult TrainJob(const TrainingJob& job, StopToken stop) {
  switch (job.kind) {
    case LearnerKind::kSingleAgent:
      return TrainSingleAgent(job, stop);
    case LearnerKind::kFedAsynQ:
      return TrainFedAsynQ(job, stop);
  }
  std::abort();  // not an enumerator: memory corruption, not input (the wire is validated)
}

bool TrainsInRounds(LearnerKind kind) {
  switch (kind) {
    case LearnerKind::kSingleAgent:
      return false;
    case LearnerKind::kFedAsynQ:
      return true;
  }
  std::abort();  // as above
}

}  // namespace dynapath
