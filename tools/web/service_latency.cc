#include "tools/web/service_latency.h"

#include <algorithm>
#include <cmath>

namespace dynapath::web {

ServiceLatency::ServiceLatency(size_t max_pending, double window_ms)
    : max_pending_(max_pending), window_ms_(window_ms) {}

std::string ServiceLatency::Key(const std::string& client, int64_t id) {
  // Client names are printable (1-64 characters): a unit separator cannot
  // join two pairs into one key.
  return client + '\x1f' + std::to_string(id);
}

std::optional<ServiceWindow> ServiceLatency::Advance(double ms) {
  const auto index = static_cast<int64_t>(std::floor(ms / window_ms_));
  if (index <= window_) return std::nullopt;  // the open window (or a clock step back)
  std::optional<ServiceWindow> closed;
  if (window_ >= 0 && (window_requests_ > 0 || window_replies_ > 0)) {
    ServiceWindow w;
    w.end_ms = static_cast<double>(window_ + 1) * window_ms_;
    w.requests = window_requests_;
    w.replies = latencies_.count();
    w.per_second = static_cast<double>(window_replies_) * 1000.0 / window_ms_;
    w.p50_ms = static_cast<double>(latencies_.Quantile(0.5)) / 1000.0;
    w.p99_ms = static_cast<double>(latencies_.Quantile(0.99)) / 1000.0;
    w.max_ms = static_cast<double>(latencies_.max()) / 1000.0;
    w.unmatched = window_unmatched_;
    closed = w;
  }
  window_ = index;
  latencies_ = LatencyHistogram();
  window_requests_ = 0;
  window_replies_ = 0;
  window_unmatched_ = 0;
  return closed;
}

std::optional<ServiceWindow> ServiceLatency::Request(const std::string& client, int64_t id,
                                                     double ms) {
  std::optional<ServiceWindow> closed = Advance(ms);
  ++window_requests_;
  std::string key = Key(client, id);
  if (sent_.emplace(key, ms).second) order_.push_back(std::move(key));
  // The order keeps answered keys until it is twice the cap: then only
  // those still waiting stay (amortised: at most one pass per cap's worth
  // of requests).
  if (order_.size() > 2 * max_pending_) {
    std::deque<std::string> waiting;
    for (std::string& k : order_) {
      if (sent_.count(k) > 0) waiting.push_back(std::move(k));
    }
    order_ = std::move(waiting);
  }
  // Beyond the cap the oldest requests still waiting are forgotten.
  while (sent_.size() > max_pending_) {
    if (sent_.erase(order_.front()) > 0) ++forgotten_;
    order_.pop_front();
  }
  return closed;
}

std::optional<ServiceWindow> ServiceLatency::Reply(const std::string& client, int64_t id,
                                                   double ms) {
  std::optional<ServiceWindow> closed = Advance(ms);
  ++window_replies_;
  auto it = sent_.find(Key(client, id));
  if (it == sent_.end()) {
    ++window_unmatched_;
    return closed;
  }
  const double latency_ms = std::max(0.0, ms - it->second);
  latencies_.Add(static_cast<int64_t>(std::llround(latency_ms * 1000.0)));
  sent_.erase(it);
  return closed;
}

}  // namespace dynapath::web
