#include "protocol/liveness.h"

#include "protocol/channels.h"

namespace dynapath::protocol {

int64_t SteadyMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

namespace {
int64_t WallUs() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}
}  // namespace

CoordinatorWatch::CoordinatorWatch(Bus& bus, Inbox* inbox) : created_ms_(SteadyMs()) {
  bus.Subscribe<heartbeat_t>(channel::kHeartbeat, [this, inbox](heartbeat_t& beat) {
    if (beat.role != heartbeat_t::ROLE_COORDINATOR) return;
    const bool first = seen_ms_.exchange(SteadyMs()) < 0;
    state_ = beat.state;
    if ((first || beat.state != heartbeat_t::STATE_RUNNING) && inbox != nullptr) inbox->Wake();
  });
}

CoordinatorWatch::Verdict CoordinatorWatch::Check(double startup_seconds,
                                                  double timeout_seconds) const {
  const int state = state_;
  if (state == heartbeat_t::STATE_FINISHED) return Verdict::kFinished;
  if (state == heartbeat_t::STATE_FAILED) return Verdict::kFailed;
  const int64_t now = SteadyMs();
  const int64_t previous_check = last_check_ms_.exchange(now);
  int64_t seen = seen_ms_;
  if (seen >= 0 && previous_check >= 0 &&
      static_cast<double>(now - previous_check) > std::min(timeout_seconds * 500, 2000.0)) {
    // We were not running: what we did not hear meanwhile says nothing
    // about the coordinator. (A heartbeat arriving now wins: max.)
    while (seen < now && !seen_ms_.compare_exchange_weak(seen, now)) {
    }
    seen = seen_ms_;
  }
  if (seen < 0) {
    return static_cast<double>(now - created_ms_) > startup_seconds * 1000 ? Verdict::kNeverCame
                                                                           : Verdict::kWaiting;
  }
  return static_cast<double>(now - seen) > timeout_seconds * 1000 ? Verdict::kGone
                                                                  : Verdict::kRunning;
}

double CoordinatorWatch::SilentSeconds() const {
  const int64_t seen = seen_ms_;
  return seen < 0 ? -1.0 : static_cast<double>(SteadyMs() - seen) / 1000.0;
}

double CoordinatorWatch::SilenceToReport() const {
  const double silent = SilentSeconds();
  if (silent < 4.0) {
    reported_silence_s_ = 0;
    return -1.0;
  }
  const int64_t reported = reported_silence_s_;
  if (reported != 0 && silent < static_cast<double>(reported) + 5.0) return -1.0;
  reported_silence_s_ = static_cast<int64_t>(silent);
  return silent;
}

HeartbeatSender::HeartbeatSender(Bus& bus, heartbeat_t base, double period_seconds,
                                 std::function<void(heartbeat_t&)> fill,
                                 std::function<void()> on_tick)
    : bus_(bus),
      base_(std::move(base)),
      period_(static_cast<int64_t>(period_seconds * 1e6)),
      fill_(std::move(fill)),
      on_tick_(std::move(on_tick)) {
  base_.run_id = bus.run_id();
  thread_ = std::thread([this] { Loop(); });
}

HeartbeatSender::~HeartbeatSender() {
  stop_ = true;
  thread_.join();
}

void HeartbeatSender::SendNow() {
  std::lock_guard lock(mutex_);
  base_.utime = WallUs();
  if (fill_) fill_(base_);
  bus_.Publish(channel::kHeartbeat, base_);
}

void HeartbeatSender::SendFinal() {
  for (int i = 0; i < 3; ++i) {
    SendNow();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

void HeartbeatSender::Loop() {
  while (!stop_) {
    SendNow();
    if (on_tick_) on_tick_();
    // Sleep in small slices so destruction is quick.
    const auto until = std::chrono::steady_clock::now() + period_;
    while (!stop_ && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(
          std::min<std::chrono::microseconds>(period_, std::chrono::microseconds(20000)));
    }
  }
}

}  // namespace dynapath::protocol
