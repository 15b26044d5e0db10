#include "runtime/service_bus.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <utility>

#include "dynapath/changes_t.hpp"
#include "dynapath/obstacle_points_t.hpp"
#include "dynapath/obstacle_update_t.hpp"
#include "dynapath/occupancy_grid_t.hpp"
#include "dynapath/path_request_t.hpp"
#include "dynapath/step_report_t.hpp"
#include "protocol/channels.h"

namespace dynapath::runtime {
namespace {

int64_t NowMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

ServiceBus::ServiceBus(protocol::Bus& bus, PathService& service, ServiceBusOptions options)
    : bus_(bus),
      service_(service),
      options_(options),
      approach_(ApproachName(service.config().approach)) {
  const Grid& maze = service_.maze();
  if (options_.goals != nullptr) {
    frame_ = options_.goals->frame();
  } else {
    frame_ = MapFrame{1.0, 0.0, 0.0, maze.rows(), maze.cols()};
  }
  bus_.Subscribe<obstacle_update_t>(
      protocol::channel::kMapUpdates,
      [this, rows = maze.rows(), cols = maze.cols()](obstacle_update_t& message) {
        SubmitUpdate(protocol::channel::kMapUpdates,
                     protocol::UpdateFromMessage(message, rows, cols, service_.maze_fingerprint()));
      });
  bus_.Subscribe<obstacle_points_t>(
      protocol::channel::kMapPoints, [this](obstacle_points_t& message) {
        SubmitUpdate(protocol::channel::kMapPoints,
                     protocol::UpdateFromPoints(message, frame_, service_.maze_fingerprint()));
      });
  bus_.Subscribe<occupancy_grid_t>(protocol::channel::kMapGrid, [this](occupancy_grid_t& message) {
    SubmitUpdate(
        protocol::channel::kMapGrid,
        protocol::UpdateFromOccupancyGrid(message, service_.maze(), frame_, options_.thresholds));
  });
  // A recorded run's environment changes (lcm-logplayer of a run's log,
  // with that run's id and secret): its first pass's steps, each step's
  // number as its sequence number, so a resent step counts as stale.
  bus_.Subscribe<changes_t>(protocol::channel::kEnvChanges, [this](changes_t& message) {
    if (message.pass != 0) return;  // the same sequence again for another approach
    const Grid& grid = service_.maze();
    Result<ChangeStep> step = protocol::ChangesFromMessage(message, grid.rows(), grid.cols());
    if (!step) {
      return RefuseUpdate(protocol::channel::kEnvChanges,
                          UpdateError{UpdateRefusal::kOutsideGrid, step.error()});
    }
    MapUpdate update;
    update.source = "envsim";
    update.sequence = message.time_step;
    update.changes = std::move(step->changes);
    (void)service_.Submit(update);
  });
  bus_.Subscribe<path_request_t>(protocol::channel::kPathRequest,
                                 [this](path_request_t& request) { OnRequest(request); });
  if (options_.goals != nullptr) {
    bus_.Subscribe<goal_request_t>(protocol::channel::kGoalRequest,
                                   [this](goal_request_t& request) { OnGoalRequest(request); });
  }
  if (options_.publish_policy) publisher_ = std::thread([this] { PublishPolicies(); });
}

ServiceBus::~ServiceBus() {
  {
    std::lock_guard lock(policy_mutex_);
    stopping_ = true;
  }
  policy_waiting_.notify_all();
  if (publisher_.joinable()) publisher_.join();
}

void ServiceBus::SubmitUpdate(std::string_view channel,
                              const Result<MapUpdate, UpdateError>& update) {
  if (!update) return RefuseUpdate(channel, update.error());
  (void)service_.Submit(*update);
}

void ServiceBus::RefuseUpdate(std::string_view channel, const UpdateError& refused) {
  service_.Refuse(refused.why);
  const int64_t now_ms = NowMicros() / 1000;
  std::lock_guard lock(refusal_mutex_);
  if (last_refusal_warning_ms_ >= 0 && now_ms - last_refusal_warning_ms_ < 1000) {
    ++refusal_warnings_suppressed_;
    return;
  }
  spdlog::warn("refused an update on {} ({}): {}{}", channel, UpdateRefusalName(refused.why),
               refused.error.message,
               refusal_warnings_suppressed_ > 0
                   ? " (" + std::to_string(refusal_warnings_suppressed_) +
                         " refusals not logged since the last)"
                   : std::string());
  last_refusal_warning_ms_ = now_ms;
  refusal_warnings_suppressed_ = 0;
}

void ServiceBus::OnRequest(const path_request_t& request) {
  if (!options_.own_probe_client.empty() && request.client == options_.own_probe_client) return;
  const int64_t received = NowMicros();
  std::vector<QueryStart> starts;
  // A request above the service's limit is refused unread: no work in
  // proportion to what a sender announces.
  const auto announced = static_cast<size_t>(std::max(0, request.num_starts));
  if (request.num_starts <= service_.config().max_starts) {
    starts.reserve(announced);
    for (size_t i = 0; i < announced; ++i) {
      starts.emplace_back(request.start_rows[i], request.start_cols[i]);
    }
  }
  const Answer answer = service_.Ask(starts, announced);
  path_reply_t reply = protocol::ReplyToMessage(request.client, request.request_id,
                                                static_cast<int8_t>(answer.refused), approach_,
                                                answer.snapshot.get(), starts, answer.routes);
  reply.run_id = bus_.run_id();
  reply.maze_fingerprint = static_cast<int64_t>(service_.maze_fingerprint());
  bus_.Publish(protocol::channel::kPathReply, reply);
  service_.RecordLatency(NowMicros() - received);
}

void ServiceBus::OnGoalRequest(const goal_request_t& request) {
  if (!options_.own_probe_client.empty() && request.client == options_.own_probe_client) return;
  const int64_t received = NowMicros();
  goal_reply_t reply = options_.goals->Answer(request);
  reply.run_id = bus_.run_id();
  reply.maze_fingerprint = static_cast<int64_t>(service_.maze_fingerprint());
  bus_.Publish(protocol::channel::kGoalReply, reply);
  options_.goals->RecordLatency(NowMicros() - received);
}

void ServiceBus::PublishCommit(const Commit& commit) {
  const StepView& view = commit.view;
  if (!view.run.steps.empty()) {
    const StepRecord& record = view.run.steps.back();
    // A service has no last step: its total is the step itself.
    const step_report_t report = protocol::StepReportToMessage(
        bus_.run_id(), approach_, view.run, record, /*pass=*/0, record.time_step);
    bus_.Publish(protocol::channel::kReport, report);
  }
  if (!options_.publish_policy) return;
  {
    std::lock_guard lock(policy_mutex_);
    // A policy still waiting is replaced: its step's trained regions stay
    // marked in the one that goes out.
    std::vector<Region> trained = view.details.trained_regions;
    if (pending_) {
      trained.insert(trained.begin(), pending_->trained_regions.begin(),
                     pending_->trained_regions.end());
    }
    pending_ = PendingPolicy{commit.snapshot, std::move(trained)};
  }
  policy_waiting_.notify_one();
}

void ServiceBus::PublishPolicies() {
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  };
  const Clock::duration gap = seconds(options_.policy_gap_seconds);
  const Clock::duration republish = seconds(options_.republish_seconds);
  Clock::time_point last_sent = Clock::now() - gap;
  std::unique_lock lock(policy_mutex_);
  while (!stopping_) {
    // The next thing to do: a waiting policy once the gap has passed, else
    // the last one again once `republish` has.
    Clock::time_point due = Clock::time_point::max();
    if (pending_) {
      due = last_sent + gap;
    } else if (last_policy_ && options_.republish_seconds > 0) {
      due = last_sent + republish;
    }
    if (Clock::now() < due) {
      if (due == Clock::time_point::max()) {
        policy_waiting_.wait(lock);
      } else {
        policy_waiting_.wait_until(lock, due);
      }
      continue;  // woken: a new policy, stopping, or due now
    }
    std::optional<PendingPolicy> next = std::move(pending_);
    pending_.reset();
    // The new policy's message, or the last one again (shared, not copied:
    // 8 bytes a cell).
    std::shared_ptr<const policy_t> message = last_policy_;
    lock.unlock();
    if (next) {
      const RouteSnapshot& snapshot = *next->snapshot;
      PolicyPicture picture;
      const bool pictured = PictureOf(snapshot, picture);
      message = std::make_shared<const policy_t>(
          protocol::PolicyToMessage(bus_.run_id(), approach_, 0, snapshot.time_step, snapshot.grid,
                                    pictured ? &picture : nullptr, next->trained_regions));
    }
    bus_.Publish(protocol::channel::kPolicy, *message);
    last_sent = Clock::now();
    lock.lock();
    ++policies_published_;
    last_policy_ = std::move(message);
  }
}

int64_t ServiceBus::policies_published() const {
  std::lock_guard lock(policy_mutex_);
  return policies_published_;
}

}  // namespace dynapath::runtime
