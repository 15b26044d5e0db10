// dynapath params: every learner and strategy parameter with its default,
// the report's value, its range, help and the approaches that read it, as
// a table, Markdown (docs/reference/PARAMETERS.md) or a config file of the
// defaults.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "dynapath/parameters.h"
#include "dynapath/planner.h"
#include "runtime/option_group.h"
#include "runtime/parameter_options.h"
#include "tools/cli/commands.h"

namespace dynapath::cli {
namespace {

std::string Readers(ParameterGroup group) {
  std::string text;
  for (const Approach approach : ApproachesReading(group)) {
    text += (text.empty() ? "" : ", ") + ApproachName(approach);
  }
  return text;
}

struct Row {
  std::string name, default_value, report, range, readers, help;
};

std::vector<Row> Rows() {
  std::vector<Row> rows;
  for (const Parameter& p : Parameters()) {
    rows.push_back({p.name, ParameterText(p, p.default_value), ParameterText(p, p.report_value),
                    ParameterText(p, p.min) + " to " + ParameterText(p, p.max), Readers(p.group),
                    std::string(p.help)});
  }
  return rows;
}

std::string Table() {
  const std::vector<Row> rows = Rows();
  size_t name = 9, value = 7, report = 6, range = 5;
  for (const Row& row : rows) {
    name = std::max(name, row.name.size());
    value = std::max(value, row.default_value.size());
    report = std::max(report, row.report.size());
    range = std::max(range, row.range.size());
  }
  auto pad = [](const std::string& text, size_t width) {
    return text + std::string(width - std::min(width, text.size()), ' ');
  };
  std::string text = pad("PARAMETER", name) + "  " + pad("DEFAULT", value) + "  " +
                     pad("REPORT", report) + "  " + pad("RANGE", range) + "  HELP\n";
  for (const Row& row : rows) {
    text += pad(row.name, name) + "  " + pad(row.default_value, value) + "  " +
            pad(row.report, report) + "  " + pad(row.range, range) + "  " + row.help + "\n" +
            std::string(name + value + report + range + 8, ' ') + "read by: " + row.readers + "\n";
  }
  return text;
}

std::string Markdown() {
  std::string text =
      "| parameter | default | report | range | read by | meaning |\n"
      "| --- | --- | --- | --- | --- | --- |\n";
  for (const Row& row : Rows()) {
    text += "| `" + row.name + "` | " + row.default_value + " | " + row.report + " | " + row.range +
            " | " + row.readers + " | " + row.help + " |\n";
  }
  return text;
}

}  // namespace

int ParamsCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Lists the learner and strategy parameters: each is an option of `dynapath run`\n"
      "and `dynapath experiment` (--NAME VALUE) and a key of their config and study\n"
      "files (NAME = VALUE). REPORT is the value `--semantics report` presets (a\n"
      "parameter given overrides it). A run writes every value to params.toml beside\n"
      "its result files.",
      "dynapath params");
  std::string format = "table";
  app.add_option("--format", format, "table, markdown, or toml (a config file of the defaults)")
      ->type_name("FORMAT")
      ->capture_default_str();
  if (int code = runtime::ParseCommandLine(app, args, "dynapath params"); code >= 0) return code;
  if (format == "table") {
    std::fputs(Table().c_str(), stdout);
  } else if (format == "markdown") {
    std::fputs(Markdown().c_str(), stdout);
  } else if (format == "toml") {
    std::fputs(runtime::ParametersToml(PlannerOptions{}).c_str(), stdout);
  } else {
    std::fprintf(stderr,
                 "dynapath params: option --format must be table, markdown or toml, got '%s'\n",
                 format.c_str());
    return kExitUsage;
  }
  return 0;
}

}  // namespace dynapath::cli
