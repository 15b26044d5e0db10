#pragma once
// Single-agent tabular Q-learning of SPEC section 6: warm start, epsilon-
// greedy over in-region actions, a FIFO experience replay buffer,
// prioritised start positions and the convergence test.

#include "dynapath/region_model.h"
#include "dynapath/stop_token.h"
#include "dynapath/training_job.h"

namespace dynapath {

// Trains `job` (kind kSingleAgent) to completion. Pure function of the job:
// the same job always gives the same table. Thread-safe (no shared state).
// Once `stop` is requested (checked every 64 episodes) it returns early: the
// result is then not the job's and is dropped.
TrainingResult TrainSingleAgent(const TrainingJob& job, StopToken stop = nullptr);

}  // namespace dynapath
