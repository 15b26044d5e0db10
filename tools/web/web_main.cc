// dynapath-web: a run's or a service's LCM traffic in a browser and in
// Foxglove, on one HTTP + WebSocket port. Listens as an authenticated
// client of the run (its secret), publishes nothing. Run directly or as
// `dynapath web`.

#include <arpa/inet.h>
#include <malloc.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "protocol/bus.h"
#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "runtime/goal_service.h"
#include "runtime/option_group.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"
#include "tools/common/build_info.h"
#include "tools/web/host_check.h"
#include "tools/web/page_files.h"
#include "tools/web/web_server.h"

namespace {

using namespace dynapath;

constexpr const char* kProgram = "dynapath-web";
constexpr int kExitFailure = 1;

double NowMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

bool IsLoopback(const std::string& address) {
  return address.rfind("127.", 0) == 0 || address == "::1";
}

bool IsIpAddress(const std::string& address) {
  unsigned char bytes[16];
  return inet_pton(AF_INET, address.c_str(), bytes) == 1 ||
         inet_pton(AF_INET6, address.c_str(), bytes) == 1;
}

int Run(const std::vector<std::string>& args) {
  CLI::App app(
      "A run's or a service's live traffic in a browser (the maze, the policy, robots' paths,\n"
      "each step's changes, plots per approach) and in Foxglove (WebSocket subprotocol\n"
      "foxglove.websocket.v1, JSON channels), on one port. Listens on the run's LCM\n"
      "channels with its secret and publishes nothing. Bound to 127.0.0.1 unless --bind\n"
      "says otherwise: watch a remote machine through `ssh -L PORT:127.0.0.1:PORT`.",
      "dynapath web");
  runtime::OptionGroup group(app);
  runtime::ProcessOptions process;
  runtime::DeclareProcessOptions(group, process, /*run_id_required=*/true);
  std::optional<long long> port_given;
  group.Option("--port", port_given, "PORT", "the HTTP and WebSocket port (0: any free one)",
               "required");
  std::string bind = "127.0.0.1";
  group.Option("--bind", bind, "ADDRESS",
               "the address to listen on (0.0.0.0: every interface; anyone who reaches it "
               "sees the run; name the address it is reached by with --allow-host)");
  std::vector<std::string> allow_hosts;
  app.add_option("--allow-host", allow_hosts,
                 "also answer requests for NAME (any port) or NAME:PORT, and WebSockets from "
                 "its pages (repeat for more): a reverse proxy's or a LAN name; other names get "
                 "HTTP 403 (DNS rebinding, other sites' pages)")
      ->type_name("NAME")
      ->allow_extra_args(false);
  long long max_clients_given = 32;
  group.Option("--max-clients", max_clients_given, "N",
               "WebSocket clients at once (1-1000); more are refused with HTTP 503");
  long long max_queue_given = 32;
  group.Option("--max-queue", max_queue_given, "MB",
               "unsent bytes per client (1-1024 MB) before the client is dropped as too slow");
  long long nice_given = 10;
  group.Option("--nice", nice_given, "N",
               "raise the nice value of the thread that serves the pages by N (0-19; 0 keeps "
               "it): it yields the CPU to the run it watches when they share cores (the thread "
               "that receives the run's messages keeps its priority)");
  std::optional<double> resolution;
  std::optional<std::string> origin;
  group.Option("--resolution", resolution, "METRES",
               "metres per cell of the service's map, to draw obstacle points in metres from "
               "the start (else from the service's first goal reply, which gives its frame)");
  group.Option("--origin", origin, "X,Y",
               "metres of the bottom-left corner of the map's bottom-left cell (with "
               "--resolution; default 0,0)");
  runtime::LogOptions log;
  runtime::DeclareLogOptions(group, log);
  if (int code = runtime::ParseCommandLine(app, args, kProgram); code >= 0) return code;
  if (Status status = runtime::ApplyLogLevel(log); !status) {
    return runtime::ProcessError(kProgram, status.error().message);
  }
  if (process.fault_drop != 0.0 || process.fault_dup != 0.0 || process.fragment_size) {
    return runtime::ProcessError(
        kProgram,
        "--fault-drop, --fault-dup and --fragment-size do not apply: web publishes "
        "nothing");
  }
  Result<runtime::ProcessSetup> setup =
      runtime::ResolveProcessOptions(process, /*run_id_required=*/true);
  if (!setup) return runtime::ProcessError(kProgram, setup.error().message);
  if (!port_given) return runtime::ProcessError(kProgram, "option --port is required");
  Result<long long> port = runtime::InRange("port", port_given, 0, 0, 65535);
  if (!port) return runtime::ProcessError(kProgram, port.error().message);
  if (!IsIpAddress(bind)) {
    return runtime::ProcessError(
        kProgram, "option --bind needs an IPv4 or IPv6 address (127.0.0.1, ::1, 0.0.0.0), got '" +
                      bind + "'");
  }
  for (const std::string& name : allow_hosts) {
    if (std::string why = web::AllowHostError(name); !why.empty()) {
      return runtime::ProcessError(kProgram, why);
    }
  }
  Result<long long> max_clients = runtime::InRange("max-clients", max_clients_given, 0, 1, 1000);
  if (!max_clients) return runtime::ProcessError(kProgram, max_clients.error().message);
  Result<long long> max_queue = runtime::InRange("max-queue", max_queue_given, 0, 1, 1024);
  if (!max_queue) return runtime::ProcessError(kProgram, max_queue.error().message);
  Result<long long> nice_by = runtime::InRange("nice", nice_given, 0, 0, 19);
  if (!nice_by) return runtime::ProcessError(kProgram, nice_by.error().message);

  web::ServerOptions options;
  if (origin && !resolution) {
    return runtime::ProcessError(kProgram, "option --origin needs --resolution");
  }
  if (resolution) {
    // The frame's rows and columns come with the run's grid; only its
    // metres are checked here, by the rule serve's are.
    Result<MapFrame> frame = runtime::ResolveMapFrame(std::nullopt, resolution, origin, Grid(1, 1));
    if (!frame) return runtime::ProcessError(kProgram, frame.error().message);
    options.frame_resolution = frame->resolution;
    options.frame_origin_x = frame->origin_x;
    options.frame_origin_y = frame->origin_y;
  }
  options.bind = bind;
  options.port = static_cast<int>(*port);
  options.allowed_hosts = allow_hosts;
  options.max_clients = static_cast<int>(*max_clients);
  options.max_queue_bytes = *max_queue << 20;
  options.nice = static_cast<int>(*nice_by);
  options.run_id = setup->run_id;
  options.version = cli::kDynapathVersion;
  options.files = web::PageFiles();

  protocol::BusOptions bus_options = setup->bus;
  bus_options.repair = false;  // a NACK would be a publish: a listener only
  const std::string url = protocol::ResolveLcmUrl(setup->lcm_url);
  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(url);
  if (!lcm) return runtime::ProcessError(kProgram, lcm.error().message, kExitFailure);

  web::WebServer server(options);
  if (Status status = server.Start(); !status) {
    return runtime::ProcessError(kProgram, status.error().message, kExitFailure);
  }
  if (!IsLoopback(bind)) {
    spdlog::warn(
        "listening on {}: anyone who reaches this address sees the run (requests must name "
        "{}localhost, 127.0.0.1, [::1]{})",
        bind, bind == "0.0.0.0" || bind == "::" ? "" : "it, ",
        allow_hosts.empty() ? "; --allow-host NAME adds a name" : " or an --allow-host name");
  }
  protocol::Bus bus(**lcm, setup->run_id, bus_options);
  namespace ch = protocol::channel;
  bus.Subscribe<grid_t>(ch::kEnvGrid, [&](grid_t& m) { server.Grid(std::move(m), NowMs()); });
  bus.Subscribe<changes_t>(ch::kEnvChanges,
                           [&](changes_t& m) { server.Changes(std::move(m), NowMs()); });
  bus.Subscribe<step_report_t>(ch::kReport, [&](step_report_t& m) { server.Report(m, NowMs()); });
  bus.Subscribe<policy_t>(ch::kPolicy, [&](policy_t& m) { server.Policy(std::move(m), NowMs()); });
  bus.Subscribe<path_request_t>(ch::kPathRequest,
                                [&](path_request_t& m) { server.Request(m, NowMs()); });
  bus.Subscribe<path_reply_t>(ch::kPathReply,
                              [&](path_reply_t& m) { server.Paths(std::move(m), NowMs()); });
  bus.Subscribe<goal_request_t>(ch::kGoalRequest,
                                [&](goal_request_t& m) { server.GoalRequest(m, NowMs()); });
  bus.Subscribe<goal_reply_t>(ch::kGoalReply,
                              [&](goal_reply_t& m) { server.GoalReply(m, NowMs()); });
  bus.Subscribe<obstacle_update_t>(
      ch::kMapUpdates, [&](obstacle_update_t& m) { server.Updates(std::move(m), NowMs()); });
  bus.Subscribe<obstacle_points_t>(
      ch::kMapPoints, [&](obstacle_points_t& m) { server.Points(std::move(m), NowMs()); });
  const std::atomic<bool>& stop = protocol::StopOnSignals();
  {
    protocol::Dispatcher dispatcher(**lcm);
    const std::string shown = bind.find(':') != std::string::npos ? "[" + bind + "]" : bind;
    spdlog::info("serving run {} at http://{}:{}/ (Foxglove: ws://{}:{}), LCM {}", setup->run_id,
                 shown, server.port(), shown, server.port(), url);
    while (!stop.load()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  server.Stop();
  const web::ServerCounters c = server.counters();
  spdlog::info(
      "stopped: {} messages taken ({} dropped while behind), {} clients served, {} refused "
      "(full), {} refused (Host or Origin not this server), {} dropped as slow, {} closed for "
      "bad input; {}",
      c.messages_in, c.inputs_dropped, c.accepted, c.refused_full, c.refused_host, c.dropped_slow,
      c.closed_bad_input, bus.TrafficSummary());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Large buffers (a 1000x1000 policy is 3 MB as it arrives, 1 MB packed,
  // 1 MB again as a frame) come from the heap and stay there when freed,
  // instead of being mapped and unmapped each time: memory touched once is
  // reused, where a fresh mapping costs a page fault per 4 KB (3-10 ms of
  // CPU per MB on the measured virtual machine, 0.03-0.06 ms reused). The
  // server's peak stays resident.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  dynapath::runtime::InitProcessLogging(kProgram);
  try {
    return Run(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const std::exception& error) {
    return dynapath::runtime::ProcessError(kProgram, error.what(), kExitFailure);
  }
}
