#pragma once
// The coordinator's view of the environment simulator: a StepSource whose
// maze and changes are requested over LCM, one time step at a time (which is
// what keeps envsim in lock-step with the coordinator). Requests are repeated
// until answered. A simulator whose heartbeats stop is "silent", not gone:
// it may be paused (SIGSTOP, a debugger, a swapping host) or its messages
// lost. After `timeout_seconds` of silence the wait is logged every few
// seconds, and only after `give_up_seconds` (the coordinator's --give-up,
// as for agents) does the run fail. A simulator that exited is seen by the
// launcher, which stops the run at once.

#include <atomic>
#include <optional>

#include "dynapath/changes_t.hpp"
#include "dynapath/experiment.h"
#include "dynapath/grid_t.hpp"
#include "protocol/bus.h"
#include "protocol/inbox.h"

namespace dynapath::coordinator {

class EnvSimClient : public StepSource {
 public:
  // Subscribes on `bus`: construct it before dispatching starts, and keep it
  // as long as the bus. `stop` (may be null) aborts waits: status() is then
  // kCancelled.
  EnvSimClient(protocol::Bus& bus, protocol::Inbox& inbox, double timeout_seconds,
               double give_up_seconds, const std::atomic<bool>* stop = nullptr);
  void set_stop(const std::atomic<bool>* stop) { stop_ = stop; }

  // Fetches the maze of pass 0 (waiting up to `startup_seconds` for envsim):
  // the run's size, labels and seed; null when status() failed.
  const grid_t* Connect(double startup_seconds);

  int total_steps() const override { return first_ ? first_->total_steps : 0; }
  Grid Initial(int pass) override;
  ChangeStep Changes(int pass, int t) override;
  // kCancelled (stopped), kUnavailable (envsim silent or gone) or kCorrupt
  // (an answer that does not fit the run); Ok before any failure.
  Status status() const override { return status_; }

 private:
  // Publishes the request and waits for its answer (either message kind);
  // false (status_ says why) when there is none.
  bool Request(int pass, int t, double startup_seconds);

  protocol::Bus& bus_;
  protocol::Inbox& inbox_;
  double timeout_seconds_;
  double give_up_seconds_;
  const std::atomic<bool>* stop_;
  // When the current silence was last logged (0: not logged).
  int64_t silence_logged_ms_ = 0;
  int64_t next_request_ = 1;
  // Smoothed time from a request to its answer, from requests answered
  // before any repeat (Karn's rule); -1 until the first.
  double round_trip_ms_ = -1.0;
  std::atomic<int64_t> envsim_seen_ms_{-1};
  std::optional<grid_t> first_;
  // The answer being waited for.
  int want_pass_ = -1, want_step_ = -1;
  std::optional<grid_t> grid_answer_;
  std::optional<changes_t> changes_answer_;
  Status status_ = Ok{};
};

}  // namespace dynapath::coordinator
