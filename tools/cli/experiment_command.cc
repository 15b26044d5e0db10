// dynapath experiment: runs a whole study (every size x difficulty, plus the
// report's edge case) one configuration after the other, each exactly as
// `dynapath run` would, and keeps it resumable: per-configuration result
// files, merged result files, a manifest and a log in one directory.

#include <fcntl.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include "core/experiment.h"
#include "lcmtypes/protocol/channels.h"
#include "lcmtypes/protocol/dispatcher.h"
#include "tools/cli/commands.h"
#include "tools/cli/launcher.h"
#include "tools/common/build_info.h"
#include "tools/common/manifest.h"
#include "tools/common/progress_bar.h"
#include "tools/common/run_driver.h"
#include "tools/common/scenario_options.h"
#include "tools/common/study_config.h"
#include "tools/common/study_plan.h"
#include "tools/common/study_results.h"

namespace dynapath::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSummary =
    "Runs a study: every approach on every maze of --sizes x --difficulties (the\n"
    "report's seeds 50 + difficulty index unless --seed), then on the report's edge\n"
    "case (the hard 50x50 maze of seed 102), one configuration after the other, each\n"
    "exactly as `dynapath run` would. Writes into DIR (--out):\n"
    "  results.csv, results_detailed.csv            the whole study, in study order\n"
    "  edge_results.csv, edge_results_detailed.csv  the edge case\n"
    "  runs/<size>_<difficulty>_<seed>/             each configuration's own files\n"
    "  manifest.json                                options, build, machine, times, status\n"
    "  study.log                                    everything the components log\n"
    "Run the same command again to resume: finished configurations are skipped and\n"
    "an interrupted one is redone. Ctrl-C stops at the end of the current time step\n"
    "(a second Ctrl-C at once). --config FILE reads options from a TOML file under\n"
    "the same names (sizes = [20, 50]); the command line overrides it. See\n"
    "docs/EXPERIMENTS.md. The full default study (up to 300x300) takes an hour or more.\n"
    "Exit status: 0 all done, 1 a configuration failed (the others still ran),\n"
    "2 bad options, 130 interrupted.";

int UsageError(const std::string& message) {
  std::fprintf(stderr, "dynapath experiment: %s\n", message.c_str());
  return kExitUsage;
}

int Failure(const std::string& message) {
  std::fprintf(stderr, "dynapath experiment: %s\n", message.c_str());
  return kExitFailure;
}

// The first Ctrl-C (or SIGTERM) sets the protocol's stop flag, which every
// mode polls (local runs at every time step); a second one ends the process
// at once (the configuration in progress stays "running" in the manifest and
// is redone on resume; result files are always written atomically).
struct sigaction g_previous_int {};
struct sigaction g_previous_term {};
std::atomic<int> g_signals{0};

void OnSignal(int signal) {
  if (g_signals.fetch_add(1) == 0) {
    const struct sigaction& previous = signal == SIGINT ? g_previous_int : g_previous_term;
    if (previous.sa_handler != SIG_DFL && previous.sa_handler != SIG_IGN &&
        previous.sa_handler != nullptr) {
      previous.sa_handler(signal);
    }
    constexpr char kMessage[] =
        "\ndynapath experiment: stopping the current configuration (Ctrl-C again: at once)\n";
    [[maybe_unused]] ssize_t written = write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
    return;
  }
  constexpr char kMessage[] = "\ndynapath experiment: stopped at once\n";
  [[maybe_unused]] ssize_t written = write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
  _exit(130);
}

const std::atomic<bool>& InstallSignalHandlers() {
  const std::atomic<bool>& stop = protocol::StopOnSignals();
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &g_previous_int);
  sigaction(SIGTERM, &action, &g_previous_term);
  return stop;
}

// The option values given on the command line.
Result<OptionValues> CommandLineValues(const ArgParser& parser) {
  OptionValues values;
  for (const StudyOptionSpec& spec : StudyOptionSpecs()) {
    if (!parser.Has(spec.name)) continue;
    const std::string origin = "option --" + spec.name;
    if (spec.name == "edge-case" || spec.name == "no-edge-case") {
      if (parser.Has("edge-case") && parser.Has("no-edge-case")) {
        return Error{"choose one of --edge-case and --no-edge-case"};
      }
      values["edge-case"] = OptionValue{spec.name == "edge-case" ? "true" : "false", origin};
    } else if (spec.value_name.empty()) {
      values[spec.name] = OptionValue{"true", origin};
    } else {
      values[spec.name] = OptionValue{parser.Get(spec.name), origin};
    }
  }
  return values;
}

// "sizes: [20, 50] there, [20] here; steps: ...".
std::string Differences(const Json& there, const Json& here) {
  std::string text;
  for (const auto& [key, value] : here.members()) {
    const Json* old = there.Find(key);
    if (old != nullptr && *old == value) continue;
    text += (text.empty() ? "" : "; ") + key + ": " + (old ? old->Dump(0) : "missing") +
            " there, " + value.Dump(0) + " here";
  }
  return text.empty() ? "different options" : text;
}

// Removes what an earlier study wrote into `out` (--force).
Status RemovePreviousStudy(const fs::path& out) {
  std::error_code error;
  fs::remove_all(out / "runs", error);
  if (error) return Error{(out / "runs").string() + ": cannot remove: " + error.message()};
  for (const char* file : {"manifest.json", "study.log", "results.csv", "results_detailed.csv",
                           "edge_results.csv", "edge_results_detailed.csv"}) {
    fs::remove(out / file, error);
    if (error) return Error{(out / file).string() + ": cannot remove: " + error.message()};
  }
  return Ok{};
}

ConfigurationRecord FreshRecord(const StudyConfiguration& configuration) {
  ConfigurationRecord record;
  record.name = configuration.Name();
  record.directory = configuration.Directory();
  record.size = configuration.size;
  record.difficulty = DifficultyName(configuration.difficulty);
  record.seed = configuration.seed;
  record.steps = configuration.steps;
  record.edge_case = configuration.edge_case;
  return record;
}

bool Complete(const fs::path& out, const StudyConfiguration& configuration,
              const StudyOptions& options) {
  return ConfigurationComplete((out / configuration.Directory()).string(), options.approaches,
                               SizeLabel(configuration.size, configuration.size),
                               DifficultyName(configuration.difficulty), configuration.steps);
}

double Seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Session {
  const StudyOptions& options;
  StudyMode mode;  // after the fall-back to embedded
  fs::path out;
  ProgressDisplay& display;
  const std::atomic<bool>& stop;
  int log_fd;
};

// Runs one configuration in the session's mode, with the arguments
// `dynapath run` would take. Ok when it ran to its end.
Status RunConfiguration(const Session& session, const StudyConfiguration& configuration,
                        int index) {
  ArgParser run_parser("dynapath run", "");
  AddScenarioOptions(run_parser);
  AddRunOptions(run_parser);
  const std::string directory = (session.out / configuration.Directory()).string();
  std::vector<std::string> args = ScenarioArguments(configuration);
  const std::vector<std::string> run_args = RunArguments(session.options, directory);
  args.insert(args.end(), run_args.begin(), run_args.end());
  if (Status status = run_parser.Parse(args); !status) return status;
  Result<ScenarioSetup> setup = ResolveScenario(run_parser);
  if (!setup) return setup.error();
  Result<RunPlan> plan = ResolveRunOptions(run_parser);
  if (!plan) return plan.error();
  const int approaches = static_cast<int>(plan->approaches.size());
  ProgressDisplay& display = session.display;

  if (session.mode == StudyMode::kLocal) {
    const std::atomic<bool>& stop = session.stop;
    Result<std::vector<ApproachRun>> runs =
        RunLocal(*plan, *setup, session.options.threads, [&](const StepView& view) {
          if (stop) throw std::runtime_error("interrupted");
          display.Step(ApproachName(view.run.approach), view.pass, approaches,
                       view.run.steps.back().time_step, view.total_steps);
        });
    if (!runs) return runs.error();
    return Ok{};
  }

  DistributedRun run;
  char suffix[16];
  std::snprintf(suffix, sizeof suffix, "-c%02d", index + 1);
  run.process.run_id = protocol::NewRunId() + suffix;
  run.process.lcm_url = session.options.lcm_url;
  run.agents = session.options.agents;
  run.threads_per_agent = std::max(1, session.options.threads / session.options.agents);
  run.envsim_args = ScenarioArguments(configuration);
  run.coordinator_args = run_args;
  run.log_level = session.options.log_level;
  run.child_stderr = session.log_fd;
  run.on_step = [&display, approaches](const StepReport& report) {
    display.Step(report.approach, report.pass, approaches, report.time_step, report.total_steps);
  };
  int code = 0;
  if (session.mode == StudyMode::kEmbedded) {
    spdlog::info("run {}: envsim, coordinator and {} agents as threads over memq://",
                 run.process.run_id, run.agents);
    code = RunEmbedded(run, *plan, *setup);
  } else {
    spdlog::info("run {}: envsim, coordinator and {} agent processes", run.process.run_id,
                 run.agents);
    code = LaunchProcesses(run);
  }
  if (code == 0) return Ok{};
  if (code == 130) return Error{"interrupted"};
  return Error{"the run failed (exit status " + std::to_string(code) + "); see study.log"};
}

}  // namespace

int ExperimentCommand(const std::vector<std::string>& args) {
  ArgParser parser("dynapath experiment [--config FILE] [options]", kSummary);
  for (const StudyOptionSpec& spec : StudyOptionSpecs()) {
    if (spec.value_name.empty()) {
      parser.AddFlag(spec.name, spec.help + (spec.default_text.empty()
                                                 ? std::string()
                                                 : " (default: " + spec.default_text + ")"));
    } else {
      parser.AddOption(spec.name, spec.value_name, spec.help, spec.default_text);
    }
  }
  parser.AddOption("config", "FILE",
                   "read options from a TOML file (key = value, same names); the command line "
                   "overrides it");
  parser.AddFlag("force", "start over: delete the results of the study already in DIR");
  if (Status status = parser.Parse(args); !status) return UsageError(status.error().message);
  if (parser.WantsHelp()) {
    std::fputs(parser.Help().c_str(), stdout);
    return 0;
  }

  // Options: the config file, overridden by the command line.
  Result<OptionValues> command_line = CommandLineValues(parser);
  if (!command_line) return UsageError(command_line.error().message);
  OptionValues file_values;
  if (parser.Has("config")) {
    Result<ConfigFile> file = ReadConfigFile(parser.Get("config"));
    if (!file) return UsageError(file.error().message);
    Result<OptionValues> values = ConfigOptionValues(*file);
    if (!values) return UsageError(values.error().message);
    file_values = std::move(*values);
  }
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  Result<StudyOptions> resolved =
      ResolveStudyOptions(MergeOptionValues(file_values, *command_line), hardware);
  if (!resolved) return UsageError(resolved.error().message);
  const StudyOptions& options = *resolved;
  const std::vector<StudyConfiguration> plan = MakeStudyPlan(options);
  const Json identity = StudyIdentityJson(options);

  // The study directory: new, or a study of the same options to resume.
  const fs::path out = options.out;
  const fs::path manifest_path = out / "manifest.json";
  const bool force = parser.Has("force");
  Manifest manifest;
  bool resumed = false;
  std::error_code error;
  if (fs::exists(out, error) && !fs::is_directory(out, error)) {
    return UsageError(out.string() + " exists and is not a directory");
  }
  if (!force) {
    if (fs::exists(manifest_path, error)) {
      Result<Manifest> previous = ReadManifest(manifest_path.string());
      if (!previous) {
        return UsageError(previous.error().message +
                          " (use --force to start over, or another --out)");
      }
      if (previous->study != identity) {
        return UsageError(out.string() + " holds a study of other options (" +
                          Differences(previous->study, identity) +
                          "); use --force to replace it, or another --out");
      }
      manifest = std::move(*previous);
      resumed = true;
    } else if (fs::exists(out / "runs", error) || fs::exists(out / "results.csv", error)) {
      return UsageError(out.string() +
                        " holds result files but no manifest.json; use --force to replace them, "
                        "or another --out");
    }
  }
  fs::create_directories(out, error);
  if (error) return Failure(out.string() + ": cannot create directory: " + error.message());
  if (force) {
    if (Status status = RemovePreviousStudy(out); !status) return Failure(status.error().message);
  }

  // Logging: everything at --log-level into study.log (the children write
  // there too); warnings and errors also on stderr, above the progress bar.
  const spdlog::level::level_enum level = spdlog::level::from_str(options.log_level);
  const bool terminal = isatty(STDERR_FILENO) && std::getenv("TERM") != nullptr &&
                        std::string(std::getenv("TERM")) != "dumb";
  ProgressDisplay display(stderr, terminal);
  const std::string log_path = (out / "study.log").string();
  std::shared_ptr<spdlog::logger> logger;
  try {
    auto file_sink = std::make_shared<spdlog::sinks::basic_file_sink_mt>(log_path, false);
    file_sink->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%l] %v");
    auto console_sink = MakeDisplaySink(display);
    console_sink->set_pattern("[%H:%M:%S] [%l] %v");
    console_sink->set_level(std::max(level, spdlog::level::warn));
    logger = std::make_shared<spdlog::logger>("experiment",
                                              spdlog::sinks_init_list{file_sink, console_sink});
  } catch (const std::exception& e) {
    return Failure(log_path + ": cannot open: " + e.what());
  }
  logger->set_level(level);
  logger->flush_on(spdlog::level::trace);
  spdlog::set_default_logger(logger);
  const int log_fd = open(log_path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (log_fd < 0) return Failure(log_path + ": cannot open: " + std::strerror(errno));
  struct CloseLog {
    int fd;
    ~CloseLog() { close(fd); }
  } close_log{log_fd};

  // The build, before entering a namespace (git runs as a child process).
  const GitCommit commit = FindGitCommit();

  // --agents: one private network for the whole study, entered while this
  // process still has a single thread (no thread has been started so far).
  StudyMode mode = options.mode;
  if (mode == StudyMode::kAgents) {
    const ProcessNetwork network = EnterProcessNetwork(options.lcm_url);
    if (network == ProcessNetwork::kNone) mode = StudyMode::kEmbedded;
    if (network == ProcessNetwork::kPrivate) {
      spdlog::info("study in a private network; watch a run with: dynapath-spy --pid {}", getpid());
    }
  }

  // The manifest of this session.
  const std::string now = NowIso8601();
  if (resumed) {
    ++manifest.sessions;
  } else {
    manifest = Manifest{};
    manifest.created = now;
  }
  manifest.version = kDynapathVersion;
  manifest.git_commit = commit.commit;
  manifest.git_commit_source = commit.source;
  manifest.study = identity;
  manifest.execution = ExecutionJson(options);
  if (mode != options.mode) manifest.execution["mode"] = StudyModeName(mode);
  manifest.machine = CollectMachineInfo();
  manifest.started = now;
  manifest.ended.clear();
  manifest.status = "running";
  std::vector<ConfigurationRecord> records;
  std::vector<double> work;
  std::vector<bool> done;
  for (const StudyConfiguration& configuration : plan) {
    const ConfigurationRecord* previous = manifest.Find(configuration.Name());
    ConfigurationRecord record = previous ? *previous : FreshRecord(configuration);
    if (Complete(out, configuration, options)) {
      record.status = "done";
    } else if (record.status != "failed" && record.status != "interrupted") {
      record.status = "pending";
    }
    records.push_back(record);
    work.push_back(configuration.Work());
    done.push_back(record.status == "done");
  }
  manifest.configurations = records;
  if (Status status = WriteManifest(manifest, manifest_path.string()); !status) {
    return Failure(status.error().message);
  }
  const int already = static_cast<int>(std::count(done.begin(), done.end(), true));
  spdlog::info(
      "dynapath {} (commit {}) on {}: study in {}, {} configurations ({} done before), "
      "{} approaches, mode {}",
      kDynapathVersion, commit.commit, manifest.machine.hostname, out.string(), plan.size(),
      already, options.approaches.size(), StudyModeName(mode));
  if (already > 0) {
    display.Print("resuming the study in " + out.string() + ": " + std::to_string(already) +
                  " of " + std::to_string(plan.size()) +
                  " configurations were done before and are skipped");
  }

  const std::atomic<bool>& stop = InstallSignalHandlers();
  display.Start(work, done);
  for (size_t i = 0; i < plan.size(); ++i) {
    if (done[i] && records[i].wall_seconds >= 0) {
      display.AddHistory(work[i], records[i].wall_seconds);
    }
  }
  const Session session{options, mode, out, display, stop, log_fd};
  const double study_start = Seconds();
  int failures = 0;
  bool interrupted = false;
  auto merge = [&] {
    std::vector<std::string> main_dirs, edge_dirs;
    bool has_edge = false;
    for (size_t i = 0; i < plan.size(); ++i) {
      has_edge = has_edge || plan[i].edge_case;
      if (manifest.configurations[i].status != "done") continue;
      (plan[i].edge_case ? edge_dirs : main_dirs).push_back((out / plan[i].Directory()).string());
    }
    Status status = MergeResultFiles(main_dirs, out.string(), "");
    if (status && has_edge) status = MergeResultFiles(edge_dirs, out.string(), "edge_");
    if (!status) spdlog::error("{}", status.error().message);
    return static_cast<bool>(status);
  };

  for (size_t i = 0; i < plan.size() && !interrupted; ++i) {
    const StudyConfiguration& configuration = plan[i];
    ConfigurationRecord& record = manifest.configurations[i];
    const std::string position = std::to_string(i + 1) + "/" + std::to_string(plan.size());
    if (record.status == "done") {
      spdlog::info("configuration {} {}: done before, skipped", position, configuration.Label());
      continue;
    }
    if (stop) {
      interrupted = true;
      break;
    }
    const fs::path directory = out / configuration.Directory();
    fs::create_directories(directory, error);
    // A run rewrites its files after every approach: drop an earlier partial run's.
    fs::remove(directory / "results.csv", error);
    fs::remove(directory / "results_detailed.csv", error);
    record.status = "running";
    record.mode = StudyModeName(mode);
    record.started = NowIso8601();
    record.ended.clear();
    record.wall_seconds = -1;
    record.error.clear();
    if (Status status = WriteManifest(manifest, manifest_path.string()); !status) {
      spdlog::error("{}", status.error().message);
    }
    spdlog::info("configuration {} {}: {} time steps, {} approaches, mode {}", position,
                 configuration.Label(), configuration.steps, options.approaches.size(),
                 StudyModeName(mode));
    if (!terminal)
      display.Print("configuration " + position + " " + configuration.Label() + ": started");
    display.BeginConfiguration(static_cast<int>(i), configuration.Label(),
                               configuration.ShortLabel());
    const double start = Seconds();
    Status result = RunConfiguration(session, configuration, static_cast<int>(i));
    const double wall = Seconds() - start;
    const bool complete = Complete(out, configuration, options);
    record.ended = NowIso8601();
    record.wall_seconds = wall;
    if (result && complete) {
      record.status = "done";
    } else if (stop) {
      record.status = "interrupted";
      record.error = "interrupted";
      interrupted = true;
    } else {
      record.status = "failed";
      record.error =
          result ? "the run ended without complete result files" : result.error().message;
      ++failures;
    }
    display.EndConfiguration(static_cast<int>(i), wall, record.status == "done");
    const std::string outcome = "configuration " + position + " " + configuration.Label() + ": " +
                                record.status + " in " + FormatDuration(wall) +
                                (record.status == "failed" ? " (" + record.error + ")" : "");
    if (record.status == "failed") {
      spdlog::error("{}", outcome);
    } else {
      spdlog::info("{}", outcome);
      display.Print(outcome);
    }
    merge();  // a failure is logged; the last merge below counts
    if (Status status = WriteManifest(manifest, manifest_path.string()); !status) {
      spdlog::error("{}", status.error().message);
      ++failures;
    }
  }
  if (!merge()) ++failures;

  manifest.status = interrupted ? "interrupted" : failures > 0 ? "failed" : "finished";
  manifest.ended = NowIso8601();
  if (Status status = WriteManifest(manifest, manifest_path.string()); !status) {
    spdlog::error("{}", status.error().message);
    if (!interrupted) failures = std::max(failures, 1);
  }
  display.Stop();
  int finished = 0;
  for (const ConfigurationRecord& record : manifest.configurations) {
    finished += record.status == "done";
  }
  const std::string summary =
      "study " + manifest.status + ": " + std::to_string(finished) + " of " +
      std::to_string(plan.size()) + " configurations done (" + std::to_string(already) +
      " before this session), " + std::to_string(failures) + " failed, " +
      FormatDuration(Seconds() - study_start) + "; results in " + (out / "results.csv").string() +
      (options.edge_case ? " and " + (out / "edge_results.csv").string() : "");
  spdlog::info("{}", summary);
  std::fprintf(stderr, "%s\n", summary.c_str());
  if (interrupted) {
    std::fprintf(stderr, "run the same command again to resume\n");
    return 130;
  }
  return failures > 0 ? kExitFailure : 0;
}

}  // namespace dynapath::cli
