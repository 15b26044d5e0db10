// dynapath compare STUDY A B: the paired difference of two approaches over
// the repeats of a study (or of `dynapath run --repeats`), with its
// bootstrap interval (tools/common/study_results.h, CompareCsv).

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "dynapath/approach.h"
#include "dynapath/text_file.h"
#include "runtime/option_group.h"
#include "tools/cli/commands.h"
#include "tools/common/study_results.h"

namespace dynapath::cli {

int CompareCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Compares approaches A and B over the repeats of a study (experiment --repeats N)\n"
      "or of run --repeats N: per configuration and metric (AvgSuccessRate,\n"
      "AvgPathLength, InitialTime, AdaptTimePerStep) the paired differences A - B of\n"
      "repeat k against repeat k (same maze, changes and learner seed): their mean,\n"
      "standard deviation, median, IQM, the 95% bootstrap interval of the mean\n"
      "difference and the share of pairs where A's value is greater (ties count\n"
      "half); then over all configurations, the bootstrap stratified by\n"
      "configuration. Prints CSV. See docs/howto/STUDIES.md, Comparing approaches.",
      "dynapath compare");
  runtime::OptionGroup group(app);
  std::string directory, a, b;
  app.add_option("STUDY", directory, "a study directory (or a run --repeats DIR)")->required();
  app.add_option("A", a, "an approach (" + ApproachNamesText() + ")")->required();
  app.add_option("B", b, "another approach")->required();
  bool edge = false;
  group.Flag("--edge", edge, "compare on the edge case (edge_repeats.csv) instead");
  std::optional<std::string> out;
  group.Option("--out", out, "FILE", "also write the CSV to FILE");
  if (int code = runtime::ParseCommandLine(app, args, "dynapath compare"); code >= 0) return code;
  auto usage_error = [](const std::string& message) {
    std::fprintf(stderr, "dynapath compare: %s\n", message.c_str());
    return kExitUsage;
  };
  for (const std::string& name : {a, b}) {
    if (!ParseApproach(name)) {
      return usage_error("unknown approach '" + name + "' (expected one of " + ApproachNamesText() +
                         ")");
    }
  }
  const std::string file = directory + "/" + (edge ? "edge_repeats.csv" : "repeats.csv");
  std::error_code error;
  if (!std::filesystem::exists(file, error)) {
    return usage_error(file +
                       " does not exist (a study or run with --repeats N, N > 1, writes it)");
  }
  Result<std::string> text = ReadTextFile(file);
  if (!text) return usage_error(text.error().message);
  Result<std::string> csv = CompareCsv(*text, a, b);
  if (!csv) return usage_error(file + ": " + csv.error().message);
  if (out) {
    if (Status status = WriteTextFileAtomically(*out, *csv); !status) {
      std::fprintf(stderr, "dynapath compare: %s\n", status.error().message.c_str());
      return kExitFailure;
    }
  }
  std::fputs(csv->c_str(), stdout);
  return 0;
}

}  // namespace dynapath::cli
