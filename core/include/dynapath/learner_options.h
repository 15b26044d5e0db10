#pragma once
// THE description of the learners' numeric options, one line each: the
// options structs (core/include/dynapath/training_job.h), both directions of the wire
// (job_batch_t's fields of the same names, protocol/convert.cc)
// and the validation of received values (protocol/validate.cc) are
// all expanded from these lists. A new option is one line here plus its
// field in lcmtypes/job_batch_t.lcm (a missing field fails to compile).
//
// Columns: member (= wire field), type, default, smallest and largest value
// accepted from the wire. For doubles the range is every finite value:
// NaN and infinities fail the comparison.

#include <limits>

namespace dynapath::learner_option {
inline constexpr int kAnyIntMin = std::numeric_limits<int>::min();
inline constexpr int kAnyIntMax = std::numeric_limits<int>::max();
inline constexpr double kFiniteMin = std::numeric_limits<double>::lowest();
inline constexpr double kFiniteMax = std::numeric_limits<double>::max();
// Learners a federated job may have (each is a table's worth of work).
inline constexpr int kMaxLearners = 4096;

template <class T>
constexpr bool InRange(T value, T min, T max) {
  return value >= min && value <= max;
}
}  // namespace dynapath::learner_option

// clang-format off
#define DYNAPATH_SINGLE_AGENT_OPTIONS(X)                                                                  \
  X(max_episodes,              int,    10000,  1,                                  learner_option::kAnyIntMax)  /* report: at most 10,000 episodes */       \
  X(epsilon_start,             double, 1.0,    learner_option::kFiniteMin,         learner_option::kFiniteMax)  /* epsilon-greedy exploration at episode 0 */ \
  X(epsilon_decay,             double, 0.999,  learner_option::kFiniteMin,         learner_option::kFiniteMax)  /* multiplied in after every episode */    \
  X(epsilon_min,               double, 0.01,   learner_option::kFiniteMin,         learner_option::kFiniteMax)  /* floor */                                \
  X(replay_capacity,           int,    1000,   1,                                  learner_option::kAnyIntMax)  /* FIFO buffer of the last transitions */  \
  X(replay_start_episode,      int,    500,    learner_option::kAnyIntMin,         learner_option::kAnyIntMax)  /* replay from this episode on */          \
  X(replay_batch,              int,    64,     0,                                  learner_option::kAnyIntMax)  /* replayed updates after each real step */ \
  X(convergence_start_episode, int,    500,    learner_option::kAnyIntMin,         learner_option::kAnyIntMax)  /* first convergence check */              \
  X(convergence_interval,      int,    50,     1,                                  learner_option::kAnyIntMax)  /* episodes between checks */              \
  X(convergence_threshold,     double, 5e-4,   learner_option::kFiniteMin,         learner_option::kFiniteMax)  /* largest absolute change */              \
  X(convergence_checks,        int,    21,     1,                                  learner_option::kAnyIntMax)  /* consecutive checks below threshold */

#define DYNAPATH_FEDASYNQ_OPTIONS(X)                                                                      \
  X(learners,                  int,    12,     1,                                  learner_option::kMaxLearners) /* K */                                  \
  X(sync_period,               int,    1000,   1,                                  learner_option::kAnyIntMax)  /* tau: steps per learner per round */     \
  X(iterations_per_cell,       int,    200,    1,                                  learner_option::kAnyIntMax)  /* T = region cells x this */
// clang-format on

// Declares a member with its default (for the options structs).
#define DYNAPATH_DECLARE_LEARNER_OPTION(member, type, default_value, min, max) \
  type member = default_value;
