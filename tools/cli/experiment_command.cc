// dynapath experiment: runs a whole study (every size x difficulty, plus the
// report's edge case) one configuration after the other, each exactly as
// `dynapath run` would, and keeps it resumable: per-configuration result
// files, merged result files, a manifest and a log in one directory.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "dynapath/result.h"
#include "runtime/option_group.h"
#include "study/study_plan.h"
#include "tools/cli/commands.h"
#include "tools/study/study_session.h"

namespace dynapath::cli {
namespace {

constexpr const char* kSummary =
    "Runs a study: every approach on every maze of --sizes x --difficulties (the\n"
    "report's seeds 50 + difficulty index unless --seed), then on the report's edge\n"
    "case (the hard 50x50 maze of seed 102), one configuration after the other, each\n"
    "exactly as `dynapath run` would. Writes into DIR (--out):\n"
    "  results.csv, results_detailed.csv            the whole study, in study order\n"
    "  edge_results.csv, edge_results_detailed.csv  the edge case\n"
    "  runs/<size>_<difficulty>_<seed>/             each configuration's own files\n"
    "  repeats.csv, summary.csv                     with --repeats N: every repeat, and means,\n"
    "                                               IQMs and 95% bootstrap intervals\n"
    "  manifest.json                                options, build, machine, times, status\n"
    "  study.log                                    everything the components log\n"
    "Run the same command again to resume: finished configurations are skipped and\n"
    "an interrupted one is redone. Ctrl-C stops the current configuration cleanly\n"
    "(a second Ctrl-C at once). --config FILE reads options from a TOML file under\n"
    "the same names (sizes = [20, 50]); the command line overrides it. See\n"
    "docs/howto/STUDIES.md. The full default study (up to 300x300) took 6.5 minutes\n"
    "with 2 agents on a 2-core machine.\n"
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
}  // namespace

int ExperimentCommand(const std::vector<std::string>& args) {
  CLI::App app(kSummary, "dynapath experiment");
  runtime::OptionGroup group(app);
  study::StudyCommandLine given;
  study::DeclareStudyCommandLine(group, given);
  StudyInput input;
  study::DeclareStudyConfigOption(group, input.config_path);
  group.Flag("--force", input.force, "start over: delete the results of the study already in DIR");
  if (int code = runtime::ParseCommandLine(app, args, "dynapath experiment"); code >= 0) {
    return code;
  }
  Result<study::GivenStudyOptions> command_line = study::CommandLineStudyOptions(app, given);
  if (!command_line) return UsageError(command_line.error().message);
  input.command_line = std::move(*command_line);
  input.hardware_threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  Result<StudyPlan> plan = PlanStudy(std::move(input));
  if (!plan) return UsageError(plan.error().message);

  StudySession session(std::move(*plan));
  if (Status prepared = session.Prepare(); !prepared) {
    return prepared.error().IsInvalidArgument() ? UsageError(prepared.error().message)
                                                : Failure(prepared.error().message);
  }
  const Status ran = session.Run();
  if (ran) return 0;
  if (ran.error().IsCancelled()) {
    std::fprintf(stderr, "run the same command again to resume\n");
    return kExitInterrupted;
  }
  if (!ran.error().message.empty()) return Failure(ran.error().message);
  return kExitFailure;
}

}  // namespace dynapath::cli
