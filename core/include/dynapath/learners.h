#pragma once
// What differs by learner kind, each as an exhaustive switch (a new
// LearnerKind fails to compile until every one handles it; the build has
// -Werror=switch). Adding a learner: CONTRIBUTING.md, "Adding a
// learner".

#include "dynapath/stop_token.h"
#include "dynapath/training_job.h"

namespace dynapath {

// Every learner kind (for the wire's round trip tests and listings).
#define DYNAPATH_LEARNER_KIND_VALUE(kind) LearnerKind::kind,
inline constexpr LearnerKind kAllLearnerKinds[] = {
    DYNAPATH_LEARNER_KINDS(DYNAPATH_LEARNER_KIND_VALUE)};
#undef DYNAPATH_LEARNER_KIND_VALUE

// Trains `job` whole with the learner of `job.kind`, in this thread.
// `job` must pass CheckJob (core/include/dynapath/training_job.h).
// Once `stop` is requested the learner ends early (every round, every 64
// episodes) and its result is partial: the caller must discard it.
TrainingResult TrainJob(const TrainingJob& job, StopToken stop = nullptr);

// True for learners that train in synchronised rounds of K learners whose
// shards are averaged (FedAsynQ): their jobs can be split over agents and
// resumed from a round.
bool TrainsInRounds(LearnerKind kind);

}  // namespace dynapath
