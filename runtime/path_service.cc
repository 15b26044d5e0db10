#include "runtime/path_service.h"

#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <optional>

#include "dynapath/local_trainer.h"
#include "dynapath/thread_pool.h"
#include "runtime/scenario_options.h"

namespace dynapath::runtime {

// Time steps from live updates, one per batch; ends (kCancelled) when the
// service stops. A loaded policy's first steps come from the change
// sequence it was saved on (the stepper catches up with them).
class PathService::LiveSource : public StepSource {
 public:
  LiveSource(PathService& service, int catch_up_steps)
      : service_(service), catch_up_steps_(catch_up_steps) {}
  // A run needs a last step; a service runs until stopped, and a
  // million steps of updates is far beyond any session.
  int total_steps() const override { return static_cast<int>(kMaxSteps); }
  Grid Initial(int /*pass*/) override { return service_.maze_; }
  ChangeStep Changes(int /*pass*/, int t) override {
    ChangeStep step;
    if (t <= catch_up_steps_) {
      step = service_.config_.catch_up.steps[static_cast<size_t>(t - 1)];
    } else {
      std::unique_lock lock(service_.updates_mutex_);
      service_.updates_ready_.wait(
          lock, [&] { return service_.stop_.load() || service_.updates_.pending(); });
      if (service_.stop_.load()) return {};
      step = service_.updates_.Take();
    }
    return step;
  }
  Status status() const override {
    if (service_.stop_.load()) return Error::Cancelled();
    return Ok{};
  }

 private:
  PathService& service_;
  int catch_up_steps_;
};

namespace {

// The step a loaded policy continues from on this maze (ApproachStepper's own
// test), 0 when it starts at step 0 (or adapts to another maze).
int CatchUpSteps(const ServiceConfig& config, const Grid& maze) {
  const PolicyState* loaded = config.load;
  if (loaded == nullptr || loaded->initial_fingerprint != MazeFingerprint(maze) ||
      loaded->run_seed != config.options.run_seed) {
    return 0;
  }
  return loaded->step;
}

Grid GridAfter(Grid grid, const ChangeSequence& changes, int steps) {
  for (int t = 0; t < steps && t < static_cast<int>(changes.steps.size()); ++t) {
    ApplyChanges(changes.steps[static_cast<size_t>(t)], grid);
  }
  return grid;
}

}  // namespace

Status PathService::CheckLoad(const Grid& maze, const ServiceConfig& config) {
  const int catch_up = CatchUpSteps(config, maze);
  if (catch_up == 0) return Ok{};
  const int have = static_cast<int>(config.catch_up.steps.size());
  if (catch_up > have) {
    return Error("the policy was saved at time step " + std::to_string(catch_up) +
                 " of its run; the service needs that run's change sequence (--changes, or "
                 "--steps " +
                 std::to_string(catch_up) + " or more) to catch up with it, and has " +
                 std::to_string(have) + " steps");
  }
  if (MazeFingerprint(GridAfter(maze, config.catch_up, catch_up)) != config.load->fingerprint) {
    return Error("the maze at step " + std::to_string(catch_up) +
                 " differs from the one the policy was saved on (another change sequence?)");
  }
  return Ok{};
}

PathService::PathService(Grid maze, ServiceConfig config, CommitHook on_commit)
    : maze_(std::move(maze)),
      maze_fingerprint_(MazeFingerprint(maze_)),
      config_(std::move(config)),
      on_commit_(std::move(on_commit)),
      updates_(GridAfter(maze_, config_.catch_up, CatchUpSteps(config_, maze_))) {}

PathService::~PathService() { (void)Stop(); }

void PathService::Start() {
  if (thread_.joinable()) return;
  thread_ = std::thread([this] { Train(); });
}

Result<ApproachRun> PathService::Stop() {
  stop_ = true;
  {
    std::lock_guard lock(updates_mutex_);  // no lost wake-up
  }
  updates_ready_.notify_all();
  if (thread_.joinable()) thread_.join();
  return result_;
}

void PathService::Train() {
  const int catch_up = CatchUpSteps(config_, maze_);
  if (Status loadable = CheckLoad(maze_, config_); !loadable) {
    result_ = loadable.error();
    spdlog::error("serve: {}", result_.error().message);
    training_ended_ = true;
    return;
  }
  // Training at a lower priority than the dispatch thread that answers
  // queries: on a machine with fewer cores than busy threads, the kernel
  // then runs an arriving request first instead of after a time slice of
  // training. Threads inherit it, so the pool's workers made below have it
  // too. Lowering one's own priority needs no privilege; failing changes
  // only latency.
  if (config_.training_nice > 0 && setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)),
                                               config_.training_nice) != 0) {
    spdlog::debug("serve: could not lower the training threads' priority");
  }
  try {
    std::optional<ThreadPool> pool;
    std::optional<LocalTrainer> local;
    Trainer* trainer = config_.trainer;
    if (trainer == nullptr) {
      pool.emplace(std::max(1, config_.threads));
      trainer = &local.emplace(*pool, &stop_);
    }
    PlannerOptions options = config_.options;
    options.stop = &stop_;
    std::unique_ptr<Planner> planner = MakePlanner(config_.approach, options, trainer);
    ApproachRun begun;
    begun.approach = config_.approach;
    begun.size_label = config_.labels.size_label;
    begun.difficulty_label = config_.labels.difficulty_label;
    LiveSource source(*this, catch_up);
    PolicyHooks hooks;
    hooks.load = config_.load;
    ApproachStepper stepper(source, 0, *planner, std::move(begun), options, trainer, hooks);
    Result<ApproachRun> run = ApproachRun{};
    if (Status started = stepper.Begin(); !started) {
      run = started.error();
    } else {
      // The first policy: step 0's, or the loaded one taken over at its
      // saved step (no step record yet).
      if (!stepper.failed()) CommitStep(stepper);
      while (!stepper.failed() && stepper.NextStep()) {
        // The interim version: the step's grid under the previous policy
        // (the exact distances already repaired), so that replies reflect
        // the changes while the training runs.
        if (stepper.retrains()) CommitSnapshot(stepper, nullptr);
        if (!stepper.Retrain()) break;
        CommitStep(stepper);
      }
      run = stepper.Take();
    }
    if (run && !trainer->status() && !trainer->status().error().IsCancelled()) {
      result_ = trainer->status().error();
    } else {
      result_ = std::move(run);
    }
  } catch (const std::exception& e) {  // a broken invariant
    result_ = Error::Internal(e.what());
  }
  if (!result_) spdlog::error("serve: training stopped: {}", result_.error().message);
  training_ended_ = true;
}

void PathService::CommitStep(ApproachStepper& stepper) {
  const StepView view = stepper.view();
  CommitSnapshot(stepper, &view);
}

void PathService::CommitSnapshot(ApproachStepper& stepper, const StepView* view) {
  Planner& planner = stepper.planner();
  const Grid& grid = stepper.grid();
  const int time_step = stepper.time_step();
  const bool want_exact = config_.answer != AnswerMode::kLearned;
  const Planner* exact = nullptr;
  if (want_exact && planner.ExactDistances() == nullptr) {
    // The exact distances beside a learner: Incremental Oracle repairs them
    // from the step's changed cells only, once per step (an interim commit
    // has done it before the step's own).
    if (exact_ == nullptr) {
      exact_ = MakePlanner(Approach::kIncrementalOracle, config_.options, nullptr);
      exact_->Initialize(grid);
    } else if (exact_step_ != time_step) {
      exact_->Adapt(grid, stepper.changed_cells());
    }
    exact_step_ = time_step;
    exact = exact_.get();
  }
  int64_t version;
  {
    std::lock_guard lock(stats_mutex_);
    version = ++stats_.commits;
    stats_.version = version;
    stats_.time_step = time_step;
    if (view == nullptr) {
      ++stats_.interim_commits;
    } else if (view->details.nodes_trained > 0) {
      ++stats_.retrainings;
      stats_.nodes_trained += view->details.nodes_trained;
    }
  }
  auto snapshot = std::make_shared<const RouteSnapshot>(
      MakeRouteSnapshot(planner, grid, exact, version, time_step));
  if (config_.on_snapshot) config_.on_snapshot(snapshot);
  {
    std::lock_guard lock(snapshot_mutex_);
    snapshot_ = snapshot;
    if (view != nullptr) committed_step_ = time_step;
  }
  committed_.notify_all();
  if (view != nullptr && on_commit_) on_commit_(Commit{*view, snapshot});
}

std::optional<UpdateRefusal> PathService::Submit(const MapUpdate& update) {
  std::optional<UpdateRefusal> refused;
  {
    std::lock_guard lock(updates_mutex_);
    refused = updates_.Submit(update);
    if (refused || !updates_.pending()) return refused;
  }
  updates_ready_.notify_one();
  return refused;
}

void PathService::Refuse(UpdateRefusal why) {
  std::lock_guard lock(updates_mutex_);
  updates_.Refuse(why);
}

std::shared_ptr<const RouteSnapshot> PathService::Current() const {
  std::lock_guard lock(snapshot_mutex_);
  return snapshot_;
}

bool PathService::WaitForVersion(int64_t version, double seconds) const {
  std::unique_lock lock(snapshot_mutex_);
  return committed_.wait_for(lock, std::chrono::duration<double>(seconds),
                             [&] { return snapshot_ != nullptr && snapshot_->version >= version; });
}

bool PathService::WaitForStep(int time_step, double seconds) const {
  std::unique_lock lock(snapshot_mutex_);
  return committed_.wait_for(lock, std::chrono::duration<double>(seconds),
                             [&] { return committed_step_ >= time_step; });
}

Answer PathService::Ask(const std::vector<QueryStart>& starts, size_t announced) {
  Answer answer;
  answer.snapshot = Current();
  if (answer.snapshot == nullptr) {
    answer.refused = Answer::kNotReady;
  } else if (std::max(announced, starts.size()) >
             static_cast<size_t>(std::max(0, config_.max_starts))) {
    answer.refused = Answer::kTooManyStarts;
  } else {
    size_t budget = config_.reply_budget;
    answer.routes.reserve(starts.size());
    for (const QueryStart& start : starts) {
      answer.routes.push_back(
          AnswerRoute(*answer.snapshot, start.first, start.second, config_.answer, budget));
      budget -= std::min(budget, answer.routes.back().cells.size());
    }
  }
  std::lock_guard lock(stats_mutex_);
  ++stats_.requests;
  if (announced == 0) ++stats_.probes;
  if (answer.refused == Answer::kNotReady) ++stats_.refused_not_ready;
  if (answer.refused == Answer::kTooManyStarts) ++stats_.refused_too_many_starts;
  for (const Route& route : answer.routes) {
    ++stats_.starts;
    ++stats_.by_status[static_cast<size_t>(route.status)];
    if (route.status == RouteStatus::kReached) {
      if (route.answered_by == AnsweredBy::kLearned) ++stats_.by_learned;
      if (route.answered_by == AnsweredBy::kExact) ++stats_.by_exact;
    }
  }
  return answer;
}

void PathService::RecordLatency(int64_t micros) {
  std::lock_guard lock(stats_mutex_);
  stats_.latency.Add(micros);
}

ServiceStats PathService::stats() const {
  ServiceStats stats;
  {
    std::lock_guard lock(stats_mutex_);
    stats = stats_;
  }
  std::lock_guard lock(updates_mutex_);
  stats.updates = updates_.counts();
  return stats;
}

std::string PathService::Summary(const ServiceStats& s) {
  std::string text = "served: " + std::to_string(s.requests) + " queries (" +
                     std::to_string(s.probes) + " of them probes without starts; " +
                     std::to_string(s.starts) + " starts: ";
  for (size_t i = 0; i < s.by_status.size(); ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(s.by_status[i]) + " " + RouteStatusName(static_cast<RouteStatus>(i));
  }
  text += "; reached by learned " + std::to_string(s.by_learned) + ", by exact " +
          std::to_string(s.by_exact) + "), refused " + std::to_string(s.refused_too_many_starts) +
          " too many starts, " + std::to_string(s.refused_not_ready) + " not ready\n";
  text += "updates: " + std::to_string(s.updates.received) + " received, " +
          std::to_string(s.updates.accepted) + " accepted (" +
          std::to_string(s.updates.cells_changed) + " cells changed, " +
          std::to_string(s.updates.cells_unchanged) + " unchanged), " +
          std::to_string(s.updates.refused_total()) + " dropped (";
  for (size_t i = 0; i < kUpdateRefusalCount; ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(s.updates.refused[i]) + " " +
            UpdateRefusalName(static_cast<UpdateRefusal>(i));
  }
  text += ")\n";
  text += "policy: version " + std::to_string(s.version) + ", time step " +
          std::to_string(s.time_step) + ", " + std::to_string(s.updates.steps) +
          " steps of updates, " + std::to_string(s.retrainings) + " retrainings (" +
          std::to_string(s.nodes_trained) + " nodes trained, " + std::to_string(s.interim_commits) +
          " interim commits before them)\n";
  text += LatencyLine("query", s.latency, "queries");
  return text;
}

std::string PathService::LatencyLine(const char* what, const LatencyHistogram& latency,
                                     const char* noun) {
  char line[200];
  std::snprintf(line, sizeof line,
                "%s latency (received to reply sent): p50 %.3f ms, p99 %.3f ms, max %.3f ms "
                "over %lld %s\n",
                what, static_cast<double>(latency.Quantile(0.5)) / 1000.0,
                static_cast<double>(latency.Quantile(0.99)) / 1000.0,
                static_cast<double>(latency.max()) / 1000.0,
                static_cast<long long>(latency.count()), noun);
  return line;
}

}  // namespace dynapath::runtime
