// dynapath compare STUDY A B: the paired difference of two approaches over
// the repeats of a study (or of `dynapath run --repeats`), with its
// bootstrap interval (study/study_results.h, CompareCsv): a table on
// a terminal, CSV otherwise (or with --csv), and a figure with --plot.

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "dynapath/approach.h"
#include "dynapath/text_file.h"
#include "runtime/option_group.h"
#include "runtime/output_check.h"
#include "study/study_results.h"
#include "tools/cli/commands.h"
#include "tools/common/compare_table.h"

namespace dynapath::cli {

namespace {

// Draws `csv` into `figure` with dynapath-plot (--compare CSV --out FILE),
// through a temporary file beside the figure.
int PlotComparison(const std::string& csv, const std::string& figure) {
  const std::filesystem::path target(figure);
  const std::filesystem::path directory =
      target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  std::string temporary = (directory / ".dynapath-compare-XXXXXX.csv").string();
  const int fd = mkstemps(temporary.data(), 4);
  if (fd < 0) {
    std::fprintf(stderr, "dynapath compare: cannot write a temporary file in %s\n",
                 directory.c_str());
    return kExitFailure;
  }
  close(fd);
  int status = kExitFailure;
  if (Status written = WriteTextFileAtomically(temporary, csv); !written) {
    std::fprintf(stderr, "dynapath compare: %s\n", written.error().message.c_str());
  } else {
    std::fflush(stdout);
    status = RunSibling("dynapath-plot", {"--compare", temporary, "--out", figure},
                        "it is installed with the build from tools/plot");
  }
  std::error_code ignored;
  std::filesystem::remove(temporary, ignored);
  return status;
}

}  // namespace

int CompareCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Compares approaches A and B over the repeats of a study (experiment --repeats N)\n"
      "or of run --repeats N: per configuration and metric (AvgSuccessRate,\n"
      "AvgPathLength, InitialTime, AdaptTimePerStep) the paired differences A - B of\n"
      "repeat k against repeat k (same maze, changes and learner seed): their mean,\n"
      "standard deviation, median, IQM, the 95% bootstrap interval of the mean\n"
      "difference and the share of pairs where A's value is greater (ties count\n"
      "half); then over all configurations, the bootstrap stratified by\n"
      "configuration. Prints a table on a terminal and CSV otherwise (into a pipe or\n"
      "a file, or with --csv); --plot FILE draws the differences. See\n"
      "docs/howto/STUDIES.md, Comparing approaches.",
      "dynapath compare");
  runtime::OptionGroup group(app);
  std::string directory, a, b;
  app.add_option("STUDY", directory, "a study directory (or a run --repeats DIR)")->required();
  app.add_option("A", a, "an approach (" + ApproachNamesText() + ")")->required();
  app.add_option("B", b, "another approach")->required();
  bool edge = false;
  group.Flag("--edge", edge, "compare on the edge case (edge_repeats.csv) instead");
  std::optional<std::string> out, plot;
  group.Option("--out", out, "FILE", "also write the CSV to FILE");
  bool csv_wanted = false, table_wanted = false;
  group.Flag("--csv", csv_wanted, "print CSV even on a terminal (the default into a pipe or file)");
  group.Flag("--table", table_wanted, "print the table even into a pipe or file");
  group.Option("--plot", plot, "FILE",
               "also draw the mean differences with their 95% intervals, one panel per metric, "
               "into FILE (.png, .svg or .pdf; by dynapath plot)");
  if (int code = runtime::ParseCommandLine(app, args, "dynapath compare"); code >= 0) return code;
  auto usage_error = [](const std::string& message) {
    std::fprintf(stderr, "dynapath compare: %s\n", message.c_str());
    return kExitUsage;
  };
  if (csv_wanted && table_wanted) return usage_error("--csv and --table exclude each other");
  if (plot) {
    const std::string extension = std::filesystem::path(*plot).extension().string();
    if (extension != ".png" && extension != ".svg" && extension != ".pdf") {
      return usage_error("--plot " + *plot + ": the file must end in .png, .svg or .pdf");
    }
    if (Status status = runtime::CheckOutputFile(*plot, "plot"); !status) {
      return usage_error(status.error().message);
    }
  }
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
  Result<std::string> csv = study::CompareCsv(*text, a, b);
  if (!csv) return usage_error(file + ": " + csv.error().message);
  if (out) {
    if (Status status = WriteTextFileAtomically(*out, *csv); !status) {
      std::fprintf(stderr, "dynapath compare: %s\n", status.error().message.c_str());
      return kExitFailure;
    }
  }
  const bool table = table_wanted || (!csv_wanted && isatty(STDOUT_FILENO));
  if (table) {
    Result<std::string> rendered = CompareTable(*csv);
    if (!rendered) {
      std::fprintf(stderr, "dynapath compare: %s\n", rendered.error().message.c_str());
      return kExitFailure;
    }
    std::fputs(rendered->c_str(), stdout);
  } else {
    std::fputs(csv->c_str(), stdout);
  }
  if (plot) return PlotComparison(*csv, *plot);
  return 0;
}

}  // namespace dynapath::cli
