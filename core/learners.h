#pragma once
// What differs by learner kind, each as an exhaustive switch (a new
// LearnerKind fails to compile until every one handles it; the build has
// -Werror=switch). Adding a learner: docs/DECISIONS.md, "Adding an approach
// or a learner".

#include "core/training_job.h"

namespace dynapath {

// Every learner kind (for the wire's round trip tests and listings).
inline constexpr LearnerKind kAllLearnerKinds[] = {LearnerKind::kSingleAgent,
                                                   LearnerKind::kFedAsynQ};

// Trains `job` whole with the learner of `job.kind`, in this thread.
// `job` must pass CheckJob (core/training_job.h).
TrainingResult TrainJob(const TrainingJob& job);

// True for learners that train in synchronised rounds of K learners whose
// shards are averaged (FedAsynQ): their jobs can be split over agents and
// resumed from a round.
bool TrainsInRounds(LearnerKind kind);

}  // namespace dynapath
