#pragma once
// Progress of the training batch in hand, for a watcher on another thread
// (the run's progress lines): jobs done of the batch's, and federated rounds
// done of the longest job's. The trainer writes, anyone may read; relaxed
// atomics (a line of progress needs no ordering).

#include <atomic>
#include <cstdint>

namespace dynapath {

struct TrainingProgress {
  std::atomic<int64_t> batches{0};  // batches started so far (a new batch: a new estimate)
  std::atomic<int64_t> jobs_total{0}, jobs_done{0};
  std::atomic<int64_t> rounds_total{0}, rounds_done{0};  // 0 total: not trained in rounds
  std::atomic<bool> running{false};

  void Start(int64_t jobs, int64_t rounds) {
    jobs_total = jobs;
    jobs_done = 0;
    rounds_total = rounds;
    rounds_done = 0;
    batches.fetch_add(1);
    running = true;
  }
  void Finish() { running = false; }
  // Done so far in [0, 1]: rounds where the batch runs in rounds, else jobs.
  double Fraction() const {
    const int64_t rounds = rounds_total, jobs = jobs_total;
    if (rounds > 0) return static_cast<double>(rounds_done) / static_cast<double>(rounds);
    return jobs > 0 ? static_cast<double>(jobs_done) / static_cast<double>(jobs) : 0.0;
  }
};

}  // namespace dynapath
