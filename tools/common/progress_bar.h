#pragma once
// Progress of a study on stderr: on a terminal, one line redrawn in place
// (configuration k/n, maze, approach, time step, elapsed time and an estimate
// of the time left); otherwise plain lines, one when a configuration reaches
// a new approach and one every 10 s. Log lines and messages are printed
// above the bar, so the two never mix.

#include <spdlog/sinks/sink.h>

#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "dynapath/text_util.h"
#include "dynapath/training_progress.h"

namespace dynapath::cli {

// Where the configuration in hand is, for TimeEstimator.
struct ConfigurationProgress {
  double work = 0.0;      // cells x steps
  double elapsed = 0.0;   // s since it began
  double fraction = 0.0;  // 0..1 done, by approaches and time steps
  int approach = -1;      // 0-based index of the approach running; -1: none yet
  int approach_count = 0;
  double approach_elapsed = 0.0;   // s since that approach began
  double approach_fraction = 0.0;  // 0..1 of its time steps done
};

// An estimate of the time left; `at_least` when some approach still to run
// has never run (its cost is unknown, so counted as nothing).
struct TimeLeft {
  double seconds = 0.0;
  bool at_least = false;
};

// The time left in a study. Each approach's cost is measured on its own,
// as seconds per unit of work (cells x steps), from the largest
// configuration it has finished (an A* Oracle costs more per cell on a
// larger maze, so a smaller one's rate underestimates it); the time left is
// the current approach's rest, then every approach still to run in this
// configuration, then every approach of the configurations after it. Before
// every approach has run once, whole configurations of earlier sessions
// (AddFinished) stand in; without those either, the approaches that have
// run give a lower bound ("at least").
class TimeEstimator {
 public:
  // A whole configuration of `work` that took `seconds`.
  void AddFinished(double work, double seconds);
  // Approach `approach` (0-based) of a configuration of `work` took `seconds`.
  void AddApproachFinished(int approach, double work, double seconds);
  // `remaining_work`: the work of the configurations after the current one.
  // None when there is nothing to go on yet.
  std::optional<TimeLeft> Remaining(const ConfigurationProgress& current,
                                    double remaining_work) const;

 private:
  struct Rate {
    double work = 0.0;  // of the largest configuration it finished
    double seconds = 0.0;
    int runs = 0;  // finished at that work (their mean)
  };
  std::optional<double> ApproachCost(int approach, double work) const;

  double work_ = 0.0;
  double seconds_ = 0.0;
  std::vector<Rate> rates_;
};

struct ProgressSnapshot {
  int index = 0;  // 1-based configuration number
  int count = 0;
  std::string label;        // "50 Hard, seed 52"
  std::string short_label;  // "50 Hard s52", for narrow terminals
  std::string approach;
  int approach_index = 0;  // 1-based; 0: no time step reported yet
  int approach_count = 0;
  int step = -1;  // time step reached, -1: none yet
  int total_steps = 0;
  std::string training;        // the training batch in hand ("training 3/12 jobs"), or empty
  double elapsed = 0.0;        // the whole session
  double done_fraction = 0.0;  // of the study's work
  std::optional<double> remaining;
  bool remaining_at_least = false;  // a lower bound: some approach has not run yet
};

// The terminal line, at most `width` characters.
std::string BarLine(const ProgressSnapshot& snapshot, size_t width);
// The plain line.
std::string PlainLine(const ProgressSnapshot& snapshot);

class ProgressDisplay {
 public:
  // `terminal`: draw the bar (else plain lines).
  ProgressDisplay(std::FILE* out, bool terminal);
  ~ProgressDisplay();
  ProgressDisplay(const ProgressDisplay&) = delete;
  ProgressDisplay& operator=(const ProgressDisplay&) = delete;

  // The work of every configuration of the study; `done[i]` for those
  // finished before this session. Starts the redraw thread.
  void Start(const std::vector<double>& work, const std::vector<bool>& done);
  // A finished configuration of an earlier session with a known wall time
  // (for the estimate).
  void AddHistory(double work, double seconds);
  // 0-based index; `short_label` is used on narrow terminals.
  void BeginConfiguration(int index, const std::string& label, const std::string& short_label);
  // A time step of the current configuration (0-based approach index); any thread.
  void Step(const std::string& approach, int approach_index, int approach_count, int step,
            int total_steps);
  // The same from configuration `index` only when it is the one shown
  // (configurations run at once: the last one begun is shown).
  void StepOf(int index, const std::string& approach, int approach_index, int approach_count,
              int step, int total_steps);
  // The training batch counter of configuration `index` (null: none any
  // more), shown while a batch lasts: a large map's step takes minutes.
  // `progress` must outlive the watch (watch null before it goes).
  void WatchTraining(int index, const TrainingProgress* progress);
  // `completed`: ran to its end (its time counts for the estimate).
  void EndConfiguration(int index, double seconds, bool completed);
  // A permanent line (above the bar); any thread.
  void Print(const std::string& line);
  // Stops the thread and clears the bar.
  void Stop();

 private:
  ProgressSnapshot Snapshot() const;  // with mutex_ held
  void Loop();
  void ClearLocked();
  void DrawLocked();

  std::FILE* out_;
  const bool terminal_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;

  double start_ = 0.0;
  std::vector<double> work_;
  std::vector<bool> finished_;
  TimeEstimator estimator_;
  int current_ = -1;
  std::string label_, short_label_;
  double current_start_ = 0.0;
  // The approach in hand: when it began (the previous one's last step) and
  // when its last step was reported.
  double approach_start_ = 0.0, last_step_time_ = 0.0;
  std::string approach_;
  int approach_index_ = 0, approach_count_ = 0, step_ = -1, total_steps_ = 0;
  const TrainingProgress* training_ = nullptr;
  int training_index_ = -1;
  bool bar_shown_ = false;
  // Plain mode: what the last line showed and when.
  int plain_config_ = -1, plain_approach_ = -1;
  double plain_last_ = 0.0;
};

// A spdlog sink printing through `display` (above its bar).
std::shared_ptr<spdlog::sinks::sink> MakeDisplaySink(ProgressDisplay& display);

}  // namespace dynapath::cli
