// EnvSim over memq://: lock-step answers every step; free-running (--hz) never
// answers a time step before the environment reached it, and answers every
// request in the end with the same changes as lock-step.
#include "envsim/envsim.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <mutex>
#include <thread>

#include "dynapath/changes_t.hpp"
#include "dynapath/grid_t.hpp"
#include "dynapath/scenario.h"
#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "protocol/liveness.h"

namespace dynapath::envsim {
namespace {

using Clock = std::chrono::steady_clock;

// Asks envsim for steps 0..T of pass 0 all at once and records when each
// answer arrived (ms after the simulator started) and its changes.
struct Answers {
  std::map<int, double> arrived_ms;
  std::map<int, std::vector<int32_t>> cells;
};

Answers AskForEveryStep(double hz, int steps) {
  lcm::LCM lcm("memq://");
  EXPECT_TRUE(lcm.good());
  protocol::Bus sim_bus(lcm, "run1");
  protocol::Bus client(lcm, "run1");
  const Scenario scenario = GenerateScenario(12, 12, Difficulty::kMedium, 51, steps);
  EnvSimOptions options;
  options.hz = hz;
  EnvSim sim(sim_bus, ScenarioInfo{scenario, RunLabels{"12", "Medium"}, 51, "generated"}, options);

  std::mutex mutex;
  Answers answers;
  Clock::time_point started;
  auto record = [&](int step, std::vector<int32_t> cells) {
    std::lock_guard lock(mutex);
    if (answers.arrived_ms.count(step) > 0) return;
    answers.arrived_ms[step] =
        std::chrono::duration<double, std::milli>(Clock::now() - started).count();
    answers.cells[step] = std::move(cells);
  };
  client.Subscribe<grid_t>(protocol::channel::kEnvGrid, [&](grid_t&) { record(0, {}); });
  client.Subscribe<changes_t>(protocol::channel::kEnvChanges,
                              [&](changes_t& m) { record(m.time_step, m.cells); });
  // A coordinator heartbeat, so envsim does not give up waiting for one.
  heartbeat_t beat{};
  beat.run_id = "run1";
  beat.role = heartbeat_t::ROLE_COORDINATOR;
  protocol::Dispatcher dispatcher(lcm);
  std::atomic<bool> stop{false};
  started = Clock::now();
  std::thread runner([&] { sim.Run(stop); });
  client.Publish(protocol::channel::kHeartbeat, beat);
  for (int t = 0; t <= steps; ++t) {
    step_request_t request{};
    request.run_id = "run1";
    request.request_id = t;
    request.time_step = t;
    client.Publish(protocol::channel::kEnvRequest, request);
  }
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  while (Clock::now() < deadline) {
    {
      std::lock_guard lock(mutex);
      if (static_cast<int>(answers.arrived_ms.size()) == steps + 1) break;
    }
    client.Publish(protocol::channel::kHeartbeat, beat);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  stop = true;
  runner.join();
  std::lock_guard lock(mutex);
  return answers;
}

TEST(EnvSimTest, LockStepAnswersEveryStepAtOnce) {
  const Answers answers = AskForEveryStep(0.0, 8);
  // Every step answered, each with its changes (no timing claims: a loaded
  // machine may be slow; pacing is what the free-running test checks).
  ASSERT_EQ(answers.arrived_ms.size(), 9u);
  for (int step = 1; step <= 8; ++step) EXPECT_EQ(answers.cells.count(step), 1u);
}

TEST(EnvSimTest, FreeRunningNeverAnswersAStepBeforeItHappened) {
  const double hz = 20.0;  // a step every 50 ms
  const Answers paced = AskForEveryStep(hz, 8);
  ASSERT_EQ(paced.arrived_ms.size(), 9u);
  for (const auto& [step, ms] : paced.arrived_ms) {
    // Lower bounds only: a loaded machine may answer late, never early.
    EXPECT_GE(ms, 1000.0 * step / hz - 1.0) << "step " << step;
  }
  // The same sequence as lock-step.
  const Answers lock_step = AskForEveryStep(0.0, 8);
  EXPECT_EQ(paced.cells, lock_step.cells);
}

}  // namespace
}  // namespace dynapath::envsim
