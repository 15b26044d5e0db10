#include "coordinator/envsim_client.h"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "dynapath/heartbeat_t.hpp"
#include "dynapath/step_request_t.hpp"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "protocol/liveness.h"

namespace dynapath::coordinator {

EnvSimClient::EnvSimClient(protocol::Bus& bus, protocol::Inbox& inbox, double timeout_seconds,
                           double give_up_seconds, const std::atomic<bool>* stop)
    : bus_(bus),
      inbox_(inbox),
      timeout_seconds_(timeout_seconds),
      give_up_seconds_(std::max(give_up_seconds, timeout_seconds)),
      stop_(stop) {
  namespace ch = protocol::channel;
  // Any message of envsim's shows it alive, not only its heartbeats (the
  // first may come after its first answer).
  bus_.Subscribe<grid_t>(ch::kEnvGrid, [this](grid_t& grid) {
    envsim_seen_ms_ = protocol::SteadyMs();
    const int64_t bytes = grid.getEncodedSize();
    inbox_.Post(
        [this, grid = std::move(grid)] {
          if (grid.pass == want_pass_ && want_step_ == 0) grid_answer_ = grid;
        },
        bytes);
  });
  bus_.Subscribe<changes_t>(ch::kEnvChanges, [this](changes_t& changes) {
    envsim_seen_ms_ = protocol::SteadyMs();
    const int64_t bytes = changes.getEncodedSize();
    inbox_.Post(
        [this, changes = std::move(changes)] {
          if (changes.pass == want_pass_ && changes.time_step == want_step_) {
            changes_answer_ = changes;
          }
        },
        bytes);
  });
  bus_.Subscribe<heartbeat_t>(ch::kHeartbeat, [this](heartbeat_t& beat) {
    if (beat.role == heartbeat_t::ROLE_ENVSIM) envsim_seen_ms_ = protocol::SteadyMs();
  });
}

bool EnvSimClient::Request(int pass, int t, double startup_seconds) {
  if (!status_) return false;
  want_pass_ = pass;
  want_step_ = t;
  grid_answer_.reset();
  changes_answer_.reset();
  step_request_t request{};
  request.run_id = bus_.run_id();
  request.pass = pass;
  request.time_step = t;
  request.request_id = next_request_++;
  const int64_t start = protocol::SteadyMs();
  int64_t sent = -1000000;
  // Repeat the request until answered (requests and answers may be lost, and
  // at start-up envsim may not listen yet): after two measured round trips
  // + 5 ms (10 ms until one is measured, at least 10), doubling up to 250.
  int64_t interval =
      round_trip_ms_ < 0
          ? 10
          : std::clamp<int64_t>(static_cast<int64_t>(2 * round_trip_ms_) + 5, 10, 250);
  int sends = 0;
  // Envsim's silence is counted from this request at the earliest (a pause
  // of the coordinator before it asked is not envsim's silence), and again
  // from any moment the coordinator itself did not run for a second (this
  // loop turns every few milliseconds).
  protocol::ResumeClock resume_clock(1000);
  while (!grid_answer_ && !changes_answer_) {
    const int64_t now = protocol::SteadyMs();
    const int64_t counted_from = std::max(start, resume_clock.CountedFrom(now));
    if (stop_ != nullptr && *stop_) {
      status_ = Error::Cancelled();
      return false;
    }
    if (now - sent >= interval) {
      if (sent >= 0) interval = std::min<int64_t>(250, 2 * interval);
      bus_.Publish(protocol::channel::kEnvRequest, request);
      sent = now;
      ++sends;
    }
    const int64_t seen = envsim_seen_ms_;
    if (seen < 0 && static_cast<double>(now - start) > startup_seconds * 1000) {
      status_ = Error::Unavailable("no environment simulator answered for run " + bus_.run_id());
      return false;
    }
    const double silent_seconds =
        seen < 0 ? 0.0 : static_cast<double>(now - std::max(seen, counted_from)) / 1000;
    if (silent_seconds > give_up_seconds_) {
      status_ = Error::Unavailable(
          fmt::format("the environment simulator has been silent for {:.0f} s (--give-up); "
                      "stopping the run",
                      silent_seconds));
      return false;
    }
    if (silent_seconds > timeout_seconds_ && now - silence_logged_ms_ >= 5000) {
      spdlog::warn(
          "coordinator: the environment simulator has been silent for {:.0f} s (paused, "
          "overloaded or unreachable?); waiting up to {:.0f} s",
          silent_seconds, give_up_seconds_);
      silence_logged_ms_ = now;
    }
    inbox_.RunFor(std::chrono::milliseconds(2));
  }
  if (silence_logged_ms_ != 0) {
    spdlog::info("coordinator: the environment simulator answers again");
    silence_logged_ms_ = 0;
  }
  if (sends == 1) {  // unambiguous: the answer is to the one request
    const double sample = static_cast<double>(protocol::SteadyMs() - start);
    round_trip_ms_ = round_trip_ms_ < 0 ? sample : 0.875 * round_trip_ms_ + 0.125 * sample;
  }
  want_pass_ = want_step_ = -1;
  return true;
}

const grid_t* EnvSimClient::Connect(double startup_seconds) {
  if (!Request(0, 0, startup_seconds)) return nullptr;
  first_ = *grid_answer_;
  return &*first_;
}

Grid EnvSimClient::Initial(int pass) {
  if (!Request(pass, 0, timeout_seconds_)) return Grid();
  const grid_t& grid = *grid_answer_;
  if (grid.rows != first_->rows || grid.cols != first_->cols ||
      grid.total_steps != first_->total_steps || grid.cells != first_->cells) {
    status_ = Error::Corrupt("the environment simulator sent a different maze for pass " +
                             std::to_string(pass));
    return Grid();
  }
  return protocol::GridFromMessage(grid);
}

ChangeStep EnvSimClient::Changes(int pass, int t) {
  if (!Request(pass, t, timeout_seconds_)) return {};
  Result<ChangeStep> step =
      protocol::ChangesFromMessage(*changes_answer_, first_->rows, first_->cols);
  if (!step) {
    status_ = step.error();
    return {};
  }
  return *step;
}

}  // namespace dynapath::coordinator
