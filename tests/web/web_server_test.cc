// The web server's handling of what clients send and how fast they read,
// over real sockets on 127.0.0.1 (any free port): oversized and malformed
// frames close the connection, the client cap refuses with HTTP 503, a
// client that does not read is dropped while the others go on; requests
// and handshakes for another host (DNS rebinding) or from another site's
// page get HTTP 403; and the page's frame codec (whole policies and
// deltas), the Foxglove client message parser and the Host/Origin check.

#include "tools/web/web_server.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include "tools/web/host_check.h"
#include "tools/web/mcap_writer.h"
#include "tools/web/messages.h"
#include "tools/web/service_latency.h"

namespace dynapath::web {
namespace {

// A raw TCP client speaking just enough WebSocket to test the server.
class RawClient {
 public:
  explicit RawClient(int port, int receive_buffer = 0) : port_(port) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    if (receive_buffer > 0) {
      setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof(receive_buffer));
    }
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0;
  }
  ~RawClient() { close(fd_); }

  bool connected() const { return connected_; }
  void Send(const std::string& bytes) {
    ASSERT_EQ(send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL),
              static_cast<ssize_t>(bytes.size()));
  }
  // "Host: 127.0.0.1:PORT\r\n", as a browser or node sends it.
  std::string HostHeader() const { return "Host: 127.0.0.1:" + std::to_string(port_) + "\r\n"; }
  // The HTTP response's status line (or "" on a closed connection). The
  // Host header is 127.0.0.1:PORT unless `host` gives another value.
  std::string Handshake(const std::string& extra_headers = "", const std::string& host = "") {
    Send("GET / HTTP/1.1\r\n" + (host.empty() ? HostHeader() : "Host: " + host + "\r\n") +
         "Upgrade: websocket\r\nConnection: Upgrade\r\n"
         "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n" +
         extra_headers + "\r\n");
    std::string response;
    while (response.find("\r\n\r\n") == std::string::npos) {
      std::string chunk = Read(5000);
      if (chunk.empty()) break;
      response += chunk;
    }
    rest_ = response.substr(std::min(response.size(), response.find("\r\n\r\n") + 4));
    return response.substr(0, response.find("\r\n"));
  }
  // What came after the handshake's response in the same reads.
  std::string TakeRest() { return std::exchange(rest_, std::string()); }
  // Reads what arrives within `ms`; "" when the peer closed (or nothing came).
  std::string Read(int ms) {
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, ms) <= 0) return "";
    char buffer[65536];
    const ssize_t n = recv(fd_, buffer, sizeof(buffer), 0);
    return n > 0 ? std::string(buffer, static_cast<size_t>(n)) : std::string();
  }
  // True once the server closed the connection (reads until EOF or a reset),
  // within `seconds`.
  bool ClosedWithin(int seconds) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    while (std::chrono::steady_clock::now() < until) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 200) <= 0) continue;
      char buffer[65536];
      const ssize_t n = recv(fd_, buffer, sizeof(buffer), 0);
      if (n <= 0) return true;
    }
    return false;
  }
  // A masked client frame.
  static std::string Frame(uint8_t first, const std::string& payload, bool mask = true) {
    std::string frame(1, static_cast<char>(first));
    const uint8_t mask_bit = mask ? 0x80 : 0;
    if (payload.size() < 126) {
      frame.push_back(static_cast<char>(mask_bit | payload.size()));
    } else if (payload.size() < 65536) {
      frame.push_back(static_cast<char>(mask_bit | 126));
      frame.push_back(static_cast<char>(payload.size() >> 8));
      frame.push_back(static_cast<char>(payload.size() & 0xff));
    } else {
      frame.push_back(static_cast<char>(mask_bit | 127));
      for (int i = 7; i >= 0; --i)
        frame.push_back(static_cast<char>((payload.size() >> (8 * i)) & 0xff));
    }
    const char key[4] = {0x11, 0x22, 0x33, 0x44};
    if (mask) frame.append(key, 4);
    for (size_t i = 0; i < payload.size(); ++i) {
      frame.push_back(mask ? static_cast<char>(payload[i] ^ key[i % 4]) : payload[i]);
    }
    return frame;
  }

 private:
  int port_ = 0;
  int fd_ = -1;
  bool connected_ = false;
  std::string rest_;
};

ServerOptions TestOptions() {
  ServerOptions options;
  options.port = 0;
  options.max_clients = 3;
  options.max_frame_bytes = 1024;
  options.max_queue_bytes = 1 << 20;
  options.run_id = "test";
  options.files["/index.html"] = PageFile{"text/html", "<p>page</p>"};
  return options;
}

bool WaitFor(const std::function<bool()>& condition, int seconds = 20) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  while (std::chrono::steady_clock::now() < until) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return condition();
}

// Reads from `client` into `received` until it holds every one of `needles`
// (within WaitFor's bound).
bool ReadUntil(RawClient& client, std::string& received,
               std::initializer_list<std::string_view> needles) {
  return WaitFor([&] {
    received += client.Read(50);
    return std::all_of(needles.begin(), needles.end(), [&](std::string_view needle) {
      return received.find(needle) != std::string::npos;
    });
  });
}

policy_t Policy(int side, int action) {
  policy_t p;
  p.run_id = "test";
  p.approach = "a";
  p.time_step = action;
  p.rows = p.cols = side;
  p.num_cells = side * side;
  p.cells.assign(p.num_cells, 1);
  p.actions.assign(p.num_cells, static_cast<int8_t>(action));
  p.reaches.assign(p.num_cells, 1);
  p.num_regions = 0;
  return p;
}

TEST(WebServer, ServesThePageAndRefusesOtherMethods) {
  WebServer server(TestOptions());
  ASSERT_TRUE(server.Start());
  RawClient get(server.port());
  get.Send("GET / HTTP/1.1\r\n" + get.HostHeader() + "\r\n");
  std::string response;
  for (int i = 0; i < 10 && response.find("page") == std::string::npos; ++i)
    response += get.Read(2000);
  EXPECT_EQ(response.rfind("HTTP/1.1 200", 0), 0u) << response;
  EXPECT_NE(response.find("<p>page</p>"), std::string::npos);
  RawClient post(server.port());
  post.Send("POST / HTTP/1.1\r\n" + post.HostHeader() + "Content-Length: 0\r\n\r\n");
  EXPECT_EQ(post.Read(5000).rfind("HTTP/1.1 405", 0), 0u);
}

TEST(WebServer, ClosesOnAnOversizedFrame) {
  WebServer server(TestOptions());
  ASSERT_TRUE(server.Start());
  RawClient client(server.port());
  ASSERT_EQ(client.Handshake("Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n"),
            "HTTP/1.1 101 Switching Protocols");
  client.Send(RawClient::Frame(0x81, std::string(4096, 'x')));  // above 1024 bytes
  EXPECT_TRUE(client.ClosedWithin(10));
  RawClient next(server.port());  // the server goes on
  EXPECT_EQ(next.Handshake(), "HTTP/1.1 101 Switching Protocols");
}

TEST(WebServer, ClosesOnMalformedFrames) {
  WebServer server(TestOptions());
  ASSERT_TRUE(server.Start());
  {
    RawClient unmasked(server.port());  // a client's frames must be masked
    ASSERT_EQ(unmasked.Handshake(), "HTTP/1.1 101 Switching Protocols");
    unmasked.Send(RawClient::Frame(0x81, "{}", /*mask=*/false));
    EXPECT_TRUE(unmasked.ClosedWithin(10));
  }
  {
    RawClient reserved(server.port());  // opcode 0x3 is reserved
    ASSERT_EQ(reserved.Handshake(), "HTTP/1.1 101 Switching Protocols");
    reserved.Send(RawClient::Frame(0x83, "x"));
    EXPECT_TRUE(reserved.ClosedWithin(10));
  }
  {
    RawClient foxglove(server.port());  // not JSON
    ASSERT_EQ(foxglove.Handshake("Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n"),
              "HTTP/1.1 101 Switching Protocols");
    foxglove.Send(RawClient::Frame(0x81, "{\"op\": subscribe"));
    EXPECT_TRUE(foxglove.ClosedWithin(10));
  }
  {
    RawClient page(server.port());  // the page's connection is read-only
    ASSERT_EQ(page.Handshake(), "HTTP/1.1 101 Switching Protocols");
    page.Send(RawClient::Frame(0x81, "{\"op\":\"subscribe\"}"));
    EXPECT_TRUE(page.ClosedWithin(10));
  }
  {
    RawClient other(server.port());  // an unknown subprotocol is refused
    EXPECT_EQ(other.Handshake("Sec-WebSocket-Protocol: chat\r\n"), "HTTP/1.1 400 Bad Request");
  }
  EXPECT_TRUE(WaitFor([&] { return server.counters().closed_bad_input >= 2; }));
  EXPECT_EQ(server.counters().refused_handshake, 1);
}

TEST(WebServer, RefusesClientsAboveTheCap) {
  WebServer server(TestOptions());
  ASSERT_TRUE(server.Start());
  std::vector<std::unique_ptr<RawClient>> clients;
  for (int i = 0; i < 3; ++i) {
    clients.push_back(std::make_unique<RawClient>(server.port()));
    ASSERT_EQ(clients.back()->Handshake(), "HTTP/1.1 101 Switching Protocols");
  }
  RawClient fourth(server.port());
  EXPECT_EQ(fourth.Handshake(), "HTTP/1.1 503 Service Unavailable");
  EXPECT_EQ(server.counters().refused_full, 1);
  clients.pop_back();  // one leaves: room for another
  ASSERT_TRUE(WaitFor([&] { return server.counters().clients == 2; }));
  RawClient again(server.port());
  EXPECT_EQ(again.Handshake(), "HTTP/1.1 101 Switching Protocols");
}

TEST(WebServer, CapsABurstOfHandshakes) {
  // Five handshakes sent before any answer is read: three get in.
  WebServer server(TestOptions());
  ASSERT_TRUE(server.Start());
  std::vector<std::unique_ptr<RawClient>> burst;
  for (int i = 0; i < 5; ++i) {
    burst.push_back(std::make_unique<RawClient>(server.port()));
    burst.back()->Send(
        "GET / HTTP/1.1\r\n" + burst.back()->HostHeader() +
        "Upgrade: websocket\r\nConnection: Upgrade\r\n"
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n");
  }
  int accepted = 0, refused = 0;
  for (auto& client : burst) {
    const std::string response = client->Read(5000);
    accepted += response.rfind("HTTP/1.1 101", 0) == 0;
    refused += response.rfind("HTTP/1.1 503", 0) == 0;
  }
  EXPECT_EQ(accepted, 3);
  EXPECT_EQ(refused, 2);
}

// The response to a plain GET / with these headers (the server closes
// the connection after an HTTP response).
std::string Get(int port, const std::string& headers) {
  RawClient client(port);
  client.Send("GET / HTTP/1.1\r\n" + headers + "\r\n");
  std::string response;
  for (std::string chunk = client.Read(5000); !chunk.empty(); chunk = client.Read(5000)) {
    response += chunk;
  }
  return response;
}

TEST(WebServer, RefusesOtherHostsAndOtherSitesWebSockets) {
  ServerOptions options = TestOptions();
  options.allowed_hosts = {"runs.example.org"};
  WebServer server(options);
  ASSERT_TRUE(server.Start());
  const std::string port = std::to_string(server.port());
  // A page whose name was rebound to 127.0.0.1 asks for its own name.
  const std::string rebound = Get(server.port(), "Host: attacker.example:" + port + "\r\n");
  EXPECT_EQ(rebound.rfind("HTTP/1.1 403", 0), 0u) << rebound;
  EXPECT_NE(rebound.find("--allow-host NAME"), std::string::npos) << rebound;
  EXPECT_EQ(rebound.find("<p>page</p>"), std::string::npos);
  // No Host at all: websocketpp's HTTP parser refuses it before the check.
  EXPECT_EQ(Get(server.port(), "").rfind("HTTP/1.1 400", 0), 0u);
  EXPECT_EQ(Get(server.port(), "Host: localhost:" + port + "\r\n").rfind("HTTP/1.1 200", 0), 0u);
  EXPECT_EQ(Get(server.port(), "Host: runs.example.org\r\n").rfind("HTTP/1.1 200", 0), 0u);
  int refused = 1;
  {
    RawClient client(server.port());
    EXPECT_EQ(client.Handshake("", "attacker.example:" + port), "HTTP/1.1 403 Forbidden");
    ++refused;
  }
  {
    RawClient client(server.port());  // the right name on another port
    EXPECT_EQ(client.Handshake("", "127.0.0.1:1"), "HTTP/1.1 403 Forbidden");
    ++refused;
  }
  {
    RawClient client(server.port());  // any site may open a WebSocket: its Origin tells
    EXPECT_EQ(client.Handshake("Origin: https://attacker.example\r\n"), "HTTP/1.1 403 Forbidden");
    ++refused;
  }
  {
    RawClient client(server.port());  // another local web server's page
    EXPECT_EQ(client.Handshake("Origin: http://localhost:3000\r\n"), "HTTP/1.1 403 Forbidden");
    ++refused;
  }
  {
    RawClient client(server.port());  // the server's own page
    EXPECT_EQ(client.Handshake("Origin: http://127.0.0.1:" + port + "\r\n"),
              "HTTP/1.1 101 Switching Protocols");
  }
  {
    RawClient client(server.port());  // a page through the allowed proxy name
    EXPECT_EQ(client.Handshake("Origin: https://runs.example.org\r\n", "runs.example.org"),
              "HTTP/1.1 101 Switching Protocols");
  }
  {
    RawClient client(server.port());  // no Origin: node, Foxglove's desktop app
    EXPECT_EQ(client.Handshake("Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n"),
              "HTTP/1.1 101 Switching Protocols");
  }
  EXPECT_EQ(server.counters().refused_host, refused);
  EXPECT_EQ(server.counters().refused_full, 0);
}

TEST(WebServer, DropsAClientThatDoesNotRead) {
  WebServer server(TestOptions());
  ASSERT_TRUE(server.Start());
  RawClient slow(server.port(), /*receive_buffer=*/4096);
  ASSERT_EQ(slow.Handshake(), "HTTP/1.1 101 Switching Protocols");
  RawClient reader(server.port());
  ASSERT_EQ(reader.Handshake(), "HTTP/1.1 101 Switching Protocols");
  ASSERT_TRUE(WaitFor([&] { return server.counters().clients == 2; }));
  // 300x300 policies whose every cell changes each time: 450 KB deltas
  // against a 1 MB queue; `reader` reads, `slow` never does. The next
  // policy waits until `reader` has drained what was sent (it has 50 KB of
  // the last one, the first, whole policy being 90 KB, and then reads
  // nothing more for 200 ms), so `reader` never holds more than one
  // policy's delta in its queue, however slowly this machine (or a
  // sanitizer) runs: waiting for 50 KB alone let it fall 400 KB further
  // behind with each policy under ASan.
  std::atomic<bool> stop{false};
  std::atomic<size_t> read_bytes{0};
  std::thread drain([&] {
    while (!stop) read_bytes += reader.Read(50).size();
  });
  const auto drained = [&](size_t before) {
    if (!WaitFor([&] {
          return read_bytes >= before + 50'000 || server.counters().dropped_slow > 0;
        })) {
      return;
    }
    for (int quiet = 0; quiet < 4 && server.counters().dropped_slow == 0;) {
      const size_t seen = read_bytes;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      quiet = read_bytes == seen ? quiet + 1 : 0;
    }
  };
  for (int i = 0; i < 200 && server.counters().dropped_slow == 0; ++i) {
    const size_t before = read_bytes;
    server.Policy(Policy(300, i % 8), 0);
    drained(before);
  }
  EXPECT_TRUE(WaitFor([&] { return server.counters().dropped_slow == 1; }));
  EXPECT_TRUE(slow.ClosedWithin(10));
  // The server counts the dropped client gone once its close completes,
  // which may come after the client sees the connection closed.
  EXPECT_TRUE(WaitFor([&] { return server.counters().clients == 1; }))
      << server.counters().clients << " clients";
  EXPECT_EQ(server.counters().dropped_slow, 1);  // the reader is still served
  stop = true;
  drain.join();
}

TEST(ServiceLatency, TimesEachReplyFromItsRequestInOneSecondWindows) {
  ServiceLatency latency;
  const double t = 1'000'000.0;  // ms: the start of a window
  // Window 1: three requests answered 2, 4 and 10 ms later; a reply whose
  // request was never seen.
  EXPECT_FALSE(latency.Request("robot", 1, t + 100));
  EXPECT_FALSE(latency.Request("robot", 2, t + 100));
  EXPECT_FALSE(latency.Request("fleet", 1, t + 200));  // another client, the same id
  EXPECT_FALSE(latency.Reply("robot", 1, t + 102));
  EXPECT_FALSE(latency.Reply("fleet", 1, t + 210));
  EXPECT_FALSE(latency.Reply("robot", 2, t + 104));
  EXPECT_FALSE(latency.Reply("robot", 99, t + 300));
  EXPECT_EQ(latency.pending(), 0u);
  // A request in the next window closes the first.
  const std::optional<ServiceWindow> w = latency.Request("robot", 3, t + 1'000);
  ASSERT_TRUE(w);
  EXPECT_EQ(w->end_ms, t + 1'000);
  EXPECT_EQ(w->replies, 3);
  EXPECT_EQ(w->unmatched, 1);
  EXPECT_EQ(w->per_second, 4.0);  // every reply, matched or not
  // Percentiles are the upper edge of a histogram bucket (1/64 of an octave
  // above 1 ms); the maximum is exact.
  EXPECT_GE(w->p50_ms, 4.0);
  EXPECT_LE(w->p50_ms, 4.0 * 1.011);
  EXPECT_GE(w->p99_ms, 10.0);
  EXPECT_LE(w->p99_ms, 10.0 * 1.011);
  EXPECT_EQ(w->max_ms, 10.0);
  EXPECT_EQ(w->requests, 3);
  // A window with requests and no reply is returned (its requests
  // counted, no percentiles): request 3's.
  const std::optional<ServiceWindow> only_requests = latency.Request("robot", 4, t + 2'500);
  ASSERT_TRUE(only_requests);
  EXPECT_EQ(only_requests->end_ms, t + 2'000);
  EXPECT_EQ(only_requests->requests, 1);
  EXPECT_EQ(only_requests->replies, 0);
  EXPECT_EQ(only_requests->p99_ms, 0.0);
  // Request 4 alone in the window of t + 2 s (answered two windows later).
  const std::optional<ServiceWindow> unanswered = latency.Request("robot", 5, t + 3'100);
  ASSERT_TRUE(unanswered);
  EXPECT_EQ(unanswered->end_ms, t + 3'000);
  EXPECT_EQ(unanswered->requests, 1);
  EXPECT_EQ(unanswered->replies, 0);
  EXPECT_FALSE(latency.Reply("robot", 5, t + 3'101));
  EXPECT_FALSE(latency.Close(t + 3'500));  // the open window
  const std::optional<ServiceWindow> next = latency.Reply("robot", 4, t + 4'000);
  ASSERT_TRUE(next);
  EXPECT_EQ(next->end_ms, t + 4'000);
  EXPECT_EQ(next->requests, 1);
  EXPECT_EQ(next->replies, 1);
  EXPECT_EQ(next->max_ms, 1.0);
  const std::optional<ServiceWindow> reply_only = latency.Close(t + 6'000);
  ASSERT_TRUE(reply_only);
  EXPECT_EQ(reply_only->requests, 0);
  EXPECT_EQ(reply_only->max_ms, 1'500.0);
  // A window without traffic is not returned.
  EXPECT_FALSE(latency.Close(t + 8'000));
}

TEST(ServiceLatency, TheClockClosesTheLastWindow) {
  ServiceLatency latency;
  const double t = 2'000'000.0;
  EXPECT_FALSE(latency.Close(t + 10));  // nothing open yet
  EXPECT_FALSE(latency.Request("robot", 1, t + 100));
  EXPECT_FALSE(latency.Request("robot", 2, t + 150));
  EXPECT_FALSE(latency.Reply("robot", 1, t + 120));
  EXPECT_FALSE(latency.Close(t + 999));  // still the open window
  const std::optional<ServiceWindow> w = latency.Close(t + 1'250);
  ASSERT_TRUE(w);
  EXPECT_EQ(w->end_ms, t + 1'000);
  EXPECT_EQ(w->requests, 2);
  EXPECT_EQ(w->replies, 1);
  EXPECT_EQ(w->max_ms, 20.0);
  // Once: the next ticks find nothing; the late reply counts in its own window.
  EXPECT_FALSE(latency.Close(t + 1'500));
  EXPECT_FALSE(latency.Reply("robot", 2, t + 1'600));
  const std::optional<ServiceWindow> late = latency.Close(t + 2'000);
  ASSERT_TRUE(late);
  EXPECT_EQ(late->requests, 0);
  EXPECT_EQ(late->replies, 1);
  EXPECT_EQ(late->max_ms, 1'450.0);
  EXPECT_FALSE(latency.Close(t + 5'000));  // windows without traffic: nothing
}

TEST(ServiceLatency, ForgetsTheOldestRequestsBeyondItsCap) {
  ServiceLatency latency(/*max_pending=*/200);
  // 100 requests wait; 1000 more are answered at once (the order of keys
  // is compacted on the way): none of the 100 is lost.
  for (int64_t id = 0; id < 100; ++id) (void)latency.Request("robot", id, 5.0);
  for (int64_t id = 1000; id < 2000; ++id) {
    (void)latency.Request("fleet", id, 5.0);
    (void)latency.Reply("fleet", id, 6.0);
  }
  EXPECT_EQ(latency.pending(), 100u);
  EXPECT_EQ(latency.forgotten(), 0);
  // 150 more unanswered: the cap keeps the latest 200 waiting.
  for (int64_t id = 100; id < 250; ++id) (void)latency.Request("robot", id, 7.0);
  EXPECT_EQ(latency.pending(), 200u);
  EXPECT_EQ(latency.forgotten(), 50);
  (void)latency.Reply("robot", 49, 9.0);   // forgotten
  (void)latency.Reply("robot", 50, 9.0);   // still waiting: 4 ms
  (void)latency.Reply("robot", 249, 9.0);  // 2 ms
  const std::optional<ServiceWindow> w = latency.Request("robot", 1000, 1'000.0);
  ASSERT_TRUE(w);
  EXPECT_EQ(w->replies, 1002);  // the 1000 answered at once, 50 and 249
  EXPECT_EQ(w->unmatched, 1);
  EXPECT_EQ(w->max_ms, 4.0);
}

TEST(WebServer, SendsTheServiceLatencyToThePage) {
  WebServer server(TestOptions());
  ASSERT_TRUE(server.Start());
  RawClient page(server.port());
  ASSERT_EQ(page.Handshake(), "HTTP/1.1 101 Switching Protocols");
  ASSERT_TRUE(WaitFor([&] { return server.counters().clients == 1; }));
  std::string received = page.TakeRest();
  path_request_t request{};
  request.client = "robot";
  request.request_id = 7;
  path_reply_t reply{};
  reply.client = "robot";
  reply.request_id = 7;
  server.Request(request, 5'000.0);
  server.Paths(reply, 5'003.0);
  request.request_id = 8;
  server.Request(request, 6'000.0);  // closes the window of 5 s
  ASSERT_TRUE(ReadUntil(page, received, {"\"t\":\"service\""}));
  EXPECT_NE(received.find("\"max\":3.0"), std::string::npos) << received;
  EXPECT_NE(received.find("\"replies\":1"), std::string::npos) << received;
  // A client that connects later gets the windows so far.
  RawClient late(server.port());
  ASSERT_EQ(late.Handshake(), "HTTP/1.1 101 Switching Protocols");
  std::string history = late.TakeRest();  // the first messages may come with the handshake
  ASSERT_TRUE(ReadUntil(late, history, {"\"t\":\"service_history\""}));
}

TEST(WebServer, TimesGoalQueriesAsASecondSeries) {
  ServerOptions options = TestOptions();
  options.max_pending_requests = 2;  // per kind
  WebServer server(options);
  ASSERT_TRUE(server.Start());
  RawClient page(server.port());
  ASSERT_EQ(page.Handshake(), "HTTP/1.1 101 Switching Protocols");
  ASSERT_TRUE(WaitFor([&] { return server.counters().clients == 1; }));
  std::string received = page.TakeRest();
  // Goal request 1 of "robot" and path request 1 of "robot": ids of the two
  // kinds are separate. Three goal requests wait at most 2: the first is
  // forgotten and its reply unmatched.
  goal_request_t goal{};
  goal.client = "robot";
  for (int64_t id = 1; id <= 3; ++id) {
    goal.request_id = id;
    server.GoalRequest(goal, 7'000.0 + static_cast<double>(id));
  }
  path_request_t path{};
  path.client = "robot";
  path.request_id = 1;
  server.Request(path, 7'010.0);
  goal_reply_t answer{};
  answer.client = "robot";
  for (int64_t id = 1; id <= 3; ++id) {
    answer.request_id = id;
    server.GoalReply(answer, 7'020.0);
  }
  path_reply_t path_answer{};
  path_answer.client = "robot";
  path_answer.request_id = 1;
  server.Paths(path_answer, 7'011.0);
  // No later request: the server's clock closes both windows.
  ASSERT_TRUE(ReadUntil(page, received, {"\"kind\":\"goal\"", "\"kind\":\"path\""})) << received;
  // Keys in order (nlohmann::json sorts them).
  EXPECT_NE(received.find("{\"end\":8000.0,\"kind\":\"goal\",\"max\":18.0,"), std::string::npos)
      << received;
  EXPECT_NE(received.find("\"rate\":3.0,\"replies\":2,\"requests\":3,\"t\":\"service\","
                          "\"unmatched\":1}"),
            std::string::npos)
      << received;
  EXPECT_NE(received.find("{\"end\":8000.0,\"kind\":\"path\",\"max\":1.0,"), std::string::npos)
      << received;
  EXPECT_NE(received.find("\"replies\":1,\"requests\":1,\"t\":\"service\",\"unmatched\":0}"),
            std::string::npos)
      << received;
  // A client that connects later gets both series.
  RawClient late(server.port());
  ASSERT_EQ(late.Handshake(), "HTTP/1.1 101 Switching Protocols");
  std::string history = late.TakeRest();
  ASSERT_TRUE(ReadUntil(late, history, {"\"t\":\"service_history\"", "\"kind\":\"path\""}))
      << history;
  EXPECT_NE(history.find("\"kind\":\"goal\""), std::string::npos) << history;
}

obstacle_points_t Points(const std::string& run, std::vector<double> x, std::vector<double> y) {
  obstacle_points_t m{};
  m.run_id = run;
  m.source = "lidar";
  m.sequence = 3;
  m.num_points = static_cast<int32_t>(x.size());
  m.states.assign(x.size(), obstacle_points_t::OBSTACLE);
  m.x = std::move(x);
  m.y = std::move(y);
  return m;
}

TEST(WebServer, SendsObstaclePointsAndTheMapFrame) {
  WebServer server(TestOptions());
  ASSERT_TRUE(server.Start());
  RawClient page(server.port());
  ASSERT_EQ(page.Handshake(), "HTTP/1.1 101 Switching Protocols");
  ASSERT_TRUE(WaitFor([&] { return server.counters().clients == 1; }));
  std::string received = page.TakeRest();
  server.Points(Points("test", {1.25, -0.5}, {2.75, 0.0}), 9'000.0);
  goal_reply_t reply{};
  reply.client = "robot";
  reply.request_id = 1;
  reply.resolution = 0.05;
  reply.origin_x = -1.0;
  reply.origin_y = -2.0;
  server.GoalReply(reply, 9'001.0);
  ASSERT_TRUE(ReadUntil(page, received, {"\"t\":\"points\"", "\"t\":\"frame\""})) << received;
  // Keys in order (nlohmann::json sorts them).
  EXPECT_NE(received.find("{\"rx\":9000.0,\"sequence\":3,\"source\":\"lidar\","
                          "\"states\":[0,0],\"t\":\"points\",\"x\":[1.25,-0.5],\"y\":[2.75,0.0]}"),
            std::string::npos)
      << received;
  EXPECT_NE(received.find("{\"origin_x\":-1.0,\"origin_y\":-2.0,\"resolution\":0.05,"
                          "\"t\":\"frame\"}"),
            std::string::npos)
      << received;
  // A client that connects later gets the frame.
  RawClient late(server.port());
  ASSERT_EQ(late.Handshake(), "HTTP/1.1 101 Switching Protocols");
  std::string history = late.TakeRest();
  ASSERT_TRUE(ReadUntil(late, history, {"\"t\":\"frame\""})) << history;
}

TEST(WebServer, AGivenFrameReachesPagesBeforeAnyGoalReplyAndTheServiceOneReplacesIt) {
  ServerOptions options = TestOptions();
  options.frame_resolution = 0.5;
  options.frame_origin_x = 3.0;
  options.frame_origin_y = -4.0;
  WebServer server(options);
  ASSERT_TRUE(server.Start());
  RawClient page(server.port());
  ASSERT_EQ(page.Handshake(), "HTTP/1.1 101 Switching Protocols");
  std::string received = page.TakeRest();
  ASSERT_TRUE(ReadUntil(page, received, {"\"t\":\"frame\""})) << received;
  EXPECT_NE(received.find("{\"origin_x\":3.0,\"origin_y\":-4.0,\"resolution\":0.5,"
                          "\"t\":\"frame\"}"),
            std::string::npos)
      << received;
  goal_reply_t reply{};
  reply.client = "robot";
  reply.request_id = 1;
  reply.resolution = 0.05;
  server.GoalReply(reply, 9'001.0);
  ASSERT_TRUE(ReadUntil(page, received, {"\"resolution\":0.05"})) << received;
  // A client that connects later gets the service's frame only.
  RawClient late(server.port());
  ASSERT_EQ(late.Handshake(), "HTTP/1.1 101 Switching Protocols");
  std::string history = late.TakeRest();
  ASSERT_TRUE(ReadUntil(late, history, {"\"t\":\"frame\""})) << history;
  EXPECT_EQ(history.find("\"resolution\":0.5,"), std::string::npos) << history;
}

TEST(FoxgloveMessages, ObstaclePointsHaveTheirChannel) {
  EXPECT_EQ(FoxgloveTopicOf("MAP_POINTS"), "/map_points");
  const uint32_t id = FoxgloveChannelId("/map_points");
  ASSERT_NE(id, 0u);
  EXPECT_NE(id, FoxgloveChannelId("/map_updates"));
  const nlohmann::json message =
      nlohmann::json::parse(PointsFoxglove(Points("test", {0.5}, {1.5})));
  for (const FoxgloveChannel& channel : FoxgloveChannels()) {
    if (channel.id != id) continue;
    EXPECT_EQ(channel.schema_name, "dynapath.MapPoints");
    // Named: a range-for over items() of a temporary's member would outlive it.
    const nlohmann::json schema = nlohmann::json::parse(channel.schema);
    for (const auto& [field, type] : schema["properties"].items()) {
      EXPECT_TRUE(message.contains(field)) << field;
    }
  }
  EXPECT_EQ(message["x"], nlohmann::json::array({0.5}));
  EXPECT_EQ(message["y"], nlohmann::json::array({1.5}));
}

// log-to-mcap: a valid MAP_POINTS message is exported; an invalid one (a
// NaN coordinate), a cut one and one whose run id is not its channel's are
// dropped and counted.
TEST(LogToMcap, ExportsObstaclePointsAndDropsBadOnes) {
  const std::string dir = ::testing::TempDir() + "points_" + std::to_string(getpid());
  const std::string log_path = dir + ".lcm", mcap_path = dir + ".mcap";
  {
    lcm::LogFile log(log_path, "w");
    ASSERT_TRUE(log.good());
    int64_t number = 0;
    auto write = [&](const std::string& channel, std::vector<uint8_t> data) {
      lcm::LogEvent event{};
      event.eventnum = number;
      event.timestamp = 1000 + number++;
      event.channel = channel;
      event.datalen = static_cast<int32_t>(data.size());
      event.data = data.data();
      ASSERT_EQ(log.writeEvent(&event), 0);
    };
    auto encode = [](const obstacle_points_t& m) {
      std::vector<uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
      m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
      return bytes;
    };
    write("DYNAPATH/r/MAP_POINTS", encode(Points("r", {1.25}, {2.5})));
    write("DYNAPATH/r/MAP_POINTS", encode(Points("r", {std::nan("")}, {2.5})));
    std::vector<uint8_t> cut = encode(Points("r", {1.0, 2.0}, {1.0, 2.0}));
    cut.resize(cut.size() - 5);
    write("DYNAPATH/r/MAP_POINTS", cut);
    write("DYNAPATH/other/MAP_POINTS", encode(Points("r", {1.0}, {1.0})));
  }
  Result<McapExport> exported = LogToMcap(log_path, mcap_path);
  ASSERT_TRUE(exported) << exported.error().message;
  EXPECT_EQ(exported->events, 4);
  EXPECT_EQ(exported->messages, 1);
  EXPECT_EQ(exported->dropped, 3);
  std::ifstream in(mcap_path, std::ios::binary);
  const std::string mcap((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(mcap.find("/map_points"), std::string::npos);
  EXPECT_NE(mcap.find("\"x\":[1.25],\"y\":[2.5]"), std::string::npos);
  std::remove(log_path.c_str());
  std::remove(mcap_path.c_str());
}

TEST(PageFrames, DeltaRebuildsThePolicy) {
  const policy_t before = Policy(7, 2);
  policy_t after = before;
  after.actions[3] = 5;
  after.reaches[10] = 0;
  after.cells[20] = 0;
  FrameHeader header;
  header.approach = "a";
  header.rows = header.cols = 7;
  header.regions = {0, 0, 7, 7};
  const std::vector<uint8_t> old_cells = PackPolicy(before), new_cells = PackPolicy(after);
  const std::vector<uint8_t> frame = DeltaFrame(header, old_cells, new_cells);
  FrameHeader parsed;
  std::vector<uint32_t> indices;
  std::vector<uint8_t> packed;
  ASSERT_TRUE(ParseFrame(frame.data(), frame.size(), parsed, indices, packed));
  EXPECT_EQ(parsed.kind, FrameKind::kDelta);
  EXPECT_EQ(indices, (std::vector<uint32_t>{3, 10, 20}));
  EXPECT_EQ(parsed.regions, header.regions);
  std::vector<uint8_t> rebuilt = old_cells;
  ASSERT_TRUE(ApplyDelta(indices, packed, rebuilt));
  EXPECT_EQ(rebuilt, new_cells);
  // Cut anywhere, the frame is refused.
  for (size_t cut = 0; cut < frame.size(); ++cut) {
    EXPECT_FALSE(ParseFrame(frame.data(), cut, parsed, indices, packed)) << cut;
  }
  EXPECT_EQ(PackCell(2, -1, -1), 2 | (2 << 2) | (15 << 4));
}

TEST(PageFrames, RepackingInPlaceGivesTheSameDelta) {
  // 37x29 cells (not a multiple of the 64-cell blocks); some cells change
  // in every block, some blocks not at all.
  policy_t before = Policy(37, 2);
  before.rows = 37;
  before.cols = 29;
  before.num_cells = 37 * 29;
  before.cells.resize(before.num_cells);
  before.actions.resize(before.num_cells);
  before.reaches.resize(before.num_cells);
  policy_t after = before;
  for (int i = 0; i < after.num_cells; i += (i % 200 < 100 ? 7 : 131)) {
    after.actions[i] = static_cast<int8_t>((after.actions[i] + 1 + i) % 8);
    if (i % 3 == 0) after.reaches[i] = 0;
  }
  after.cells[after.num_cells - 1] = 2;  // the last, partial block
  FrameHeader header;
  header.approach = "a";
  header.rows = 37;
  header.cols = 29;
  const std::vector<uint8_t> old_cells = PackPolicy(before), new_cells = PackPolicy(after);
  std::vector<uint8_t> cells = old_cells;
  std::vector<uint32_t> changed = {99};  // cleared first
  ASSERT_TRUE(RepackPolicy(after, cells, changed));
  EXPECT_EQ(cells, new_cells);
  EXPECT_FALSE(changed.empty());
  EXPECT_EQ(DeltaFrame(header, changed, cells), DeltaFrame(header, old_cells, new_cells));
  ASSERT_TRUE(RepackPolicy(after, cells, changed));  // nothing changed now
  EXPECT_TRUE(changed.empty());
  after.actions.pop_back();  // a policy of another size is refused, untouched
  std::vector<uint8_t> small(10, 0);
  EXPECT_FALSE(RepackPolicy(after, cells, changed));
  EXPECT_FALSE(RepackPolicy(before, small, changed));
  EXPECT_EQ(small, std::vector<uint8_t>(10, 0));
}

TEST(FoxgloveMessages, ParsesSubscribeAndRefusesMalformed) {
  ClientMessage m =
      ParseClientMessage(R"({"op":"subscribe","subscriptions":[{"id":7,"channelId":3}]})");
  ASSERT_EQ(m.kind, ClientMessage::kSubscribe);
  EXPECT_EQ(m.subscribe, (std::vector<std::pair<uint32_t, uint32_t>>{{7, 3}}));
  m = ParseClientMessage(R"({"op":"unsubscribe","subscriptionIds":[7]})");
  ASSERT_EQ(m.kind, ClientMessage::kUnsubscribe);
  EXPECT_EQ(m.unsubscribe, std::vector<uint32_t>{7});
  EXPECT_EQ(ParseClientMessage(R"({"op":"getParameters"})").kind, ClientMessage::kUnsupported);
  for (const char* bad : {"", "[]", "{\"op\":1}", "{\"op\":\"subscribe\"}",
                          R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":3}]})",
                          R"({"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":3}]})",
                          R"({"op":"unsubscribe","subscriptionIds":["7"]})", "{\"op\":\"x\""}) {
    EXPECT_EQ(ParseClientMessage(bad).kind, ClientMessage::kMalformed) << bad;
  }
  const std::string frame = MessageDataFrame(0x01020304, 5, "{}");
  EXPECT_EQ(frame, std::string("\x01\x04\x03\x02\x01\x05\0\0\0\0\0\0\0{}", 15));
}

TEST(HostCheck, AcceptsThisServerAndAllowedNamesOnly) {
  const HostPolicy local{"127.0.0.1", 8080, {}};
  for (const char* host : {"127.0.0.1:8080", "localhost:8080", "LocalHost:8080", "[::1]:8080",
                           "[0:0:0:0:0:0:0:1]:8080", " 127.0.0.1:8080 "}) {
    EXPECT_TRUE(HostAllowed(host, local)) << host;
  }
  for (const char* host : {"",
                           "attacker.example:8080",
                           "attacker.example",
                           "127.0.0.1.attacker.example:8080",
                           "localhost.attacker.example:8080",
                           "localhost.:8080",
                           "127.0.0.1:8081",
                           "localhost:80",
                           "127.0.0.1",
                           "localhost",
                           "[::1]",
                           "[::1]:8081",
                           "::1:8080",
                           "[::2]:8080",
                           "[::ffff:127.0.0.1]:8080",
                           "127.0.0.2:8080",
                           "2130706433:8080",
                           "0.0.0.0:8080",
                           "127.0.0.1:08080x",
                           "127.0.0.1:",
                           "127.0.0.1:0",
                           "127.0.0.1:99999",
                           "[::1:8080",
                           "[::1]x:8080",
                           "user@127.0.0.1:8080",
                           "127.0.0.1:8080/",
                           "127.0.0.1:8080, evil:8080",
                           "[fe80::1%25eth0]:8080"}) {
    EXPECT_FALSE(HostAllowed(host, local)) << host;
  }
  // No port means 80.
  EXPECT_TRUE(HostAllowed("localhost", HostPolicy{"127.0.0.1", 80, {}}));
  // The bound address counts (IPv6 by value); 0.0.0.0 and :: do not.
  EXPECT_TRUE(HostAllowed("192.168.1.5:8080", HostPolicy{"192.168.1.5", 8080, {}}));
  EXPECT_TRUE(HostAllowed("[fe80:0::1]:8080", HostPolicy{"fe80::1", 8080, {}}));
  EXPECT_FALSE(HostAllowed("0.0.0.0:8080", HostPolicy{"0.0.0.0", 8080, {}}));
  EXPECT_FALSE(HostAllowed("[::]:8080", HostPolicy{"::", 8080, {}}));
  EXPECT_FALSE(HostAllowed("192.168.1.5:8080", HostPolicy{"0.0.0.0", 8080, {}}));
  // --allow-host: a name with any port, NAME:PORT with that port only.
  const HostPolicy lan{
      "0.0.0.0", 8080, {"Runhost.lan", "192.168.1.5:8080", "fe80::1", "[fe80::2]:9"}};
  for (const char* host : {"runhost.lan", "RUNHOST.LAN:443", "runhost.lan:8080", "192.168.1.5:8080",
                           "[fe80::1]:1234", "[fe80::2]:9", "localhost:8080"}) {
    EXPECT_TRUE(HostAllowed(host, lan)) << host;
  }
  for (const char* host : {"runhost.lan.attacker.example", "192.168.1.5:8081", "192.168.1.5",
                           "[fe80::2]:8080", "runhost:8080"}) {
    EXPECT_FALSE(HostAllowed(host, lan)) << host;
  }
}

TEST(HostCheck, AcceptsOnlyThisServersOrigins) {
  const HostPolicy local{"127.0.0.1", 8080, {"proxy.example"}};
  for (const char* origin : {"http://127.0.0.1:8080", "http://localhost:8080", "HTTP://[::1]:8080",
                             "https://proxy.example", "http://proxy.example:8000"}) {
    EXPECT_TRUE(OriginAllowed(origin, local)) << origin;
  }
  for (const char* origin :
       {"", "null", "http://attacker.example", "https://attacker.example:8080",
        "http://127.0.0.1:8081", "http://127.0.0.1", "https://127.0.0.1:443",
        "http://localhost:3000", "file://", "chrome-extension://abcdef", "ws://127.0.0.1:8080",
        "http://127.0.0.1:8080/", "http://127.0.0.1:8080/page", "http://user@127.0.0.1:8080",
        "http:/127.0.0.1:8080", "http://[::1:8080"}) {
    EXPECT_FALSE(OriginAllowed(origin, local)) << origin;
  }
  // The default ports of the schemes.
  EXPECT_TRUE(OriginAllowed("http://localhost", HostPolicy{"127.0.0.1", 80, {}}));
  EXPECT_TRUE(OriginAllowed("https://localhost", HostPolicy{"127.0.0.1", 443, {}}));
  EXPECT_FALSE(OriginAllowed("https://localhost", HostPolicy{"127.0.0.1", 80, {}}));
}

TEST(HostCheck, ChecksAllowHostValues) {
  for (const char* good :
       {"runs.example.org", "runs.example.org:8443", "192.168.1.5", "192.168.1.5:8080", "fe80::1",
        "[fe80::1]", "[fe80::1]:8080", "localhost"}) {
    EXPECT_EQ(AllowHostError(good), "") << good;
  }
  for (const char* bad :
       {"", ":8080", "runs.example.org:", "runs.example.org:0", "runs.example.org:70000",
        "http://runs.example.org", "a/b", "[fe80::1", "fe80::1:x:", "[::1]:x", "*.example.org"}) {
    EXPECT_NE(AllowHostError(bad), "") << bad;
    EXPECT_NE(AllowHostError(bad).find("--allow-host"), std::string::npos);
  }
}

}  // namespace
}  // namespace dynapath::web
