// dynapath-coordinator: runs a distributed experiment (see coordinator.h).

#include <spdlog/spdlog.h>

#include <string>

#include "coordinator/command_line.h"
#include "coordinator/coordinator.h"
#include "protocol/dispatcher.h"
#include "runtime/output_lock.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"
#include "runtime/test_hold.h"

int main(int argc, char** argv) {
  using namespace dynapath;
  runtime::InitProcessLogging("coordinator");
  coordinator::CoordinatorCommandLine given;
  const int code = runtime::ParseProcessCommandLine(
      "dynapath-coordinator",
      "Runs the chosen approaches on the maze of the run's environment simulator,\n"
      "training on the run's agent processes, and writes DIR/results.csv and\n"
      "DIR/results_detailed.csv exactly as `dynapath run --local` does.",
      [&given](runtime::OptionGroup& group) {
        coordinator::DeclareCoordinatorCommandLine(group, given);
      },
      given.log, argc, argv);
  if (code >= 0) return code;
  auto fail = [](const std::string& message) {
    return runtime::ProcessError("dynapath-coordinator", message);
  };
  Result<runtime::ProcessSetup> setup = runtime::ResolveProcessOptions(given.process, true);
  if (!setup) return fail(setup.error().message);
  Result<runtime::RunPlan> plan = runtime::ResolveRunOptions(given.run);
  if (!plan) return fail(plan.error().message);
  Result<long long> agent_count = runtime::InRange("agents", given.agents, 0, 1, 4096);
  if (!agent_count) return fail(agent_count.error().message);
  Result<double> wait_seconds = runtime::ResolveWaitSeconds(given.wait);
  if (!wait_seconds) return fail(wait_seconds.error().message);
  Result<long long> give_up_seconds = runtime::InRange("give-up", given.give_up, 0, 5, 86400);
  if (!give_up_seconds) return fail(give_up_seconds.error().message);

  // One writer per --out: the launcher's lock, or our own.
  Result<runtime::OutputLock> out_lock =
      given.out_lock_fd >= 0
          ? runtime::OutputLock::Adopt(plan->out_dir, static_cast<int>(given.out_lock_fd))
          : runtime::LockResultDirectory(plan->out_dir);
  if (!out_lock) return fail(out_lock.error().message);

  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(setup->lcm_url);
  if (!lcm) return runtime::ProcessError("dynapath-coordinator", lcm.error().message, 1);
  const std::atomic<bool>& stop = protocol::StopOnSignals();
  protocol::Bus bus(**lcm, setup->run_id, setup->bus);
  coordinator::CoordinatorOptions options;
  options.plan = std::move(*plan);
  options.min_agents = static_cast<int>(*agent_count);
  options.agent_wait_seconds = *wait_seconds;
  options.give_up_seconds = static_cast<double>(*give_up_seconds);
  options.hold_at_step = runtime::TestHoldStep("coordinator");
  coordinator::Coordinator coordinator(bus, std::move(options));
  protocol::Dispatcher dispatcher(**lcm);
  return coordinator.Run(stop);
}
