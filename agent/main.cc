// dynapath-agent: hosts learners for a run's coordinator. Start any number,
// on this machine or others (same --run-id and LCM network).

#include <spdlog/spdlog.h>

#include <functional>
#include <string>
#include <thread>

#include "agent/agent.h"
#include "lcmtypes/protocol/dispatcher.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"

int main(int argc, char** argv) {
  using namespace dynapath;
  runtime::InitProcessLogging("agent");
  runtime::ArgParser parser(
      "dynapath-agent --run-id ID --secret-file PATH [options]",
      "Hosts Q-learning learners for the coordinator of a run: receives jobs,\n"
      "returns Q-table shards per round (or final tables), sends heartbeats.\n"
      "Exits when the coordinator finishes, fails or is silent for 4 s.");
  runtime::AddProcessOptions(parser, true);
  parser.AddOption("id", "N", "agent id, unique within the run", "random");
  parser.AddOption("threads", "N", "worker threads", "hardware threads");
  parser.AddOption("wait", "SECONDS", "how long to wait for a coordinator to appear", "60");
  runtime::AddLogLevelOption(parser);
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (int code = runtime::ParseProcessArgs(parser, args, "dynapath-agent"); code >= 0) return code;
  auto fail = [](const std::string& message) {
    return runtime::ProcessError("dynapath-agent", message);
  };
  Result<runtime::ProcessSetup> setup = runtime::ResolveProcessOptions(parser, true);
  if (!setup) return fail(setup.error().message);
  // Random, not derived from host name and pid: agents in containers of their
  // own share both. A collision is still detected (Agent::Run).
  Result<long long> id = parser.GetInt("id", agent::RandomAgentId(), 0, 2147483647LL);
  if (!id) return fail(id.error().message);
  const long long hardware = std::max(1u, std::thread::hardware_concurrency());
  Result<long long> threads = parser.GetInt("threads", hardware, 1, 1024);
  if (!threads) return fail(threads.error().message);
  Result<long long> wait = parser.GetInt("wait", 60, 1, 86400);
  if (!wait) return fail(wait.error().message);

  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(setup->lcm_url);
  if (!lcm) return runtime::ProcessError("dynapath-agent", lcm.error().message, 1);
  const std::atomic<bool>& stop = protocol::StopOnSignals();
  protocol::Bus bus(**lcm, setup->run_id, setup->bus);
  agent::AgentOptions options;
  options.id = static_cast<int>(*id);
  options.threads = static_cast<int>(*threads);
  options.startup_timeout_seconds = static_cast<double>(*wait);
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
