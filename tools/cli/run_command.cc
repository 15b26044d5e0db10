#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>
#include <thread>

#include "launch/launcher.h"
#include "lcmtypes/protocol/dispatcher.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"
#include "tools/cli/commands.h"

namespace dynapath::cli {

int RunCommand(const std::vector<std::string>& args) {
  runtime::ArgParser parser(
      "dynapath run [--local | --agents N | --embedded] [options]",
      "Runs the chosen approaches on one shared maze and change sequence and writes\n"
      "DIR/results.csv and DIR/results_detailed.csv (the report's columns).\n"
      "  --local       everything in this process on a thread pool (default)\n"
      "  --agents N    envsim, coordinator and N agent processes over LCM, in a private\n"
      "                network namespace (or on --lcm-url's network)\n"
      "  --embedded    the same components as threads of this process over memq://\n"
      "Results are identical in every mode (apart from the time columns).");
  parser.AddFlag("local", "run in this process (default)");
  parser.AddOption("agents", "N", "run distributed with N agent processes");
  parser.AddFlag("embedded", "run envsim, coordinator and agents as threads over memq://");
  runtime::AddScenarioOptions(parser);
  runtime::AddRunOptions(parser);
  runtime::AddProcessOptions(parser, false);
  parser.AddOption("threads", "N", "worker threads (--local), in all (distributed)",
                   "hardware threads");
  parser.AddOption("log", "FILE", "record the run's LCM messages with lcm-logger (--agents)");
  runtime::AddLogLevelOption(parser);
  auto usage_error = [](const std::string& message) {
    std::fprintf(stderr, "dynapath run: %s\n", message.c_str());
    return kExitUsage;
  };
  if (Status status = parser.Parse(args); !status) return usage_error(status.error().message);
  if (parser.WantsHelp()) {
    std::fputs(parser.Help().c_str(), stdout);
    return 0;
  }
  if (Status status = runtime::ApplyLogLevel(parser); !status)
    return usage_error(status.error().message);
  const int modes = parser.Has("local") + parser.Has("agents") + parser.Has("embedded");
  if (modes > 1 && !(parser.Has("embedded") && parser.Has("agents") && !parser.Has("local"))) {
    return usage_error("choose one of --local, --agents N and --embedded");
  }
  const bool distributed = parser.Has("agents") || parser.Has("embedded");
  Result<long long> agents = parser.GetInt("agents", 1, 1, 256);
  if (!agents) return usage_error(agents.error().message);
  const long long hardware = std::max(1u, std::thread::hardware_concurrency());
  Result<long long> threads = parser.GetInt("threads", hardware, 1, 1024);
  if (!threads) return usage_error(threads.error().message);
  Result<runtime::RunPlan> plan = runtime::ResolveRunOptions(parser);
  if (!plan) return usage_error(plan.error().message);
  Result<runtime::ProcessSetup> process = runtime::ResolveProcessOptions(parser, false);
  if (!process) return usage_error(process.error().message);
  if (!distributed) {
    for (const char* option :
         {"lcm-url", "log", "run-id", "fault-drop", "fault-dup", "secret-file", "insecure"}) {
      if (parser.Has(option)) {
        return usage_error(std::string("--") + option + " needs --agents N or --embedded");
      }
    }
  }
  if (parser.Has("embedded") && parser.Has("lcm-url")) {
    // Embedded runs are threads over memq://; silently ignoring the URL
    // would leave agents started elsewhere waiting for a run they never see.
    return usage_error("--lcm-url needs processes on a network: use --agents N, not --embedded");
  }
  if (parser.Has("log") && !parser.Has("agents")) {
    return usage_error("--log records a multi-process run: use it with --agents N");
  }
  // Check the maze options here, so a bad one is one error line, not one per process.
  Result<runtime::ScenarioSetup> setup = runtime::ResolveScenario(parser);
  if (!setup) return usage_error(setup.error().message);

  if (distributed) {
    launch::DistributedRun run;
    run.process = *process;
    run.process.bus.max_grid_cells =
        static_cast<int64_t>(setup->scenario.grid.rows()) * setup->scenario.grid.cols();
    run.agents = static_cast<int>(*agents);
    run.threads_per_agent = static_cast<int>(std::max(1LL, *threads / *agents));
    run.envsim_args = parser.Forward(runtime::ScenarioOptionNames());
    run.coordinator_args = parser.Forward(runtime::RunOptionNames());
    run.log_level = parser.Get("log-level", "info");
    run.log_file = parser.Get("log", "");
    bool embedded = parser.Has("embedded");
    if (!embedded) {
      const launch::ProcessNetwork network = launch::EnterProcessNetwork(process->lcm_url);
      if (network == launch::ProcessNetwork::kNone) embedded = true;
      if (network == launch::ProcessNetwork::kPrivate) {
        spdlog::info("run {} in a private network; watch it with: dynapath-spy --pid {}",
                     process->run_id, getpid());
      }
    }
    if (embedded) {
      if (!run.log_file.empty()) return usage_error("--log needs a network; not with --embedded");
      spdlog::info("run {}: envsim, coordinator and {} agents as threads over memq://",
                   process->run_id, run.agents);
      return launch::RunEmbedded(run, *plan, *setup);
    }
    spdlog::info("run {}: envsim, coordinator and {} agent processes", process->run_id, run.agents);
    if (!process->lcm_url.empty() && !parser.Has("secret-file") && !parser.Has("insecure")) {
      // The secret the launcher made is known to its children only.
      spdlog::info(
          "processes started elsewhere cannot join this run: its secret is the launcher's own "
          "(to share one, make it with `dynapath secret PATH` and pass --secret-file PATH here "
          "and to them)");
    }
    return launch::LaunchProcesses(run);
  }

  spdlog::info("maze {} {} ({}), {} time steps, {} approaches, {} threads",
               setup->labels.size_label, setup->labels.difficulty_label, setup->source,
               setup->scenario.changes.steps.size(), plan->approaches.size(), *threads);
  Result<std::vector<ApproachRun>> runs =
      runtime::RunLocal(*plan, *setup, static_cast<int>(*threads));
  if (!runs) {
    spdlog::error("{}", runs.error().message);
    return kExitFailure;
  }
  std::printf("%s", SummaryResultsCsv(*runs).c_str());
  spdlog::info("wrote {}/results.csv and {}/results_detailed.csv", plan->out_dir, plan->out_dir);
  return 0;
}

}  // namespace dynapath::cli
