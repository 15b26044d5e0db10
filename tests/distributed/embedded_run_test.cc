// The coordinator and the agents over memq:// as threads of this test (the
// pieces of `dynapath run --embedded`): no network namespace needed, so these
// run everywhere. A distributed run must give exactly the figures of a
// `--local` run of the same maze and seed, also when an agent stops mid-run
// and its work is reassigned to the other.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "agent/agent.h"
#include "coordinator/coordinator.h"
#include "coordinator/distributed_trainer.h"
#include "dynapath/fragment_t.hpp"
#include "dynapath/job_batch_t.hpp"
#include "dynapath/policy_t.hpp"
#include "dynapath/scenario.h"
#include "dynapath/step_report_t.hpp"
#include "dynapath/text_util.h"
#include "envsim/envsim.h"
#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"

namespace dynapath {
namespace {

namespace fs = std::filesystem;
using runtime::ScenarioSetup;

constexpr int kSize = 20;
constexpr unsigned kSeed = 52;  // the report's hard maze seed
constexpr int kSteps = 6;

ScenarioSetup HardMaze() {
  ScenarioSetup setup;
  setup.scenario = GenerateScenario(kSize, kSize, Difficulty::kHard, kSeed, kSteps);
  setup.labels = RunLabels{SizeLabel(kSize, kSize), "Hard"};
  setup.seed = kSeed;
  setup.source = "generated";
  return setup;
}

runtime::RunPlan Plan(const fs::path& out) {
  runtime::RunPlan plan;
  Result<std::vector<Approach>> approaches =
      ParseApproachList("BFS Oracle,singleAgent,fedAsynQ_EqAvg,fedAsynQ_ImAvg");
  EXPECT_TRUE(approaches.ok());
  plan.approaches = *approaches;
  plan.options.leaf_limit = 10;  // 4 leaves: batches of several jobs
  plan.out_dir = out.string();
  return plan;
}

// A result file without its time columns (what must be identical).
std::string WithoutTimes(const fs::path& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in.good()) << file;
  std::string line, out;
  std::vector<bool> keep;
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = Split(line, ',');
    if (keep.empty()) {
      for (const std::string& name : fields) {
        keep.push_back(name.find("Time") == std::string::npos || name == "TimeStep");
      }
    }
    for (size_t i = 0; i < fields.size(); ++i) {
      if (i >= keep.size() || keep[i]) out += fields[i] + ",";
    }
    out += "\n";
  }
  return out;
}

class EmbeddedRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dynapath_embedded_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // The reference: everything in this process on a thread pool.
    Result<std::vector<ApproachRun>> local = runtime::RunLocal(Plan(dir_ / "local"), HardMaze(), 2);
    ASSERT_TRUE(local.ok()) << local.error().message;
  }
  void TearDown() override { fs::remove_all(dir_); }

  void ExpectSameResultsAsLocal() {
    for (const char* file : {"results.csv", "results_detailed.csv"}) {
      const std::string local = WithoutTimes(dir_ / "local" / file);
      EXPECT_FALSE(local.empty());
      EXPECT_EQ(WithoutTimes(dir_ / "distributed" / file), local) << file;
    }
  }

  // Runs envsim, the coordinator and two agents over one memq:// until the
  // coordinator ends. With `stop_agent_2_mid_run`, agent 2 stops while it
  // holds work, which must be reassigned to agent 1.
  int RunDistributed(bool stop_agent_2_mid_run, int64_t* epochs,
                     runtime::Placement placement = runtime::Placement::kAuto) {
    lcm::LCM lcm("memq://");
    EXPECT_TRUE(lcm.good());
    const std::string run_id = "embedded-test";
    protocol::BusOptions bus_options;
    bus_options.fragment_above = 0;
    protocol::Bus envsim_bus(lcm, run_id, bus_options);
    protocol::Bus coordinator_bus(lcm, run_id, bus_options);
    protocol::Bus watcher_bus(lcm, run_id, bus_options);
    const ScenarioSetup setup = HardMaze();
    envsim::EnvSim sim(envsim_bus,
                       envsim::ScenarioInfo{setup.scenario, setup.labels, setup.seed, setup.source},
                       envsim::EnvSimOptions{});
    // Agent 2 "dies" the moment it is given work: its stop flag is set and
    // everything it would send from then on is dropped (its bus fragments
    // every message, and drops every fragment once muted), so however fast
    // it trains, its results never arrive and its work must be reassigned.
    // The watcher subscribes before the agents, so it sees each batch first.
    std::atomic<bool> stop_components{false}, stop_agent_2{false}, mute_agent_2{false};
    std::atomic<int> batches_for_agent_2{0};
    // With split placement, agent 2 stops once it hosts learners of a split
    // job (in the middle of its rounds); else at its first batch.
    const bool wait_for_split = placement == runtime::Placement::kSplit;
    watcher_bus.Subscribe<job_batch_t>(protocol::channel::kJobs, [&](job_batch_t& batch) {
      for (size_t i = 0; i < batch.item_agent.size(); ++i) {
        if (batch.item_agent[i] != 2) continue;
        ++batches_for_agent_2;
        if (stop_agent_2_mid_run && (!wait_for_split || batch.item_learner[i] >= 0)) {
          mute_agent_2 = true;
          stop_agent_2 = true;
        }
        break;
      }
    });
    // A step's POLICY comes before its REPORT (the report announces a step
    // whose products are out): the watcher lists each REPORT whose POLICY it
    // has not seen yet.
    std::mutex order_mutex;
    std::set<std::string> policies_seen;
    std::vector<std::string> reports_before_policy;
    int reports_seen = 0;
    const auto step_key = [](const std::string& approach, int pass, int time_step) {
      return approach + "/" + std::to_string(pass) + "/" + std::to_string(time_step);
    };
    watcher_bus.Subscribe<policy_t>(protocol::channel::kPolicy, [&](policy_t& policy) {
      std::lock_guard lock(order_mutex);
      policies_seen.insert(step_key(policy.approach, policy.pass, policy.time_step));
    });
    watcher_bus.Subscribe<step_report_t>(protocol::channel::kReport, [&](step_report_t& report) {
      std::lock_guard lock(order_mutex);
      ++reports_seen;
      const std::string key = step_key(report.approach, report.pass, report.time_step);
      if (policies_seen.count(key) == 0) reports_before_policy.push_back(key);
    });
    std::vector<std::unique_ptr<protocol::Bus>> agent_buses;
    std::vector<std::unique_ptr<agent::Agent>> agents;
    for (int id = 1; id <= 2; ++id) {
      protocol::BusOptions agent_bus_options = bus_options;
      if (id == 2 && stop_agent_2_mid_run) {
        agent_bus_options.fragment_above = 1;
        agent_bus_options.drop_fragment = [&](const fragment_t&, bool) {
          return mute_agent_2.load();
        };
      }
      agent_buses.push_back(std::make_unique<protocol::Bus>(lcm, run_id, agent_bus_options));
      agent::AgentOptions options;
      options.id = id;
      options.threads = 1;
      agents.push_back(std::make_unique<agent::Agent>(*agent_buses.back(), options));
    }
    coordinator::CoordinatorOptions options;
    options.plan = Plan(dir_ / "distributed");
    options.plan.placement = placement;
    options.min_agents = 2;
    options.agent_timeout_seconds = 0.5;  // notice the stopped agent quickly
    coordinator::Coordinator coordinator(coordinator_bus, options);

    protocol::Dispatcher dispatcher(lcm);
    std::vector<std::thread> threads;
    threads.emplace_back([&] { sim.Run(stop_components); });
    std::atomic<agent::AgentExit> exit_2{agent::AgentExit::kCoordinatorFinished};
    threads.emplace_back([&] { agents[0]->Run(stop_components); });
    threads.emplace_back([&] { exit_2 = agents[1]->Run(stop_agent_2); });
    // Agent 2's own flag also follows the common one, for the end of the run.
    std::thread relay([&] {
      while (!stop_components) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      stop_agent_2 = true;
    });
    const std::atomic<bool> never{false};
    const int code = coordinator.Run(never);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    stop_components = true;
    relay.join();
    for (std::thread& thread : threads) thread.join();
    {
      std::lock_guard lock(order_mutex);
      EXPECT_GT(reports_seen, 0) << "no REPORT seen";
      EXPECT_TRUE(reports_before_policy.empty())
          << reports_before_policy.size() << " REPORT(s) before their step's POLICY, the first "
          << (reports_before_policy.empty() ? "" : reports_before_policy.front());
    }
    *epochs = coordinator.traffic().epochs;
    rounds_ = coordinator.traffic().rounds;
    EXPECT_GT(batches_for_agent_2.load(), 0) << "agent 2 was never given work";
    if (stop_agent_2_mid_run) {
      EXPECT_EQ(exit_2.load(), agent::AgentExit::kStopped);
    }
    return code;
  }

  fs::path dir_;
  int64_t rounds_ = 0;  // federated rounds combined from split jobs
};

TEST_F(EmbeddedRunTest, TwoAgentsGiveTheFiguresOfALocalRun) {
  int64_t epochs = -1;
  ASSERT_EQ(RunDistributed(/*stop_agent_2_mid_run=*/false, &epochs), 0);
  ExpectSameResultsAsLocal();
}

TEST_F(EmbeddedRunTest, WorkOfAnAgentThatStopsIsReassigned) {
  int64_t epochs = -1;
  ASSERT_EQ(RunDistributed(/*stop_agent_2_mid_run=*/true, &epochs), 0);
  EXPECT_GE(epochs, 1) << "no batch was reassigned";
  ExpectSameResultsAsLocal();
}

TEST_F(EmbeddedRunTest, LearnersSplitOverTwoAgentsGiveTheFiguresOfALocalRun) {
  int64_t epochs = -1;
  ASSERT_EQ(RunDistributed(/*stop_agent_2_mid_run=*/false, &epochs, runtime::Placement::kSplit), 0);
  EXPECT_GT(rounds_, 0) << "no job was split over the agents";
  ExpectSameResultsAsLocal();
}

TEST_F(EmbeddedRunTest, SplitWorkOfAnAgentThatStopsIsReassigned) {
  int64_t epochs = -1;
  ASSERT_EQ(RunDistributed(/*stop_agent_2_mid_run=*/true, &epochs, runtime::Placement::kSplit), 0);
  EXPECT_GE(epochs, 1) << "no batch was reassigned";
  EXPECT_GT(rounds_, 0) << "no job was split over the agents";
  ExpectSameResultsAsLocal();
}

}  // namespace
}  // namespace dynapath

// The wait between repeats of a batch without progress doubles per repeat
// from the first interval, up to kMaxRepeatIntervalMs, and never drops below
// the first interval (a first interval above the cap stays as it is).
TEST(RepeatIntervalTest, DoublesPerRepeatUpToTheCap) {
  using dynapath::coordinator::kMaxRepeatIntervalMs;
  using dynapath::coordinator::RepeatIntervalMs;
  EXPECT_EQ(RepeatIntervalMs(30, 0), 30);
  EXPECT_EQ(RepeatIntervalMs(30, 1), 60);
  EXPECT_EQ(RepeatIntervalMs(30, 2), 120);
  EXPECT_EQ(RepeatIntervalMs(30, 5), 960);
  EXPECT_EQ(RepeatIntervalMs(30, 6), kMaxRepeatIntervalMs);
  EXPECT_EQ(RepeatIntervalMs(30, 1000000), kMaxRepeatIntervalMs);
  EXPECT_EQ(RepeatIntervalMs(200, 3), kMaxRepeatIntervalMs);
  EXPECT_EQ(RepeatIntervalMs(1500, 4), 1500);
}

// The slowest recent split round, which sets how long an agent still
// computing a round is waited for before it counts as a loss.
TEST(SlowRoundTest, KeepsTheSlowestAndForgetsItByAnEighthPerRound) {
  using dynapath::coordinator::SlowRoundMs;
  EXPECT_EQ(SlowRoundMs(0, 120), 120);
  EXPECT_EQ(SlowRoundMs(120, 3000), 3000);  // a slow round counts at once
  EXPECT_EQ(SlowRoundMs(3000, 100), 2625);  // and fades: 3000 - 3000 / 8
  int64_t slow = 3000;
  for (int round = 0; round < 40; ++round) slow = SlowRoundMs(slow, 100);
  EXPECT_EQ(slow, 100);  // forty fast rounds later, only they count
}
