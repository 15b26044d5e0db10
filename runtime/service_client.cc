#include "runtime/service_client.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include "dynapath/change_sequence.h"
#include "dynapath/step_report_t.hpp"
#include "protocol/channels.h"

namespace dynapath::runtime {

Result<std::unique_ptr<ServiceClient>> ServiceClient::Open(const ProcessSetup& process,
                                                           std::string client, int listen,
                                                           ReplyHook on_reply) {
  std::unique_ptr<ServiceClient> c(new ServiceClient());
  c->client_ = std::move(client);
  c->on_reply_ = std::move(on_reply);
  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(process.lcm_url);
  if (!lcm) return lcm.error();
  c->lcm_ = std::move(*lcm);
  c->bus_ = std::make_unique<protocol::Bus>(*c->lcm_, process.run_id, process.bus);
  ServiceClient* self = c.get();
  c->bus_->Subscribe<path_reply_t>(protocol::channel::kPathReply, [self](path_reply_t& reply) {
    if (reply.client != self->client_) return;  // another client's
    {
      std::lock_guard lock(self->mutex_);
      const bool first = self->witness_.Saw(reply);
      if (self->on_reply_) {
        if (first) self->on_reply_(reply);
        return;
      }
      // A second service's different reply does not replace the first.
      if (first) self->reply_ = std::move(reply);
    }
    self->changed_.notify_all();
  });
  if ((listen & kPolicy) != 0) {
    c->bus_->Subscribe<policy_t>(protocol::channel::kPolicy, [self](policy_t& policy) {
      {
        std::lock_guard lock(self->mutex_);
        self->policy_ = std::move(policy);
      }
      self->changed_.notify_all();
    });
  }
  if ((listen & kReports) != 0) {
    c->bus_->Subscribe<step_report_t>(protocol::channel::kReport, [self](step_report_t& report) {
      const auto now = std::chrono::steady_clock::now();
      {
        std::lock_guard lock(self->mutex_);
        self->reports_.emplace(report.time_step, now);
        if (self->reports_.size() > kKeptReports) self->reports_.erase(self->reports_.begin());
      }
      self->changed_.notify_all();
    });
  }
  c->dispatcher_ = std::make_unique<protocol::Dispatcher>(*c->lcm_);
  return c;
}

ServiceClient::~ServiceClient() { dispatcher_.reset(); }

void ServiceClient::Send(int64_t request_id,
                         const std::vector<std::pair<int32_t, int32_t>>& starts) {
  path_request_t request{};
  request.run_id = bus_->run_id();
  request.client = client_;
  request.request_id = request_id;
  request.num_starts = static_cast<int32_t>(starts.size());
  for (const auto& [row, col] : starts) {
    request.start_rows.push_back(row);
    request.start_cols.push_back(col);
  }
  bus_->Publish(protocol::channel::kPathRequest, request);
}

std::optional<path_reply_t> ServiceClient::Ask(
    const std::vector<std::pair<int32_t, int32_t>>& starts, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(seconds));
  std::optional<path_reply_t> last;
  while (std::chrono::steady_clock::now() < deadline) {
    const int64_t id = next_id_++;
    Send(id, starts);
    std::unique_lock lock(mutex_);
    const auto retry =
        std::min(deadline, std::chrono::steady_clock::now() + std::chrono::milliseconds(200));
    changed_.wait_until(lock, retry, [&] { return reply_ && reply_->request_id == id; });
    if (reply_ && reply_->request_id == id) {
      if (reply_->refused != path_reply_t::NOT_READY) return reply_;
      last = reply_;
      lock.unlock();
      // Not ready: the service is still training its first policy.
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  return last;
}

std::optional<std::string> ServiceClient::SecondService() {
  std::this_thread::sleep_for(std::chrono::duration<double>(kSecondReplySeconds));
  std::lock_guard lock(mutex_);
  return witness_.conflict();
}

Result<path_reply_t> ServiceClient::Meet(const Grid& maze, double seconds) {
  std::optional<path_reply_t> reply = Ask({}, seconds);
  if (!reply || reply->refused == path_reply_t::NOT_READY) {
    return Error("no policy from a service of run " + bus_->run_id() + " within --timeout",
                 Error::Code::kUnavailable);
  }
  if (std::optional<std::string> two = SecondService()) {
    return Error(*two, Error::Code::kUnavailable);
  }
  const uint64_t ours = MazeFingerprint(maze);
  if (static_cast<uint64_t>(reply->maze_fingerprint) != ours) {
    return Error("run " + bus_->run_id() + " is served by " + DescribeReplier(*reply) +
                 ", not this maze (fingerprint " + FingerprintText(ours) +
                 "): give the service's maze options (size, difficulty, seed, maze file, "
                 "stations)");
  }
  return *reply;
}

std::optional<policy_t> ServiceClient::LatestPolicy(double seconds) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, std::chrono::duration<double>(seconds),
                    [&] { return policy_.has_value(); });
  return policy_;
}

std::optional<std::chrono::steady_clock::time_point> ServiceClient::ReportArrival(int time_step,
                                                                                  double seconds) {
  std::unique_lock lock(mutex_);
  auto found = reports_.end();
  changed_.wait_for(lock, std::chrono::duration<double>(seconds), [&] {
    found = reports_.lower_bound(time_step);
    return found != reports_.end();
  });
  if (found == reports_.end()) return std::nullopt;
  return found->second;
}

}  // namespace dynapath::runtime
