// Federated training of convQ's model on agents over memq:// as threads of
// this test: coordinator::ConvQTrainer with launch::EmbeddedAgents. The
// model must be the in-process federated training's at 1 and 3 agents; an
// agent that falls silent owing shards has its learners reassigned; with no
// agent left the training fails with the reason, in bounded time.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <thread>

#include "coordinator/convq_trainer.h"
#include "dynapath/convq_training.h"
#include "launch/launcher.h"
#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "protocol/liveness.h"

namespace dynapath {
namespace {

ConvQTrainingOptions FederatedOptions(ConvQAveraging averaging) {
  ConvQTrainingOptions options;
  options.seed = 11;
  options.rounds = 3;
  options.mazes_per_round = 7;
  options.samples_per_maze = 64;
  options.min_side = 8;
  options.max_side = 16;
  options.learners = 5;
  options.averaging = averaging;
  return options;
}

protocol::BusOptions ConvQMemqBus() {
  protocol::BusOptions options;
  options.fragment_above = 0;
  return options;
}

Result<ConvQModel> TrainOnAgents(const ConvQTrainingOptions& options, int agents,
                                 coordinator::ConvQTrainerStats* stats = nullptr) {
  lcm::LCM lcm("memq://");
  if (!lcm.good()) return Error::Unavailable("no memq://");
  const std::string run = "convq-agents-" + std::to_string(agents);
  protocol::Bus bus(lcm, run, ConvQMemqBus());
  coordinator::ConvQTrainerOptions trainer_options;
  trainer_options.min_agents = agents;
  trainer_options.agent_wait_seconds = 120;
  coordinator::ConvQTrainer trainer(bus, trainer_options);
  launch::EmbeddedAgents embedded(lcm, run, ConvQMemqBus(), agents, 2);
  protocol::Dispatcher dispatcher(lcm);
  trainer.Start();
  embedded.Start();
  Result<ConvQModel> model = TrainConvQFederated(
      options, [&](int round, const ConvQModel& m) { return trainer.Round(options, round, m); },
      {});
  trainer.Finish();
  embedded.Stop();
  if (stats != nullptr) *stats = trainer.stats();
  return model;
}

TEST(ConvQOnAgents, TheModelIsTheInProcessOneAtOneAndThreeAgents) {
  for (ConvQAveraging averaging : {ConvQAveraging::kEqual, ConvQAveraging::kImportance}) {
    const ConvQTrainingOptions options = FederatedOptions(averaging);
    Result<ConvQModel> local = TrainConvQModel(options, nullptr, {});
    ASSERT_TRUE(local.ok());
    for (int agents : {1, 3}) {
      coordinator::ConvQTrainerStats stats;
      Result<ConvQModel> distributed = TrainOnAgents(options, agents, &stats);
      ASSERT_TRUE(distributed.ok()) << distributed.error().message;
      EXPECT_EQ(*distributed, *local) << agents << " agents";
      EXPECT_EQ(stats.rounds, options.rounds);
      EXPECT_EQ(stats.shards, options.rounds * options.learners);
    }
  }
}

// An agent that announces itself by heartbeats, then falls silent as soon as
// it is given learners (a process killed mid-training).
class VanishingAgent {
 public:
  VanishingAgent(protocol::Bus& bus, int id) {
    bus.Subscribe<model_round_t>(protocol::channel::kModelRound, [this, id](model_round_t& m) {
      for (int32_t agent : m.item_agent) {
        if (agent == id) given_ = true;
      }
    });
    heartbeat_t base{};
    base.role = heartbeat_t::ROLE_AGENT;
    base.sender = id;
    base.threads = 1;
    beat_.emplace(bus, base, 0.05, [](heartbeat_t&) {});
  }
  // Called by the test's loop: stops the heartbeat once given learners.
  void Poll() {
    if (given_ && beat_) beat_.reset();
  }
  bool vanished() const { return !beat_.has_value(); }

 private:
  std::atomic<bool> given_{false};
  std::optional<protocol::HeartbeatSender> beat_;
};

TEST(ConvQOnAgents, ASilentAgentsLearnersAreReassigned) {
  const ConvQTrainingOptions options = FederatedOptions(ConvQAveraging::kEqual);
  Result<ConvQModel> local = TrainConvQModel(options, nullptr, {});
  ASSERT_TRUE(local.ok());
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  protocol::Bus bus(lcm, "convq-vanish", ConvQMemqBus());
  protocol::Bus ghost_bus(lcm, "convq-vanish", ConvQMemqBus());
  coordinator::ConvQTrainerOptions trainer_options;
  trainer_options.min_agents = 2;
  trainer_options.agent_wait_seconds = 120;
  trainer_options.agent_timeout_seconds = 0.5;
  coordinator::ConvQTrainer trainer(bus, trainer_options);
  VanishingAgent ghost(ghost_bus, 1000);
  launch::EmbeddedAgents embedded(lcm, "convq-vanish", ConvQMemqBus(), 1, 1);
  protocol::Dispatcher dispatcher(lcm);
  trainer.Start();
  embedded.Start();
  std::atomic<bool> done{false};
  std::thread poller([&] {
    while (!done) {
      ghost.Poll();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  Result<ConvQModel> model = TrainConvQFederated(
      options, [&](int round, const ConvQModel& m) { return trainer.Round(options, round, m); },
      {});
  done = true;
  poller.join();
  trainer.Finish();
  embedded.Stop();
  ASSERT_TRUE(model.ok()) << model.error().message;
  EXPECT_EQ(*model, *local);
  EXPECT_TRUE(ghost.vanished());
  EXPECT_GE(trainer.stats().epochs, 1);
}

TEST(ConvQOnAgents, WithNoAgentLeftTheTrainingFailsSayingSo) {
  const ConvQTrainingOptions options = FederatedOptions(ConvQAveraging::kEqual);
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  protocol::Bus bus(lcm, "convq-none", ConvQMemqBus());
  protocol::Bus ghost_bus(lcm, "convq-none", ConvQMemqBus());
  coordinator::ConvQTrainerOptions trainer_options;
  trainer_options.agent_wait_seconds = 1;
  trainer_options.agent_timeout_seconds = 0.3;
  coordinator::ConvQTrainer trainer(bus, trainer_options);
  VanishingAgent ghost(ghost_bus, 7);
  protocol::Dispatcher dispatcher(lcm);
  trainer.Start();
  std::atomic<bool> done{false};
  std::thread poller([&] {
    while (!done) {
      ghost.Poll();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  Result<ConvQModel> model = TrainConvQFederated(
      options, [&](int round, const ConvQModel& m) { return trainer.Round(options, round, m); },
      {});
  done = true;
  poller.join();
  trainer.Finish();
  ASSERT_FALSE(model.ok());
  EXPECT_FALSE(model.error().IsCancelled());
  EXPECT_NE(model.error().message.find("agents appeared"), std::string::npos)
      << model.error().message;
}

TEST(ConvQOnAgents, StopsAtOnceWhileWaitingForAgents) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  protocol::Bus bus(lcm, "convq-stop", ConvQMemqBus());
  coordinator::ConvQTrainer trainer(bus, coordinator::ConvQTrainerOptions{});
  protocol::Dispatcher dispatcher(lcm);
  std::atomic<bool> stop{false};
  trainer.set_stop(&stop);
  trainer.Start();
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    stop = true;
  });
  const ConvQTrainingOptions options = FederatedOptions(ConvQAveraging::kEqual);
  Result<std::vector<ConvQShard>> shards = trainer.Round(options, 1, InitialConvQModel());
  stopper.join();
  ASSERT_FALSE(shards.ok());
  EXPECT_TRUE(shards.error().IsCancelled());
}

}  // namespace
}  // namespace dynapath
