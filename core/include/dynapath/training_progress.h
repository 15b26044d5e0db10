#pragma once
// Progress of the training batch in hand, for a watcher on another thread
// (the run's progress lines): jobs done of the batch's, federated rounds
// done of the longest job's (a batch run round by round), and the work done
// inside the jobs (a batch of whole jobs: episodes of single-agent jobs,
// rounds of federated ones). The trainer writes, anyone may read; relaxed
// atomics (a line of progress needs no ordering).

#include <atomic>
#include <cstdint>
#include <string>

namespace dynapath {

// What a whole-job batch counts as its work.
enum class TrainingWork : int { kNone = 0, kEpisodes = 1, kRounds = 2 };

struct TrainingProgress {
  std::atomic<int64_t> batches{0};  // batches started so far (a new batch: a new estimate)
  std::atomic<int64_t> jobs_total{0}, jobs_done{0};
  std::atomic<int64_t> rounds_total{0}, rounds_done{0};  // 0 total: not trained in rounds
  // Work inside whole jobs: the sum of the jobs' budgets (single agent:
  // max_episodes; federated: its rounds) and what of it is done. A learner
  // adds at the interval it checks its stop flag, and adds its unused budget
  // when it ends early, so work_done ends at work_total. 0 total: not counted
  // (jobs only).
  std::atomic<int64_t> work_total{0}, work_done{0};
  std::atomic<TrainingWork> work_kind{TrainingWork::kNone};
  std::atomic<bool> running{false};

  void Start(int64_t jobs, int64_t rounds, int64_t work = 0,
             TrainingWork kind = TrainingWork::kNone) {
    jobs_total = jobs;
    jobs_done = 0;
    rounds_total = rounds;
    rounds_done = 0;
    work_total = work > 0 ? work : 0;
    work_done = 0;
    work_kind = work > 0 ? kind : TrainingWork::kNone;
    batches.fetch_add(1);
    running = true;
  }
  void Finish() { running = false; }
  // Done so far in [0, 1]: rounds where the batch runs in rounds, else the
  // work inside the jobs where counted, else jobs.
  double Fraction() const;
};

// The batch in one line, for the run's log and the study's progress line:
// "training round 40/225 of 4 jobs" (a batch in rounds), "training 0/1 jobs,
// 38% of episodes" (whole jobs, their work counted), "training 3/12 jobs".
std::string DescribeTraining(const TrainingProgress& progress);

}  // namespace dynapath
