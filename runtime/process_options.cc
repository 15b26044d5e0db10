#include "runtime/process_options.h"

#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "protocol/limits.h"
#include "runtime/scenario_options.h"

namespace dynapath::runtime {

void DeclareLcmUrlOption(OptionGroup& group, std::string& lcm_url) {
  group.Option("--lcm-url", lcm_url, "URL",
               "LCM provider URL (else $LCM_DEFAULT_URL, else udpm ttl=0)");
}

void DeclareRunNetworkOptions(OptionGroup& group, ProcessOptions& o, bool run_id_required) {
  group.Option("--run-id", o.run_id, "ID",
               run_id_required ? "the run to join (printed by the coordinator/launcher)"
                               : "id of the run (channels DYNAPATH/<ID>/...)",
               run_id_required ? "required" : "generated");
  DeclareLcmUrlOption(group, o.lcm_url);
  group.Option("--secret-file", o.secret_file, "PATH",
               run_id_required
                   ? "the run's secret (mode 600; made by `dynapath secret PATH`)"
                   : "the run's secret, for processes started by hand elsewhere (mode 600)",
               run_id_required ? "required, or --insecure" : "a new one for this run");
  group.Flag("--insecure", o.insecure,
             "no secret: a well-known key anyone on the network can forge messages with");
}

void DeclareProcessOptions(OptionGroup& group, ProcessOptions& o, bool run_id_required) {
  DeclareRunNetworkOptions(group, o, run_id_required);
  group.Option("--grid-cells", o.grid_cells, "N",
               "cells of the run's grid at most: caps what the process buffers of "
               "fragmented messages");
  group.Option("--fragment-size", o.fragment_size, "BYTES",
               "payload bytes per fragment of large messages (1024-60000)",
               "one Ethernet frame when the URL's ttl > 0, else 60000");
  group.Option("--fault-drop", o.fault_drop, "P",
               "testing: drop published messages with probability P");
  group.Option("--fault-dup", o.fault_dup, "P",
               "testing: send published messages twice with probability P");
}

namespace {
// Data pieces per parity piece on a LAN (BusOptions::parity_group).
constexpr int kLanParityGroup = 8;

Result<double> CheckProbability(const std::string& name, double value) {
  if (!(value >= 0.0 && value < 1.0)) {
    return Error::Option(name, "must be a probability in [0, 1), got " + fmt::format("{}", value));
  }
  return value;
}
}  // namespace

Result<ProcessSetup> ResolveProcessOptions(const ProcessOptions& o, bool run_id_required) {
  ProcessSetup setup;
  if (o.run_id) {
    setup.run_id = *o.run_id;
  } else if (run_id_required) {
    return Error::Option("run-id", "is required");
  } else {
    setup.run_id = protocol::NewRunId();
  }
  if (Status status = protocol::CheckRunId(setup.run_id); !status) return status.error();
  setup.lcm_url = o.lcm_url;
  Result<double> drop = CheckProbability("fault-drop", o.fault_drop);
  if (!drop) return drop.error();
  Result<double> dup = CheckProbability("fault-dup", o.fault_dup);
  if (!dup) return dup.error();
  if (o.secret_file && o.insecure) {
    return Error{"choose one of --secret-file PATH and --insecure"};
  }
  if (o.secret_file) {
    const std::string& path = *o.secret_file;
    Result<std::string> text = protocol::ReadSecretText(path);
    if (!text) return text.error();
    // The launcher's pipe (/dev/fd/N): read once, now drained.
    CloseInheritedFd(path);
    Result<protocol::RunKey> key = protocol::KeyFromSecretText(*text);
    if (!key) return key.error().Prefixed("secret file " + path + ": ");
    setup.secret = std::move(*text);
    setup.bus.key = *key;
  } else if (o.insecure) {
    setup.bus.key = protocol::InsecureKey();
  } else if (run_id_required) {
    return Error::Option("secret-file",
                         "PATH is required: the run's secret, the same file for every process of "
                         "the run (make one with `dynapath secret PATH`), or --insecure to run "
                         "without one");
  } else {
    MakeRunSecret(setup);
  }
  Result<long long> cells = InRange("grid-cells", o.grid_cells, 0, 1, protocol::kMaxGridCells);
  if (!cells) return cells.error();
  setup.bus.max_grid_cells = *cells;
  setup.bus.drop_probability = *drop;
  setup.bus.duplicate_probability = *dup;
  const std::string url = protocol::ResolveLcmUrl(setup.lcm_url);
  if (protocol::IsMemq(url)) setup.bus.fragment_above = 0;
  Result<long long> fragment_size =
      InRange("fragment-size", o.fragment_size, protocol::DefaultFragmentSize(url), 1024, 60000);
  if (!fragment_size) return fragment_size.error();
  setup.bus.fragment_size = static_cast<int>(*fragment_size);
  setup.fragment_size = o.fragment_size;
  // Messages above one piece are fragmented (a datagram above the MTU
  // would be split by IP, and a lost frame would lose all of it).
  if (setup.bus.fragment_above > 0 &&
      (o.fragment_size || *fragment_size == protocol::kFrameFragmentSize)) {
    setup.bus.fragment_above = std::min(setup.bus.fragment_above, setup.bus.fragment_size);
  }
  // Frame-sized pieces mean a LAN, where a lost frame is a lost piece: one
  // parity piece per 8 (12.5% more frames) rebuilds one lost piece of each
  // group without a NACK round trip.
  if (setup.bus.fragment_above > 0 && *fragment_size == protocol::kFrameFragmentSize) {
    setup.bus.parity_group = kLanParityGroup;
  }
  return setup;
}

ProcessOptions ChildProcessOptions(const ProcessSetup& setup) {
  ProcessOptions options;
  options.run_id = setup.run_id;
  options.lcm_url = setup.lcm_url;
  options.grid_cells = setup.bus.max_grid_cells;
  options.fragment_size = setup.fragment_size;
  options.fault_drop = setup.bus.drop_probability;
  options.fault_dup = setup.bus.duplicate_probability;
  return options;
}

void DeclareThreadOptions(OptionGroup& group, ThreadOptions& options) {
  group.Option("--threads", options.threads, "N",
               "worker threads (of this process; with --agents or --embedded, in all)",
               "hardware threads");
}

Result<int> ResolveThreads(const ThreadOptions& options) {
  const long long hardware = std::max(1u, std::thread::hardware_concurrency());
  Result<long long> threads = InRange("threads", options.threads, hardware, 1, kMaxThreads);
  if (!threads) return threads.error();
  return static_cast<int>(*threads);
}

void DeclareModeOptions(OptionGroup& group, ModeOptions& o) {
  group.Flag("--local", o.local, "everything in this process on a thread pool (default)");
  group.Option("--agents", o.agents, "N",
               "train on N agent processes over LCM (run: with envsim and a coordinator process, "
               "in a private network namespace or on --lcm-url's network; serve: on the "
               "service's network)");
  group.Flag("--embedded", o.embedded,
             "the processes (run: envsim, coordinator and agents; serve: the agents) as threads "
             "of this process over memq://");
}

Result<RunMode> ResolveMode(const ModeOptions& o, long long max_agents) {
  if (o.local && (o.agents || o.embedded)) {
    return Error{"choose one of --local, --agents N and --embedded"};
  }
  RunMode mode;
  Result<long long> agents = InRange("agents", o.agents, 1, 1, max_agents);
  if (!agents) return agents.error();
  mode.agents = static_cast<int>(*agents);
  mode.kind = o.embedded ? RunMode::kEmbedded : o.agents ? RunMode::kAgents : RunMode::kLocal;
  return mode;
}

void DeclareWaitOptions(OptionGroup& group, WaitOptions& options) {
  group.Option("--wait", options.wait, "SECONDS",
               "how long to wait for the other processes of the run to appear (the "
               "coordinator: its agents and envsim; the others: the coordinator), and (agents, "
               "envsim) for a silent coordinator to be heard again");
}

Result<double> ResolveWaitSeconds(const WaitOptions& options) {
  Result<long long> wait = InRange("wait", options.wait, 0, 1, 86400);
  if (!wait) return wait.error();
  return static_cast<double>(*wait);
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

namespace {

int ParseProcessArgs(CLI::App& app, const LogOptions& log, int argc, char** argv,
                     const char* program) {
  AddConfigOption(app);
  std::vector<std::string> args(argv + 1, argv + argc);
  if (int code = ParseCommandLine(app, std::move(args), program); code >= 0) return code;
  // The launcher's pipe (/dev/fd/N): read once, now drained.
  if (const CLI::Option* config = app.get_config_ptr(); config != nullptr && config->count() > 0) {
    CloseInheritedFd(config->as<std::string>());
  }
  if (Status status = ApplyLogLevel(log); !status) {
    return ProcessError(program, status.error().message);
  }
  return -1;
}

}  // namespace

int ParseProcessCommandLine(const char* program, const std::string& description,
                            const std::function<void(OptionGroup&)>& declare, const LogOptions& log,
                            int argc, char** argv) {
  CLI::App app(description, program);
  OptionGroup group(app);
  declare(group);
  return ParseProcessArgs(app, log, argc, argv, program);
}

}  // namespace dynapath::runtime
