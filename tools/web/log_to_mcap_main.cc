// dynapath-log-to-mcap: an LCM log of a run or a service as MCAP, for
// Foxglove and Lichtblick. Run directly or as `dynapath log-to-mcap`.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "runtime/option_group.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"
#include "tools/web/mcap_writer.h"

namespace {

constexpr const char* kProgram = "dynapath-log-to-mcap";
constexpr int kExitFailure = 1;

int Run(const std::vector<std::string>& args) {
  CLI::App app(
      "Writes the messages of an LCM log (dynapath run --log, lcm-logger) that dynapath web\n"
      "shows as MCAP: the channels /grid, /policy, /report, /changes, /paths,\n"
      "/map_updates and /map_points, JSON with JSON schemas, as `dynapath web` sends them\n"
      "to Foxglove.\n"
      "Fragmented messages are reassembled; undecodable or invalid ones are skipped and\n"
      "counted.",
      "dynapath log-to-mcap");
  std::string in, out;
  app.add_option("IN", in, "the LCM log")->required();
  app.add_option("OUT", out, "the MCAP file to write (replaced)")->required();
  dynapath::runtime::OptionGroup group(app);
  dynapath::runtime::LogOptions log;
  dynapath::runtime::DeclareLogOptions(group, log);
  if (int code = dynapath::runtime::ParseCommandLine(app, args, kProgram); code >= 0) return code;
  if (dynapath::Status status = dynapath::runtime::ApplyLogLevel(log); !status) {
    return dynapath::runtime::ProcessError(kProgram, status.error().message);
  }
  dynapath::Result<dynapath::web::McapExport> result = dynapath::web::LogToMcap(in, out);
  if (!result) {
    std::remove(out.c_str());
    return dynapath::runtime::ProcessError(kProgram, result.error().message, kExitFailure);
  }
  spdlog::info(
      "{}: {} messages from {} events ({} skipped: other channels or pieces; {} "
      "dropped: invalid)",
      out, result->messages, result->events, result->skipped, result->dropped);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  dynapath::runtime::InitProcessLogging(kProgram);
  try {
    return Run(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const std::exception& error) {
    return dynapath::runtime::ProcessError(kProgram, error.what(), kExitFailure);
  }
}
