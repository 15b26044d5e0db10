// dynapath-coordinator: runs a distributed experiment (see coordinator.h).

#include <spdlog/spdlog.h>

#include <string>

#include "coordinator/coordinator.h"
#include "lcmtypes/protocol/dispatcher.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"

int main(int argc, char** argv) {
  using namespace dynapath;
  runtime::InitProcessLogging("coordinator");
  runtime::ArgParser parser(
      "dynapath-coordinator --run-id ID --secret-file PATH [options]",
      "Runs the chosen approaches on the maze of the run's environment simulator,\n"
      "training on the run's agent processes, and writes DIR/results.csv and\n"
      "DIR/results_detailed.csv exactly as `dynapath run --local` does.");
  runtime::AddProcessOptions(parser, true);
  runtime::AddRunOptions(parser);
  parser.AddOption("agents", "N", "wait for N live agents before starting", "1");
  parser.AddOption("wait", "SECONDS", "how long to wait for agents and envsim", "60");
  parser.AddOption("give-up", "SECONDS",
                   "fail when a training batch makes no progress this long although its agents "
                   "are alive (its work is reassigned every 5 s before that)",
                   "60");
  runtime::AddLogLevelOption(parser);
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (int code = runtime::ParseProcessArgs(parser, args, "dynapath-coordinator"); code >= 0) {
    return code;
  }
  auto fail = [](const std::string& message) {
    return runtime::ProcessError("dynapath-coordinator", message);
  };
  Result<runtime::ProcessSetup> setup = runtime::ResolveProcessOptions(parser, true);
  if (!setup) return fail(setup.error().message);
  Result<runtime::RunPlan> plan = runtime::ResolveRunOptions(parser);
  if (!plan) return fail(plan.error().message);
  Result<long long> agents = parser.GetInt("agents", 1, 1, 4096);
  if (!agents) return fail(agents.error().message);
  Result<long long> wait = parser.GetInt("wait", 60, 1, 86400);
  if (!wait) return fail(wait.error().message);
  Result<long long> give_up = parser.GetInt("give-up", 60, 5, 86400);
  if (!give_up) return fail(give_up.error().message);

  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(setup->lcm_url);
  if (!lcm) return runtime::ProcessError("dynapath-coordinator", lcm.error().message, 1);
  const std::atomic<bool>& stop = protocol::StopOnSignals();
  protocol::Bus bus(**lcm, setup->run_id, setup->bus);
  coordinator::CoordinatorOptions options;
  options.plan = std::move(*plan);
  options.min_agents = static_cast<int>(*agents);
  options.agent_wait_seconds = static_cast<double>(*wait);
  options.give_up_seconds = static_cast<double>(*give_up);
  coordinator::Coordinator coordinator(bus, std::move(options));
  protocol::Dispatcher dispatcher(**lcm);
  return coordinator.Run(stop);
}
