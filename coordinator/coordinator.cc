#include "coordinator/coordinator.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <exception>

#include "coordinator/envsim_client.h"
#include "dynapath/policy_t.hpp"
#include "dynapath/step_report_t.hpp"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "protocol/liveness.h"
#include "runtime/test_hold.h"

namespace dynapath::coordinator {
Coordinator::Coordinator(protocol::Bus& bus, CoordinatorOptions options)
    : bus_(bus),
      options_(std::move(options)),
      agents_(options_.agent_timeout_seconds),
      trainer_(bus, inbox_, agents_,
               MakeTrainerOptions(options_.agent_wait_seconds, options_.give_up_seconds,
                                  options_.plan.placement)),
      envsim_(bus, inbox_, options_.envsim_timeout_seconds, options_.give_up_seconds) {
  bus_.Subscribe<heartbeat_t>(protocol::channel::kHeartbeat, [this](heartbeat_t& beat) {
    // Wake the coordinator thread for a new agent:
    // the run starts as soon as enough are there.
    if (agents_.OnHeartbeat(beat)) inbox_.Wake();
  });
}

void Coordinator::PublishStep(const StepView& view, int pass) {
  const StepRecord& record = view.run.steps.back();
  const step_report_t report =
      protocol::StepReportToMessage(bus_.run_id(), ApproachName(view.run.approach), view.run,
                                    record, pass, view.total_steps);
  // The step's POLICY goes out before its REPORT: the report announces a
  // step whose products are out, so a watcher (dynapath web) has the policy
  // in hand when the report comes (a 1000x1000 policy is 3 MB in about 50
  // fragments). Both are on this thread, one after the other, either way.
  if (options_.publish_policy) {
    PolicyPicture picture;
    const bool pictured = view.planner.Picture(view.grid, picture);
    const policy_t policy =
        protocol::PolicyToMessage(bus_.run_id(), report.approach, pass, record.time_step, view.grid,
                                  pictured ? &picture : nullptr, view.details.trained_regions);
    bus_.Publish(protocol::channel::kPolicy, policy);
  }
  bus_.Publish(protocol::channel::kReport, report);
  if (pass == 0 && record.time_step == options_.hold_at_step) {
    runtime::HoldForTest("coordinator", record.time_step);
  }
}

int Coordinator::Run(const std::atomic<bool>& stop) {
  std::atomic<int> state{heartbeat_t::STATE_RUNNING};
  heartbeat_t base{};
  base.role = heartbeat_t::ROLE_COORDINATOR;
  base.batch_id = -1;
  base.round = -1;
  protocol::HeartbeatSender heartbeat(bus_, base, 0.1, [&state](heartbeat_t& beat) {
    beat.state = static_cast<int8_t>(state.load());
  });
  spdlog::info("coordinator: run {}, waiting for {} agent(s)", bus_.run_id(), options_.min_agents);

  // Every wait of the trainer (agents, outstanding batches) watches `stop`.
  trainer_.set_stop(&stop);
  envsim_.set_stop(&stop);
  Status status = Ok{};
  try {
    status = RunExperiment(stop);
  } catch (const std::exception& e) {  // a broken invariant
    status = Error::Internal(e.what());
  }
  int exit_code = 0;
  if (status) {
    state = heartbeat_t::STATE_FINISHED;
  } else {
    spdlog::error("coordinator: {}", status.error().message);
    spdlog::info("coordinator: messages {}", bus_.TrafficSummary());
    state = heartbeat_t::STATE_FAILED;
    exit_code = 1;
  }
  // Let agents and envsim hear the final state.
  heartbeat.SendFinal();
  return exit_code;
}

Status Coordinator::RunExperiment(const std::atomic<bool>& stop) {
  Result<std::string> ids =
      WaitForAgents(agents_, inbox_, options_.min_agents, options_.agent_wait_seconds, &stop);
  if (!ids) return ids.error();
  spdlog::info("coordinator: agents{} alive", *ids);

  EnvSimClient& envsim = envsim_;
  const grid_t* maze = envsim.Connect(options_.agent_wait_seconds);
  if (maze == nullptr) return envsim.status();
  runtime::RunPlan plan = options_.plan;
  plan.options.run_seed = plan.RunSeed(static_cast<uint64_t>(maze->seed));
  const RunLabels labels{maze->size_label, maze->difficulty};
  spdlog::info("coordinator: maze {} {} ({}), {} time steps, {} approaches", labels.size_label,
               labels.difficulty_label, maze->source, maze->total_steps, plan.approaches.size());
  for (const std::string& warning :
       runtime::LongRunWarnings(plan, protocol::GridFromMessage(*maze), maze->total_steps)) {
    spdlog::warn("coordinator: {}", warning);
  }
  Result<std::vector<ApproachRun>> runs = runtime::RunApproaches(
      envsim, trainer_, plan, labels, [&](const StepView& view) { PublishStep(view, view.pass); },
      &stop);
  if (!runs) return runs.error();
  const TrafficStats& t = trainer_.traffic();
  spdlog::info(
      "coordinator: {} training batches, {} federated rounds; out {} messages / {} bytes, in {} "
      "messages / {} bytes; {} resends, {} reassignments ({} for lack of progress, {} split "
      "batches run whole); {} split rounds asked for again; round trip {:.1f} ms",
      t.batches, t.rounds, t.messages_out, t.bytes_out, t.messages_in, t.bytes_in, t.resends,
      t.epochs, t.stalls, t.split_fallbacks, t.round_requests, t.round_trip_ms);
  spdlog::info("coordinator: messages {}", bus_.TrafficSummary());
  spdlog::info("coordinator: wrote {}/results.csv and {}/results_detailed.csv", plan.out_dir,
               plan.out_dir);
  return Ok{};
}

}  // namespace dynapath::coordinator
