#pragma once
// THE description of the learners' numeric options, one line each: the
// options structs (core/include/dynapath/training_job.h), both directions of the wire
// (job_batch_t's fields of the same names, protocol/convert.cc), the
// validation of received values (protocol/validate.cc) and the parameters of
// the command line, config and study files, `dynapath params`, params.toml
// and the study manifest (core/include/dynapath/parameters.h) are all
// expanded from these lists. A new option is one line here plus its field in
// lcmtypes/job_batch_t.lcm (a missing field fails to compile).
//
// Columns: member (= wire field; the option's name with '_' as '-'), type,
// default, the report's value (what `--semantics report` presets), smallest
// and largest value accepted (from the command line, files and the wire), and
// a line of help. The ranges also bound the work and memory one job may ask
// for (an agent takes them from the wire).

namespace dynapath::learner_option {
// Learners a federated job may have (each is a table's worth of work).
inline constexpr int kMaxLearners = 4096;

template <class T>
constexpr bool InRange(T value, T min, T max) {
  return value >= min && value <= max;
}
}  // namespace dynapath::learner_option

// clang-format off
#define DYNAPATH_SINGLE_AGENT_OPTIONS(X)                                                                  \
  X(max_episodes,              int,    10000, 10000, 1,    10000000, "episodes per training at most")                          \
  X(epsilon_start,             double, 1.0,   1.0,   0.0,  1.0,      "epsilon-greedy exploration rate at the first episode")           \
  X(epsilon_decay,             double, 0.999, 0.999, 0.0,  1.0,      "epsilon is multiplied by this after every episode")              \
  X(epsilon_min,               double, 0.01,  0.01,  0.0,  1.0,      "epsilon's floor")                                                \
  X(replay_capacity,           int,    1000,  1000,  1,    10000000, "replay buffer: the last N transitions")                         \
  X(replay_start_episode,      int,    500,   501,   0,    10000000, "replay from this 0-based episode on")                           \
  X(replay_batch,              int,    64,    64,    0,    10000,    "replayed updates after each real step (K)")                     \
  X(convergence_start_episode, int,    500,   501,   0,    10000000, "first convergence check, before this 0-based episode")        \
  X(convergence_interval,      int,    50,    50,    1,    10000000, "episodes between convergence checks")                           \
  X(convergence_threshold,     double, 5e-4,  5e-4,  0.0,  1e300,    "converged: largest absolute change of the table below this")   \
  X(convergence_checks,        int,    21,    21,    1,    10000000, "converged after this many checks in a row below it")

#define DYNAPATH_FEDASYNQ_OPTIONS(X)                                                                      \
  X(learners,                  int,    12,    12,    1,    learner_option::kMaxLearners, "learners per trained node (K)")     \
  X(sync_period,               int,    1000,  1000,  1,    1000000,  "tau: steps per learner per round, then the tables are averaged") \
  X(iterations_per_cell,       int,    200,   200,   1,    1000000,  "T = region cells x this; rounds = max(1, T / tau)")
// clang-format on

// Declares a member with its default (for the options structs).
#define DYNAPATH_DECLARE_LEARNER_OPTION(member, type, default_value, ...) \
  type member = default_value;

// THE list of the tree strategy's thresholds (SPEC 5), in the same columns:
// the planner's options carry them (RetrainingThresholds, below), the
// strategy (core/plan/retraining_strategy.h) applies them, and the
// parameters (dynapath/parameters.h) are expanded from the list. The
// coordinator applies them; they never travel.
// clang-format off
#define DYNAPATH_RETRAINING_THRESHOLDS(X)                                                                \
  X(max_drop,         double, 0.01, 0.01, 0.0, 1.0, "retrain a changed node whose success rate fell by more than this")  \
  X(min_success_rate, double, 0.9,  0.9,  0.0, 1.0, "retrain a changed node whose success rate is below this")         \
  X(escalate_below,   double, 0.9,  0.9,  0.0, 1.0, "escalation: a trained node still below this makes its parent a candidate (0: never)")
// clang-format on

namespace dynapath {
struct RetrainingThresholds {
  DYNAPATH_RETRAINING_THRESHOLDS(DYNAPATH_DECLARE_LEARNER_OPTION)
};
}  // namespace dynapath
