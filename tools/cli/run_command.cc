#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <mutex>
#include <optional>
#include <thread>

#include "dynapath/text_file.h"
#include "launch/launcher.h"
#include "protocol/dispatcher.h"
#include "runtime/output_check.h"
#include "runtime/output_lock.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"
#include "tools/cli/commands.h"
#include "tools/common/study_plan.h"
#include "tools/common/study_results.h"

namespace dynapath::cli {
namespace {

// run --repeats N (N > 1, --local): `threads` repeats at once, one thread
// each; repeat 1 in the output directory, repeat k in DIR/r<k>; then
// repeats.csv and summary.csv. Returns the exit status.
int RunRepeats(const runtime::RunPlan& plan, const runtime::ScenarioSetup& setup, int repeats,
               std::optional<long long> learner_seed, int threads, const std::atomic<bool>& stop) {
  std::vector<runtime::RunPlan> plans;
  std::vector<RepeatFiles> files;
  for (int k = 1; k <= repeats; ++k) {
    runtime::RunPlan repeat = plan;
    repeat.learner_seed = RepeatLearnerSeed(learner_seed, setup.seed, k);
    if (k > 1) repeat.out_dir = plan.out_dir + "/r" + std::to_string(k);
    files.push_back(RepeatFiles{repeat.out_dir, k, setup.seed, repeat.RunSeed(setup.seed)});
    plans.push_back(std::move(repeat));
  }
  const int workers = std::max(1, std::min(threads, repeats));
  const int threads_each = std::max(1, threads / workers);
  spdlog::info("{} repeats, {} at once with {} thread{} each", repeats, workers, threads_each,
               threads_each == 1 ? "" : "s");
  std::mutex mutex;
  int next = 0;
  std::vector<std::string> errors(static_cast<size_t>(repeats));
  bool cancelled = false;
  auto work = [&] {
    for (;;) {
      int k = 0;
      {
        std::lock_guard lock(mutex);
        if (next == repeats || stop) return;
        k = next++;
      }
      Result<std::vector<ApproachRun>> runs =
          runtime::RunLocal(plans[static_cast<size_t>(k)], setup, threads_each, {}, &stop);
      std::lock_guard lock(mutex);
      if (!runs) {
        errors[static_cast<size_t>(k)] = runs.error().message;
        cancelled = cancelled || runs.error().IsCancelled();
      } else {
        spdlog::info("repeat {} of {} done (learner seed {})", k + 1, repeats,
                     files[static_cast<size_t>(k)].learner_seed);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int w = 0; w < workers; ++w) pool.emplace_back(work);
  for (std::thread& thread : pool) thread.join();
  if (cancelled || stop) return 130;
  for (int k = 0; k < repeats; ++k) {
    if (!errors[static_cast<size_t>(k)].empty()) {
      spdlog::error("repeat {}: {}", k + 1, errors[static_cast<size_t>(k)]);
      return kExitFailure;
    }
  }
  if (Status status = WriteRepeatFiles(files, plan.out_dir, ""); !status) {
    spdlog::error("{}", status.error().message);
    return kExitFailure;
  }
  Result<std::string> summary = ReadTextFile(plan.out_dir + "/summary.csv");
  if (summary) std::printf("%s", summary->c_str());
  spdlog::info("wrote {}/repeats.csv and {}/summary.csv (repeat 1 in {}, repeat k in {}/r<k>)",
               plan.out_dir, plan.out_dir, plan.out_dir, plan.out_dir);
  return 0;
}

}  // namespace

int RunCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Runs the chosen approaches on one shared maze and change sequence and writes\n"
      "DIR/results.csv and DIR/results_detailed.csv (the report's columns).\n"
      "  --local       everything in this process on a thread pool (default)\n"
      "  --agents N    envsim, coordinator and N agent processes over LCM, in a private\n"
      "                network namespace (or on --lcm-url's network)\n"
      "  --embedded    the same components as threads of this process over memq://\n"
      "Results are identical in every mode (apart from the time columns).\n"
      "--repeats N (with --local) runs N times with independent learner streams: repeat 1\n"
      "in DIR, repeat k in DIR/r<k>; DIR/repeats.csv and DIR/summary.csv (means and 95%\n"
      "bootstrap intervals; docs/howto/STUDIES.md, Repeats).",
      "dynapath run");
  runtime::OptionGroup group(app);
  runtime::ModeOptions mode;
  runtime::DeclareModeOptions(group, mode);
  runtime::ScenarioOptions scenario;
  runtime::DeclareScenarioOptions(group, scenario);
  runtime::RunOptions run_options;
  runtime::DeclareRunOptions(group, run_options);
  runtime::ProcessOptions process_options;
  runtime::DeclareProcessOptions(group, process_options, false);
  runtime::ThreadOptions thread_options;
  runtime::DeclareThreadOptions(group, thread_options);
  std::optional<std::string> log_file;
  group.Option("--log", log_file, "FILE",
               "record the run's LCM messages with lcm-logger (--agents)");
  runtime::LogOptions log;
  runtime::DeclareLogOptions(group, log);
  std::optional<long long> repeats;
  DeclareRepeatsOption(group, repeats, "1");
  runtime::AddConfigOption(app);
  auto usage_error = [](const std::string& message) {
    std::fprintf(stderr, "dynapath run: %s\n", message.c_str());
    return kExitUsage;
  };
  if (int code = runtime::ParseCommandLine(app, args, "dynapath run"); code >= 0) return code;
  if (Status status = runtime::ApplyLogLevel(log); !status) {
    return usage_error(status.error().message);
  }
  Result<runtime::RunMode> run_mode = runtime::ResolveMode(mode, runtime::kMaxAgents);
  if (!run_mode) return usage_error(run_mode.error().message);
  const bool distributed = run_mode->kind != runtime::RunMode::kLocal;
  Result<int> threads = runtime::ResolveThreads(thread_options);
  if (!threads) return usage_error(threads.error().message);
  Result<runtime::RunPlan> plan = runtime::ResolveRunOptions(run_options);
  if (!plan) return usage_error(plan.error().message);
  Result<runtime::ProcessSetup> process = runtime::ResolveProcessOptions(process_options, false);
  if (!process) return usage_error(process.error().message);
  if (!distributed) {
    const std::pair<const char*, bool> network_options[] = {
        {"lcm-url", !process_options.lcm_url.empty()},
        {"log", log_file.has_value()},
        {"run-id", process_options.run_id.has_value()},
        {"fault-drop", app.count("--fault-drop") > 0},
        {"fault-dup", app.count("--fault-dup") > 0},
        {"secret-file", process_options.secret_file.has_value()},
        {"insecure", process_options.insecure}};
    for (const auto& [option, given] : network_options) {
      if (given) return usage_error(std::string("--") + option + " needs --agents N or --embedded");
    }
  }
  if (run_mode->kind == runtime::RunMode::kEmbedded && !process_options.lcm_url.empty()) {
    // Embedded runs are threads over memq://; silently ignoring the URL
    // would leave agents started elsewhere waiting for a run they never see.
    return usage_error("--lcm-url needs processes on a network: use --agents N, not --embedded");
  }
  if (log_file && run_mode->kind != runtime::RunMode::kAgents) {
    return usage_error("--log records a multi-process run: use it with --agents N");
  }
  // Check the maze options here, so a bad one is one error line, not one per process.
  Result<runtime::ScenarioSetup> setup = runtime::ResolveScenario(scenario);
  if (!setup) return usage_error(setup.error().message);
  if (Status policy = runtime::CheckPolicyPlan(
          plan->policy, plan->approaches, plan->options, setup->scenario.grid.rows(),
          setup->scenario.grid.cols(), static_cast<int>(setup->scenario.changes.steps.size()));
      !policy) {
    return usage_error(policy.error().message);
  }
  // Every output checked, and --out ours alone, before any work.
  if (log_file) {
    if (Status status = runtime::CheckOutputFile(*log_file, "log"); !status) {
      return usage_error(status.error().message);
    }
  }
  if (!plan->policy.save_path.empty()) {
    if (Status status = runtime::CheckOutputFile(plan->policy.save_path, "save-policy"); !status) {
      return usage_error(status.error().message);
    }
  }
  Result<long long> repeat_count = runtime::InRange("repeats", repeats, 1, 1, kMaxRepeats);
  if (!repeat_count) return usage_error(repeat_count.error().message);
  if (*repeat_count > 1) {
    if (distributed) {
      return usage_error(
          "--repeats needs --local (for agents: dynapath experiment --repeats N --agents M)");
    }
    if (!plan->policy.save_path.empty() || !plan->policy.load_path.empty()) {
      return usage_error("--repeats runs without --save-policy and --load-policy");
    }
    const long long last = static_cast<long long>(plan->RunSeed(setup->seed)) +
                           (*repeat_count - 1) * static_cast<long long>(kRepeatSeedStride);
    if (last > runtime::kMaxLearnerSeed) {
      return usage_error("option --learner-seed: the last repeat's learner seed " +
                         std::to_string(last) + " would exceed " +
                         std::to_string(runtime::kMaxLearnerSeed));
    }
  }
  Result<runtime::OutputLock> out_lock = runtime::LockResultDirectory(plan->out_dir);
  if (!out_lock) return usage_error(out_lock.error().message);

  if (distributed) {
    launch::DistributedRun run;
    run.process = *process;
    run.process.bus.max_grid_cells =
        static_cast<int64_t>(setup->scenario.grid.rows()) * setup->scenario.grid.cols();
    run.agents = run_mode->agents;
    run.threads_per_agent = std::max(1, *threads / run_mode->agents);
    run.scenario = scenario;
    run.run = run_options;
    run.log_level = log.log_level;
    run.log_file = log_file.value_or("");
    run.out_lock_fd = out_lock->fd();
    bool embedded = run_mode->kind == runtime::RunMode::kEmbedded;
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
    if (!process->lcm_url.empty() && !process_options.secret_file && !process_options.insecure) {
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
  // The first Ctrl-C (or SIGTERM) stops the run within about a second, also
  // inside one large training job; the approaches finished so far stay
  // written. A second one ends the process at once.
  const std::atomic<bool>& stop =
      protocol::StopOnSignals("\ndynapath run: stopping (Ctrl-C again: at once)\n",
                              "\ndynapath run: stopped at once\n");
  if (*repeat_count > 1) {
    return RunRepeats(*plan, *setup, static_cast<int>(*repeat_count), run_options.learner_seed,
                      *threads, stop);
  }
  Result<std::vector<ApproachRun>> runs = runtime::RunLocal(*plan, *setup, *threads, {}, &stop);
  if (!runs) {
    spdlog::error("{}", runs.error().message);
    return runs.error().IsCancelled() ? 130 : kExitFailure;
  }
  std::printf("%s", SummaryResultsCsv(*runs).c_str());
  spdlog::info("wrote {}/results.csv and {}/results_detailed.csv", plan->out_dir, plan->out_dir);
  return 0;
}

}  // namespace dynapath::cli
