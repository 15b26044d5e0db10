// The web server's handling of what clients send and how fast they read,
// over real sockets on 127.0.0.1 (any free port): oversized and malformed
// frames close the connection, the client cap refuses with HTTP 503, a
// client that does not read is dropped while the others go on; and the
// page's frame codec (whole policies and deltas) and the Foxglove client
// message parser.

#include "tools/web/web_server.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "tools/web/messages.h"

namespace dynapath::web {
namespace {

// A raw TCP client speaking just enough WebSocket to test the server.
class RawClient {
 public:
  explicit RawClient(int port, int receive_buffer = 0) {
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
  // The HTTP response's status line (or "" on a closed connection).
  std::string Handshake(const std::string& extra_headers = "") {
    Send(
        "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
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
  get.Send("GET / HTTP/1.1\r\nHost: x\r\n\r\n");
  std::string response;
  for (int i = 0; i < 10 && response.find("page") == std::string::npos; ++i)
    response += get.Read(2000);
  EXPECT_EQ(response.rfind("HTTP/1.1 200", 0), 0u) << response;
  EXPECT_NE(response.find("<p>page</p>"), std::string::npos);
  RawClient post(server.port());
  post.Send("POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\n\r\n");
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
        "GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
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
  // policy waits until `reader` has 100 KB of the last one, so `reader` is
  // never a queue behind, however slowly this machine (or a sanitizer) runs.
  std::atomic<bool> stop{false};
  std::atomic<size_t> read_bytes{0};
  std::thread drain([&] {
    while (!stop) read_bytes += reader.Read(50).size();
  });
  for (int i = 0; i < 200 && server.counters().dropped_slow == 0; ++i) {
    const size_t before = read_bytes;
    server.Policy(Policy(300, i % 8), 0);
    WaitFor([&] { return read_bytes >= before + 100'000 || server.counters().dropped_slow > 0; });
  }
  EXPECT_TRUE(WaitFor([&] { return server.counters().dropped_slow == 1; }));
  EXPECT_TRUE(slow.ClosedWithin(10));
  EXPECT_EQ(server.counters().clients, 1);  // the reader is still served
  stop = true;
  drain.join();
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

}  // namespace
}  // namespace dynapath::web
