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

#include "dynapath/training_progress.h"

namespace dynapath::cli {

// The time left in a study, from the wall times of finished configurations
// scaled by their work (cells x steps), or, before any has finished, from
// the fraction of the current one done.
class TimeEstimator {
 public:
  void AddFinished(double work, double seconds);
  // `current_work` has run `elapsed` s and is `fraction` (0..1) done;
  // `remaining_work` is the work of the configurations after it. None when
  // there is nothing to go on yet.
  std::optional<double> Remaining(double current_work, double elapsed, double fraction,
                                  double remaining_work) const;

 private:
  double work_ = 0.0;
  double seconds_ = 0.0;
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
  std::string training;  // the training batch in hand ("training 3/12 jobs"), or empty
  double elapsed = 0.0;        // the whole session
  double done_fraction = 0.0;  // of the study's work
  std::optional<double> remaining;
};

// "42 s", "12:03", "1:02:03".
std::string FormatDuration(double seconds);
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
