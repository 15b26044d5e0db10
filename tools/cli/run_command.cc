#include <fcntl.h>
#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "dynapath/text_file.h"
#include "launch/launcher.h"
#include "protocol/dispatcher.h"
#include "runtime/output_check.h"
#include "runtime/output_lock.h"
#include "runtime/policy_saver.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"
#include "tools/cli/commands.h"
#include "tools/common/results_table.h"
#include "tools/common/study_config.h"
#include "tools/common/study_plan.h"
#include "tools/common/study_results.h"
#include "tools/common/toml_config.h"

namespace dynapath::cli {
namespace {

// The summary table on stdout, from the result file every mode writes (so
// --local, --embedded and --agents print the same).
void PrintResultsTable(const std::string& csv_path) {
  Result<std::string> csv = ReadTextFile(csv_path);
  if (!csv) {
    spdlog::warn("no summary table: {}", csv.error().message);
    return;
  }
  std::fputs(ResultsTable(*csv).c_str(), stdout);
}

// The exit status of a finished run, its table printed when it succeeded.
int WithResultsTable(int code, const std::string& out_dir) {
  if (code == 0) PrintResultsTable(out_dir + "/results.csv");
  return code;
}

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
  PrintResultsTable(plan.out_dir + "/summary.csv");
  spdlog::info("wrote {}/repeats.csv and {}/summary.csv (repeat 1 in {}, repeat k in {}/r<k>)",
               plan.out_dir, plan.out_dir, plan.out_dir, plan.out_dir);
  return 0;
}

// `--resume DIR` (or --resume=DIR) in `args`: its DIR, and `rest` the other
// arguments; nullopt when absent.
std::optional<std::string> TakeResume(const std::vector<std::string>& args,
                                      std::vector<std::string>& rest) {
  std::optional<std::string> dir;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--resume" && i + 1 < args.size()) {
      dir = args[++i];
    } else if (args[i].rfind("--resume=", 0) == 0) {
      dir = args[i].substr(9);
    } else {
      rest.push_back(args[i]);
    }
  }
  return dir;
}

// The arguments that resume the run whose checkpoints are in `dir`: its
// recorded options (DIR/run.toml) as a config file over a pipe, then the
// ones given now, which override them. A mode given now (--local, --agents,
// --embedded) replaces the recorded one.
Result<std::vector<std::string>> ResumeArgs(const std::string& dir,
                                            const std::vector<std::string>& given) {
  for (const std::string& arg : given) {
    if (arg == "--config" || arg.rfind("--config=", 0) == 0) {
      return Error::Option("resume", "takes the run's options from " + dir + "; not with --config");
    }
  }
  const std::string recorded_path = dir + "/" + runtime::kCheckpointOptionsName;
  Result<std::string> recorded = ReadTextFile(recorded_path);
  if (!recorded) {
    return Error::Option("resume", dir + " is not the checkpoint directory of a run (" +
                                       recorded.error().message + ")");
  }
  // The options files' one rule, checked here so that an error names the
  // file (the run reads it from a pipe).
  if (Result<ConfigFile> checked = ParseConfigText(*recorded, recorded_path); !checked) {
    return checked.error();
  }
  bool mode_given = false;
  for (const std::string& arg : given) {
    for (const char* mode : {"--local", "--agents", "--embedded"}) {
      mode_given = mode_given || arg == mode || arg.rfind(std::string(mode) + "=", 0) == 0;
    }
  }
  std::string text;
  size_t at = 0;
  while (at < recorded->size()) {
    size_t end = recorded->find('\n', at);
    if (end == std::string::npos) end = recorded->size();
    const std::string line = recorded->substr(at, end - at);
    at = end + 1;
    const bool mode_line = line.rfind("local=", 0) == 0 || line.rfind("agents=", 0) == 0 ||
                           line.rfind("embedded=", 0) == 0;
    if (mode_given && mode_line) continue;
    text += line + "\n";
  }
  const int fd = launch::TextPipe(text);
  if (fd < 0) return Error::Io(recorded_path + ": cannot hand it to the run");
  // DIR as given now: the recorded path may be relative to another folder,
  // or the directory copied.
  std::vector<std::string> args = {"--config", "/dev/fd/" + std::to_string(fd),
                                   "--resume-checkpoint", "--checkpoint", dir};
  args.insert(args.end(), given.begin(), given.end());
  return args;
}

}  // namespace

int RunCommand(const std::vector<std::string>& given_args) {
  std::vector<std::string> args;
  const std::optional<std::string> resume_dir = TakeResume(given_args, args);
  if (resume_dir) {
    Result<std::vector<std::string>> resumed = ResumeArgs(*resume_dir, args);
    if (!resumed) {
      std::fprintf(stderr, "dynapath run: %s\n", resumed.error().message.c_str());
      return kExitUsage;
    }
    args = std::move(*resumed);
  }
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
  std::optional<std::string> resume_option;  // taken out of the arguments above
  group.Option(
      "--resume", resume_option, "DIR",
      "finish the run whose --checkpoint DIR this is, from its last checkpoint, with "
      "its recorded options (a mode given here replaces its mode; docs/howto/CHECKPOINTS.md)");
  bool force = false;
  group.Flag("--force", force,
             "with --checkpoint DIR: start a new run there even when DIR holds the checkpoint of "
             "an unfinished run (which is then lost; without it such a DIR is refused)");
  std::optional<long long> restarts;
  group.Option("--restart-coordinator", restarts, "N",
               "--agents with --checkpoint: when the coordinator process dies, start the run's "
               "processes again from the last checkpoint, at most N times (0: never)",
               "3 with --checkpoint, else 0");
  std::optional<long long> repeats;
  DeclareRepeatsOption(group, repeats, "1");
  runtime::AddConfigOption(app);
  ReadConfigAsToml(app);
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
  const bool checkpointing = !plan->checkpoint.dir.empty();
  Result<long long> restart_limit =
      runtime::InRange("restart-coordinator", restarts, checkpointing ? 3 : 0, 0, 100);
  if (!restart_limit) return usage_error(restart_limit.error().message);
  if (*restart_limit > 0 && !checkpointing) {
    return usage_error("--restart-coordinator restarts from checkpoints: give --checkpoint DIR");
  }
  if (force && (!checkpointing || run_options.resume_checkpoint)) {
    return usage_error(
        "--force starts a new run over the checkpoint in --checkpoint DIR: give --checkpoint "
        "DIR, and not with --resume");
  }
  if (restarts && run_mode->kind != runtime::RunMode::kAgents) {
    return usage_error(
        "--restart-coordinator restarts coordinator processes: use it with --agents N");
  }
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
          plan->policy, plan->approaches, plan->options, setup->scenario.grid,
          static_cast<int>(setup->scenario.changes.steps.size()), plan->RunSeed(setup->seed));
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
    // A file there is kept (its other sections) or, resuming, must be the
    // one the checkpoint recorded: checked here too, before any process starts.
    Result<runtime::PolicySaver> saver = runtime::PolicySaver::Open(
        plan->policy, plan->approaches, static_cast<int>(setup->scenario.changes.steps.size()),
        plan->checkpoint.resume.get());
    if (!saver) return usage_error(saver.error().message);
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
    if (!plan->checkpoint.dir.empty()) {
      return usage_error(
          "--repeats runs without --checkpoint (dynapath experiment --repeats N checkpoints each "
          "repeat)");
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
  std::optional<runtime::OutputLock> checkpoint_lock;
  if (checkpointing) {
    std::error_code ignored;
    if (std::filesystem::weakly_canonical(plan->checkpoint.dir, ignored) !=
        std::filesystem::weakly_canonical(plan->out_dir, ignored)) {  // else locked as --out
      Result<runtime::OutputLock> locked =
          runtime::OutputLock::Acquire(plan->checkpoint.dir, "checkpoint");
      if (!locked) return usage_error(locked.error().message);
      checkpoint_lock.emplace(std::move(*locked));
    }
    if (!run_options.resume_checkpoint) {
      if (!force) {
        if (Status free = runtime::CheckCheckpointFree(plan->checkpoint.dir); !free) {
          return usage_error(free.error().message);
        }
      }
      // A new run: the checkpoint before it (of a finished run, or given up
      // with --force) must not be taken up by a --resume of this one.
      std::error_code removed;
      std::filesystem::remove(plan->checkpoint.dir + "/" + runtime::kCheckpointFileName, removed);
      if (removed) return usage_error("option --checkpoint: " + removed.message());
      // What `run --resume DIR` runs again: every option of the run but the
      // process and log ones (a new run id and secret are fine).
      runtime::ConfigWriter recorded;
      runtime::OptionGroup record(recorded);
      runtime::DeclareModeOptions(record, mode);
      runtime::DeclareScenarioOptions(record, scenario);
      runtime::DeclareRunOptions(record, run_options);
      runtime::DeclareThreadOptions(record, thread_options);
      Status written = recorded.status();
      if (written) {
        written = WriteFileDurably(plan->checkpoint.dir + "/" + runtime::kCheckpointOptionsName,
                                   recorded.Text());
      }
      if (!written) return usage_error("option --checkpoint: " + written.error().message);
    } else if (plan->checkpoint.resume) {
      const runtime::RunCheckpoint& from = *plan->checkpoint.resume;
      spdlog::info("resuming from {}/{}: {} of {} approaches finished{}", plan->checkpoint.dir,
                   runtime::kCheckpointFileName, from.pass, plan->approaches.size(),
                   from.policy
                       ? fmt::format(", {} after step {}", ApproachName(from.runs.back().approach),
                                     from.policy->step)
                       : std::string());
    } else {
      spdlog::info("{} holds no checkpoint yet: the run starts from the beginning",
                   plan->checkpoint.dir);
    }
  }

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
    run.coordinator_restarts = static_cast<int>(*restart_limit);
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
      return WithResultsTable(launch::RunEmbedded(run, *plan, *setup), plan->out_dir);
    }
    spdlog::info("run {}: envsim, coordinator and {} agent processes", process->run_id, run.agents);
    if (!process->lcm_url.empty() && !process_options.secret_file && !process_options.insecure) {
      // The secret the launcher made is known to its children only.
      spdlog::info(
          "processes started elsewhere cannot join this run: its secret is the launcher's own "
          "(to share one, make it with `dynapath secret PATH` and pass --secret-file PATH here "
          "and to them)");
    }
    return WithResultsTable(launch::LaunchProcesses(run), plan->out_dir);
  }

  spdlog::info("maze {} {} ({}), {} time steps, {} approaches, {} threads",
               setup->labels.size_label, setup->labels.difficulty_label, setup->source,
               setup->scenario.changes.steps.size(), plan->approaches.size(), *threads);
  // The first Ctrl-C (or SIGTERM) stops the run within about a second, also
  // inside one large training job; the approaches finished so far stay
  // written. A second one ends the process at once.
  const std::atomic<bool>& stop = protocol::StopOnSignals(
      "\ndynapath run: stopping (Ctrl-C again: at once)\n", "\ndynapath run: stopped at once\n");
  if (*repeat_count > 1) {
    return RunRepeats(*plan, *setup, static_cast<int>(*repeat_count), run_options.learner_seed,
                      *threads, stop);
  }
  Result<std::vector<ApproachRun>> runs = runtime::RunLocal(*plan, *setup, *threads, {}, &stop);
  if (!runs) {
    spdlog::error("{}", runs.error().message);
    if (runs.error().IsCancelled()) return 130;
    // A checkpoint or loaded policy that does not fit the run is a usage error.
    return runs.error().code == Error::Code::kInvalidArgument ? kExitUsage : kExitFailure;
  }
  PrintResultsTable(plan->out_dir + "/results.csv");
  spdlog::info("wrote {}/results.csv and {}/results_detailed.csv", plan->out_dir, plan->out_dir);
  return 0;
}

}  // namespace dynapath::cli
