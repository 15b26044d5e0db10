#include "coordinator/training_session.h"

#include <spdlog/spdlog.h>

#include <string>

#include "protocol/channels.h"

namespace dynapath::coordinator {

TrainingSession::TrainingSession(protocol::Bus& bus, TrainingSessionOptions options)
    : bus_(bus),
      options_(options),
      agents_(options_.agent_timeout_seconds),
      trainer_(bus, inbox_, agents_,
               MakeTrainerOptions(options_.agent_wait_seconds, options_.give_up_seconds,
                                  options_.placement)) {
  bus_.Subscribe<heartbeat_t>(protocol::channel::kHeartbeat, [this](heartbeat_t& beat) {
    if (agents_.OnHeartbeat(beat)) inbox_.Wake();  // a new agent: the wait may be over
  });
}

TrainingSession::~TrainingSession() { Finish(); }

void TrainingSession::Start() { heartbeat_.Start(); }

void TrainingSession::set_stop(const std::atomic<bool>* stop) {
  stop_ = stop;
  trainer_.set_stop(stop);
}

void TrainingSession::Finish() {
  // A launcher stops its agent processes anyway.
  if (heartbeat_.beating()) heartbeat_.Finish(status());
}

Status TrainingSession::WaitForAgents() {
  Result<std::string> ids = coordinator::WaitForAgents(agents_, inbox_, options_.min_agents,
                                                       options_.agent_wait_seconds, stop_);
  if (!ids) return ids.error();
  spdlog::info("training on agents{}", *ids);
  return Ok{};
}

TrainingStats TrainingSession::Train(const std::vector<NodeId>& nodes,
                                     const std::vector<uint64_t>& seeds,
                                     const LearnerConfig& config, const QuadTree& tree,
                                     const Grid& grid, RootQTable& root) {
  if (!waited_) {
    waited_ = true;
    wait_status_ = WaitForAgents();
  }
  if (!wait_status_) return {};
  return trainer_.Train(nodes, seeds, config, tree, grid, root);
}

Status TrainingSession::status() const {
  if (!wait_status_) return wait_status_;
  return trainer_.status();
}

}  // namespace dynapath::coordinator
