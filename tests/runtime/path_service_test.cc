#include "runtime/path_service.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <thread>

#include "dynapath/bfs_oracle.h"
#include "dynapath/local_trainer.h"
#include "dynapath/scenario.h"
#include "dynapath/thread_pool.h"

namespace dynapath::runtime {
namespace {

constexpr double kWait = 120;  // seconds: a loaded machine, a sanitizer

// Each path valid on the grid it was answered on: neighbouring non-obstacle
// cells ending on a station.
bool ValidOn(const Grid& grid, const Route& route) {
  if (route.status != RouteStatus::kReached) return true;
  if (route.cells.size() != static_cast<size_t>(route.length) + 1) return false;
  for (size_t i = 0; i < route.cells.size(); ++i) {
    if (grid.at(route.cells[i]) == Cell::kObstacle) return false;
    if (i == 0) continue;
    const int dr = grid.RowOf(route.cells[i]) - grid.RowOf(route.cells[i - 1]);
    const int dc = grid.ColOf(route.cells[i]) - grid.ColOf(route.cells[i - 1]);
    if (std::abs(dr) > 1 || std::abs(dc) > 1 || (dr == 0 && dc == 0)) return false;
  }
  return grid.at(route.cells.back()) == Cell::kStation;
}

std::vector<QueryStart> AllCells(const Grid& grid) {
  std::vector<QueryStart> starts;
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) starts.emplace_back(r, c);
  }
  return starts;
}

MapUpdate UpdateOf(const ChangeStep& step, int64_t sequence) {
  MapUpdate update;
  update.source = "test";
  update.sequence = sequence;
  update.changes = step.changes;
  return update;
}

ServiceConfig Config(const Scenario& scenario, unsigned seed, int max_starts) {
  ServiceConfig config;
  config.approach = Approach::kFedAsynQEqAvg;
  config.answer = AnswerMode::kLearnedElseExact;
  config.options.run_seed = seed;
  config.threads = 1;
  config.max_starts = max_starts;
  config.catch_up = scenario.changes;
  return config;
}

// The service fed a run's change sequence one update per step scores every
// step as the run does (the same planner, strategy and trainer path), and
// each snapshot's learned answers reach exactly the evaluated successes.
TEST(PathService, StepsFromUpdatesScoreAsTheRun) {
  const unsigned seed = 3;
  const Scenario scenario = GenerateScenario(20, 20, Difficulty::kHard, seed, 6);
  for (const ChangeStep& step : scenario.changes.steps) ASSERT_FALSE(step.changes.empty());
  ThreadPool pool(1);
  LocalTrainer trainer(pool);
  PlannerOptions options;
  options.run_seed = seed;
  const ApproachRun run =
      RunApproach(scenario, Approach::kFedAsynQEqAvg, options, &trainer, RunLabels{});

  PathService service(scenario.grid, Config(scenario, seed, 1000));
  EXPECT_EQ(service.Ask({{0, 0}}).refused, Answer::kNotReady);
  service.Start();
  ASSERT_TRUE(service.WaitForVersion(1, kWait));
  for (size_t t = 0; t <= scenario.changes.steps.size(); ++t) {
    if (t > 0) {
      ASSERT_FALSE(
          service.Submit(UpdateOf(scenario.changes.steps[t - 1], static_cast<int64_t>(t))));
      ASSERT_TRUE(service.WaitForStep(static_cast<int>(t), kWait));
    }
    const Answer answer = service.Ask(AllCells(scenario.grid));
    ASSERT_EQ(answer.refused, Answer::kAccepted);
    EXPECT_EQ(answer.snapshot->time_step, static_cast<int>(t));
    std::vector<int32_t> distance, queue;
    NearestStationDistances(answer.snapshot->grid, distance, queue);
    int starts = 0, learned = 0;
    for (size_t i = 0; i < answer.routes.size(); ++i) {
      const Route& route = answer.routes[i];
      EXPECT_TRUE(ValidOn(answer.snapshot->grid, route));
      if (route.status == RouteStatus::kStartObstacle) continue;
      ++starts;
      if (route.answered_by == AnsweredBy::kLearned && route.status == RouteStatus::kReached) {
        ++learned;
      }
      // learned-else-exact answers every start that can reach a station.
      EXPECT_EQ(route.status == RouteStatus::kReached, distance[i] != kUnreachable);
      if (route.status == RouteStatus::kReached) {
        EXPECT_GE(route.length, distance[i]);
      }
    }
    EXPECT_DOUBLE_EQ(static_cast<double>(learned) / starts, run.steps[t].success_rate);
  }
  Result<ApproachRun> served = service.Stop();
  ASSERT_TRUE(served.ok());
  ASSERT_EQ(served->steps.size(), run.steps.size());
  int retraining_steps = 0;
  for (size_t t = 0; t < run.steps.size(); ++t) {
    EXPECT_EQ(served->steps[t].success_rate, run.steps[t].success_rate) << "step " << t;
    EXPECT_EQ(served->steps[t].average_path_length, run.steps[t].average_path_length);
    EXPECT_EQ(served->steps[t].nodes_trained, run.steps[t].nodes_trained);
    retraining_steps += t > 0 && run.steps[t].nodes_trained > 0;
  }
  // One commit per step, and an interim one before each step's retraining.
  const ServiceStats stats = service.stats();
  ASSERT_GT(retraining_steps, 0);  // the scenario exercises interim commits
  EXPECT_EQ(stats.interim_commits, retraining_steps);
  EXPECT_EQ(stats.commits, static_cast<int64_t>(run.steps.size()) + retraining_steps);
}

// Bad input is refused and counted; the service keeps answering; a burst
// of updates is one step; concurrent queries never see a half-made policy.
TEST(PathService, RefusesBadInputAndKeepsAnswering) {
  const unsigned seed = 5;
  const Scenario scenario = GenerateScenario(16, 16, Difficulty::kHard, seed, 4);
  PathService service(scenario.grid, Config(scenario, seed, 8));
  service.Start();
  ASSERT_TRUE(service.WaitForVersion(1, kWait));
  int station = -1;
  for (int cell = 0; cell < scenario.grid.size() && station < 0; ++cell) {
    if (scenario.grid.at(cell) == Cell::kStation) station = cell;
  }
  ASSERT_GE(station, 0);
  EXPECT_EQ(service.Submit(UpdateOf(ChangeStep{0, {{station, Cell::kObstacle}}}, 1)),
            UpdateRefusal::kStationToObstacle);
  EXPECT_EQ(service.Submit(UpdateOf(ChangeStep{0, {{16 * 16, Cell::kObstacle}}}, 2)),
            UpdateRefusal::kOutsideGrid);
  EXPECT_EQ(service.Submit(UpdateOf(ChangeStep{}, 2)), UpdateRefusal::kStale);
  service.Refuse(UpdateRefusal::kUnknownState);
  EXPECT_EQ(service.Ask(std::vector<QueryStart>(9, {0, 0})).refused, Answer::kTooManyStarts);
  // A request announcing more starts than allowed is refused unread.
  EXPECT_EQ(service.Ask({}, 1000).refused, Answer::kTooManyStarts);

  // Queries from another thread while every step's updates arrive as a
  // burst of single-cell updates.
  std::atomic<bool> done{false};
  std::atomic<int> answers{0}, invalid{0};
  std::thread asker([&] {
    const std::vector<QueryStart> starts = {{0, 0}, {3, 3}, {8, 8}, {15, 15}, {7, 2}};
    while (!done.load()) {
      const Answer answer = service.Ask(starts);
      for (const Route& route : answer.routes) {
        if (!ValidOn(answer.snapshot->grid, route)) ++invalid;
      }
      ++answers;
    }
  });
  // A failed assertion below returns early: stop and join the asker first.
  struct JoinAsker {
    std::atomic<bool>& done;
    std::thread& asker;
    ~JoinAsker() {
      done = true;
      if (asker.joinable()) asker.join();
    }
  } join_asker{done, asker};
  // The asker thread may not be scheduled before the bursts are done (they
  // take milliseconds), so the test waits for its answers, not for time:
  // one before the first burst, and one begun after the last.
  const auto wait_for_answers_beyond = [&](int count) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(kWait);
    while (answers.load() <= count && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return answers.load() > count;
  };
  ASSERT_TRUE(wait_for_answers_beyond(0));
  int64_t sequence = 10;
  int bursts = 0;
  for (const ChangeStep& step : scenario.changes.steps) {
    for (const CellChange& change : step.changes) {
      ASSERT_FALSE(service.Submit(UpdateOf(ChangeStep{0, {change}}, sequence++)));
    }
    // At least one step per burst has been committed.
    ASSERT_TRUE(service.WaitForStep(++bursts, kWait));
  }
  EXPECT_TRUE(wait_for_answers_beyond(answers.load() + 1));
  done = true;
  asker.join();
  EXPECT_EQ(invalid.load(), 0);
  const ServiceStats stats = service.stats();
  EXPECT_EQ(stats.updates.refused_total(), 4);
  EXPECT_EQ(stats.refused_too_many_starts, 2);
  EXPECT_GE(stats.updates.steps, static_cast<int64_t>(scenario.changes.steps.size()));
  EXPECT_LE(stats.updates.steps, stats.updates.cells_changed);
  EXPECT_GE(stats.commits, 2);
  EXPECT_TRUE(service.Stop().ok());
  EXPECT_NE(PathService::Summary(stats).find("1 station_to_obstacle"), std::string::npos);
}

// A policy saved at step 2 of a run is taken over at step 2 (its changes
// caught up from the sequence) and answers as the run scored that step;
// the next update makes step 3, scored as the run's.
TEST(PathService, TakesOverALoadedPolicyAtItsStep) {
  const unsigned seed = 3;
  const Scenario scenario = GenerateScenario(20, 20, Difficulty::kHard, seed, 4);
  ThreadPool pool(1);
  LocalTrainer trainer(pool);
  PlannerOptions options;
  options.run_seed = seed;
  PolicyState saved;
  PolicyHooks hooks;
  hooks.save_at = 2;
  hooks.save = [&](PolicyState&& state) { saved = std::move(state); };
  ScenarioStepSource source(scenario);
  Result<ApproachRun> run =
      RunApproach(source, 0, Approach::kFedAsynQEqAvg, options, &trainer, RunLabels{}, hooks);
  ASSERT_TRUE(run.ok());
  ASSERT_EQ(saved.step, 2);

  ServiceConfig config = Config(scenario, seed, 1000);
  config.load = &saved;
  PathService service(scenario.grid, config);
  service.Start();
  ASSERT_TRUE(service.WaitForVersion(1, kWait));
  EXPECT_EQ(service.Current()->time_step, 2);
  ASSERT_FALSE(service.Submit(UpdateOf(scenario.changes.steps[2], 1)));
  ASSERT_TRUE(service.WaitForStep(3, kWait));
  const Answer answer = service.Ask(AllCells(scenario.grid));
  EXPECT_EQ(answer.snapshot->time_step, 3);
  int starts = 0, learned = 0;
  for (const Route& route : answer.routes) {
    if (route.status == RouteStatus::kStartObstacle) continue;
    ++starts;
    learned += route.answered_by == AnsweredBy::kLearned && route.status == RouteStatus::kReached;
  }
  EXPECT_DOUBLE_EQ(static_cast<double>(learned) / starts, run->steps[3].success_rate);
  Result<ApproachRun> served = service.Stop();
  ASSERT_TRUE(served.ok());
  ASSERT_EQ(served->steps.size(), 1u);  // step 3 only: the saved step is not scored again
  EXPECT_EQ(served->steps[0].success_rate, run->steps[3].success_rate);

  // The same policy with fewer steps than its saved step, or with another
  // change sequence: refused before any work, with the reason; and Start
  // ends at once instead of answering not_ready for ever.
  ServiceConfig short_config = config;
  short_config.catch_up.steps.resize(1);
  const Status too_short = PathService::CheckLoad(scenario.grid, short_config);
  ASSERT_FALSE(too_short.ok());
  EXPECT_NE(too_short.error().message.find("saved at time step 2"), std::string::npos);
  EXPECT_NE(too_short.error().message.find("has 1 steps"), std::string::npos);
  ServiceConfig other_changes = config;
  other_changes.catch_up = GenerateScenario(20, 20, Difficulty::kHard, seed + 1, 4).changes;
  EXPECT_FALSE(PathService::CheckLoad(scenario.grid, other_changes).ok());
  EXPECT_TRUE(PathService::CheckLoad(scenario.grid, config).ok());
  PathService refused(scenario.grid, short_config);
  refused.Start();
  for (int i = 0; i < 1000 && !refused.training_ended(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(refused.training_ended());
  EXPECT_FALSE(refused.Stop().ok());
}

// A request without starts is a probe: answered with the version and step,
// counted as a probe, not as a start of any status.
TEST(PathService, ProbesAreCountedApartFromStarts) {
  const unsigned seed = 5;
  const Scenario scenario = GenerateScenario(16, 16, Difficulty::kHard, seed, 0);
  PathService service(scenario.grid, Config(scenario, seed, 8));
  service.Start();
  ASSERT_TRUE(service.WaitForVersion(1, kWait));
  const Answer probe = service.Ask({});
  EXPECT_EQ(probe.refused, Answer::kAccepted);
  ASSERT_NE(probe.snapshot, nullptr);
  EXPECT_EQ(probe.snapshot->version, 1);
  EXPECT_TRUE(probe.routes.empty());
  const ServiceStats stats = service.stats();
  EXPECT_EQ(stats.requests, 1);
  EXPECT_EQ(stats.probes, 1);
  EXPECT_EQ(stats.starts, 0);
  for (int64_t n : stats.by_status) EXPECT_EQ(n, 0);
  EXPECT_NE(PathService::Summary(stats).find("1 of them probes without starts"), std::string::npos);
  EXPECT_TRUE(service.Stop().ok());
}

// convQ served: no training (its model settles on the map), each update
// re-settled around the changed cells (Adapt, no interim commit). With the
// shipped weights its policy is the optimum (as convQ's planner and end-to-
// end tests assert), so every learned reply has the Incremental Oracle's
// exact length, and every step scores as a run of convQ.
TEST(PathService, ConvQAnswersWithTheOraclesLengths) {
  const unsigned seed = 7;
  const Scenario scenario = GenerateScenario(16, 16, Difficulty::kHard, seed, 5);
  ThreadPool pool(1);
  LocalTrainer trainer(pool);
  PlannerOptions options;
  options.run_seed = seed;
  const ApproachRun run = RunApproach(scenario, Approach::kConvQ, options, &trainer, RunLabels{});

  ServiceConfig learned_config = Config(scenario, seed, 1000);
  learned_config.approach = Approach::kConvQ;
  learned_config.answer = AnswerMode::kLearned;
  ServiceConfig exact_config = Config(scenario, seed, 1000);
  exact_config.approach = Approach::kIncrementalOracle;
  exact_config.answer = AnswerMode::kExact;
  PathService convq(scenario.grid, learned_config);
  PathService oracle(scenario.grid, exact_config);
  convq.Start();
  oracle.Start();
  ASSERT_TRUE(convq.WaitForVersion(1, kWait));
  ASSERT_TRUE(oracle.WaitForVersion(1, kWait));
  int reached = 0;
  for (size_t t = 0; t <= scenario.changes.steps.size(); ++t) {
    if (t > 0) {
      const MapUpdate update = UpdateOf(scenario.changes.steps[t - 1], static_cast<int64_t>(t));
      ASSERT_FALSE(convq.Submit(update));
      ASSERT_FALSE(oracle.Submit(update));
      ASSERT_TRUE(convq.WaitForStep(static_cast<int>(t), kWait));
      ASSERT_TRUE(oracle.WaitForStep(static_cast<int>(t), kWait));
    }
    const Answer got = convq.Ask(AllCells(scenario.grid));
    const Answer want = oracle.Ask(AllCells(scenario.grid));
    ASSERT_EQ(got.refused, Answer::kAccepted);
    ASSERT_EQ(want.refused, Answer::kAccepted);
    ASSERT_EQ(got.snapshot->time_step, static_cast<int>(t));
    ASSERT_EQ(got.snapshot->grid, want.snapshot->grid);
    ASSERT_EQ(got.routes.size(), want.routes.size());
    for (size_t i = 0; i < got.routes.size(); ++i) {
      const Route& route = got.routes[i];
      EXPECT_TRUE(ValidOn(got.snapshot->grid, route));
      // The same starts reached, at the same lengths (where no station can
      // be reached the policy's route fails its own way: loops, say).
      EXPECT_EQ(route.status == RouteStatus::kReached,
                want.routes[i].status == RouteStatus::kReached)
          << "step " << t << ", start " << i;
      EXPECT_EQ(route.length, want.routes[i].length) << "step " << t << ", start " << i;
      if (route.status == RouteStatus::kReached) {
        EXPECT_EQ(route.answered_by, AnsweredBy::kLearned);
        ++reached;
      }
    }
  }
  EXPECT_GT(reached, 0);
  Result<ApproachRun> served = convq.Stop();
  ASSERT_TRUE(served.ok());
  ASSERT_TRUE(oracle.Stop().ok());
  ASSERT_EQ(served->steps.size(), run.steps.size());
  for (size_t t = 0; t < run.steps.size(); ++t) {
    EXPECT_EQ(served->steps[t].success_rate, run.steps[t].success_rate) << "step " << t;
    EXPECT_EQ(served->steps[t].average_path_length, run.steps[t].average_path_length);
    EXPECT_EQ(served->steps[t].nodes_trained, 0);
  }
  const ServiceStats stats = convq.stats();
  EXPECT_EQ(stats.interim_commits, 0);
  EXPECT_EQ(stats.retrainings, 0);
  EXPECT_EQ(stats.commits, static_cast<int64_t>(run.steps.size()));
}

}  // namespace
}  // namespace dynapath::runtime
