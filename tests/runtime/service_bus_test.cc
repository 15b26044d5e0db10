#include "runtime/service_bus.h"

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "dynapath/policy_t.hpp"
#include "dynapath/scenario.h"
#include "protocol/channels.h"
#include "protocol/dispatcher.h"

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
  ASSERT_TRUE(served.viewer.WaitFor(2));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
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

}  // namespace
}  // namespace dynapath::runtime
