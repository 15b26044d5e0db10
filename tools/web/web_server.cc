#include "tools/web/web_server.h"

#define ASIO_STANDALONE 1
#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <asio/steady_timer.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>
#include <vector>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include "tools/web/host_check.h"
#include "tools/web/messages.h"

namespace dynapath::web {
namespace {

using Server = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;
using Opcode = websocketpp::frame::opcode::value;

constexpr const char* kFoxgloveSubprotocol = "foxglove.websocket.v1";
constexpr size_t kMaxSubscriptions = 256;

struct Client {
  bool foxglove = false;
  std::map<uint32_t, uint32_t> subscriptions;  // subscription id -> channel id
};

// A policy as every page client holds it.
struct ApproachState {
  FrameHeader header;
  std::vector<uint8_t> cells;
};

double WallMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Keeps a page message (JSON text) for new clients: at most `cap`, the
// older half dropped when full.
void KeepForNewClients(std::vector<std::string>& kept, std::string text, int cap) {
  if (static_cast<int>(kept.size()) >= cap) {
    kept.erase(kept.begin(), kept.begin() + static_cast<std::ptrdiff_t>(kept.size() / 2));
  }
  kept.push_back(std::move(text));
}

// {"t":"<type>","<key>":[kept...]}: the kept messages as one.
std::string HistoryJson(const char* type, const char* key, const std::vector<std::string>& kept) {
  std::string history = std::string("{\"t\":\"") + type + "\",\"" + key + "\":[";
  for (size_t i = 0; i < kept.size(); ++i) {
    if (i > 0) history += ',';
    history += kept[i];
  }
  return history + "]}";
}

// Raises the calling thread's nice value by `by`, at most to 19 (Linux
// keeps one per thread; raising one's own needs no privilege).
void LowerThreadPriority(int by) {
  const pid_t thread = gettid();
  errno = 0;
  const int current = getpriority(PRIO_PROCESS, static_cast<id_t>(thread));
  if ((current == -1 && errno != 0) ||
      setpriority(PRIO_PROCESS, static_cast<id_t>(thread), std::min(19, current + by)) != 0) {
    spdlog::warn("web server: cannot lower its thread's priority: {}", std::strerror(errno));
    return;
  }
  spdlog::info("web server: serving the pages at nice {}", std::min(19, current + by));
}

}  // namespace

struct WebServer::Impl {
  explicit Impl(ServerOptions o)
      : options(std::move(o)),
        path_latency(options.max_pending_requests),
        goal_latency(options.max_pending_requests) {
    if (options.frame_resolution > 0) {
      map_frame =
          FrameJson(options.frame_resolution, options.frame_origin_x, options.frame_origin_y);
    }
  }

  ServerOptions options;
  Server server;
  // Closes the service's latency windows each quarter second (I/O thread).
  // After `server`: destroyed before the io_service it was made on.
  std::unique_ptr<asio::steady_timer> window_timer;
  std::thread thread;
  std::atomic<int> bound_port{0};
  std::atomic<int64_t> pending_bytes{0};
  std::atomic<bool> started{false};

  // I/O thread only.
  std::map<Handle, Client, std::owner_less<Handle>> clients;
  // Handshakes accepted whose connection is not open yet: they count
  // against the cap too (a burst of connections is validated before any
  // of them opens).
  std::set<Handle, std::owner_less<Handle>> opening;
  bool have_maze = false;
  FrameHeader maze_header;
  std::vector<uint8_t> maze;
  std::vector<std::string> approach_order;
  std::map<std::string, ApproachState> approaches;
  std::vector<std::string> reports;
  ServiceLatency path_latency;               // PATH_REQUEST to PATH_REPLY
  ServiceLatency goal_latency;               // GOAL_REQUEST to GOAL_REPLY
  std::vector<std::string> service_windows;  // ServiceJson texts of both, for new clients
  std::vector<uint32_t> changed_cells;  // TakePolicy's, kept for its capacity
  // FrameJson of the latest goal reply's frame, else --resolution's ("" none).
  std::string map_frame;

  mutable std::mutex counters_mutex;
  ServerCounters counters;

  void Count(int64_t ServerCounters::*field, int64_t by = 1) {
    std::lock_guard lock(counters_mutex);
    counters.*field += by;
  }

  // Runs `work` on the I/O thread, unless too much waits already.
  template <class F>
  void Post(int64_t bytes, F work) {
    if (!started) return;
    Count(&ServerCounters::messages_in);
    if (pending_bytes.load() + bytes > options.max_pending_bytes) {
      Count(&ServerCounters::inputs_dropped);
      return;
    }
    pending_bytes += bytes;
    asio::post(server.get_io_service(), [this, bytes, work = std::move(work)]() mutable {
      pending_bytes -= bytes;
      work();
    });
  }

  // Sends to one client unless its queue is above the cap; then it is
  // listed in `slow` (dropped after the loop).
  // `prepared`, when given, is the whole frame already (see Prepare): sent
  // as it is, not copied and framed again for this client.
  bool SendTo(const Handle& handle, const void* data, size_t size, Opcode opcode,
              std::vector<Handle>& slow, Server::message_ptr* prepared = nullptr) {
    websocketpp::lib::error_code ec;
    Server::connection_ptr connection = server.get_con_from_hdl(handle, ec);
    if (ec || !connection) return false;
    // A queue already above the cap: the client is not keeping up. (One
    // message larger than the cap still goes to a client with an empty
    // queue: a 1000x1000 maze's whole policy is 1 MB.)
    if (static_cast<int64_t>(connection->get_buffered_amount()) > options.max_queue_bytes) {
      slow.push_back(handle);
      return false;
    }
    if (prepared != nullptr) {
      if (!*prepared) *prepared = Prepare(*connection, data, size, opcode);
      ec = connection->send(*prepared);
    } else {
      ec = connection->send(data, size, opcode);
    }
    if (ec) return false;
    Count(&ServerCounters::frames_sent);
    return true;
  }

  // One server frame (unmasked, uncompressed: the same bytes for every
  // client), marked prepared so that each connection queues this one
  // message instead of copying and framing the payload again.
  static Server::message_ptr Prepare(Server::connection_type& connection, const void* data,
                                     size_t size, Opcode opcode) {
    Server::message_ptr message = connection.get_message(opcode, size);
    message->append_payload(data, size);
    const websocketpp::frame::basic_header header(opcode, size, /*fin=*/true, /*mask=*/false);
    message->set_header(
        websocketpp::frame::prepare_header(header, websocketpp::frame::extended_header(size)));
    message->set_prepared(true);
    return message;
  }

  void DropSlow(const std::vector<Handle>& slow) {
    for (const Handle& handle : slow) {
      if (clients.find(handle) == clients.end()) continue;  // dropped already
      websocketpp::lib::error_code ec;
      Server::connection_ptr connection = server.get_con_from_hdl(handle, ec);
      if (ec || !connection) continue;
      Count(&ServerCounters::dropped_slow);
      spdlog::warn("dropped a slow client ({} bytes unsent)", connection->get_buffered_amount());
      // Not a close handshake: that would wait behind the unsent bytes.
      asio::error_code ignored;
      connection->get_raw_socket().shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
      connection->get_raw_socket().close(ignored);
      // Gone now, not when websocketpp's close handler runs later: until
      // then the next message would find it slow again, count it again
      // and queue more for it.
      OnClose(handle);
    }
  }

  // To every page client: one frame, made once.
  void ToPages(const void* data, size_t size, Opcode opcode) {
    std::vector<Handle> slow;
    Server::message_ptr prepared;
    for (auto& [handle, client] : clients) {
      if (!client.foxglove) SendTo(handle, data, size, opcode, slow, &prepared);
    }
    DropSlow(slow);
  }

  // `payload` is made only when some Foxglove client subscribed to `topic`.
  template <class MakePayload>
  void ToFoxglove(std::string_view topic, double received_ms, MakePayload make) {
    const uint32_t channel = FoxgloveChannelId(topic);
    std::string payload;
    bool made = false;
    std::vector<Handle> slow;
    const uint64_t time_ns = static_cast<uint64_t>(received_ms * 1e6);
    for (auto& [handle, client] : clients) {
      if (!client.foxglove) continue;
      for (const auto& [subscription, subscribed] : client.subscriptions) {
        if (subscribed != channel) continue;
        if (!made) {
          payload = make();
          made = true;
        }
        const std::string frame = MessageDataFrame(subscription, time_ns, payload);
        SendTo(handle, frame.data(), frame.size(), websocketpp::frame::opcode::binary, slow);
      }
    }
    DropSlow(slow);
  }

  void SendText(const Handle& handle, const std::string& text) {
    std::vector<Handle> slow;
    SendTo(handle, text.data(), text.size(), websocketpp::frame::opcode::text, slow);
    DropSlow(slow);
  }

  void SendBinary(const Handle& handle, const std::vector<uint8_t>& bytes) {
    std::vector<Handle> slow;
    SendTo(handle, bytes.data(), bytes.size(), websocketpp::frame::opcode::binary, slow);
    DropSlow(slow);
  }

  void CloseBadClient(const Handle& handle, websocketpp::close::status::value code,
                      const std::string& why) {
    Count(&ServerCounters::closed_bad_input);
    spdlog::warn("closing a client: {}", why);
    websocketpp::lib::error_code ec;
    server.close(handle, code, why.substr(0, 120), ec);
  }

  // --- handlers (I/O thread) ---

  // False (and a 403 set on the connection) unless the request's Host
  // header, and its Origin header when `check_origin` and it has one,
  // name this server: DNS rebinding and other sites' pages are refused.
  bool FromAllowedHost(const Server::connection_ptr& connection, bool check_origin) {
    const HostPolicy policy{options.bind, bound_port.load(), options.allowed_hosts};
    const std::string host = connection->get_request_header("Host");
    const std::string origin = check_origin ? connection->get_request_header("Origin") : "";
    const bool host_ok = HostAllowed(host, policy);
    if (host_ok && (origin.empty() || OriginAllowed(origin, policy))) return true;
    int64_t refused;
    {
      std::lock_guard lock(counters_mutex);
      refused = ++counters.refused_host;
    }
    // Every refusal counted, the first ones logged (a hostile page may retry).
    if (refused <= 10) {
      std::string shown = host_ok ? "Origin " + origin : "Host " + host;
      shown.resize(std::min<size_t>(shown.size(), 120));
      for (char& c : shown) {
        if (c < 0x20 || c > 0x7e) c = '?';
      }
      spdlog::warn("refused a request for {} (not this server; --allow-host NAME allows a name){}",
                   shown, refused == 10 ? "; further refusals are counted, not logged" : "");
    }
    connection->set_status(websocketpp::http::status_code::forbidden);
    connection->append_header("Content-Type", "text/plain");
    connection->set_body(
        host_ok ? "forbidden: a WebSocket from another site's page; start dynapath web with "
                  "--allow-host NAME to allow that site\n"
                : "forbidden: this server answers requests for localhost, 127.0.0.1, [::1] "
                  "or its address on its port; start dynapath web with --allow-host NAME to "
                  "allow another name\n");
    return false;
  }

  bool OnValidate(Handle handle) {
    Server::connection_ptr connection = server.get_con_from_hdl(handle);
    // No Nagle: a step's small messages (its report, its policy's few
    // changed cells) leave at once instead of waiting until the one before
    // is acknowledged (which a client may delay).
    asio::error_code ignored;
    connection->get_raw_socket().set_option(asio::ip::tcp::no_delay(true), ignored);
    if (!FromAllowedHost(connection, /*check_origin=*/true)) return false;
    if (static_cast<int>(clients.size() + opening.size()) >= options.max_clients) {
      Count(&ServerCounters::refused_full);
      connection->set_status(websocketpp::http::status_code::service_unavailable);
      connection->set_body("too many clients (--max-clients " +
                           std::to_string(options.max_clients) + ")\n");
      return false;
    }
    const std::vector<std::string>& asked = connection->get_requested_subprotocols();
    if (!asked.empty()) {
      bool foxglove = false;
      for (const std::string& protocol : asked) foxglove |= protocol == kFoxgloveSubprotocol;
      if (!foxglove) {
        Count(&ServerCounters::refused_handshake);
        connection->set_status(websocketpp::http::status_code::bad_request);
        connection->set_body(std::string("unknown subprotocol: this server speaks ") +
                             kFoxgloveSubprotocol + " or none\n");
        return false;
      }
      connection->select_subprotocol(kFoxgloveSubprotocol);
    }
    opening.insert(handle);
    return true;
  }

  void OnOpen(Handle handle) {
    Server::connection_ptr connection = server.get_con_from_hdl(handle);
    opening.erase(handle);
    Client client;
    client.foxglove = connection->get_subprotocol() == kFoxgloveSubprotocol;
    clients[handle] = client;
    {
      std::lock_guard lock(counters_mutex);
      ++counters.accepted;
      counters.clients = static_cast<int64_t>(clients.size());
      if (client.foxglove) ++counters.foxglove_clients;
    }
    if (client.foxglove) {
      nlohmann::json info = {{"op", "serverInfo"},
                             {"name", "dynapath web " + options.version},
                             {"capabilities", nlohmann::json::array()},
                             {"supportedEncodings", nlohmann::json::array()},
                             {"metadata", {{"run_id", options.run_id}}}};
      SendText(handle, info.dump());
      nlohmann::json channels = nlohmann::json::array();
      for (const FoxgloveChannel& channel : FoxgloveChannels()) {
        channels.push_back({{"id", channel.id},
                            {"topic", channel.topic},
                            {"encoding", "json"},
                            {"schemaName", channel.schema_name},
                            {"schema", channel.schema},
                            {"schemaEncoding", "jsonschema"}});
      }
      SendText(handle, nlohmann::json{{"op", "advertise"}, {"channels", channels}}.dump());
      return;
    }
    SendText(handle, HelloJson(options.run_id, options.version, options.max_clients));
    if (have_maze) SendBinary(handle, FullFrame(maze_header, maze));
    for (const std::string& name : approach_order) {
      const ApproachState& state = approaches[name];
      SendBinary(handle, FullFrame(state.header, state.cells));
    }
    if (!reports.empty()) SendText(handle, HistoryJson("history", "reports", reports));
    if (!service_windows.empty()) {
      SendText(handle, HistoryJson("service_history", "windows", service_windows));
    }
    if (!map_frame.empty()) SendText(handle, map_frame);
  }

  void OnClose(Handle handle) {
    opening.erase(handle);
    auto it = clients.find(handle);
    if (it == clients.end()) return;
    const bool foxglove = it->second.foxglove;
    clients.erase(it);
    std::lock_guard lock(counters_mutex);
    counters.clients = static_cast<int64_t>(clients.size());
    if (foxglove) --counters.foxglove_clients;
  }

  void OnMessage(Handle handle, Server::message_ptr message) {
    auto it = clients.find(handle);
    if (it == clients.end()) return;
    if (!it->second.foxglove) {
      return CloseBadClient(handle, websocketpp::close::status::policy_violation,
                            "the page's connection is read-only");
    }
    if (message->get_opcode() != websocketpp::frame::opcode::text) {
      return CloseBadClient(handle, websocketpp::close::status::unsupported_data,
                            "binary client messages are not supported (no capabilities)");
    }
    ClientMessage parsed = ParseClientMessage(message->get_payload());
    Client& client = it->second;
    switch (parsed.kind) {
      case ClientMessage::kMalformed:
        return CloseBadClient(handle, websocketpp::close::status::invalid_payload,
                              "malformed message: " + parsed.why);
      case ClientMessage::kUnsupported:
        SendText(handle,
                 nlohmann::json{
                     {"op", "status"}, {"level", 1}, {"message", "unsupported op: " + parsed.op}}
                     .dump());
        return;
      case ClientMessage::kSubscribe:
        for (const auto& [id, channel] : parsed.subscribe) {
          bool known = false;
          for (const FoxgloveChannel& c : FoxgloveChannels()) known |= c.id == channel;
          if (!known || client.subscriptions.size() >= kMaxSubscriptions) {
            SendText(handle, nlohmann::json{{"op", "status"},
                                            {"level", 1},
                                            {"message", "cannot subscribe to channel " +
                                                            std::to_string(channel)}}
                                 .dump());
            continue;
          }
          client.subscriptions[id] = channel;
        }
        return;
      case ClientMessage::kUnsubscribe:
        for (uint32_t id : parsed.unsubscribe) client.subscriptions.erase(id);
        return;
    }
  }

  void OnHttp(Handle handle) {
    Count(&ServerCounters::http_requests);
    Server::connection_ptr connection = server.get_con_from_hdl(handle);
    if (!FromAllowedHost(connection, /*check_origin=*/false)) return;
    const websocketpp::http::parser::request& request = connection->get_request();
    if (request.get_method() != "GET" && request.get_method() != "HEAD") {
      connection->set_status(websocketpp::http::status_code::method_not_allowed);
      connection->set_body("read-only: GET only\n");
      return;
    }
    std::string path = connection->get_resource();
    if (size_t query = path.find('?'); query != std::string::npos) path.resize(query);
    if (path == "/stats.json") {
      const ServerCounters c = Counters();
      nlohmann::json stats = {{"clients", c.clients},
                              {"foxglove_clients", c.foxglove_clients},
                              {"accepted", c.accepted},
                              {"refused_full", c.refused_full},
                              {"refused_handshake", c.refused_handshake},
                              {"refused_host", c.refused_host},
                              {"dropped_slow", c.dropped_slow},
                              {"closed_bad_input", c.closed_bad_input},
                              {"messages_in", c.messages_in},
                              {"inputs_dropped", c.inputs_dropped},
                              {"frames_sent", c.frames_sent}};
      connection->set_status(websocketpp::http::status_code::ok);
      connection->append_header("Content-Type", "application/json");
      connection->append_header("Cache-Control", "no-store");
      connection->set_body(stats.dump() + "\n");
      return;
    }
    auto file = options.files.find(path == "/" ? "/index.html" : path);
    if (file == options.files.end()) {
      connection->set_status(websocketpp::http::status_code::not_found);
      connection->set_body("not found\n");
      return;
    }
    connection->set_status(websocketpp::http::status_code::ok);
    connection->append_header("Content-Type", file->second.content_type);
    connection->append_header("Cache-Control", "no-cache");
    connection->append_header("X-Content-Type-Options", "nosniff");
    connection->set_body(file->second.body);
  }

  ServerCounters Counters() const {
    std::lock_guard lock(counters_mutex);
    return counters;
  }

  // --- run messages (I/O thread) ---

  void TakeGrid(const grid_t& grid, double received_ms) {
    maze_header = FrameHeader{};
    maze_header.kind = FrameKind::kMaze;
    maze_header.rows = grid.rows;
    maze_header.cols = grid.cols;
    maze_header.received_ms = received_ms;
    maze = PackCodes(grid.cells);
    have_maze = true;
    const std::vector<uint8_t> frame = FullFrame(maze_header, maze);
    ToPages(frame.data(), frame.size(), websocketpp::frame::opcode::binary);
    ToFoxglove("/grid", received_ms, [&] { return GridFoxglove(grid); });
  }

  void TakeChanges(const changes_t& changes, double received_ms) {
    if (have_maze) {
      for (int i = 0; i < changes.num_changes; ++i) {
        const int32_t cell = changes.cells[i];
        if (cell >= 0 && static_cast<size_t>(cell) < maze.size()) {
          maze[cell] = PackCell(changes.codes[i], -1, -1);
        }
      }
      maze_header.step = changes.time_step;
    }
    const std::string text = ChangesJson(changes, received_ms);
    ToPages(text.data(), text.size(), websocketpp::frame::opcode::text);
    ToFoxglove("/changes", received_ms, [&] { return ChangesFoxglove(changes); });
  }

  void TakeReport(const step_report_t& report, double received_ms) {
    std::string text = ReportJson(report, received_ms);
    ToPages(text.data(), text.size(), websocketpp::frame::opcode::text);
    KeepForNewClients(reports, std::move(text), options.max_reports);
    ToFoxglove("/report", received_ms, [&] { return ReportFoxglove(report); });
  }

  void TakePolicy(const policy_t& policy, double received_ms) {
    const double taken_ms = WallMs();
    FrameHeader header;
    header.approach = policy.approach;
    header.step = policy.time_step;
    header.rows = policy.rows;
    header.cols = policy.cols;
    header.received_ms = received_ms;
    for (int i = 0; i < policy.num_regions; ++i) {
      header.regions.insert(header.regions.end(), {policy.region_row0[i], policy.region_col0[i],
                                                   policy.region_rows[i], policy.region_cols[i]});
    }
    auto it = approaches.find(policy.approach);
    std::vector<uint8_t> frame;
    if (it != approaches.end() && it->second.header.rows == header.rows &&
        it->second.header.cols == header.cols &&
        RepackPolicy(policy, it->second.cells, changed_cells)) {
      // The usual step: the approach's cells repacked in place, the
      // changed ones sent.
      frame = DeltaFrame(header, changed_cells, it->second.cells);
    } else {
      if (it == approaches.end()) approach_order.push_back(policy.approach);
      header.kind = FrameKind::kFull;
      std::vector<uint8_t> cells = PackPolicy(policy);
      frame = FullFrame(header, cells);
      approaches[policy.approach].cells = std::move(cells);
    }
    ApproachState& state = approaches[policy.approach];
    state.header = header;
    state.header.kind = FrameKind::kFull;
    const double packed_ms = WallMs();
    ToPages(frame.data(), frame.size(), websocketpp::frame::opcode::binary);
    ToFoxglove("/policy", received_ms, [&] { return PolicyFoxglove(policy); });
    spdlog::debug(
        "policy {} step {}: {} bytes to the pages; waited {:.1f} ms for the I/O thread, packed in "
        "{:.1f} ms, sent in {:.1f} ms",
        policy.approach, policy.time_step, frame.size(), taken_ms - received_ms,
        packed_ms - taken_ms, WallMs() - packed_ms);
  }

  void TakeServiceWindow(const char* kind, const std::optional<ServiceWindow>& window) {
    if (!window) return;
    std::string text = ServiceJson(kind, *window);
    ToPages(text.data(), text.size(), websocketpp::frame::opcode::text);
    KeepForNewClients(service_windows, std::move(text), options.max_service_windows);
  }

  // The timer's tick: windows past their end are sent without waiting for
  // the next request or reply (the last second of a burst).
  void CloseServiceWindows() {
    const double now = WallMs();
    TakeServiceWindow("path", path_latency.Close(now));
    TakeServiceWindow("goal", goal_latency.Close(now));
  }

  void ArmWindowTimer() {
    window_timer->expires_after(std::chrono::milliseconds(250));
    window_timer->async_wait([this](const asio::error_code& ec) {
      if (ec) return;  // cancelled: stopping
      CloseServiceWindows();
      ArmWindowTimer();
    });
  }

  void TakeRequest(const std::string& client, int64_t request_id, double received_ms) {
    TakeServiceWindow("path", path_latency.Request(client, request_id, received_ms));
  }

  void TakeGoalRequest(const std::string& client, int64_t request_id, double received_ms) {
    TakeServiceWindow("goal", goal_latency.Request(client, request_id, received_ms));
  }

  void TakeGoalReply(const std::string& client, int64_t request_id, double received_ms) {
    TakeServiceWindow("goal", goal_latency.Reply(client, request_id, received_ms));
  }

  void TakeMapFrame(double resolution, double origin_x, double origin_y) {
    if (!(resolution > 0)) return;  // a reply without a frame
    std::string text = FrameJson(resolution, origin_x, origin_y);
    if (text == map_frame) return;
    map_frame = std::move(text);
    ToPages(map_frame.data(), map_frame.size(), websocketpp::frame::opcode::text);
  }

  void TakePaths(const path_reply_t& reply, double received_ms) {
    TakeServiceWindow("path", path_latency.Reply(reply.client, reply.request_id, received_ms));
    const std::string text = PathsJson(reply, received_ms, options.max_paths);
    ToPages(text.data(), text.size(), websocketpp::frame::opcode::text);
    ToFoxglove("/paths", received_ms, [&] { return PathsFoxglove(reply); });
  }

  void TakeUpdates(const obstacle_update_t& update, double received_ms) {
    const std::string text = UpdatesJson(update, received_ms);
    ToPages(text.data(), text.size(), websocketpp::frame::opcode::text);
    ToFoxglove("/map_updates", received_ms, [&] { return UpdatesFoxglove(update); });
  }

  void TakePoints(const obstacle_points_t& update, double received_ms) {
    const std::string text = PointsJson(update, received_ms);
    ToPages(text.data(), text.size(), websocketpp::frame::opcode::text);
    ToFoxglove("/map_points", received_ms, [&] { return PointsFoxglove(update); });
  }
};

WebServer::WebServer(ServerOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}

WebServer::~WebServer() { Stop(); }

Status WebServer::Start() {
  Impl& s = *impl_;
  Server& server = s.server;
  server.clear_access_channels(websocketpp::log::alevel::all);
  server.clear_error_channels(websocketpp::log::elevel::all);
  websocketpp::lib::error_code ec;
  server.init_asio(ec);
  if (ec) return Error::Io("cannot start the server: " + ec.message());
  server.set_reuse_addr(true);
  server.set_max_message_size(static_cast<size_t>(s.options.max_frame_bytes));
  server.set_max_http_body_size(static_cast<size_t>(s.options.max_frame_bytes));
  server.set_open_handshake_timeout(5000);
  server.set_close_handshake_timeout(2000);
  server.set_validate_handler([&s](Handle h) { return s.OnValidate(h); });
  server.set_open_handler([&s](Handle h) { s.OnOpen(h); });
  server.set_close_handler([&s](Handle h) { s.OnClose(h); });
  server.set_fail_handler([&s](Handle h) { s.OnClose(h); });
  server.set_message_handler([&s](Handle h, Server::message_ptr m) { s.OnMessage(h, m); });
  server.set_http_handler([&s](Handle h) { s.OnHttp(h); });

  asio::ip::address address = asio::ip::make_address(s.options.bind, ec);
  if (ec) return Error::Io("cannot listen on '" + s.options.bind + "': not an IP address");
  const asio::ip::tcp::endpoint endpoint(address, static_cast<uint16_t>(s.options.port));
  server.listen(endpoint, ec);
  if (ec) {
    return Error::Io("cannot listen on " + s.options.bind + ":" + std::to_string(s.options.port) +
                     ": " + ec.message());
  }
  asio::error_code local_ec;
  const asio::ip::tcp::endpoint local = server.get_local_endpoint(local_ec);
  s.bound_port = local_ec ? s.options.port : local.port();
  server.start_accept(ec);
  if (ec) return Error::Io("cannot accept connections: " + ec.message());
  s.window_timer = std::make_unique<asio::steady_timer>(server.get_io_service());
  s.ArmWindowTimer();
  s.started = true;
  s.thread = std::thread([&s] {
    if (s.options.nice > 0) LowerThreadPriority(s.options.nice);
    for (;;) {
      try {
        s.server.run();
        return;
      } catch (const std::exception& error) {
        spdlog::error("web server: {}", error.what());
      }
    }
  });
  return Ok{};
}

void WebServer::Stop() {
  Impl& s = *impl_;
  if (!s.started) return;
  s.started = false;
  asio::post(s.server.get_io_service(), [&s] {
    websocketpp::lib::error_code ec;
    s.server.stop_listening(ec);
    s.window_timer->cancel();
    for (auto& [handle, client] : s.clients) {
      s.server.close(handle, websocketpp::close::status::going_away, "server stopping", ec);
    }
  });
  // Give the close handshakes a moment, then stop whatever is left.
  for (int i = 0; i < 20 && s.Counters().clients > 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  s.server.stop();
  if (s.thread.joinable()) s.thread.join();
}

int WebServer::port() const { return impl_->bound_port.load(); }

ServerCounters WebServer::counters() const { return impl_->Counters(); }

void WebServer::Grid(grid_t grid, double received_ms) {
  const int64_t bytes = grid.num_cells + 64;
  impl_->Post(bytes,
              [this, grid = std::move(grid), received_ms] { impl_->TakeGrid(grid, received_ms); });
}
void WebServer::Changes(changes_t changes, double received_ms) {
  const int64_t bytes = int64_t{changes.num_changes} * 5 + 64;
  impl_->Post(bytes, [this, changes = std::move(changes), received_ms] {
    impl_->TakeChanges(changes, received_ms);
  });
}
void WebServer::Report(const step_report_t& report, double received_ms) {
  impl_->Post(256, [this, report, received_ms] { impl_->TakeReport(report, received_ms); });
}
void WebServer::Policy(policy_t policy, double received_ms) {
  const int64_t bytes = int64_t{policy.num_cells} * 3 + 64;
  impl_->Post(bytes, [this, policy = std::move(policy), received_ms] {
    impl_->TakePolicy(policy, received_ms);
  });
}
void WebServer::Paths(path_reply_t reply, double received_ms) {
  const int64_t bytes = int64_t{reply.num_path} * 8 + int64_t{reply.num_starts} * 24 + 64;
  impl_->Post(bytes, [this, reply = std::move(reply), received_ms] {
    impl_->TakePaths(reply, received_ms);
  });
}
void WebServer::Request(const path_request_t& request, double received_ms) {
  const int64_t bytes = static_cast<int64_t>(request.client.size()) + 64;
  impl_->Post(bytes, [this, client = request.client, id = request.request_id, received_ms] {
    impl_->TakeRequest(client, id, received_ms);
  });
}
void WebServer::GoalRequest(const goal_request_t& request, double received_ms) {
  const int64_t bytes = static_cast<int64_t>(request.client.size()) + 64;
  impl_->Post(bytes, [this, client = request.client, id = request.request_id, received_ms] {
    impl_->TakeGoalRequest(client, id, received_ms);
  });
}
void WebServer::GoalReply(const goal_reply_t& reply, double received_ms) {
  const int64_t bytes = static_cast<int64_t>(reply.client.size()) + 64;
  impl_->Post(bytes, [this, client = reply.client, id = reply.request_id, received_ms,
                      resolution = reply.resolution, x = reply.origin_x, y = reply.origin_y] {
    impl_->TakeGoalReply(client, id, received_ms);
    impl_->TakeMapFrame(resolution, x, y);
  });
}
void WebServer::Updates(obstacle_update_t update, double received_ms) {
  const int64_t bytes = int64_t{update.num_cells} * 9 + 64;
  impl_->Post(bytes, [this, update = std::move(update), received_ms] {
    impl_->TakeUpdates(update, received_ms);
  });
}
void WebServer::Points(obstacle_points_t update, double received_ms) {
  const int64_t bytes = int64_t{update.num_points} * 17 + 64;
  impl_->Post(bytes, [this, update = std::move(update), received_ms] {
    impl_->TakePoints(update, received_ms);
  });
}

}  // namespace dynapath::web
