// dynapath run: parses the options into a run plan and runs it
// (app/run_session.h: the option rules, the outputs, the modes, the
// repeats); here only the command line, --resume's recorded options and
// what is printed.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>

#include "app/run_session.h"
#include "dynapath/text_file.h"
#include "protocol/dispatcher.h"
#include "study/study_config.h"
#include "study/study_plan.h"
#include "study/study_results.h"
#include "tools/cli/commands.h"
#include "tools/cli/run_resume.h"
#include "tools/common/results_table.h"
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

}  // namespace

int RunCommand(const std::vector<std::string>& given_args) {
  auto usage_error = [](const std::string& message) {
    std::fprintf(stderr, "dynapath run: %s\n", message.c_str());
    return kExitUsage;
  };
  std::vector<std::string> args;
  const std::optional<std::string> resume_dir = TakeResume(given_args, args);
  std::optional<study::ConfigFile> recorded;
  if (resume_dir) {
    Result<study::ConfigFile> read = ReadRecordedOptions(*resume_dir, args);
    if (!read) return usage_error(read.error().message);
    recorded = std::move(*read);
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
  app::RunOptions o;
  runtime::DeclareModeOptions(group, o.mode);
  runtime::DeclareScenarioOptions(group, o.scenario);
  runtime::DeclareRunOptions(group, o.run);
  runtime::DeclareProcessOptions(group, o.process, false);
  runtime::DeclareThreadOptions(group, o.threads);
  group.Option("--log", o.log_file, "FILE",
               "record the run's LCM messages into an LCM log (--agents; dynapath-recorder)");
  runtime::DeclareLogOptions(group, o.log);
  std::optional<std::string> resume_option;  // taken out of the arguments above
  group.Option(
      "--resume", resume_option, "DIR",
      "finish the run whose --checkpoint DIR this is, from its last checkpoint, with "
      "its recorded options (a mode given here replaces its mode; docs/howto/CHECKPOINTS.md)");
  group.Flag("--force", o.force,
             "with --checkpoint DIR: start a new run there even when DIR holds the checkpoint of "
             "an unfinished run (which is then lost; without it such a DIR is refused)");
  group.Option("--restart-coordinator", o.restarts, "N",
               "--agents with --checkpoint: when the coordinator process dies, start the run's "
               "processes again from the last checkpoint, at most N times (0: never)",
               "3 with --checkpoint, else 0");
  study::DeclareRepeatsOption(group, o.repeats, "1");
  runtime::AddConfigOption(app);
  ReadConfigAsToml(app);
  if (int code = runtime::ParseCommandLine(app, args, "dynapath run"); code >= 0) return code;
  if (resume_dir) {
    auto given_now = [&app](const std::string& key) {
      const CLI::Option* option = app.get_option_no_throw("--" + key);
      return option != nullptr && option->count() > 0;
    };
    if (Status resumed = ApplyRecordedOptions(*resume_dir, *recorded, given_now, o); !resumed) {
      return usage_error(resumed.error().message);
    }
  }
  if (Status status = runtime::ApplyLogLevel(o.log); !status) {
    return usage_error(status.error().message);
  }
  o.fault_drop_given = app.count("--fault-drop") > 0;
  o.fault_dup_given = app.count("--fault-dup") > 0;
  Result<app::RunPlan> plan = app::PlanRun(std::move(o));
  if (!plan) return usage_error(plan.error().message);
  app::RunSession session(std::move(*plan));
  if (Status prepared = session.Prepare(); !prepared) {
    return usage_error(prepared.error().message);
  }
  // Local: the first Ctrl-C (or SIGTERM) stops the run within about a
  // second, also inside one large training job; the approaches finished so
  // far stay written. A second one ends the process at once. (The launcher
  // handles the signals of a distributed run.)
  static const std::atomic<bool> never{false};
  const std::atomic<bool>& stop =
      session.plan().distributed()
          ? never
          : protocol::StopOnSignals("\ndynapath run: stopping (Ctrl-C again: at once)\n",
                                    "\ndynapath run: stopped at once\n");
  const Status ran = session.Run(stop);
  if (!ran) {
    if (!ran.error().message.empty()) spdlog::error("{}", ran.error().message);
    if (ran.error().IsCancelled()) return kExitInterrupted;
    return ran.error().IsInvalidArgument() ? kExitUsage : kExitFailure;
  }
  const std::string& out = session.plan().run.out_dir;
  if (!session.repeats().empty()) {
    std::vector<study::RepeatFiles> files;
    for (const app::RepeatDone& r : session.repeats()) {
      files.push_back(study::RepeatFiles{r.directory, r.repeat, r.seed, r.learner_seed});
    }
    if (Status written = study::WriteRepeatFiles(files, out, ""); !written) {
      spdlog::error("{}", written.error().message);
      return kExitFailure;
    }
    PrintResultsTable(out + "/summary.csv");
    spdlog::info("wrote {}/repeats.csv and {}/summary.csv (repeat 1 in {}, repeat k in {}/r<k>)",
                 out, out, out, out);
    return 0;
  }
  PrintResultsTable(out + "/results.csv");
  if (!session.plan().distributed()) {
    spdlog::info("wrote {}/results.csv and {}/results_detailed.csv", out, out);
  }
  return 0;
}

}  // namespace dynapath::cli
