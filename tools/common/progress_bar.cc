#include "tools/common/progress_bar.h"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/base_sink.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace dynapath::cli {
namespace {

double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

size_t TerminalWidth(std::FILE* out) {
  struct winsize size {};
  if (ioctl(fileno(out), TIOCGWINSZ, &size) == 0 && size.ws_col > 10) return size.ws_col;
  return 100;
}

// Where the current configuration is, 0..1, by approaches and time steps;
// `in_step`: the fraction of the step in progress done (its training).
double ConfigurationFraction(int approach_index, int approach_count, int step, int total_steps,
                             double in_step) {
  if (approach_count <= 0 || approach_index <= 0) return 0.0;
  const double in_approach = (static_cast<double>(std::max(step, -1)) + 1.0 + in_step) /
                             (static_cast<double>(total_steps) + 1.0);
  return std::clamp((approach_index - 1 + in_approach) / approach_count, 0.0, 1.0);
}

std::string Where(const ProgressSnapshot& s) {
  std::string text = std::to_string(s.index) + "/" + std::to_string(s.count) + " " + s.label;
  if (s.approach_index > 0) {
    text += " | " + s.approach + " " + std::to_string(s.approach_index) + "/" +
            std::to_string(s.approach_count) + " step " + std::to_string(s.step) + "/" +
            std::to_string(s.total_steps);
  } else {
    text += " | starting";
  }
  if (!s.training.empty()) text += ", " + s.training;
  return text;
}

// "~56 s left", or "at least 56 s left" while an approach to come has
// never run (`compact`: ">56 s left").
std::string Left(const ProgressSnapshot& s, bool compact) {
  if (!s.remaining) return "time left unknown";
  const std::string time = FormatDuration(*s.remaining);
  if (!s.remaining_at_least) return "~" + time + " left";
  return (compact ? ">" : "at least ") + time + " left";
}

std::string Times(const ProgressSnapshot& s) {
  return FormatDuration(s.elapsed) + " elapsed, " + Left(s, false);
}

}  // namespace

void TimeEstimator::AddFinished(double work, double seconds) {
  if (work <= 0 || seconds < 0) return;
  work_ += work;
  seconds_ += seconds;
}

void TimeEstimator::AddApproachFinished(int approach, double work, double seconds) {
  if (approach < 0 || work <= 0 || seconds < 0) return;
  if (static_cast<size_t>(approach) >= rates_.size()) rates_.resize(approach + 1);
  Rate& rate = rates_[static_cast<size_t>(approach)];
  if (work > rate.work * (1 + 1e-9)) rate = Rate{work, 0.0, 0};
  if (work < rate.work * (1 - 1e-9)) return;  // a smaller one: the larger's rate stays
  rate.seconds += seconds;
  ++rate.runs;
}

std::optional<double> TimeEstimator::ApproachCost(int approach, double work) const {
  if (approach < 0 || static_cast<size_t>(approach) >= rates_.size()) return std::nullopt;
  const Rate& rate = rates_[static_cast<size_t>(approach)];
  if (rate.runs == 0) return std::nullopt;
  return rate.seconds / rate.runs / rate.work * work;
}

std::optional<TimeLeft> TimeEstimator::Remaining(const ConfigurationProgress& c,
                                                 double remaining_work) const {
  // The current approach by its own time steps: reliable once it is a few
  // per cent through and a second old.
  auto by_steps = [](double elapsed, double fraction) -> std::optional<double> {
    if (fraction < 0.02 || elapsed < 1.0) return std::nullopt;
    return elapsed * (1 - fraction) / fraction;
  };
  const int count = std::max(c.approach_count, static_cast<int>(rates_.size()));
  bool every_rate = count > 0;
  for (int a = 0; a < count; ++a) every_rate = every_rate && ApproachCost(a, 1.0).has_value();
  if (!every_rate && work_ > 0 && seconds_ > 0) {
    // Whole configurations of earlier sessions, scaled by work.
    const double rate = seconds_ / work_;
    double current_left = rate * c.work - c.elapsed;
    if (current_left < 0) current_left = by_steps(c.elapsed, c.fraction).value_or(0.0);
    return TimeLeft{current_left + rate * remaining_work, false};
  }
  TimeLeft left;
  bool anything = false;
  auto add = [&](std::optional<double> seconds) {
    if (seconds) {
      left.seconds += std::max(0.0, *seconds);
      anything = true;
    } else {
      left.at_least = true;
    }
  };
  if (c.approach >= 0) {
    // The current approach: its measured cost less the time it has run;
    // past that (a slower run than before), its own steps.
    std::optional<double> rest;
    if (const std::optional<double> cost = ApproachCost(c.approach, c.work)) {
      rest = *cost - c.approach_elapsed;
      if (*rest < 0) rest = by_steps(c.approach_elapsed, c.approach_fraction).value_or(0.0);
    } else {
      rest = by_steps(c.approach_elapsed, c.approach_fraction);
    }
    add(rest);
  }
  // Before its first step the configuration's approaches are the study's.
  const int in_this = c.approach_count > 0 ? c.approach_count : count;
  for (int a = std::max(c.approach + 1, 0); a < in_this; ++a) add(ApproachCost(a, c.work));
  if (remaining_work > 0) {
    for (int a = 0; a < count; ++a) add(ApproachCost(a, remaining_work));
  }
  if (!anything) return std::nullopt;
  return left;
}

std::string BarLine(const ProgressSnapshot& s, size_t width) {
  constexpr int kBar = 12;
  const double done = std::clamp(s.done_fraction, 0.0, 1.0);
  const int filled = static_cast<int>(std::floor(done * kBar));
  char percent[8];
  std::snprintf(percent, sizeof percent, "%3d%%", static_cast<int>(std::floor(done * 100)));
  const std::string bar = std::string("[") + std::string(static_cast<size_t>(filled), '#') +
                          std::string(static_cast<size_t>(kBar - filled), '.') + "] " + percent +
                          " ";
  const std::string full = bar + Where(s) + " | " + Times(s);
  if (full.size() <= width) return full;
  // Narrow terminals: a compact line, without the bar if need be, then cut.
  std::string compact = std::to_string(s.index) + "/" + std::to_string(s.count) + " " +
                        (s.short_label.empty() ? s.label : s.short_label);
  if (s.approach_index > 0) {
    compact += " " + s.approach + " " + std::to_string(s.approach_index) + "/" +
               std::to_string(s.approach_count) + " t" + std::to_string(s.step) + "/" +
               std::to_string(s.total_steps);
  }
  compact += " ";
  compact += FormatDuration(s.elapsed);
  if (s.remaining) compact += " " + Left(s, true);
  if (bar.size() + compact.size() <= width) return bar + compact;
  if (compact.size() <= width) return compact;
  return compact.substr(0, width > 3 ? width - 3 : width) + "...";
}

std::string PlainLine(const ProgressSnapshot& s) {
  return std::string("[") + FormatDuration(s.elapsed) + "] configuration " + Where(s) + "; " +
         Left(s, false);
}

ProgressDisplay::ProgressDisplay(std::FILE* out, bool terminal)
    : out_(out), terminal_(terminal), start_(Now()) {}

ProgressDisplay::~ProgressDisplay() { Stop(); }

void ProgressDisplay::Start(const std::vector<double>& work, const std::vector<bool>& done) {
  std::lock_guard lock(mutex_);
  work_ = work;
  finished_ = done;
  finished_.resize(work_.size(), false);
  start_ = Now();
  if (!thread_.joinable()) thread_ = std::thread([this] { Loop(); });
}

void ProgressDisplay::AddHistory(double work, double seconds) {
  std::lock_guard lock(mutex_);
  estimator_.AddFinished(work, seconds);
}

void ProgressDisplay::BeginConfiguration(int index, const std::string& label,
                                         const std::string& short_label) {
  std::lock_guard lock(mutex_);
  current_ = index;
  label_ = label;
  short_label_ = short_label;
  current_start_ = approach_start_ = last_step_time_ = Now();
  approach_.clear();
  approach_index_ = approach_count_ = total_steps_ = 0;
  step_ = -1;
  if (terminal_) DrawLocked();
}

void ProgressDisplay::Step(const std::string& approach, int approach_index, int approach_count,
                           int step, int total_steps) {
  std::lock_guard lock(mutex_);
  if (current_ < 0) return;
  const double now = Now();
  if (approach_index + 1 != approach_index_) {
    // A new approach: the previous one ended with its last step, and this
    // one began then.
    if (approach_index_ > 0) {
      estimator_.AddApproachFinished(approach_index_ - 1, work_[static_cast<size_t>(current_)],
                                     last_step_time_ - approach_start_);
    }
    approach_start_ = last_step_time_;
  }
  last_step_time_ = now;
  approach_ = approach;
  approach_index_ = approach_index + 1;
  approach_count_ = approach_count;
  step_ = step;
  total_steps_ = total_steps;
  if (!terminal_ && (plain_config_ != current_ || plain_approach_ != approach_index_)) {
    wake_.notify_one();  // a line for the new approach
  }
}

void ProgressDisplay::StepOf(int index, const std::string& approach, int approach_index,
                             int approach_count, int step, int total_steps) {
  {
    std::lock_guard lock(mutex_);
    if (current_ != index) return;
  }
  Step(approach, approach_index, approach_count, step, total_steps);
}

void ProgressDisplay::WatchTraining(int index, const TrainingProgress* progress) {
  std::lock_guard lock(mutex_);
  if (progress == nullptr && index != training_index_) return;  // another one is watched
  training_ = progress;
  training_index_ = progress != nullptr ? index : -1;
}

void ProgressDisplay::EndConfiguration(int index, double seconds, bool completed) {
  std::lock_guard lock(mutex_);
  if (index >= 0 && static_cast<size_t>(index) < work_.size()) {
    if (completed) {
      estimator_.AddFinished(work_[static_cast<size_t>(index)], seconds);
      finished_[static_cast<size_t>(index)] = true;
      if (current_ == index && approach_index_ > 0) {  // its last approach
        estimator_.AddApproachFinished(approach_index_ - 1, work_[static_cast<size_t>(index)],
                                       Now() - approach_start_);
      }
    }
  }
  if (current_ != index) return;  // another one (run at once) is shown
  current_ = -1;
  if (terminal_) ClearLocked();
}

void ProgressDisplay::Print(const std::string& line) {
  std::lock_guard lock(mutex_);
  if (terminal_) ClearLocked();
  std::fputs(line.c_str(), out_);
  if (line.empty() || line.back() != '\n') std::fputc('\n', out_);
  if (terminal_ && current_ >= 0) DrawLocked();
  std::fflush(out_);
}

void ProgressDisplay::Stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    if (terminal_) ClearLocked();
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

ProgressSnapshot ProgressDisplay::Snapshot() const {
  ProgressSnapshot s;
  const double now = Now();
  s.index = current_ + 1;
  s.count = static_cast<int>(work_.size());
  s.label = label_;
  s.short_label = short_label_;
  s.approach = approach_;
  s.approach_index = approach_index_;
  s.approach_count = approach_count_;
  s.step = step_;
  s.total_steps = total_steps_;
  s.elapsed = now - start_;
  double total = 0, done = 0, after = 0, current = 0;
  for (size_t i = 0; i < work_.size(); ++i) {
    total += work_[i];
    if (finished_[i]) {
      done += work_[i];
    } else if (static_cast<int>(i) == current_) {
      current = work_[i];
    } else {
      after += work_[i];
    }
  }
  double in_step = 0.0;
  if (training_ != nullptr && training_index_ == current_ && training_->running) {
    in_step = std::clamp(training_->Fraction(), 0.0, 1.0);
    s.training = DescribeTraining(*training_);
  }
  ConfigurationProgress progress;
  progress.work = current;
  progress.elapsed = now - current_start_;
  progress.fraction =
      ConfigurationFraction(approach_index_, approach_count_, step_, total_steps_, in_step);
  progress.approach = approach_index_ - 1;
  progress.approach_count = approach_count_;
  progress.approach_elapsed = now - approach_start_;
  progress.approach_fraction = ConfigurationFraction(1, 1, step_, total_steps_, in_step);
  if (approach_index_ <= 0) progress.approach_elapsed = progress.approach_fraction = 0.0;
  s.done_fraction = total > 0 ? (done + current * progress.fraction) / total : 0.0;
  if (const std::optional<TimeLeft> left = estimator_.Remaining(progress, after)) {
    s.remaining = left->seconds;
    s.remaining_at_least = left->at_least;
  }
  return s;
}

void ProgressDisplay::ClearLocked() {
  if (!bar_shown_) return;
  std::fputs("\r\033[K", out_);
  std::fflush(out_);
  bar_shown_ = false;
}

void ProgressDisplay::DrawLocked() {
  if (current_ < 0) return;
  const std::string line = BarLine(Snapshot(), TerminalWidth(out_) - 1);
  std::fputs(("\r\033[K" + line).c_str(), out_);
  std::fflush(out_);
  bar_shown_ = true;
}

void ProgressDisplay::Loop() {
  constexpr double kPlainInterval = 10.0;
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, std::chrono::milliseconds(terminal_ ? 250 : 500));
    if (stopping_ || current_ < 0) continue;
    if (terminal_) {
      DrawLocked();
      continue;
    }
    const double now = Now();
    const bool new_approach =
        approach_index_ > 0 && (plain_config_ != current_ || plain_approach_ != approach_index_);
    if (new_approach || now - plain_last_ >= kPlainInterval) {
      std::fputs((PlainLine(Snapshot()) + "\n").c_str(), out_);
      std::fflush(out_);
      plain_config_ = current_;
      plain_approach_ = approach_index_;
      plain_last_ = now;
    }
  }
}

namespace {

class DisplaySink : public spdlog::sinks::base_sink<std::mutex> {
 public:
  explicit DisplaySink(ProgressDisplay& display) : display_(display) {}

 protected:
  void sink_it_(const spdlog::details::log_msg& message) override {
    spdlog::memory_buf_t formatted;
    formatter_->format(message, formatted);
    display_.Print(std::string(formatted.data(), formatted.size()));
  }
  void flush_() override {}

 private:
  ProgressDisplay& display_;
};

}  // namespace

std::shared_ptr<spdlog::sinks::sink> MakeDisplaySink(ProgressDisplay& display) {
  return std::make_shared<DisplaySink>(display);
}

}  // namespace dynapath::cli
