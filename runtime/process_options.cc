#include "runtime/process_options.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "lcmtypes/protocol/channels.h"
#include "lcmtypes/protocol/dispatcher.h"
#include "lcmtypes/protocol/limits.h"
#include "runtime/scenario_options.h"

namespace dynapath::runtime {

void AddProcessOptions(ArgParser& parser, bool run_id_required) {
  parser.AddOption("run-id", "ID",
                   run_id_required ? "the run to join (printed by the coordinator/launcher)"
                                   : "id of the run (channels DYNAPATH/<ID>/...)",
                   run_id_required ? "required" : "generated");
  parser.AddOption("lcm-url", "URL", "LCM provider URL (else $LCM_DEFAULT_URL, else udpm ttl=0)");
  parser.AddOption("secret-file", "PATH",
                   run_id_required
                       ? "the run's secret (mode 600; made by `dynapath secret PATH`)"
                       : "the run's secret, for processes started by hand elsewhere (mode 600)",
                   run_id_required ? "required, or --insecure" : "a new one for this run");
  parser.AddFlag("insecure",
                 "no secret: a well-known key anyone on the network can forge messages with");
  parser.AddOption("grid-cells", "N",
                   "cells of the run's grid at most: caps what the process buffers of "
                   "fragmented messages",
                   std::to_string(protocol::kMaxGridCells));
  parser.AddOption("fault-drop", "P", "testing: drop published messages with probability P", "0");
  parser.AddOption("fault-dup", "P", "testing: send published messages twice with probability P",
                   "0");
}

const std::vector<std::string>& ProcessOptionNames() {
  static const std::vector<std::string> names = {"fault-drop", "fault-dup"};
  return names;
}

namespace {
Result<double> GetProbability(const ArgParser& parser, const std::string& name) {
  const std::string text = parser.Get(name, "0");
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(value >= 0.0 && value < 1.0)) {
    return Error{"option --" + name + " must be a probability in [0, 1), got '" + text + "'"};
  }
  return value;
}
}  // namespace

Result<ProcessSetup> ResolveProcessOptions(const ArgParser& parser, bool run_id_required) {
  ProcessSetup setup;
  if (parser.Has("run-id")) {
    setup.run_id = parser.Get("run-id");
  } else if (run_id_required) {
    return Error{"option --run-id is required"};
  } else {
    setup.run_id = protocol::NewRunId();
  }
  if (Status status = protocol::CheckRunId(setup.run_id); !status) return status.error();
  setup.lcm_url = parser.Get("lcm-url", "");
  Result<double> drop = GetProbability(parser, "fault-drop");
  if (!drop) return drop.error();
  Result<double> dup = GetProbability(parser, "fault-dup");
  if (!dup) return dup.error();
  if (parser.Has("secret-file") && parser.Has("insecure")) {
    return Error{"choose one of --secret-file PATH and --insecure"};
  }
  if (parser.Has("secret-file")) {
    const std::string path = parser.Get("secret-file");
    Result<std::string> text = protocol::ReadSecretText(path);
    if (!text) return text.error();
    // The launcher's pipe (/dev/fd/N): read once, now drained; close the
    // inherited descriptor too, so nothing this process starts inherits it.
    if (path.rfind("/dev/fd/", 0) == 0) {
      char* end = nullptr;
      const long fd = std::strtol(path.c_str() + 8, &end, 10);
      if (end != path.c_str() + 8 && *end == '\0' && fd > STDERR_FILENO)
        close(static_cast<int>(fd));
    }
    Result<protocol::RunKey> key = protocol::KeyFromSecretText(*text);
    if (!key) return Error{"secret file " + path + ": " + key.error().message};
    setup.secret = std::move(*text);
    setup.bus.key = *key;
  } else if (parser.Has("insecure")) {
    setup.bus.key = protocol::InsecureKey();
  } else if (run_id_required) {
    return Error{
        "option --secret-file PATH is required: the run's secret, the same file for every "
        "process of the run (make one with `dynapath secret PATH`), or --insecure to run "
        "without one"};
  } else {
    MakeRunSecret(setup);
  }
  Result<long long> cells =
      parser.GetInt("grid-cells", protocol::kMaxGridCells, 1, protocol::kMaxGridCells);
  if (!cells) return cells.error();
  setup.bus.max_grid_cells = *cells;
  setup.bus.drop_probability = *drop;
  setup.bus.duplicate_probability = *dup;
  if (protocol::IsMemq(protocol::ResolveLcmUrl(setup.lcm_url))) setup.bus.fragment_above = 0;
  return setup;
}

void MakeRunSecret(ProcessSetup& setup) {
  setup.secret = protocol::NewSecretText();
  Result<protocol::RunKey> key = protocol::KeyFromSecretText(setup.secret);
  setup.bus.key = *key;  // a new secret always makes a key
}

void InitProcessLogging(const std::string& name) {
  spdlog::set_default_logger(spdlog::stderr_color_mt(name));
  spdlog::set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
}

int ProcessError(const char* program, const std::string& message, int exit_code) {
  std::fprintf(stderr, "%s: %s\n", program, message.c_str());
  return exit_code;
}

int ParseProcessArgs(ArgParser& parser, const std::vector<std::string>& args, const char* program) {
  if (Status status = parser.Parse(args); !status)
    return ProcessError(program, status.error().message);
  if (parser.WantsHelp()) {
    std::fputs(parser.Help().c_str(), stdout);
    return 0;
  }
  if (Status status = ApplyLogLevel(parser); !status) {
    return ProcessError(program, status.error().message);
  }
  return -1;
}

}  // namespace dynapath::runtime
