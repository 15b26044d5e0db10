#pragma once
// The heartbeat of a component that hands work to agents (role
// COORDINATOR): agents that stop hearing it leave, and its final state
// tells them whether the work finished or failed (protocol::CoordinatorWatch).

#include <atomic>
#include <optional>

#include "dynapath/heartbeat_t.hpp"
#include "dynapath/result.h"
#include "protocol/bus.h"
#include "protocol/liveness.h"

namespace dynapath::coordinator {

class CoordinatorHeartbeat {
 public:
  explicit CoordinatorHeartbeat(protocol::Bus& bus) : bus_(bus) {}

  // Starts beating every 0.1 s, in the running state; nothing while beating.
  void Start() {
    if (sender_) return;
    heartbeat_t base{};
    base.role = heartbeat_t::ROLE_COORDINATOR;
    base.batch_id = -1;
    base.round = -1;
    sender_.emplace(bus_, base, 0.1, [this](heartbeat_t& beat) {
      beat.state = static_cast<int8_t>(state_.load());
    });
  }
  bool beating() const { return sender_.has_value(); }
  // Sends the final state (finished when `ended` is ok or cancelled, else
  // failed) and stops beating; nothing when not beating.
  void Finish(const Status& ended) {
    if (!sender_) return;
    state_ = ended || ended.error().IsCancelled() ? heartbeat_t::STATE_FINISHED
                                                  : heartbeat_t::STATE_FAILED;
    sender_->SendFinal();
    sender_.reset();
  }

 private:
  protocol::Bus& bus_;
  std::atomic<int> state_{heartbeat_t::STATE_RUNNING};
  std::optional<protocol::HeartbeatSender> sender_;
};

}  // namespace dynapath::coordinator
