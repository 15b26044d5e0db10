#pragma once
// The planning service of `dynapath serve`, without LCM (the bus glue is
// runtime/service_bus.h): a maze, one approach trained on it, live updates
// merged into time steps, and path queries answered from the last committed
// policy while the next one trains.
//
// Threads. The training thread steps through a run as RunApproach does for
// `run` (core's ApproachStepper, dynapath/experiment.h) over a live step
// source: each time step is the batch of
// updates accepted since the previous one began, so the retraining strategy
// decides exactly as in a run given that change sequence. After each step
// it builds a RouteSnapshot (dynapath/routes.h) and commits it by swapping
// one shared_ptr under a mutex: a query copies the pointer and answers every
// start of its request from that one snapshot, so it never waits for
// training and never mixes two versions. A step that retrains commits twice:
// first, between taking in the step's changes and retraining (the
// stepper's NextStep and Retrain), an interim version (the step's
// grid under the previous policy, the exact distances already repaired, so
// learned-else-exact answers around the new obstacles at once), then the
// retrained one. Submit and Answer are safe from any thread.

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/change_sequence.h"
#include "dynapath/experiment.h"
#include "dynapath/latency_histogram.h"
#include "dynapath/map_update.h"
#include "dynapath/planner.h"
#include "dynapath/policy_state.h"
#include "dynapath/routes.h"
#include "dynapath/trainer.h"

namespace dynapath::runtime {

struct ServiceConfig {
  Approach approach = Approach::kFedAsynQEqAvg;
  AnswerMode answer = AnswerMode::kLearnedElseExact;
  PlannerOptions options;  // run_seed set from the scenario
  RunLabels labels;
  int threads = 1;
  // Starts one request may carry; larger requests are refused whole.
  int max_starts = 64;
  // Path cells one reply may carry (all its starts together): bounds a
  // reply's size; a start beyond it is answered kOverBudget.
  size_t reply_budget = size_t{1} << 20;
  // The training threads' nice value (0: the process's own): above the
  // dispatch thread's, so queries are answered first on a busy machine.
  int training_nice = 5;
  // A policy to start from (runtime/policy_file.h) instead of the initial
  // training, and the changes that lead from the maze to the step it was
  // saved at (the scenario's change sequence; only its first steps are used).
  const PolicyState* load = nullptr;
  ChangeSequence catch_up;
  // Trains instead of a LocalTrainer on `threads` threads of this process
  // (dynapath serve --agents N: the agents' trainer, made and owned by the
  // caller, whose waits watch stopping()). Its Train runs on the training
  // thread. Null: in process.
  Trainer* trainer = nullptr;
  // Sees every committed snapshot (interim ones too) on the training
  // thread just before it is swapped in: the goal service's map.
  std::function<void(const std::shared_ptr<const RouteSnapshot>&)> on_snapshot;
};

// What the training thread hands the glue at every commit (policy
// publishing, step reports). The view lives for the call only; the
// snapshot (immutable) as long as anyone holds it.
struct Commit {
  const StepView& view;
  std::shared_ptr<const RouteSnapshot> snapshot;
};

struct Answer {
  enum Refusal { kAccepted = 0, kTooManyStarts = 1, kNotReady = 2 };
  Refusal refused = kAccepted;
  std::shared_ptr<const RouteSnapshot> snapshot;  // the one every route came from
  std::vector<Route> routes;                      // one per start
};

struct ServiceStats {
  int64_t requests = 0;
  int64_t probes = 0;  // of them, without starts: a client asking for the version and step
  int64_t starts = 0;
  int64_t refused_too_many_starts = 0;
  int64_t refused_not_ready = 0;
  std::array<int64_t, 8> by_status{};  // RouteStatus
  int64_t by_learned = 0, by_exact = 0;
  UpdateCounts updates;
  int64_t commits = 0;
  int64_t interim_commits = 0;  // of them, before a step's retraining
  int64_t retrainings = 0;      // steps that trained at least one node
  int64_t nodes_trained = 0;
  LatencyHistogram latency;  // request received to reply sent, microseconds
  int64_t version = 0;
  int time_step = 0;
};

// Starts (row, col) of one request.
using QueryStart = std::pair<int32_t, int32_t>;

class PathService {
 public:
  using CommitHook = std::function<void(const Commit&)>;
  // `maze`: the grid at time step 0. `on_commit` (may be empty) runs on the
  // training thread after each commit.
  PathService(Grid maze, ServiceConfig config, CommitHook on_commit = {});
  ~PathService();  // stops and joins
  // Ok when `config` can serve `maze`: a loaded policy saved on this maze
  // needs the steps of its run's change sequence up to its saved step, and
  // they must lead to the maze it was saved on. Checked before any work
  // (Start fails the same way later).
  static Status CheckLoad(const Grid& maze, const ServiceConfig& config);
  PathService(const PathService&) = delete;
  PathService& operator=(const PathService&) = delete;

  // Starts training (the initial policy, or taking over the loaded one).
  void Start();
  // Ends the training thread within about a second (the trainer checks
  // the stop flag inside long jobs) and returns the run as far as it got:
  // one step record per committed step. Fails when training failed.
  Result<ApproachRun> Stop();

  // Any thread. An update: nullopt when accepted (it goes into the next
  // time step), else why it was refused (counted).
  std::optional<UpdateRefusal> Submit(const MapUpdate& update);
  void Refuse(UpdateRefusal why);
  // Answers `starts` from the current snapshot.
  Answer Ask(const std::vector<QueryStart>& starts) { return Ask(starts, starts.size()); }
  // The same for a request that announced `announced` starts: above the
  // service's max_starts it is refused (kTooManyStarts) without reading
  // `starts`, which a caller need not have filled then.
  Answer Ask(const std::vector<QueryStart>& starts, size_t announced);
  void RecordLatency(int64_t micros);

  // Set once Stop() was called: the flag an outside trainer's waits watch.
  const std::atomic<bool>& stopping() const { return stop_; }
  // The training thread has ended before Stop() (it failed: no agent left,
  // a broken invariant); queries are still answered from the last policy.
  bool training_ended() const { return training_ended_.load(); }

  std::shared_ptr<const RouteSnapshot> Current() const;
  // Blocks until a snapshot of at least `version` is committed or
  // `seconds` pass; true when it was (tests, feeding in lock step).
  bool WaitForVersion(int64_t version, double seconds) const;
  // Blocks until time step `time_step` (or a later one) is committed
  // retrained, not only as an interim version, or `seconds` pass; true
  // when it was (tests, feeding in lock step).
  bool WaitForStep(int time_step, double seconds) const;
  ServiceStats stats() const;
  // The grid of the service's map (size and stations never change).
  const Grid& maze() const { return maze_; }
  // MazeFingerprint of maze(): what every reply names and every obstacle
  // update must name.
  uint64_t maze_fingerprint() const { return maze_fingerprint_; }
  const ServiceConfig& config() const { return config_; }
  // Multi-line summary of stats() for the end of a service.
  static std::string Summary(const ServiceStats& stats);
  // The summary's latency line: "<what> latency (received to reply sent):
  // p50 .. ms, p99 .. ms, max .. ms over N <noun>\n", from microseconds.
  static std::string LatencyLine(const char* what, const LatencyHistogram& latency,
                                 const char* noun);

 private:
  class LiveSource;
  void Train();
  // Commits the stepper's last step (its record in the hook's view).
  void CommitStep(ApproachStepper& stepper);
  // Builds and swaps in the snapshot of the stepper's planner on its grid
  // (`view`: the step's record, null for an interim commit).
  void CommitSnapshot(ApproachStepper& stepper, const StepView* view);

  const Grid maze_;
  const uint64_t maze_fingerprint_;
  ServiceConfig config_;
  CommitHook on_commit_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> training_ended_{false};

  mutable std::mutex updates_mutex_;  // guards updates_
  std::condition_variable updates_ready_;
  UpdateQueue updates_;

  mutable std::mutex snapshot_mutex_;
  mutable std::condition_variable committed_;
  std::shared_ptr<const RouteSnapshot> snapshot_;  // guarded by snapshot_mutex_
  int committed_step_ = -1;  // the last step's own (not interim) commit; likewise

  mutable std::mutex stats_mutex_;  // guards stats_ (but its updates)
  ServiceStats stats_;

  std::unique_ptr<Planner> exact_;  // Incremental Oracle beside a learner
  int exact_step_ = -1;             // the time step exact_ was last repaired for
  Result<ApproachRun> result_ = ApproachRun{};
  std::thread thread_;
};

}  // namespace dynapath::runtime
