#pragma once
// The HTTP + WebSocket server of `dynapath web`, on one port (websocketpp
// over standalone asio, one I/O thread):
//
//   * GET of the page's files (served from memory), and /stats.json;
//   * only for requests whose Host header (and, on a WebSocket handshake,
//     Origin header when there is one) names this server or an allowed
//     name (tools/web/host_check.h): others get HTTP 403;
//   * WebSocket connections of the page (no subprotocol: binary policy
//     frames and JSON messages, tools/web/messages.h) and of Foxglove
//     clients (subprotocol foxglove.websocket.v1: serverInfo, advertise,
//     subscribe/unsubscribe, messageData).
//
// Read-only: a page client sends nothing (any data frame from it closes the
// connection); a Foxglove client may subscribe and unsubscribe only.
// Frames above max_frame_bytes and malformed frames close the connection;
// at most max_clients WebSocket clients (more: HTTP 503); a client whose
// unsent bytes are above max_queue_bytes when a message is due is dropped,
// never waited for (its queue holds at most that and one message).
//
// The I/O thread runs at `nice` above the process's nice value: on cores
// shared with the run it watches, the run goes first (the caller's thread
// receiving the run's messages keeps its priority: a UDP fragment not read
// in time loses its message).
//
// The message inputs (Grid, Policy, ...) may be called from any thread
// (the LCM dispatch thread): they post to the I/O thread, which owns the
// state new clients get (the maze, every approach's latest policy, the
// reports so far). While more than max_pending_bytes of input wait for the
// I/O thread, new input is dropped and counted.

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dynapath/changes_t.hpp"
#include "dynapath/goal_reply_t.hpp"
#include "dynapath/goal_request_t.hpp"
#include "dynapath/grid_t.hpp"
#include "dynapath/obstacle_points_t.hpp"
#include "dynapath/obstacle_update_t.hpp"
#include "dynapath/path_reply_t.hpp"
#include "dynapath/path_request_t.hpp"
#include "dynapath/policy_t.hpp"
#include "dynapath/result.h"
#include "dynapath/step_report_t.hpp"

namespace dynapath::web {

struct PageFile {
  std::string content_type;
  std::string body;
};

struct ServerOptions {
  std::string bind = "127.0.0.1";
  int port = 8080;                         // 0: any free port (tests)
  std::vector<std::string> allowed_hosts;  // --allow-host: NAME or NAME:PORT
  int max_clients = 32;
  int64_t max_frame_bytes = 64 * 1024;
  int64_t max_queue_bytes = int64_t{32} << 20;
  int64_t max_pending_bytes = int64_t{256} << 20;
  int max_reports = 20000;  // kept for new clients' plots
  int max_paths = 1000;     // paths of one PATH_REPLY sent to the page
  int max_service_windows = 3600;       // service latency windows kept for new clients (both kinds)
  int nice = 0;  // the I/O thread raises its nice value by this (0-19): the run goes first
  size_t max_pending_requests = 65536;  // per kind: requests waiting for their reply
  // The map's frame given on the command line (resolution 0: none): pages
  // place obstacle points in metres with it until a goal reply gives the
  // service's own.
  double frame_resolution = 0;
  double frame_origin_x = 0;
  double frame_origin_y = 0;
  std::string run_id;
  std::string version;
  std::map<std::string, PageFile> files;  // "/" and "/app.js", ...
};

struct ServerCounters {
  int64_t clients = 0;            // WebSocket clients connected now
  int64_t foxglove_clients = 0;   // of them, Foxglove's
  int64_t accepted = 0;           // WebSocket connections opened so far
  int64_t refused_full = 0;       // refused: max_clients reached
  int64_t refused_handshake = 0;  // refused: an unknown subprotocol
  int64_t refused_host = 0;       // refused (403): a Host or Origin that is not this server
  int64_t dropped_slow = 0;       // dropped: their queue passed max_queue_bytes
  int64_t closed_bad_input = 0;   // closed: a frame they must not send or a malformed one
  int64_t http_requests = 0;
  int64_t messages_in = 0;     // run messages taken
  int64_t inputs_dropped = 0;  // run messages dropped: the I/O thread was behind
  int64_t frames_sent = 0;
};

class WebServer {
 public:
  explicit WebServer(ServerOptions options);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  // Binds and listens, then serves on its own thread. Error: the address
  // cannot be bound (in use, not local, ...).
  Status Start();
  void Stop();
  int port() const;  // the bound port
  ServerCounters counters() const;

  // received_ms: wall clock (ms since the epoch) when the message arrived.
  // Taken by value: a caller done with a message moves it in (a 1000x1000
  // policy is 3 MB).
  void Grid(grid_t grid, double received_ms);
  void Changes(changes_t changes, double received_ms);
  void Report(const step_report_t& report, double received_ms);
  void Policy(policy_t policy, double received_ms);
  // A request only times its reply (ServiceLatency): it is not sent on.
  void Request(const path_request_t& request, double received_ms);
  void Paths(path_reply_t reply, double received_ms);
  // Goal queries are timed the same way, as a second series ("goal"). A
  // reply's map frame (resolution, origin) is sent on to the pages when it
  // changes, and to new clients: it places obstacle updates in metres.
  void GoalRequest(const goal_request_t& request, double received_ms);
  void GoalReply(const goal_reply_t& reply, double received_ms);
  void Updates(obstacle_update_t update, double received_ms);
  // An obstacle update in metres (MAP_POINTS).
  void Points(obstacle_points_t update, double received_ms);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dynapath::web
