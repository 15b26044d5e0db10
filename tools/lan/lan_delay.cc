// dynapath-lan-delay: holds the packets of one NFQUEUE queue for a while
// before letting them through, to simulate delay, jitter and reordering on
// the simulated LAN of tools/lan/lan.sh (the kernels this project is tested
// on have no sch_netem; where one has, `tc qdisc add dev vb root netem delay
// 20ms 5ms` does the same).
//
// Every packet is released `delay` ms after it arrived, plus a uniform jitter
// in [-jitter, +jitter] ms (packets closer together than the jitter get
// reordered, as with netem); with --early P, a fraction P of the packets is
// released at once instead (netem's "reorder": they overtake the held ones).
// Only the packet metadata is copied to user space; verdicts are given out of
// order, which NFQUEUE allows. On SIGTERM/SIGINT the held packets are released
// and the program exits; packets arriving while no program listens pass
// undelayed (the iptables rule uses --queue-bypass).

#include <arpa/inet.h>
#include <libnetfilter_queue/libnetfilter_queue.h>
#include <linux/netfilter.h>
#include <linux/netlink.h>
#include <poll.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/socket.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <queue>
#include <random>
#include <string>
#include <vector>

#include "runtime/option_group.h"

namespace {

volatile sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }

struct Held {
  int64_t release_us;
  uint32_t id;
  bool operator>(const Held& other) const { return release_us > other.release_us; }
};

struct Options {
  int queue = 0;
  double delay_ms = 0, jitter_ms = 0, early = 0;
};

struct State {
  Options options;
  std::mt19937_64 rng;
  std::priority_queue<Held, std::vector<Held>, std::greater<Held>> held;
  nfq_q_handle* queue = nullptr;
  int64_t packets = 0, early = 0;
};

int64_t NowUs() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// The options, with their bounds, on CLI11 as every command's.
// --queue and --delay are required, checked after parsing (CheckRequired):
// CLI11's own check would come before, and hide, an unknown option's error.
void DeclareOptions(CLI::App& app, Options& o) {
  app.add_option("--queue", o.queue, "the NFQUEUE queue whose packets to hold (required)")
      ->type_name("N")
      ->transform(dynapath::runtime::DecimalInteger())
      ->check(CLI::Range(0, 65535));
  app.add_option("--delay", o.delay_ms, "hold every packet this long (required)")
      ->type_name("MS")
      ->check(CLI::Range(0.0, 10000.0));
  app.add_option("--jitter", o.jitter_ms, "plus a uniform jitter in [-MS, +MS] (reorders)")
      ->type_name("MS")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10000.0));
  app.add_option("--early", o.early, "release a fraction P of the packets at once (overtaking)")
      ->type_name("P")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
}

// Exit code 2 with one line unless --queue and --delay were given, else -1.
int CheckRequired(const CLI::App& app) {
  if (app.count("--queue") > 0 && app.count("--delay") > 0) return -1;
  std::fputs("dynapath-lan-delay: --queue and --delay are required (see --help)\n", stderr);
  return 2;
}

int OnPacket(nfq_q_handle*, nfgenmsg*, nfq_data* data, void* arg) {
  auto* state = static_cast<State*>(arg);
  const nfqnl_msg_packet_hdr* header = nfq_get_msg_packet_hdr(data);
  if (header == nullptr) return 0;
  const uint32_t id = ntohl(header->packet_id);
  const Options& o = state->options;
  ++state->packets;
  double hold_ms = o.delay_ms;
  if (o.early > 0 && std::uniform_real_distribution<double>(0, 1)(state->rng) < o.early) {
    hold_ms = 0;
    ++state->early;
  } else if (o.jitter_ms > 0) {
    hold_ms += std::uniform_real_distribution<double>(-o.jitter_ms, o.jitter_ms)(state->rng);
  }
  if (hold_ms <= 0) return nfq_set_verdict(state->queue, id, NF_ACCEPT, 0, nullptr);
  state->held.push(Held{NowUs() + static_cast<int64_t>(hold_ms * 1000), id});
  return 0;
}

void ReleaseDue(State& state, int64_t now_us) {
  while (!state.held.empty() && state.held.top().release_us <= now_us) {
    nfq_set_verdict(state.queue, state.held.top().id, NF_ACCEPT, 0, nullptr);
    state.held.pop();
  }
}

}  // namespace

int main(int argc, char** argv) {
  State state;
  CLI::App app("Holds the packets of an NFQUEUE queue for a while (delay, jitter, reordering).",
               "dynapath-lan-delay");
  DeclareOptions(app, state.options);
  if (int code =
          dynapath::runtime::ParseCommandLine(app, {argv + 1, argv + argc}, "dynapath-lan-delay");
      code >= 0) {
    return code;
  }
  if (int code = CheckRequired(app); code >= 0) return code;
  uint64_t seed = 0;
  if (getrandom(&seed, sizeof seed, 0) != sizeof seed) seed = static_cast<uint64_t>(NowUs());
  state.rng.seed(seed);

  nfq_handle* handle = nfq_open();
  if (handle == nullptr) {
    std::fprintf(stderr, "dynapath-lan-delay: nfq_open: %s\n", std::strerror(errno));
    return 1;
  }
  state.queue =
      nfq_create_queue(handle, static_cast<uint16_t>(state.options.queue), &OnPacket, &state);
  if (state.queue == nullptr) {
    std::fprintf(stderr, "dynapath-lan-delay: cannot bind queue %d: %s\n", state.options.queue,
                 std::strerror(errno));
    nfq_close(handle);
    return 1;
  }
  nfq_set_mode(state.queue, NFQNL_COPY_META, 0);
  nfq_set_queue_maxlen(state.queue, 1 << 16);
  const int fd = nfq_fd(handle);
  int on = 1;
  setsockopt(fd, SOL_NETLINK, NETLINK_NO_ENOBUFS, &on, sizeof on);
  int buffer = 16 << 20;
  setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &buffer, sizeof buffer);

  struct sigaction action = {};
  action.sa_handler = OnSignal;
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
  std::fprintf(stderr, "dynapath-lan-delay: queue %d, delay %.1f ms, jitter %.1f ms, early %.2f\n",
               state.options.queue, state.options.delay_ms, state.options.jitter_ms,
               state.options.early);

  std::vector<char> packet(1 << 16);
  while (!g_stop) {
    int timeout_ms = 100;
    if (!state.held.empty()) {
      const int64_t wait_us = state.held.top().release_us - NowUs();
      timeout_ms = wait_us <= 0 ? 0 : static_cast<int>((wait_us + 999) / 1000);
      if (timeout_ms > 100) timeout_ms = 100;
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = poll(&p, 1, timeout_ms);
    if (ready > 0) {
      // Drain what is there without blocking.
      while (true) {
        const ssize_t n = recv(fd, packet.data(), packet.size(), MSG_DONTWAIT);
        if (n <= 0) break;
        nfq_handle_packet(handle, packet.data(), static_cast<int>(n));
      }
    } else if (ready < 0 && errno != EINTR) {
      std::fprintf(stderr, "dynapath-lan-delay: poll: %s\n", std::strerror(errno));
      break;
    }
    ReleaseDue(state, NowUs());
  }
  ReleaseDue(state, INT64_MAX);
  std::fprintf(stderr, "dynapath-lan-delay: %lld packets, %lld released early\n",
               static_cast<long long>(state.packets), static_cast<long long>(state.early));
  nfq_destroy_queue(state.queue);
  nfq_close(handle);
  return 0;
}
