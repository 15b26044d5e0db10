// Federated training of convQ's model on agents over memq:// as threads of
// this test: coordinator::ConvQTrainer with launch::EmbeddedAgents. The
// model must be the in-process federated training's at 1 and 3 agents; an
// agent that falls silent owing shards has its learners reassigned; with no
// agent left the training fails with the reason, in bounded time. An agent
// its launcher saw exit is dropped at once, however long the silence
// timeout, and with every agent process gone the training fails at once.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "coordinator/convq_trainer.h"
#include "dynapath/convq_training.h"
#include "launch/launcher.h"
#include "protocol/auth.h"
#include "protocol/channels.h"
#include "protocol/convert.h"
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
  bool given() const { return given_; }

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

// The only agent of a training, which sends, before its real shards of
// every round, shards that must not count: one with a weight that is not
// finite (Validate drops it), one of a learner the training does not have
// (the trainer refuses it), and one of learner 0 with other weights under
// another key (unauthenticated: dropped unread). memq:// delivers in order,
// so all three reach the trainer while it still collects the round.
class HostileAgent {
 public:
  HostileAgent(protocol::Bus& bus, protocol::Bus& forger) : bus_(bus), forger_(forger) {
    bus.Subscribe<model_round_t>(protocol::channel::kModelRound, [this](model_round_t& m) {
      std::lock_guard lock(mutex_);
      if (!round_ || m.round > round_->round) round_ = m;
    });
    heartbeat_t base{};
    base.role = heartbeat_t::ROLE_AGENT;
    base.sender = kId;
    base.threads = 1;
    beat_.emplace(bus, base, 0.05, [](heartbeat_t&) {});
    thread_ = std::thread([this] {
      int sent = 0;
      while (!done_) {
        std::optional<model_round_t> round;
        {
          std::lock_guard lock(mutex_);
          if (round_ && round_->round > sent) round = round_;
        }
        if (round) {
          sent = round->round;
          Answer(*round);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
  }
  ~HostileAgent() {
    done_ = true;
    thread_.join();
  }

 private:
  static constexpr int kId = 66;

  model_shards_t Message(const std::vector<ConvQShard>& shards, int round) {
    model_shards_t message = protocol::ConvQShardsToMessage(shards);
    message.run_id = bus_.run_id();
    message.round = round;
    message.agent = kId;
    return message;
  }

  void Answer(const model_round_t& m) {
    ConvQShard fake;
    fake.model = ConvQModel{1, 2, 3, 0.5, 0.5};
    fake.samples = 1000;
    model_shards_t not_finite = Message({fake}, m.round);
    not_finite.weights[1] = std::nan("");
    bus_.Publish(protocol::channel::kModelShards, not_finite);
    model_shards_t stranger = Message({fake}, m.round);
    stranger.learner[0] = 99;
    bus_.Publish(protocol::channel::kModelShards, stranger);
    forger_.Publish(protocol::channel::kModelShards, Message({fake}, m.round));
    const ConvQTrainingOptions options = protocol::ConvQOptionsFromRound(m);
    std::vector<ConvQShard> real;
    for (int k = 0; k < m.learners; ++k) {
      real.push_back(TrainConvQLearner(options, protocol::ConvQModelFromRound(m), m.round, k));
    }
    bus_.Publish(protocol::channel::kModelShards, Message(real, m.round));
  }

  protocol::Bus& bus_;
  protocol::Bus& forger_;
  std::mutex mutex_;
  std::optional<model_round_t> round_;
  std::optional<protocol::HeartbeatSender> beat_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

TEST(ConvQOnAgents, BadAndForgedShardsAreDroppedAndCounted) {
  const ConvQTrainingOptions options = FederatedOptions(ConvQAveraging::kImportance);
  Result<ConvQModel> local = TrainConvQModel(options, nullptr, {});
  ASSERT_TRUE(local.ok());
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  protocol::Bus bus(lcm, "convq-hostile", ConvQMemqBus());
  protocol::Bus agent_bus(lcm, "convq-hostile", ConvQMemqBus());
  protocol::BusOptions forged = ConvQMemqBus();
  forged.key = *protocol::KeyFromSecretText("not the run's secret: 0123456789abcdef0123456789");
  protocol::Bus forger_bus(lcm, "convq-hostile", forged);
  coordinator::ConvQTrainerOptions trainer_options;
  trainer_options.agent_wait_seconds = 120;
  coordinator::ConvQTrainer trainer(bus, trainer_options);
  Result<ConvQModel> model = Error::Internal("not run");
  {
    HostileAgent agent(agent_bus, forger_bus);
    protocol::Dispatcher dispatcher(lcm);
    trainer.Start();
    model = TrainConvQFederated(
        options, [&](int round, const ConvQModel& m) { return trainer.Round(options, round, m); },
        {});
    trainer.Finish();
  }
  ASSERT_TRUE(model.ok()) << model.error().message;
  EXPECT_EQ(*model, *local);
  const protocol::BusCounters counters = bus.counters();
  EXPECT_GE(counters.unauthenticated, options.rounds);
  EXPECT_GE(counters.dropped - counters.unauthenticated - counters.replayed, options.rounds);
  EXPECT_EQ(trainer.stats().shards_refused, options.rounds);
  EXPECT_EQ(trainer.stats().shards, options.rounds * options.learners);
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

// A ghost agent that goes on beating after it was given learners (never
// silent: only its launcher's word drops it) is reported exited then.
TEST(ConvQOnAgents, AnAgentSeenToExitIsDroppedAtOnce) {
  const ConvQTrainingOptions options = FederatedOptions(ConvQAveraging::kEqual);
  Result<ConvQModel> local = TrainConvQModel(options, nullptr, {});
  ASSERT_TRUE(local.ok());
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  protocol::Bus bus(lcm, "convq-exit", ConvQMemqBus());
  protocol::Bus ghost_bus(lcm, "convq-exit", ConvQMemqBus());
  coordinator::ConvQTrainerOptions trainer_options;
  trainer_options.min_agents = 2;
  trainer_options.agent_wait_seconds = 120;
  trainer_options.agent_timeout_seconds = 3600;  // silence never drops it here
  trainer_options.give_up_seconds = 3600;
  coordinator::ConvQTrainer trainer(bus, trainer_options);
  VanishingAgent ghost(ghost_bus, 1000);
  launch::EmbeddedAgents embedded(lcm, "convq-exit", ConvQMemqBus(), 1, 1);
  protocol::Dispatcher dispatcher(lcm);
  trainer.Start();
  embedded.Start();
  std::atomic<bool> done{false};
  std::thread launcher([&] {
    while (!done && !ghost.given()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (ghost.given()) trainer.AgentExited(1000, "was killed by signal 9");
  });
  Result<ConvQModel> model = TrainConvQFederated(
      options, [&](int round, const ConvQModel& m) { return trainer.Round(options, round, m); },
      {});
  done = true;
  launcher.join();
  trainer.Finish();
  embedded.Stop();
  ASSERT_TRUE(model.ok()) << model.error().message;
  EXPECT_EQ(*model, *local);
  EXPECT_GE(trainer.stats().epochs, 1);
  EXPECT_EQ(trainer.stats().shards_by_agent.count(1000), 0u);
}

TEST(ConvQOnAgents, WithEveryAgentProcessGoneTheTrainingFailsAtOnce) {
  const ConvQTrainingOptions options = FederatedOptions(ConvQAveraging::kEqual);
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  protocol::Bus bus(lcm, "convq-gone", ConvQMemqBus());
  protocol::Bus ghost_bus(lcm, "convq-gone", ConvQMemqBus());
  coordinator::ConvQTrainerOptions trainer_options;
  trainer_options.agent_wait_seconds = 3600;  // only the launcher's word ends it
  trainer_options.agent_timeout_seconds = 3600;
  trainer_options.give_up_seconds = 3600;
  coordinator::ConvQTrainer trainer(bus, trainer_options);
  VanishingAgent ghost(ghost_bus, 7);
  protocol::Dispatcher dispatcher(lcm);
  trainer.Start();
  std::atomic<bool> done{false};
  std::thread launcher([&] {
    while (!done && !ghost.given()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (!ghost.given()) return;
    trainer.AgentExited(7, "was killed by signal 9");
    trainer.NoAgentProcessLeft();
  });
  Result<ConvQModel> model = TrainConvQFederated(
      options, [&](int round, const ConvQModel& m) { return trainer.Round(options, round, m); },
      {});
  done = true;
  launcher.join();
  trainer.Finish();
  ASSERT_FALSE(model.ok());
  EXPECT_TRUE(model.error().IsUnavailable());
  EXPECT_NE(
      model.error().message.find("every agent process has exited (agent 7 was killed by signal 9)"),
      std::string::npos)
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
