#include "envsim/envsim.h"

#include <spdlog/spdlog.h>

#include "dynapath/changes_t.hpp"
#include "dynapath/grid_t.hpp"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "runtime/test_hold.h"

namespace dynapath::envsim {

EnvSim::EnvSim(protocol::Bus& bus, ScenarioInfo info, EnvSimOptions options)
    : bus_(bus), info_(std::move(info)), options_(options), coordinator_(bus, &inbox_) {
  bus_.Subscribe<step_request_t>(protocol::channel::kEnvRequest, [this](step_request_t& request) {
    inbox_.Post([this, request] { OnRequest(request); }, request.getEncodedSize());
  });
}

int EnvSim::ReachedStep() const {
  const int total = static_cast<int>(info_.scenario.changes.steps.size());
  if (options_.hz <= 0.0) return total;
  const double seconds = static_cast<double>(protocol::SteadyMs() - started_ms_) / 1000.0;
  return std::min(total, static_cast<int>(seconds * options_.hz));
}

void EnvSim::OnRequest(const step_request_t& request) {
  const int total = static_cast<int>(info_.scenario.changes.steps.size());
  if (request.time_step > total) {
    spdlog::warn("envsim: request for time step {} of a {}-step sequence ignored",
                 request.time_step, total);
    return;
  }
  if (request.time_step > ReachedStep()) {
    pending_.push_back(request);  // answered when the environment gets there
    return;
  }
  if (request.time_step == 0) {
    grid_t grid = protocol::GridToMessage(info_.scenario.grid);
    grid.run_id = bus_.run_id();
    grid.request_id = request.request_id;
    grid.pass = request.pass;
    grid.total_steps = total;
    grid.seed = static_cast<int64_t>(info_.seed);
    grid.size_label = info_.labels.size_label;
    grid.difficulty = info_.labels.difficulty_label;
    grid.source = info_.source;
    bus_.Publish(protocol::channel::kEnvGrid, grid);
  } else {
    changes_t changes = protocol::ChangesToMessage(
        info_.scenario.changes.steps[static_cast<size_t>(request.time_step - 1)], request.time_step,
        total);
    changes.run_id = bus_.run_id();
    changes.request_id = request.request_id;
    changes.pass = request.pass;
    bus_.Publish(protocol::channel::kEnvChanges, changes);
    if (request.pass == 0 && request.time_step == options_.hold_at_step) {
      runtime::HoldForTest("envsim", request.time_step);
    }
  }
  ++answered_;
}

EnvSimExit EnvSim::Run(const std::atomic<bool>& stop) {
  using Verdict = protocol::CoordinatorWatch::Verdict;
  started_ms_ = protocol::SteadyMs();
  heartbeat_t base{};
  base.role = heartbeat_t::ROLE_ENVSIM;
  base.state = heartbeat_t::STATE_RUNNING;
  base.batch_id = -1;
  base.round = -1;
  protocol::HeartbeatSender heartbeat(bus_, base, 0.2, {});
  spdlog::info("envsim: maze {} {} ({}), {} time steps, {}; run {}", info_.labels.size_label,
               info_.labels.difficulty_label, info_.source, info_.scenario.changes.steps.size(),
               options_.hz > 0 ? "free-running at " + std::to_string(options_.hz) + " Hz"
                               : std::string("lock-step"),
               bus_.run_id());
  while (!stop) {
    inbox_.RunFor(std::chrono::milliseconds(options_.hz > 0 ? 10 : 50));
    if (!pending_.empty()) {
      std::vector<step_request_t> waiting;
      waiting.swap(pending_);
      for (const step_request_t& request : waiting) OnRequest(request);
    }
    // Checked first: a pause of our own resets the coordinator's silence.
    const Verdict verdict =
        coordinator_.Check(options_.startup_timeout_seconds, options_.coordinator_timeout_seconds);
    if (const double silent = coordinator_.SilenceToReport(); silent > 0) {
      spdlog::warn("envsim: the coordinator has been silent for {:.0f} s (waiting up to {:.0f} s)",
                   silent, options_.coordinator_timeout_seconds);
    }
    switch (verdict) {
      case Verdict::kFinished:
        return EnvSimExit::kCoordinatorFinished;
      case Verdict::kFailed:
        return EnvSimExit::kCoordinatorFailed;
      case Verdict::kNeverCame:
        spdlog::error("envsim: no coordinator of run {} appeared within {:.0f} s", bus_.run_id(),
                      options_.startup_timeout_seconds);
        return EnvSimExit::kCoordinatorGone;
      case Verdict::kGone:
        spdlog::error("envsim: the coordinator of run {} is gone", bus_.run_id());
        return EnvSimExit::kCoordinatorGone;
      default:
        break;
    }
  }
  return EnvSimExit::kStopped;
}

}  // namespace dynapath::envsim
