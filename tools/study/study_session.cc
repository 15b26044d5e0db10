// The study session of `dynapath experiment` (study_session.h).

#include "tools/study/study_session.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>
#include <variant>

#include "app/resources.h"
#include "dynapath/experiment.h"
#include "dynapath/parameters.h"
#include "launch/launcher.h"
#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "runtime/output_check.h"
#include "runtime/output_lock.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"
#include "study/manifest.h"
#include "study/study_config.h"
#include "study/study_log.h"
#include "study/study_results.h"
#include "tools/common/build_info.h"
#include "tools/common/progress_bar.h"
#include "tools/common/space_reserve.h"

namespace dynapath::cli {
namespace {

namespace fs = std::filesystem;

constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

// The first Ctrl-C (or SIGTERM) sets the protocol's stop flag, which every
// mode polls (local runs at every time step); a second one ends the process
// at once (the configuration in progress stays "running" in the manifest and
// is redone on resume; result files are always written atomically).
const std::atomic<bool>& InstallSignalHandlers() {
  return protocol::StopOnSignals(
      "\ndynapath experiment: stopping the current configuration (Ctrl-C again: at once)\n",
      "\ndynapath experiment: stopped at once\n");
}

// The option values given on the command line.
// "sizes: [20, 50] there, [20] here; steps: ...".
std::string Differences(const study::Json& there, const study::Json& here) {
  std::string text;
  for (const auto& [key, value] : here.items()) {
    const study::Json* old = study::Member(there, key);
    if (old != nullptr && *old == value) continue;
    text += (text.empty() ? "" : "; ") + key + ": " +
            (old ? study::DumpJson(*old, -1) : "missing") + " there, " +
            study::DumpJson(value, -1) + " here";
  }
  return text.empty() ? "different options" : text;
}

// The files a study writes at its top.
const std::vector<std::string>& StudyFiles() {
  static const std::vector<std::string> files = {"manifest.json",    "study.log",
                                                 "results.csv",      "results_detailed.csv",
                                                 "edge_results.csv", "edge_results_detailed.csv",
                                                 "repeats.csv",      "summary.csv",
                                                 "edge_repeats.csv", "edge_summary.csv",
                                                 "sweep.csv",        "sweep_summary.csv",
                                                 "edge_sweep.csv",   "edge_sweep_summary.csv"};
  return files;
}

// A configuration's checkpoints, in its directory until it is done.
constexpr const char* kCheckpointFolder = "checkpoint";

// Removes what an earlier study wrote into `out` (--force).
Status RemovePreviousStudy(const fs::path& out) {
  std::error_code error;
  fs::remove_all(out / "runs", error);
  if (error) return Error::Io((out / "runs").string() + ": cannot remove: " + error.message());
  for (const std::string& file : StudyFiles()) {
    fs::remove(out / file, error);
    if (error) return Error::Io((out / file).string() + ": cannot remove: " + error.message());
  }
  return Ok{};
}

bool Complete(const fs::path& out, const study::StudyConfiguration& configuration,
              const study::StudyOptions& options) {
  return study::ConfigurationComplete((out / configuration.Directory()).string(),
                                      options.approaches, configuration.SizeText(),
                                      configuration.DifficultyText(), configuration.steps);
}

double Seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Session {
  const study::StudyOptions& options;
  study::StudyMode mode;  // after the fall-back to embedded
  int threads;     // of each configuration (--threads / --parallel)
  fs::path out;
  ProgressDisplay& display;
  const std::atomic<bool>& stop;
  int log_fd;
};

// Runs one configuration in the session's mode, with the arguments
// `dynapath run` would take. Ok when it ran to its end.
Status RunConfiguration(const Session& session, const study::StudyConfiguration& configuration,
                        int index) {
  const std::string directory = (session.out / configuration.Directory()).string();
  const runtime::ScenarioSpec scenario = study::ScenarioSpecOf(configuration);
  Result<runtime::ScenarioSetup> setup = runtime::ResolveScenario(scenario);
  if (!setup) return setup.error();
  // The study's plan with this configuration's directory, learner seed and
  // sweep point. An interrupted configuration goes on from its last
  // checkpoint (at most one every 2 s: small configurations take a step in
  // milliseconds).
  const std::string checkpoint = (fs::path(directory) / kCheckpointFolder).string();
  constexpr double kCheckpointSeconds = 2;
  runtime::RunPlan plan = study::RunPlanOf(session.options, configuration, directory);
  if (Status status = runtime::ResolveCheckpointOptions(checkpoint, std::nullopt,
                                                        kCheckpointSeconds, true, plan);
      !status) {
    return status.error();
  }
  const int approaches = static_cast<int>(plan.approaches.size());
  ProgressDisplay& display = session.display;

  if (session.mode == study::StudyMode::kLocal) {
    TrainingProgress training;
    display.WatchTraining(index, &training);
    struct Unwatch {
      ProgressDisplay& display;
      int index;
      ~Unwatch() { display.WatchTraining(index, nullptr); }
    } unwatch{display, index};
    Result<std::vector<ApproachRun>> runs = runtime::RunLocal(
        plan, *setup, session.threads,
        [&](const StepView& view) {
          display.StepOf(index, ApproachName(view.run.approach), view.pass, approaches,
                         view.run.steps.back().time_step, view.total_steps);
        },
        &session.stop, &training);
    if (!runs) return runs.error();
    return Ok{};
  }

  launch::DistributedRun run;
  char suffix[16];
  std::snprintf(suffix, sizeof suffix, "-c%02d", index + 1);
  run.process.run_id = protocol::NewRunId() + suffix;
  run.process.lcm_url = session.options.lcm_url;
  runtime::MakeRunSecret(run.process);  // a new secret for each run of the study
  run.process.bus.max_grid_cells = app::GridCap(setup->scenario.grid);
  run.agents = session.options.mode.agents;
  run.threads_per_agent =
      app::ThreadsPerAgent(session.options.threads, session.options.mode.agents);
  run.scenario = runtime::ScenarioOptionsOf(scenario);  // envsim's command line
  // The coordinator process's options (written into its config pipe).
  run.run = study::RunOptionsOf(session.options, configuration, directory);
  run.run.checkpoint = checkpoint;
  run.run.checkpoint_interval = kCheckpointSeconds;
  run.run.resume_checkpoint = true;
  run.log_level = session.options.log.log_level;
  run.child_stderr = session.log_fd;
  run.on_step = [&display, approaches](const launch::StepReport& report) {
    display.Step(report.approach, report.pass, approaches, report.time_step, report.total_steps);
  };
  Status ran = Ok{};
  if (session.mode == study::StudyMode::kEmbedded) {
    spdlog::info("run {}: envsim, coordinator and {} agents as threads over memq://",
                 run.process.run_id, run.agents);
    ran = launch::RunEmbedded(run, plan, *setup);
  } else {
    spdlog::info("run {}: envsim, coordinator and {} agent processes", run.process.run_id,
                 run.agents);
    ran = launch::LaunchProcesses(run);
  }
  if (ran || ran.error().IsCancelled()) return ran;
  return Error::Unavailable("the run failed (" + ran.error().message + "); see study.log");
}

// The options of the config file `config_path` (if any) overridden by the
// command line's.
// An error of the command and its exit status.
struct CommandError {
  int code;
  std::string message;
};

// Checks the study directory and locks it (`lock`; one study writes it at a
// time): the manifest of the same study to resume, or none (a new study;
// with --force, the old one is deleted first).
std::variant<std::optional<study::Manifest>, CommandError> OpenStudyDirectory(
    const fs::path& out, const study::Json& identity, bool force,
    std::optional<runtime::OutputLock>& lock) {
  std::error_code error;
  if (fs::exists(out, error) && !fs::is_directory(out, error)) {
    return CommandError{kExitUsage, out.string() + " exists and is not a directory"};
  }
  Result<runtime::OutputLock> locked = runtime::OutputLock::Acquire(out.string(), "out");
  if (!locked) return CommandError{kExitUsage, locked.error().message};
  lock.emplace(std::move(*locked));
  if (Status status = runtime::CheckOutputFiles(out.string(), StudyFiles(), "out"); !status) {
    return CommandError{kExitUsage, status.error().message};
  }
  std::optional<study::Manifest> previous;
  const fs::path manifest_path = out / "manifest.json";
  if (!force) {
    if (fs::exists(manifest_path, error)) {
      Result<study::Manifest> read = study::ReadManifest(manifest_path.string());
      if (!read) {
        return CommandError{
            kExitUsage, read.error().message + " (use --force to start over, or another --out)"};
      }
      const study::Json study = study::StudyIdentityWithParameters(read->study);
      if (study != identity) {
        return CommandError{kExitUsage, out.string() + " holds a study of other options (" +
                                            Differences(study, identity) +
                                            "); use --force to replace it, or another --out"};
      }
      previous = std::move(*read);
    } else if (fs::exists(out / "runs", error) || fs::exists(out / "results.csv", error)) {
      return CommandError{kExitUsage, out.string() +
                                          " holds result files but no manifest.json; use "
                                          "--force to replace them, or another --out"};
    }
  }
  if (force) {
    if (Status status = RemovePreviousStudy(out); !status) {
      return CommandError{kExitFailure, status.error().message};
    }
  }
  return previous;
}

// The default logger of the study: everything at `level` into the log file
// `log_fd` (the components' processes write there too), warnings and errors
// also on stderr through the progress display.
Result<std::shared_ptr<spdlog::logger>> StudyLogger(
    const std::string& log_path, int log_fd, spdlog::level::level_enum level,
    ProgressDisplay& display, std::shared_ptr<study::StudyLogSink>& file_sink) {
  std::shared_ptr<spdlog::logger> logger;
  try {
    file_sink = std::make_shared<study::StudyLogSink>(log_fd);
    file_sink->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%l] %v");
    auto console_sink = MakeDisplaySink(display);
    console_sink->set_pattern("[%H:%M:%S] [%l] %v");
    console_sink->set_level(std::max(level, spdlog::level::warn));
    logger = std::make_shared<spdlog::logger>("experiment",
                                              spdlog::sinks_init_list{file_sink, console_sink});
  } catch (const std::exception& e) {
    return Error::Io(log_path + ": cannot open: " + e.what());
  }
  logger->set_level(level);
  logger->flush_on(spdlog::level::trace);  // in order with the processes' lines
  return logger;
}

// The manifest of this session: the previous one's records (resume) with
// their status taken from the configurations' files.
study::Manifest SessionManifest(std::optional<study::Manifest> previous,
                                const study::StudyOptions& options, study::StudyMode mode,
                                const std::vector<study::StudyConfiguration>& plan,
                                const fs::path& out) {
  const std::string now = study::NowIso8601();
  study::Manifest manifest;
  if (previous) {
    manifest = std::move(*previous);
    ++manifest.sessions;
  } else {
    manifest.created = now;
  }
  const GitCommit commit = FindGitCommit();
  manifest.version = kDynapathVersion;
  manifest.git_commit = commit.commit;
  manifest.git_commit_source = commit.source;
  manifest.study = study::StudyIdentityJson(options);
  manifest.execution = study::ExecutionJson(options);
  manifest.execution["mode"] = study::StudyModeName(mode);  // after a fall-back to embedded
  manifest.machine = study::CollectMachineInfo();
  manifest.started = now;
  manifest.ended.clear();
  manifest.status = "running";
  std::vector<study::ConfigurationRecord> records;
  for (const study::StudyConfiguration& configuration : plan) {
    const study::ConfigurationRecord* record = manifest.Find(configuration.Name());
    records.push_back(record ? *record : study::FreshRecord(configuration));
    if (Complete(out, configuration, options)) {
      records.back().status = "done";
    } else if (records.back().status != "failed" && records.back().status != "interrupted") {
      records.back().status = "pending";
    }
  }
  manifest.configurations = std::move(records);
  return manifest;
}

// Runs the configurations of a study that are not done, in order, keeping
// the manifest and the merged result files up to date.
class StudyRunner {
 public:
  // `reserve` (may be null): space given back for the final manifest.
  StudyRunner(const Session& session, const std::vector<study::StudyConfiguration>& plan,
              study::Manifest& manifest, bool terminal, SpaceReserve* reserve)
      : session_(session),
        plan_(plan),
        manifest_(manifest),
        terminal_(terminal),
        reserve_(reserve) {}

  // Returns the exit status: 0, kExitFailure or 130 (interrupted).
  int Run() {
    std::vector<size_t> to_run;
    for (size_t i = 0; i < plan_.size(); ++i) {
      if (manifest_.configurations[i].status == "done") {
        spdlog::info("configuration {} {}: done before, skipped", Position(i), plan_[i].Label());
      } else {
        to_run.push_back(i);
      }
    }
    // --parallel P: P workers take the configurations in study order.
    std::mutex next_mutex;
    size_t next = 0;
    auto work = [&] {
      for (;;) {
        size_t i = 0;
        {
          std::lock_guard lock(next_mutex);
          if (next == to_run.size() || interrupted_) return;
          if (session_.stop) {
            interrupted_ = true;
            return;
          }
          i = to_run[next++];
        }
        RunOne(i);
        std::lock_guard lock(mutex_);
        (void)Merge(false);  // a failure is logged; the last merge below counts
        (void)Save();
      }
    };
    const int workers =
        std::min(session_.options.parallel, static_cast<int>(std::max<size_t>(1, to_run.size())));
    if (workers <= 1) {
      work();
    } else {
      std::vector<std::thread> threads;
      for (int w = 0; w < workers; ++w) threads.emplace_back(work);
      for (std::thread& thread : threads) thread.join();
    }
    // The files that could not be written are told at the end, by name.
    const Status merged = Merge(true);
    if (!merged) unwritten_.push_back(merged.error().message);
    manifest_.status = interrupted_                    ? "interrupted"
                       : failures_ > 0 || !merged.ok() ? "failed"
                                                       : "finished";
    manifest_.ended = study::NowIso8601();
    Status saved = Save();
    // A full disk: the space held back for this last manifest, then again.
    if (!saved && reserve_ != nullptr && reserve_->Release()) saved = Save();
    if (!saved) {
      unwritten_.push_back(saved.error().message + " (it still says the study is running)");
    }
    if (interrupted_) return 130;
    return failures_ > 0 || !unwritten_.empty() ? kExitFailure : 0;
  }

  // Configurations that failed (not files).
  int failures() const { return failures_; }
  // The final result files and manifest not written, each with its reason.
  const std::vector<std::string>& unwritten() const { return unwritten_; }

 private:
  std::string Position(size_t i) const {
    return std::to_string(i + 1) + "/" + std::to_string(plan_.size());
  }

  // Runs configuration i; with --parallel on several threads at once (the
  // manifest and the files are touched under mutex_).
  void RunOne(size_t i) {
    const study::StudyConfiguration& configuration = plan_[i];
    const fs::path directory = session_.out / configuration.Directory();
    const std::string name = "configuration " + Position(i) + " " + configuration.Label();
    {
      std::lock_guard lock(mutex_);
      study::ConfigurationRecord& record = manifest_.configurations[i];
      std::error_code error;
      fs::create_directories(directory, error);
      // A run rewrites its files after every approach: drop an earlier partial run's.
      fs::remove(directory / "results.csv", error);
      fs::remove(directory / "results_detailed.csv", error);
      record.status = "running";
      record.mode = study::StudyModeName(session_.mode);
      record.started = study::NowIso8601();
      record.ended.clear();
      record.wall_seconds = -1;
      record.error.clear();
      (void)Save();  // a failure is logged; the study's last save is the one that counts
      spdlog::info("{}: {} time steps, {} approaches, mode {}", name, configuration.steps,
                   session_.options.approaches.size(), study::StudyModeName(session_.mode));
      if (!terminal_) session_.display.Print(name + ": started");
      session_.display.BeginConfiguration(static_cast<int>(i), configuration.Label(),
                                          configuration.ShortLabel());
    }

    const double start = Seconds();
    const Status result = RunConfiguration(session_, configuration, static_cast<int>(i));
    const double wall = Seconds() - start;
    std::lock_guard lock(mutex_);
    study::ConfigurationRecord& record = manifest_.configurations[i];
    record.ended = study::NowIso8601();
    record.wall_seconds = wall;
    if (result && Complete(session_.out, configuration, session_.options)) {
      record.status = "done";
      std::error_code ignored;
      fs::remove_all(directory / kCheckpointFolder, ignored);  // nothing left to resume
    } else if ((!result && result.error().IsCancelled()) || session_.stop) {
      record.status = "interrupted";
      record.error = "interrupted";
      interrupted_ = true;
    } else {
      record.status = "failed";
      record.error =
          result ? "the run ended without complete result files" : result.error().message;
      ++failures_;
    }
    session_.display.EndConfiguration(static_cast<int>(i), wall, record.status == "done");
    const std::string outcome = name + ": " + record.status + " in " + FormatDuration(wall);
    if (record.status == "failed") {
      spdlog::error("{} ({})", outcome, record.error);
    } else {
      spdlog::info("{}", outcome);
      session_.display.Print(outcome);
    }
  }

  // Rewrites the merged result files from the configurations done: the
  // first repeat's results*.csv, and with repeats every repeat's
  // repeats.csv and their summary.csv (with a sweep the sweep's files).
  // The summaries' bootstrap takes about a second for a large study, so
  // they are rewritten at most every kSummaryInterval, and at the `last`
  // merge.
  static constexpr double kSummaryInterval = 30;
  Status Merge(bool last) {
    const bool summaries = last || Seconds() - last_summary_ >= kSummaryInterval;
    if (summaries) last_summary_ = Seconds();
    std::vector<std::string> main_dirs, edge_dirs;
    std::vector<study::RepeatFiles> main_repeats, edge_repeats;
    // With sweeps: the grid's points in order, main and edge.
    std::vector<std::string> sweep_names;
    for (const study::StudyOptions::Sweep& sweep : session_.options.sweeps) {
      sweep_names.push_back(Parameters()[sweep.parameter].name);
    }
    std::vector<study::SweepPoint> main_points, edge_points;
    std::vector<std::vector<std::pair<size_t, double>>> point_keys;
    bool has_edge = false;
    for (size_t i = 0; i < plan_.size(); ++i) {
      const study::StudyConfiguration& configuration = plan_[i];
      has_edge = has_edge || configuration.edge_case;
      size_t point = 0;
      if (!sweep_names.empty()) {
        const auto found = std::find(point_keys.begin(), point_keys.end(), configuration.point);
        point = static_cast<size_t>(found - point_keys.begin());
        if (found == point_keys.end()) {
          point_keys.push_back(configuration.point);
          study::SweepPoint empty;
          for (const auto& [index, value] : configuration.point) {
            empty.values.push_back(ParameterText(Parameters()[index], value));
          }
          main_points.push_back(empty);
          edge_points.push_back(empty);
        }
      }
      if (manifest_.configurations[i].status != "done") continue;
      const std::string directory = (session_.out / configuration.Directory()).string();
      const study::RepeatFiles files{directory, configuration.repeat, configuration.seed,
                                     configuration.learner_seed.value_or(configuration.seed)};
      if (!sweep_names.empty()) {
        (configuration.edge_case ? edge_points : main_points)[point].repeats.push_back(files);
      }
      if (point != 0) continue;  // the merged files hold the sweep's first point
      if (configuration.repeat == 1) {
        (configuration.edge_case ? edge_dirs : main_dirs).push_back(directory);
      }
      (configuration.edge_case ? edge_repeats : main_repeats).push_back(files);
    }
    std::string failures;
    auto failed = [&](const Status& status) {
      if (!status) failures += (failures.empty() ? "" : "; ") + status.error().message;
    };
    const bool repeats = session_.options.repeats > 1;
    const std::string out = session_.out.string();
    const bool sweeps = !sweep_names.empty();
    failed(study::MergeResultFiles(main_dirs, out, ""));
    if (repeats) failed(study::WriteRepeatFiles(main_repeats, out, "", summaries));
    if (sweeps) failed(study::WriteSweepFiles(sweep_names, main_points, out, "", summaries));
    if (has_edge) {
      failed(study::MergeResultFiles(edge_dirs, out, "edge_"));
      if (repeats) failed(study::WriteRepeatFiles(edge_repeats, out, "edge_", summaries));
      if (sweeps) failed(study::WriteSweepFiles(sweep_names, edge_points, out, "edge_", summaries));
    }
    if (failures.empty()) return Ok{};
    spdlog::error("{}", failures);
    return Error::Io(failures);
  }

  Status Save() {
    Status status = study::WriteManifest(manifest_, (session_.out / "manifest.json").string());
    if (!status) spdlog::error("{}", status.error().message);
    return status;
  }

  const Session& session_;
  const std::vector<study::StudyConfiguration>& plan_;
  study::Manifest& manifest_;
  const bool terminal_;
  SpaceReserve* reserve_;
  std::mutex mutex_;  // the manifest, the merged files, the counts below
  double last_summary_ = Seconds();
  int failures_ = 0;
  std::atomic<bool> interrupted_{false};
  std::vector<std::string> unwritten_;
};

}  // namespace

// The options of the config file (if any) overridden by the command line's.
Result<StudyPlan> PlanStudy(StudyInput input) {
  study::GivenStudyOptions file_options;
  if (input.config_path) {
    Result<study::ConfigFile> file = study::ReadConfigFile(*input.config_path);
    if (!file) return file.error();
    Result<study::GivenStudyOptions> read = study::StudyFileOptions(*file);
    if (!read) return read.error();
    file_options = std::move(*read);
  }
  Result<study::StudyOptions> options = study::ResolveStudyOptions(
      study::MergeStudyOptions(file_options, input.command_line), input.hardware_threads);
  if (!options) return options.error();
  StudyPlan plan;
  plan.options = std::move(*options);
  plan.configurations = study::MakeStudyPlan(plan.options);
  plan.force = input.force;
  return plan;
}

// What a session holds from Prepare to the end of Run.
struct StudySession::State {
  std::optional<runtime::OutputLock> lock;
  std::optional<study::Manifest> previous;
  bool terminal = false;
  std::unique_ptr<ProgressDisplay> display;
  std::string log_path;
  int log_fd = -1;
  std::shared_ptr<study::StudyLogSink> log_sink;
  study::StudyMode mode = study::StudyMode::kLocal;
  study::Manifest manifest;
  ~State() {
    if (log_fd >= 0) close(log_fd);
  }
};

StudySession::StudySession(StudyPlan plan)
    : plan_(std::move(plan)), state_(std::make_unique<State>()) {}

StudySession::~StudySession() = default;

Status StudySession::Prepare() {
  const study::StudyOptions& options = plan_.options;
  const std::vector<study::StudyConfiguration>& plan = plan_.configurations;
  const fs::path out = plan_.out();
  State& s = *state_;

  auto opened = OpenStudyDirectory(out, study::StudyIdentityJson(options), plan_.force, s.lock);
  if (const CommandError* error = std::get_if<CommandError>(&opened)) {
    if (error->code == kExitUsage) return app::OptionError(error->message, "out");
    return Error::Io(error->message);
  }
  s.previous = std::get<std::optional<study::Manifest>>(std::move(opened));

  const char* term = std::getenv("TERM");
  s.terminal = isatty(STDERR_FILENO) && term != nullptr && std::string(term) != "dumb";
  s.display = std::make_unique<ProgressDisplay>(stderr, s.terminal);
  s.log_path = (out / "study.log").string();
  s.log_fd = open(s.log_path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (s.log_fd < 0) return Error::Io(s.log_path + ": cannot open: " + std::strerror(errno));
  Result<std::shared_ptr<spdlog::logger>> logger = StudyLogger(
      s.log_path, s.log_fd, spdlog::level::from_str(options.log.log_level), *s.display, s.log_sink);
  if (!logger) return Error::Io(logger.error().message);
  spdlog::set_default_logger(*logger);

  // --agents: one private network for the whole study, entered while this
  // process still has a single thread (no thread has been started so far;
  // the manifest, which runs git, comes after: children are fine).
  s.mode = options.mode.kind;
  if (s.mode == study::StudyMode::kAgents) {
    const launch::ProcessNetwork network = launch::EnterProcessNetwork(options.lcm_url);
    if (network == launch::ProcessNetwork::kNone) s.mode = study::StudyMode::kEmbedded;
    if (network == launch::ProcessNetwork::kPrivate) {
      spdlog::info("study in a private network; watch a run with: dynapath-spy --pid {}", getpid());
    }
  }

  s.manifest = SessionManifest(std::move(s.previous), options, s.mode, plan, out);
  s.previous.reset();
  if (Status status = study::WriteManifest(s.manifest, (out / "manifest.json").string()); !status) {
    return Error::Io(status.error().message);
  }
  return Ok{};
}

Status StudySession::Run() {
  const study::StudyOptions& options = plan_.options;
  const std::vector<study::StudyConfiguration>& plan = plan_.configurations;
  const fs::path out = plan_.out();
  State& s = *state_;
  study::Manifest& manifest = s.manifest;
  ProgressDisplay& display = *s.display;

  std::vector<double> work;
  std::vector<bool> done;
  for (size_t i = 0; i < plan.size(); ++i) {
    work.push_back(plan[i].Work());
    done.push_back(manifest.configurations[i].status == "done");
  }
  const int already = static_cast<int>(std::count(done.begin(), done.end(), true));
  spdlog::info(
      "dynapath {} (commit {}) on {}: study in {}, {} configurations ({} done before), "
      "{} approaches, mode {}",
      manifest.version, manifest.git_commit, manifest.machine.hostname, out.string(), plan.size(),
      already, options.approaches.size(), study::StudyModeName(s.mode));
  if (already > 0) {
    display.Print("resuming the study in " + out.string() + ": " + std::to_string(already) +
                  " of " + std::to_string(plan.size()) +
                  " configurations were done before and are skipped");
  }

  const std::atomic<bool>& stop = InstallSignalHandlers();
  display.Start(work, done);
  for (size_t i = 0; i < plan.size(); ++i) {
    const double seconds = manifest.configurations[i].wall_seconds;
    if (done[i] && seconds >= 0) display.AddHistory(work[i], seconds);
  }
  const int threads = s.mode == study::StudyMode::kLocal
                          ? std::max(1, options.threads / options.parallel)
                          : options.threads;
  const Session session{options, s.mode, threads, out, display, stop, s.log_fd};
  const double study_start = Seconds();
  // Room for the final manifest on a disk that fills up (twice its size).
  SpaceReserve reserve(
      (out / ".manifest.reserve").string(),
      std::max<size_t>(8192, 2 * study::DumpJson(study::ManifestToJson(manifest)).size()));
  StudyRunner runner(session, plan, manifest, s.terminal, &reserve);
  int code = runner.Run();
  display.Stop();

  int finished = 0;
  for (const study::ConfigurationRecord& record : manifest.configurations) {
    finished += record.status == "done";
  }
  std::string summary = "study " + manifest.status + ": " + std::to_string(finished) + " of " +
                        std::to_string(plan.size()) + " configurations done (" +
                        std::to_string(already) + " before this session), " +
                        std::to_string(runner.failures()) + " failed, " +
                        FormatDuration(Seconds() - study_start);
  if (runner.unwritten().empty()) {
    summary += "; results in " + (out / "results.csv").string() +
               (options.edge_case ? " and " + (out / "edge_results.csv").string() : "");
  } else {
    summary += "; NOT WRITTEN: ";
    for (size_t i = 0; i < runner.unwritten().size(); ++i) {
      summary += (i > 0 ? "; " : "") + runner.unwritten()[i];
    }
  }
  spdlog::info("{}", summary);
  std::fprintf(stderr, "%s\n", summary.c_str());
  // Said last, when nothing more is logged: what study.log lacks.
  if (const std::string missing = s.log_sink->MissingText(s.log_path); !missing.empty()) {
    std::fprintf(stderr, "dynapath experiment: %s\n", missing.c_str());
    if (code == 0) code = kExitFailure;
  }
  if (code == 130) return Error::Cancelled();
  if (code != 0) return Error::Io("");  // told above
  return Ok{};
}

}  // namespace dynapath::cli
