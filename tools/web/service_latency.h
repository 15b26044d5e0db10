#pragma once
// A planning service's latency and throughput as `dynapath web` sees them
// on the bus: the time from a PATH_REQUEST to the PATH_REPLY with the same
// client and request id, both as received here, in windows of one second
// of wall clock. Measured where the page's server listens, so it holds the
// bus's two legs and the service's own time, not the client's.
//
// Memory is bounded: at most max_pending requests wait for their reply
// (the oldest forgotten beyond that, counted); a reply whose request was
// not seen (the server started later, or it was forgotten) is counted as
// unmatched. A window is closed, and returned, by the first request or
// reply past its end; windows without a reply are not returned.

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <unordered_map>

#include "dynapath/latency_histogram.h"

namespace dynapath::web {

struct ServiceWindow {
  double end_ms = 0;        // the window's end (wall clock, ms since the epoch)
  int64_t replies = 0;      // replies matched to their request in the window
  double per_second = 0;    // replies (matched or not) per second
  double p50_ms = 0;        // latency percentiles of the matched replies
  double p99_ms = 0;
  double max_ms = 0;
  int64_t unmatched = 0;    // replies in the window whose request was not seen
};

class ServiceLatency {
 public:
  explicit ServiceLatency(size_t max_pending = 65536, double window_ms = 1000);

  // Each returns the window the message's time closed, if one with replies.
  std::optional<ServiceWindow> Request(const std::string& client, int64_t id, double ms);
  std::optional<ServiceWindow> Reply(const std::string& client, int64_t id, double ms);

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
  int64_t window_replies_ = 0;  // matched or not
  int64_t window_unmatched_ = 0;
};

}  // namespace dynapath::web
