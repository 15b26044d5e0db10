// dynapath-agent: hosts learners for a run's coordinator. Start any number,
// on this machine or others (same --run-id and LCM network).

#include <spdlog/spdlog.h>

#include <functional>
#include <optional>
#include <string>
#include <thread>

#include "agent/agent.h"
#include "agent/command_line.h"
#include "protocol/dispatcher.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"

int main(int argc, char** argv) {
  using namespace dynapath;
  runtime::InitProcessLogging("agent");
  agent::AgentCommandLine given;
  const int code = runtime::ParseProcessCommandLine(
      "dynapath-agent",
      "Hosts Q-learning learners for the coordinator of a run: receives jobs,\n"
      "returns Q-table shards per round (or final tables), sends heartbeats.\n"
      "Also hosts the learners of convQ's model for `dynapath train-model\n"
      "--agents` (one parameter shard per learner and round).\n"
      "Exits when the coordinator finishes, fails or is silent for --wait seconds.",
      [&given](runtime::OptionGroup& group) { agent::DeclareAgentCommandLine(group, given); },
      given.log, argc, argv);
  if (code >= 0) return code;
  auto fail = [](const std::string& message) {
    return runtime::ProcessError("dynapath-agent", message);
  };
  Result<runtime::ProcessSetup> setup = runtime::ResolveProcessOptions(given.process, true);
  if (!setup) return fail(setup.error().message);
  // Random, not derived from host name and pid: agents in containers of their
  // own share both. A collision is still detected (Agent::Run).
  Result<long long> agent_id =
      runtime::InRange("id", given.id, agent::RandomAgentId(), 0, 2147483647LL);
  if (!agent_id) return fail(agent_id.error().message);
  Result<int> thread_count = runtime::ResolveThreads(given.threads);
  if (!thread_count) return fail(thread_count.error().message);
  Result<double> wait_seconds = runtime::ResolveWaitSeconds(given.wait);
  if (!wait_seconds) return fail(wait_seconds.error().message);

  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(setup->lcm_url);
  if (!lcm) return runtime::ProcessError("dynapath-agent", lcm.error().message, 1);
  const std::atomic<bool>& stop = protocol::StopOnSignals();
  protocol::Bus bus(**lcm, setup->run_id, setup->bus);
  agent::AgentOptions options;
  options.id = static_cast<int>(*agent_id);
  options.threads = *thread_count;
  options.startup_timeout_seconds = *wait_seconds;
  options.coordinator_timeout_seconds = *wait_seconds;
  options.exit_process_when_orphaned = true;
  agent::Agent agent(bus, options);
  protocol::Dispatcher dispatcher(**lcm);
  const agent::AgentExit exit = agent.Run(stop);
  spdlog::info("agent {}: exiting; messages {}", options.id, bus.TrafficSummary());
  switch (exit) {
    case agent::AgentExit::kCoordinatorFinished:
    case agent::AgentExit::kStopped:
      return 0;

    default:
      return 1;
  }
}
