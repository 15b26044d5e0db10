#pragma once
// A planning service's latency and throughput as `dynapath web` sees them
// on the bus: the time from a request (PATH_REQUEST, or GOAL_REQUEST: one
// instance per kind, their ids are separate) to the reply with the same
// client and request id, both as received here, in windows of one second
// of wall clock. Measured where the page's server listens, so it holds the
// bus's two legs and the service's own time, not the client's.
//
// Memory is bounded: at most max_pending requests wait for their reply
// (the oldest forgotten beyond that, counted); a reply whose request was
// not seen (the server started later, or it was forgotten) is counted as
// unmatched. A window is closed, and returned, by the first request or
// reply past its end, or by Close (the server's clock, so that the last
// window of a burst is shown without waiting for more traffic); windows
// without a request or a reply are not returned.

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <unordered_map>

#include "dynapath/latency_histogram.h"

namespace dynapath::web {

struct ServiceWindow {
  double end_ms = 0;        // the window's end (wall clock, ms since the epoch)
  int64_t requests = 0;     // requests seen in the window
  int64_t replies = 0;      // replies matched to their request in the window
  double per_second = 0;    // replies (matched or not) per second
  double p50_ms = 0;        // latency percentiles of the matched replies (0 without any)
  double p99_ms = 0;
  double max_ms = 0;
  int64_t unmatched = 0;    // replies in the window whose request was not seen
};

class ServiceLatency {
 public:
  explicit ServiceLatency(size_t max_pending = 65536, double window_ms = 1000);

  // Each returns the window the message's time closed, if it had a request or a reply.
  std::optional<ServiceWindow> Request(const std::string& client, int64_t id, double ms);
  std::optional<ServiceWindow> Reply(const std::string& client, int64_t id, double ms);
  // The open window, when `ms` is past its end (a timer's tick).
  std::optional<ServiceWindow> Close(double ms) { return Advance(ms); }

  size_t pending() const { return sent_.size(); }
  int64_t forgotten() const { return forgotten_; }  // requests dropped past max_pending

 private:
  std::optional<ServiceWindow> Advance(double ms);
  static std::string Key(const std::string& client, int64_t id);

  size_t max_pending_;
  double window_ms_;
  std::unordered_map<std::string, double> sent_;  // key -> when the request was seen
  std::deque<std::string> order_;                 // keys, oldest first (some answered)
  int64_t forgotten_ = 0;
  int64_t window_ = -1;  // index of the open window: floor(ms / window_ms)
  LatencyHistogram latencies_;
  int64_t window_requests_ = 0;
  int64_t window_replies_ = 0;  // matched or not
  int64_t window_unmatched_ = 0;
};

}  // namespace dynapath::web
