#pragma once
// Runs one approach over a scenario (SPEC section 9): initial training at
// time step 0, then for every step apply the changes, adapt (timed), evaluate.

#include <functional>
#include <string>
#include <vector>

#include "core/approach.h"
#include "core/planner.h"
#include "core/scenario.h"

namespace dynapath {

struct StepRecord {
  int time_step = 0;
  int num_changes = 0;         // obstacle moves requested (the report's NumChanges)
  double adapt_seconds = 0.0;  // 0 at time step 0 and for A* Static
  double success_rate = 0.0;
  double average_path_length = 0.0;
  int nodes_trained = 0;
  int highest_level = -1;
};

struct ApproachRun {
  Approach approach = Approach::kBfsOracle;
  std::string size_label;        // "50" for square mazes, "40x60" otherwise
  std::string difficulty_label;  // "Easy", "Medium", "Hard", or "Custom"
  double initial_seconds = 0.0;
  std::vector<StepRecord> steps;  // time steps 0..T

  // SPEC 9 summary: success and length averaged over steps 0..T, adaptation
  // time over 1..T.
  double AverageSuccessRate() const;
  double AveragePathLength() const;
  double AdaptSecondsPerStep() const;
};

struct RunLabels {
  std::string size_label;
  std::string difficulty_label;
};

// Seconds on a monotonic clock; injectable so tests need no real time.
using Clock = std::function<double()>;
Clock SteadyClock();

// Called after each time step (progress display).
using StepCallback = std::function<void(const ApproachRun& run, int total_steps)>;

ApproachRun RunApproach(const Scenario& scenario, Approach approach, const PlannerOptions& options,
                        Trainer* trainer, const RunLabels& labels,
                        const Clock& clock = SteadyClock(), const StepCallback& on_step = {});

// "50" for a 50x50 maze, "40x60" for 40 rows and 60 columns.
std::string SizeLabel(int rows, int cols);

}  // namespace dynapath
