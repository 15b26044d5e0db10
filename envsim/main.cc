// dynapath-envsim: the environment simulator of a run.

#include <spdlog/spdlog.h>

#include <cstdlib>
#include <string>

#include "envsim/envsim.h"
#include "lcmtypes/protocol/dispatcher.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"

int main(int argc, char** argv) {
  using namespace dynapath;
  runtime::InitProcessLogging("envsim");
  runtime::ArgParser parser(
      "dynapath-envsim --run-id ID --secret-file PATH [maze options] [--hz RATE]",
      "Holds a run's maze and its change sequence (generated from a seed exactly as\n"
      "the report's runs, loaded from files, or replayed from an LCM log) and hands\n"
      "them to the coordinator one time step at a time: in lock-step with it by\n"
      "default, or free-running at --hz steps per second.");
  runtime::AddProcessOptions(parser, true);
  runtime::AddScenarioOptions(parser);
  parser.AddOption("hz", "RATE", "free-running: time steps per second", "0 (lock-step)");
  parser.AddOption("wait", "SECONDS", "how long to wait for a coordinator to appear", "60");
  runtime::AddLogLevelOption(parser);
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (int code = runtime::ParseProcessArgs(parser, args, "dynapath-envsim"); code >= 0) return code;
  auto fail = [](const std::string& message) {
    return runtime::ProcessError("dynapath-envsim", message);
  };
  Result<runtime::ProcessSetup> setup = runtime::ResolveProcessOptions(parser, true);
  if (!setup) return fail(setup.error().message);
  Result<runtime::ScenarioSetup> scenario = runtime::ResolveScenario(parser);
  if (!scenario) return fail(scenario.error().message);
  envsim::EnvSimOptions options;
  const std::string hz_text = parser.Get("hz", "0");
  char* end = nullptr;
  options.hz = std::strtod(hz_text.c_str(), &end);
  if (end == hz_text.c_str() || *end != '\0' || !(options.hz >= 0.0 && options.hz <= 1e6)) {
    return fail("option --hz must be a rate in [0, 1e6], got '" + hz_text + "'");
  }
  Result<long long> wait = parser.GetInt("wait", 60, 1, 86400);
  if (!wait) return fail(wait.error().message);
  options.startup_timeout_seconds = static_cast<double>(*wait);

  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(setup->lcm_url);
  if (!lcm) return runtime::ProcessError("dynapath-envsim", lcm.error().message, 1);
  const std::atomic<bool>& stop = protocol::StopOnSignals();
  protocol::Bus bus(**lcm, setup->run_id, setup->bus);
  envsim::ScenarioInfo info{std::move(scenario->scenario), scenario->labels, scenario->seed,
                            scenario->source};
  envsim::EnvSim sim(bus, std::move(info), options);
  protocol::Dispatcher dispatcher(**lcm);
  const envsim::EnvSimExit exit = sim.Run(stop);
  spdlog::info("envsim: exiting; messages {}", bus.TrafficSummary());
  return exit == envsim::EnvSimExit::kCoordinatorFinished || exit == envsim::EnvSimExit::kStopped
             ? 0
             : 1;
}
