#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/learners.h"
#endif
// Single-agent tabular Q-learning of SPEC section 6: warm start, epsilon-
// greedy over in-region actions, a FIFO experience replay buffer,
// prioritised start positions and the convergence test; under --semantics
// report the report code's details of SPEC section 11.

#include <atomic>
#include <cstdint>

#include "core/learn/region_model.h"
#include "dynapath/stop_token.h"
#include "dynapath/training_job.h"

namespace dynapath {

// The report code's single-agent rules (SPEC section 11, points 1, 2 and 5;
// docs/concepts/DECISIONS.md, "The report code's semantics"). All of them
// apply under `--semantics report`, which a job carries as
// Bootstrap::kAllStored (only that switch selects it); none under ours. Each
// can be turned on alone (tests, bench/semantics_spread).
struct SingleAgentRules {
  // 11.1: a start on a station is an ordinary start: the episode takes a
  // step from it (a blocked move stays on the station, pays +100 and ends
  // the episode), so station rows are learned. Off: an immediate success.
  bool station_starts_step = false;
  // 11.2: starts are uniform over the region's non-obstacle cells in every
  // episode (the start statistics are never written). Off: prioritised
  // after the first 10 episodes (SPEC 6).
  bool uniform_starts = false;
  // 11.5: at most region rows + cols - 1 steps per episode (off: + cols).
  bool one_step_fewer = false;
  // 11.5: the first convergence check compares the table with the one the
  // training started from (off: it only takes the first snapshot).
  bool first_check_against_start = false;

  bool operator==(const SingleAgentRules&) const = default;
};

// Every rule on: the report code's learner.
SingleAgentRules ReportSingleAgentRules();
// The rules a job's semantics select: ReportSingleAgentRules() for
// Bootstrap::kAllStored (--semantics report), none otherwise.
SingleAgentRules SingleAgentRulesOf(const TrainingJob& job);

// Trains `job` (kind kSingleAgent) to completion with the rules its
// semantics select. Pure function of the job: the same job always gives the
// same table. Thread-safe (no shared state). Once `stop` is requested
// (checked every 64 episodes) it returns early: the result is then not the
// job's and is dropped. `work` (may be null) counts the episodes done, at
// the same interval, for a progress watcher; when the job ends (converged
// early, stopped, or nothing to learn) its unused budget is added too, so it
// has grown by exactly SingleAgentBudget(job) once the call returns.
TrainingResult TrainSingleAgent(const TrainingJob& job, StopToken stop = nullptr,
                                std::atomic<int64_t>* work = nullptr);
// The same with the rules given (experiments and tests).
TrainingResult TrainSingleAgent(const TrainingJob& job, const SingleAgentRules& rules,
                                StopToken stop = nullptr, std::atomic<int64_t>* work = nullptr);
// A single-agent job's work budget, in episodes: its max_episodes.
int64_t SingleAgentBudget(const TrainingJob& job);

}  // namespace dynapath
