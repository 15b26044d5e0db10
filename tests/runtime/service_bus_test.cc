#include "runtime/service_bus.h"

#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "dynapath/obstacle_points_t.hpp"
#include "dynapath/obstacle_update_t.hpp"
#include "dynapath/occupancy_grid_t.hpp"
#include "dynapath/path_request_t.hpp"
#include "dynapath/policy_t.hpp"
#include "dynapath/scenario.h"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "protocol/dispatcher.h"
#include "runtime/reply_witness.h"

namespace dynapath::runtime {
namespace {

constexpr double kBusWait = 120;  // seconds: a loaded machine, a sanitizer

ServiceConfig BusServiceConfig(const Scenario& scenario) {
  ServiceConfig config;
  config.approach = Approach::kFedAsynQEqAvg;
  config.options.run_seed = 3;
  config.threads = 1;
  config.catch_up = scenario.changes;
  return config;
}

protocol::BusOptions MemqBusOptions() {
  protocol::BusOptions options;
  options.fragment_above = 0;
  return options;
}

// The time steps of the policy messages a viewer receives.
class PolicyViewer {
 public:
  PolicyViewer(lcm::LCM& lcm, const std::string& run) : bus_(lcm, run, MemqBusOptions()) {
    bus_.Subscribe<policy_t>(protocol::channel::kPolicy, [this](policy_t& policy) {
      {
        std::lock_guard lock(mutex_);
        steps_.push_back(policy.time_step);
      }
      changed_.notify_all();
    });
  }
  // Waits until `count` messages came (false after kBusWait seconds).
  bool WaitFor(size_t count) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, std::chrono::duration<double>(kBusWait),
                             [&] { return steps_.size() >= count; });
  }
  // Waits until the last message came for time step `step`.
  bool WaitForStep(int step) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, std::chrono::duration<double>(kBusWait),
                             [&] { return !steps_.empty() && steps_.back() == step; });
  }
  std::vector<int> steps() {
    std::lock_guard lock(mutex_);
    return steps_;
  }

 private:
  protocol::Bus bus_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<int> steps_;
};

// A service on `scenario` with its ServiceBus over memq://, and a viewer
// of its policy messages; started. Members are destroyed in reverse order:
// dispatching stops first, then the training, then the ServiceBus its
// commits went to.
struct ServedOnMemq {
  ServedOnMemq(const Scenario& scenario, const ServiceBusOptions& options)
      : service(scenario.grid, BusServiceConfig(scenario),
                [this](const Commit& commit) {
                  if (glue != nullptr) glue->PublishCommit(commit);
                }),
        service_bus(bus, service, options),
        glue(&service_bus) {
    service.Start();
  }
  ~ServedOnMemq() { (void)service.Stop(); }

  lcm::LCM lcm{"memq://"};
  protocol::Bus bus{lcm, "service-bus", MemqBusOptions()};
  PolicyViewer viewer{lcm, "service-bus"};
  PathService service;
  ServiceBus service_bus;
  ServiceBus* glue = nullptr;
  protocol::Dispatcher dispatcher{lcm};
};

// Commits within the gap after a policy message go out as one message,
// the latest policy's, once the gap has passed.
TEST(ServiceBus, CoalescesCommitsWithinTheGapIntoTheLatestPolicy) {
  const Scenario scenario = GenerateScenario(16, 16, Difficulty::kHard, 3, 4);
  ServiceBusOptions options;
  options.policy_gap_seconds = 2;  // the steps below take far less, even under a sanitizer
  options.republish_seconds = 0;
  ServedOnMemq served(scenario, options);
  ASSERT_TRUE(served.lcm.good());
  ASSERT_TRUE(served.service.WaitForStep(0, kBusWait));
  ASSERT_TRUE(served.viewer.WaitFor(1));  // the first policy goes out at once
  const auto first = std::chrono::steady_clock::now();
  int64_t sequence = 0;
  for (const ChangeStep& step : scenario.changes.steps) {
    MapUpdate update;
    update.source = "test";
    update.sequence = ++sequence;
    update.changes = step.changes;
    ASSERT_FALSE(served.service.Submit(update));
    ASSERT_TRUE(served.service.WaitForStep(static_cast<int>(sequence), kBusWait));
  }
  const bool within_gap = std::chrono::steady_clock::now() - first < std::chrono::seconds(2);
  // The last step's policy goes out once the gap has passed, however long
  // the steps took (on a loaded machine, more than the gap).
  ASSERT_TRUE(served.viewer.WaitForStep(4));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // nothing may follow
  if (within_gap) {
    // Four commits, one message: the last step's.
    EXPECT_EQ(served.viewer.steps(), (std::vector<int>{0, 4}));
    EXPECT_EQ(served.service_bus.policies_published(), 2);
  }
  EXPECT_EQ(served.viewer.steps().back(), 4);
  EXPECT_TRUE(served.service.Stop().ok());
}

// Without a new policy, the last one is published again after
// republish_seconds, for viewers that joined since.
TEST(ServiceBus, RepublishesTheLastPolicyForLateViewers) {
  const Scenario scenario = GenerateScenario(16, 16, Difficulty::kHard, 3, 0);
  ServiceBusOptions options;
  options.policy_gap_seconds = 0;
  options.republish_seconds = 0.05;
  ServedOnMemq served(scenario, options);
  ASSERT_TRUE(served.lcm.good());
  ASSERT_TRUE(served.viewer.WaitFor(3));
  for (int step : served.viewer.steps()) EXPECT_EQ(step, 0);
  EXPECT_TRUE(served.service.Stop().ok());
}

// The replies to one client, witnessed as a client does.
class ReplyListener {
 public:
  ReplyListener(lcm::LCM& lcm, const std::string& run) : bus_(lcm, run, MemqBusOptions()) {
    bus_.Subscribe<path_reply_t>(protocol::channel::kPathReply, [this](path_reply_t& reply) {
      {
        std::lock_guard lock(mutex_);
        witness_.Saw(reply);
        replies_.push_back(reply);
      }
      changed_.notify_all();
    });
  }
  void Ask(int64_t id) {
    path_request_t request{};
    request.run_id = bus_.run_id();
    request.client = "asker";
    request.request_id = id;
    bus_.Publish(protocol::channel::kPathRequest, request);
  }
  bool WaitFor(size_t count) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, std::chrono::duration<double>(kBusWait),
                             [&] { return replies_.size() >= count; });
  }
  std::vector<path_reply_t> replies() {
    std::lock_guard lock(mutex_);
    return replies_;
  }
  std::optional<std::string> conflict() {
    std::lock_guard lock(mutex_);
    return witness_.conflict();
  }
  protocol::Bus& bus() { return bus_; }

 private:
  protocol::Bus bus_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<path_reply_t> replies_;
  ReplyWitness witness_;
};

obstacle_update_t UpdateMessage(const ChangeStep& step, const Grid& grid, uint64_t maze,
                                int64_t sequence) {
  obstacle_update_t update = protocol::UpdateToMessage(step, grid.cols(), "test", sequence, maze);
  update.run_id = "service-bus";
  return update;
}

// A service on its own Bus of a shared memq:// (as a process of its own
// on a network would be); subscribed on construction, started by Start.
struct BusService {
  BusService(lcm::LCM& lcm, const Scenario& scenario)
      : bus(lcm, "service-bus", MemqBusOptions()),
        service(scenario.grid, BusServiceConfig(scenario)),
        service_bus(bus, service, Quiet()) {}
  static ServiceBusOptions Quiet() {
    ServiceBusOptions options;
    options.publish_policy = false;
    return options;
  }
  protocol::Bus bus;
  PathService service;
  ServiceBus service_bus;
};

// The default logger's messages while it lives (set up before any thread
// of the test logs, restored after the last one stopped).
class LogCapture {
 public:
  LogCapture()
      : sink_(std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(64)),
        previous_(spdlog::default_logger()) {
    sink_->set_pattern("%v");
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("capture", sink_));
  }
  ~LogCapture() { spdlog::set_default_logger(previous_); }
  bool Contains(const std::string& text) const {
    for (const std::string& line : sink_->last_formatted()) {
      if (line.find(text) != std::string::npos) return true;
    }
    return false;
  }

 private:
  std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> sink_;
  std::shared_ptr<spdlog::logger> previous_;
};

// Every reply names the service's maze; an update made for another maze
// (its fingerprint) is dropped, counted and logged with what was wrong, one
// for this maze is taken.
TEST(ServiceBus, RepliesNameTheMazeAndForeignUpdatesAreDropped) {
  const Scenario scenario = GenerateScenario(16, 16, Difficulty::kHard, 3, 2);
  const Scenario other = GenerateScenario(16, 16, Difficulty::kHard, 99, 2);
  const LogCapture captured;
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  ReplyListener client(lcm, "service-bus");
  BusService served(lcm, scenario);
  protocol::Dispatcher dispatcher(lcm);
  served.service.Start();
  ASSERT_TRUE(served.service.WaitForStep(0, kBusWait));
  client.Ask(1);
  ASSERT_TRUE(client.WaitFor(1));
  EXPECT_EQ(static_cast<uint64_t>(client.replies()[0].maze_fingerprint),
            MazeFingerprint(scenario.grid));

  const uint64_t foreign = MazeFingerprint(other.grid);
  ASSERT_NE(foreign, MazeFingerprint(scenario.grid));
  client.bus().Publish(protocol::channel::kMapUpdates,
                       UpdateMessage(other.changes.steps[0], other.grid, foreign, 1));
  client.bus().Publish(
      protocol::channel::kMapUpdates,
      UpdateMessage(scenario.changes.steps[0], scenario.grid, MazeFingerprint(scenario.grid), 2));
  ASSERT_TRUE(served.service.WaitForStep(1, kBusWait));
  const ServiceStats stats = served.service.stats();
  EXPECT_EQ(stats.updates.refused[static_cast<size_t>(UpdateRefusal::kOtherMaze)], 1);
  EXPECT_EQ(stats.updates.accepted, 1);
  EXPECT_EQ(stats.updates.cells_changed,
            static_cast<int64_t>(scenario.changes.steps[0].changes.size()));
  EXPECT_NE(PathService::Summary(stats).find("1 other_maze"), std::string::npos);
  EXPECT_TRUE(
      captured.Contains("refused an update on MAP_UPDATES (other_maze): an update for the "
                        "maze of fingerprint " +
                        FingerprintText(foreign)));
  EXPECT_TRUE(served.service.Stop().ok());
}

// Obstacles named in metres (the service's frame without a goal service:
// 1 m cells from (0, 0)) become the cells holding them; a point outside the
// map and an occupancy grid of another resolution are refused and counted
// by their reasons; a source's sequence numbers are shared between its
// points and its cell updates.
TEST(ServiceBus, ObstaclePointsAndGridsAreInTheMapsFrame) {
  const Scenario scenario = GenerateScenario(16, 16, Difficulty::kHard, 3, 2);
  const uint64_t maze = MazeFingerprint(scenario.grid);
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  ReplyListener client(lcm, "service-bus");
  BusService served(lcm, scenario);
  protocol::Dispatcher dispatcher(lcm);
  served.service.Start();
  ASSERT_TRUE(served.service.WaitForStep(0, kBusWait));

  obstacle_points_t points{};
  points.run_id = "service-bus";
  points.source = "test";
  points.sequence = 1;
  points.maze_fingerprint = static_cast<int64_t>(maze);
  points.num_points = 1;
  points.x = {16.0};  // the right border of the map: outside
  points.y = {3.0};
  points.states = {obstacle_points_t::OBSTACLE};
  client.bus().Publish(protocol::channel::kMapPoints, points);
  occupancy_grid_t grid{};
  grid.run_id = "service-bus";
  grid.source = "test";
  grid.sequence = 2;
  grid.resolution = 0.5F;
  grid.rows = 16;
  grid.cols = 16;
  grid.num_cells = 256;
  grid.data.assign(256, -1);
  client.bus().Publish(protocol::channel::kMapGrid, grid);
  // Step 0's changes at their cells' centres, then a cell update of the
  // same source with a lower number: stale.
  const ChangeStep& step = scenario.changes.steps[0];
  ASSERT_FALSE(step.changes.empty());
  points.sequence = 5;
  points.x.clear();
  points.y.clear();
  points.states.clear();
  for (const CellChange& change : step.changes) {
    points.x.push_back(scenario.grid.ColOf(change.cell) + 0.5);
    points.y.push_back(scenario.grid.rows() - 1 - scenario.grid.RowOf(change.cell) + 0.5);
    points.states.push_back(change.code == Cell::kObstacle ? obstacle_points_t::OBSTACLE
                                                           : obstacle_points_t::FREE);
  }
  points.num_points = static_cast<int32_t>(points.x.size());
  client.bus().Publish(protocol::channel::kMapPoints, points);
  client.bus().Publish(protocol::channel::kMapUpdates, UpdateMessage(step, scenario.grid, maze, 4));
  // A request after them: its reply means all of them were handled.
  client.Ask(1);
  ASSERT_TRUE(client.WaitFor(1));
  ASSERT_TRUE(served.service.WaitForStep(1, kBusWait));
  const ServiceStats stats = served.service.stats();
  EXPECT_EQ(stats.updates.refused[static_cast<size_t>(UpdateRefusal::kOutsideGrid)], 1);
  EXPECT_EQ(stats.updates.refused[static_cast<size_t>(UpdateRefusal::kResolution)], 1);
  EXPECT_EQ(stats.updates.refused[static_cast<size_t>(UpdateRefusal::kStale)], 1);
  EXPECT_EQ(stats.updates.accepted, 1);
  EXPECT_EQ(stats.updates.cells_changed, static_cast<int64_t>(step.changes.size()));
  EXPECT_NE(PathService::Summary(stats).find("1 resolution"), std::string::npos);
  EXPECT_TRUE(served.service.Stop().ok());
}

// Two services of one run id (other mazes) on one network both answer a
// request: the client's witness names both mazes instead of taking the
// first reply.
TEST(ServiceBus, TwoServicesOfOneRunAreWitnessedByTheirClient) {
  const Scenario scenario = GenerateScenario(16, 16, Difficulty::kHard, 3, 0);
  const Scenario other = GenerateScenario(20, 20, Difficulty::kHard, 4, 0);
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  ReplyListener client(lcm, "service-bus");
  BusService first(lcm, scenario), second(lcm, other);
  protocol::Dispatcher dispatcher(lcm);
  first.service.Start();
  second.service.Start();
  ASSERT_TRUE(first.service.WaitForStep(0, kBusWait));
  ASSERT_TRUE(second.service.WaitForStep(0, kBusWait));
  client.Ask(1);
  ASSERT_TRUE(client.WaitFor(2));
  const std::optional<std::string> conflict = client.conflict();
  ASSERT_TRUE(conflict.has_value());
  EXPECT_NE(conflict->find(FingerprintText(MazeFingerprint(scenario.grid))), std::string::npos);
  EXPECT_NE(conflict->find(FingerprintText(MazeFingerprint(other.grid))), std::string::npos);

  // One service: the same reply twice is no conflict.
  ReplyWitness witness;
  const path_reply_t reply = client.replies()[0];
  EXPECT_TRUE(witness.Saw(reply));
  EXPECT_TRUE(witness.Saw(reply));
  EXPECT_FALSE(witness.conflict().has_value());
  EXPECT_TRUE(first.service.Stop().ok());
  EXPECT_TRUE(second.service.Stop().ok());
}

}  // namespace
}  // namespace dynapath::runtime
