// dynapath serve --embedded's pieces over memq:// as threads of this test:
// a PathService whose trainer is a coordinator::TrainingSession with two
// launch::EmbeddedAgents. Fed a change sequence one update per step, it
// must make exactly the steps of an in-process run; stopped while it waits
// for agents, it must end at once.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <lcm/lcm-cpp.hpp>

#include "coordinator/training_session.h"
#include "dynapath/local_trainer.h"
#include "dynapath/scenario.h"
#include "dynapath/thread_pool.h"
#include "launch/launcher.h"
#include "protocol/dispatcher.h"
#include "runtime/path_service.h"

namespace dynapath {
namespace {

constexpr double kWaitSeconds = 120;  // a loaded machine, a sanitizer

runtime::ServiceConfig Config(const Scenario& scenario, unsigned seed, Trainer* trainer) {
  runtime::ServiceConfig config;
  config.approach = Approach::kFedAsynQEqAvg;
  config.options.run_seed = seed;
  config.options.leaf_limit = 10;  // several leaves: batches of several jobs
  config.threads = 1;
  config.catch_up = scenario.changes;
  config.trainer = trainer;
  return config;
}

protocol::BusOptions MemqBus() {
  protocol::BusOptions options;
  options.fragment_above = 0;
  return options;
}

TEST(ServiceOnAgents, StepsAreThoseOfARunInProcess) {
  const unsigned seed = 3;
  const Scenario scenario = GenerateScenario(20, 20, Difficulty::kHard, seed, 6);
  ThreadPool pool(1);
  LocalTrainer local(pool);
  const runtime::ServiceConfig reference = Config(scenario, seed, nullptr);
  const ApproachRun run =
      RunApproach(scenario, reference.approach, reference.options, &local, RunLabels{});

  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  const protocol::BusOptions bus_options = MemqBus();
  protocol::Bus bus(lcm, "service-agents", bus_options);
  coordinator::TrainingSessionOptions session_options;
  session_options.min_agents = 2;
  coordinator::TrainingSession session(bus, session_options);
  launch::EmbeddedAgents agents(lcm, "service-agents", bus_options, 2, 1);
  runtime::PathService service(scenario.grid, Config(scenario, seed, &session));
  session.set_stop(&service.stopping());
  protocol::Dispatcher dispatcher(lcm);
  session.Start();
  agents.Start();
  service.Start();
  ASSERT_TRUE(service.WaitForVersion(1, kWaitSeconds));
  for (size_t t = 1; t <= scenario.changes.steps.size(); ++t) {
    MapUpdate update;
    update.source = "test";
    update.sequence = static_cast<int64_t>(t);
    update.changes = scenario.changes.steps[t - 1].changes;
    ASSERT_FALSE(service.Submit(update));
    ASSERT_TRUE(service.WaitForStep(static_cast<int>(t), kWaitSeconds));
  }
  Result<ApproachRun> served = service.Stop();
  session.Finish();
  agents.Stop();
  ASSERT_TRUE(served.ok()) << served.error().message;
  ASSERT_EQ(served->steps.size(), run.steps.size());
  for (size_t t = 0; t < run.steps.size(); ++t) {
    EXPECT_EQ(served->steps[t].success_rate, run.steps[t].success_rate) << "step " << t;
    EXPECT_EQ(served->steps[t].average_path_length, run.steps[t].average_path_length);
    EXPECT_EQ(served->steps[t].nodes_trained, run.steps[t].nodes_trained);
  }
  EXPECT_TRUE(session.status().ok());
  EXPECT_GE(session.traffic().batches, 1);  // trained on the agents, not beside them
  EXPECT_EQ(session.agents().Live().size(), 2u);
}

TEST(ServiceOnAgents, StopsAtOnceWhileWaitingForAgents) {
  const Scenario scenario = GenerateScenario(20, 20, Difficulty::kHard, 3, 2);
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  protocol::Bus bus(lcm, "service-no-agents", MemqBus());
  coordinator::TrainingSession session(bus, coordinator::TrainingSessionOptions{});
  runtime::PathService service(scenario.grid, Config(scenario, 3, &session));
  session.set_stop(&service.stopping());
  protocol::Dispatcher dispatcher(lcm);
  session.Start();
  service.Start();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(service.Current(), nullptr);  // no agent: no policy
  const auto start = std::chrono::steady_clock::now();
  (void)service.Stop();
  // Not the agent wait (60 s by default); the bound leaves room for a
  // loaded machine and a sanitizer.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
  EXPECT_TRUE(session.status().error().IsCancelled());
}

}  // namespace
}  // namespace dynapath
