#include "dynapath/training_progress.h"

#include <algorithm>

namespace dynapath {

double TrainingProgress::Fraction() const {
  const int64_t rounds = rounds_total, work = work_total, jobs = jobs_total;
  double fraction = 0.0;
  if (rounds > 0) {
    fraction = static_cast<double>(rounds_done) / static_cast<double>(rounds);
  } else if (work > 0) {
    fraction = static_cast<double>(work_done) / static_cast<double>(work);
  } else if (jobs > 0) {
    fraction = static_cast<double>(jobs_done) / static_cast<double>(jobs);
  }
  return std::clamp(fraction, 0.0, 1.0);
}

std::string DescribeTraining(const TrainingProgress& progress) {
  const int64_t jobs = progress.jobs_total, rounds = progress.rounds_total;
  if (rounds > 0) {
    return "training round " + std::to_string(progress.rounds_done.load()) + "/" +
           std::to_string(rounds) + " of " + std::to_string(jobs) + (jobs == 1 ? " job" : " jobs");
  }
  std::string text = "training " + std::to_string(progress.jobs_done.load()) + "/" +
                     std::to_string(jobs) + " jobs";
  const TrainingWork kind = progress.work_kind;
  const int64_t work = progress.work_total;
  if (work > 0 && kind != TrainingWork::kNone) {
    // Rounded down: 100% only once all of it is done.
    const int64_t percent = std::clamp<int64_t>(progress.work_done.load(), 0, work) * 100 / work;
    text += ", " + std::to_string(percent) + "% of " +
            (kind == TrainingWork::kEpisodes ? "episodes" : "rounds");
  }
  return text;
}

}  // namespace dynapath
