#pragma once
// Heartbeats: every process publishes its own a few times a second from a
// dedicated thread (so a process deep in computation still looks alive), and
// agents and envsim watch the coordinator's to exit when it finished, failed
// or vanished.

#include <atomic>
#include <chrono>
#include <functional>
#include <thread>

#include "dynapath/heartbeat_t.hpp"
#include "protocol/bus.h"
#include "protocol/inbox.h"

namespace dynapath::protocol {

int64_t SteadyMs();

// For a caller that checks every few milliseconds: when it did not run for
// longer than `gap_ms` between two checks (paused by SIGSTOP or a debugger,
// or starved), the silence of others it did not hear meanwhile is its own.
// CountedFrom says from when to count their silence: the end of its last
// such gap (0 before any).
class ResumeClock {
 public:
  explicit ResumeClock(int64_t gap_ms) : gap_ms_(gap_ms) {}
  int64_t CountedFrom(int64_t now_ms) {
    if (last_check_ms_ >= 0 && now_ms - last_check_ms_ > gap_ms_) counted_from_ms_ = now_ms;
    last_check_ms_ = now_ms;
    return counted_from_ms_;
  }

 private:
  int64_t gap_ms_;
  int64_t last_check_ms_ = -1;
  int64_t counted_from_ms_ = 0;
};

class CoordinatorWatch {
 public:
  enum class Verdict { kWaiting, kRunning, kFinished, kFailed, kGone, kNeverCame };

  // Subscribes on `bus`; wakes `inbox` (may be null) when the coordinator is
  // first heard from, and when it reports it finished or failed.
  CoordinatorWatch(Bus& bus, Inbox* inbox);

  // A coordinator heartbeat arrived.
  bool Seen() const { return seen_ms_ >= 0; }

  // `startup_seconds`: how long to wait for a first heartbeat;
  // `timeout_seconds`: how long a seen coordinator may be silent. Callers
  // check often (at least every heartbeat period); a gap of more than half
  // the timeout since the previous check means this process did not run
  // (paused by SIGSTOP or a debugger, or starved), so the silence is its
  // own: the coordinator's silence is counted again from now.
  Verdict Check(double startup_seconds, double timeout_seconds) const;
  std::string message() const;  // the coordinator's failure message
  // Seconds since the last heartbeat of a coordinator seen before (as
  // Check last counted them), or -1 when none was seen.
  double SilentSeconds() const;
  // The silence to log now: after 4 s without a heartbeat, and every 5 s
  // after that while it lasts; otherwise -1 (for "the coordinator has been
  // silent for N s").
  double SilenceToReport() const;

 private:
  int64_t created_ms_;
  mutable std::atomic<int64_t> seen_ms_{-1};
  mutable std::atomic<int64_t> last_check_ms_{-1};
  mutable std::atomic<int64_t> reported_silence_s_{0};  // the last SilenceToReport, 0: none
  std::atomic<int> state_{heartbeat_t::STATE_RUNNING};
};

class HeartbeatSender {
 public:
  // Publishes `base` every `period_seconds` after `fill` updated it;
  // `on_tick` (may be empty) runs after each publish on the same thread.
  HeartbeatSender(Bus& bus, heartbeat_t base, double period_seconds,
                  std::function<void(heartbeat_t&)> fill, std::function<void()> on_tick = {});
  ~HeartbeatSender();
  // Sends one heartbeat now (e.g. the final state) from the calling thread.
  void SendNow();
  // A final state, sent three times 5 ms apart: heartbeats may be lost (if
  // all are, the others still notice the silence).
  void SendFinal();

 private:
  void Loop();
  Bus& bus_;
  heartbeat_t base_{};
  std::chrono::microseconds period_;
  std::function<void(heartbeat_t&)> fill_;
  std::function<void()> on_tick_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;  // guards base_ between the thread and SendNow
  std::thread thread_;
};

}  // namespace dynapath::protocol
