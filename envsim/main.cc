// dynapath-envsim: the environment simulator of a run.

#include <spdlog/spdlog.h>

#include <cstdlib>
#include <string>

#include "envsim/command_line.h"
#include "envsim/envsim.h"
#include "protocol/dispatcher.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"
#include "runtime/test_hold.h"

int main(int argc, char** argv) {
  using namespace dynapath;
  runtime::InitProcessLogging("envsim");
  envsim::EnvSimCommandLine given;
  const int code = runtime::ParseProcessCommandLine(
      "dynapath-envsim",
      "Holds a run's maze and its change sequence (generated from a seed exactly as\n"
      "the report's runs, loaded from files, or replayed from an LCM log) and hands\n"
      "them to the coordinator one time step at a time: in lock-step with it by\n"
      "default, or free-running at --hz steps per second.",
      [&given](runtime::OptionGroup& group) { envsim::DeclareEnvSimCommandLine(group, given); },
      given.log, argc, argv);
  if (code >= 0) return code;
  auto fail = [](const std::string& message) {
    return runtime::ProcessError("dynapath-envsim", message);
  };
  Result<runtime::ProcessSetup> setup = runtime::ResolveProcessOptions(given.process, true);
  if (!setup) return fail(setup.error().message);
  Result<runtime::ScenarioSetup> scenario = runtime::ResolveScenario(given.scenario);
  if (!scenario) return fail(scenario.error().message);
  envsim::EnvSimOptions options;
  options.hz = given.hz;
  if (!(options.hz >= 0.0 && options.hz <= 1e6)) {
    return fail("option --hz must be a rate in [0, 1e6], got " + std::to_string(options.hz));
  }
  Result<double> wait_seconds = runtime::ResolveWaitSeconds(given.wait);
  if (!wait_seconds) return fail(wait_seconds.error().message);
  options.startup_timeout_seconds = *wait_seconds;
  options.coordinator_timeout_seconds = *wait_seconds;
  options.hold_at_step = runtime::TestHoldStep("envsim");

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
