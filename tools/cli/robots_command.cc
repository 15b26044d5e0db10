// dynapath robots: a simulated fleet in closed loop with a running
// `dynapath serve` (docs/howto/SERVICE.md). N robots at seeded free cells
// run lifelong tasks (a station, then a goal of the pool, then a station...);
// on the way to a station a robot asks the service for a path and prefers
// its next cell; the joint move of each tick is the fleet planner's
// (dynapath/fleet.h: robots block each other, no conflicts), checked by the
// validator (dynapath/fleet_validator.h). The obstacles move per the maze's
// change sequence, published to the service as live updates. Wiring only:
// the planning is core's.

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "dynapath/fleet.h"
#include "dynapath/fleet_validator.h"
#include "dynapath/latency_histogram.h"
#include "dynapath/obstacle_update_t.hpp"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"
#include "tools/cli/commands.h"
#include "tools/cli/service_client.h"

namespace dynapath::cli {
namespace {

constexpr const char* kRobotsProgram = "dynapath robots";

// A robot's path from the service, on its way to a station.
struct Robot {
  int optimum = 0;        // exact distance to a station at the start (tick 0)
  std::vector<int> plan;  // cells from the one it was asked at on; empty: none
  size_t next = 0;        // index of the next cell in `plan`
  int64_t plan_version = 0;
  int64_t tasks_seen = 0;  // the fleet's count of its tasks when planned
  bool asked = false;
};

}  // namespace

int RobotsCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "A simulated fleet in closed loop with a running `dynapath serve`: --robots N\n"
      "robots start on distinct seeded free cells that can reach a station and run\n"
      "lifelong tasks: reach a station, then a goal of a pool of --goal-count cells drawn from\n"
      "--robot-seed, then a station again, and so on. On the way to a station a robot\n"
      "asks the service for a path and prefers its next cell; on the way to a goal it\n"
      "follows the fleet's own exact distance field of the goal. Each tick makes one\n"
      "joint move in which robots block each other: no two end on one cell, swap cells\n"
      "or cross diagonally (PIBT; --ignore-conflicts: each moves as if alone), and an\n"
      "independent validator checks every tick. Every --ticks-per-step ticks the\n"
      "obstacles move by the maze's next change step, which this command publishes to\n"
      "the service as an update (--xy: in metres) and waits for its commit; a robot asks\n"
      "again when its next cell became an obstacle (a blocked move), it left its path\n"
      "or its plan comes from an older policy. The maze options must be the service's (its maze\n"
      "fingerprint is checked first); the obstacles start from the service's current\n"
      "step of the maze's change sequence.\n"
      "Prints one JSON line: robots, arrived (robots that reached their first station),\n"
      "arrival_rate, ticks_over_optimal (their ticks over their exact optimum at tick\n"
      "0), tasks, throughput (tasks per tick), conflicts (the validator's), overruns\n"
      "(obstacles that appeared under a robot), delays, blocked_moves, queries,\n"
      "requeries, queries_per_s, ms_per_tick_p50/p99 (the fleet's planning).",
      kRobotsProgram);
  runtime::OptionGroup group(app);
  runtime::ScenarioOptions scenario;
  runtime::DeclareScenarioOptions(group, scenario);
  runtime::ProcessOptions process_options;
  runtime::DeclareProcessOptions(group, process_options, true);
  long long robots = 10, ticks = 200, ticks_per_step = 1, robot_seed = 1;
  group.Option("--robots", robots, "N", "robots of the fleet (1-10000)");
  group.Option("--ticks", ticks, "T", "ticks to simulate (1-1000000)");
  group.Option("--ticks-per-step", ticks_per_step, "K",
               "ticks between two change steps of the obstacles (1-1000000)");
  group.Option("--robot-seed", robot_seed, "S",
               "seed of the robots' start cells, goals, priorities and delays");
  long long goals = 16;
  group.Option("--goal-count", goals, "G", "goal cells of the tasks, drawn from --robot-seed (1-1024)");
  double delay_prob = 0;
  group.Option("--delay-prob", delay_prob, "P",
               "each move fails with probability P (0-0.9; seeded): the robot stays and so do "
               "the robots that would enter its cell");
  bool ignore_conflicts = false;
  group.Flag("--ignore-conflicts", ignore_conflicts,
             "robots do not block each other (each moves as if alone; for comparison)");
  MetresOptions metres;
  DeclareMetresOptions(group, metres);
  double timeout = 60;
  DeclareServiceWaitOption(group, timeout);
  runtime::LogOptions log;
  runtime::DeclareLogOptions(group, log);
  if (int code = runtime::ParseCommandLine(app, args, kRobotsProgram); code >= 0) return code;
  if (Status status = runtime::ApplyLogLevel(log); !status) {
    return runtime::ProcessError(kRobotsProgram, status.error().message);
  }
  for (const auto& [name, value, max] :
       {std::tuple{"robots", robots, 10000LL}, std::tuple{"ticks", ticks, 1000000LL},
        std::tuple{"ticks-per-step", ticks_per_step, 1000000LL},
        std::tuple{"robot-seed", robot_seed, 4294967295LL}}) {
    Result<long long> checked =
        runtime::InRange(name, value, value, name == std::string("robot-seed") ? 0 : 1, max);
    if (!checked) return runtime::ProcessError(kRobotsProgram, checked.error().message);
  }
  if (!(delay_prob >= 0 && delay_prob <= 0.9)) {
    return runtime::ProcessError(kRobotsProgram, "--delay-prob must be between 0 and 0.9");
  }
  if (!(timeout > 0 && timeout <= 3600)) {
    return runtime::ProcessError(kRobotsProgram, "--timeout must be between 0 and 3600 seconds");
  }
  Result<runtime::ProcessSetup> process = runtime::ResolveProcessOptions(process_options, true);
  if (!process) return runtime::ProcessError(kRobotsProgram, process.error().message);
  Result<runtime::ScenarioSetup> setup = runtime::ResolveScenario(scenario);
  if (!setup) return runtime::ProcessError(kRobotsProgram, setup.error().message);
  Grid grid = setup->scenario.grid;
  Result<std::optional<MapFrame>> frame = ResolveMetresOptions(metres, scenario.maze, grid);
  if (!frame) return runtime::ProcessError(kRobotsProgram, frame.error().message);
  const std::vector<ChangeStep>& steps = setup->scenario.changes.steps;

  Result<std::unique_ptr<ServiceClient>> opened =
      ServiceClient::Open(*process, "robots-" + std::to_string(getpid()), ServiceClient::kReports);
  if (!opened) return runtime::ProcessError(kRobotsProgram, opened.error().message, kExitFailure);
  ServiceClient& client = **opened;
  Result<path_reply_t> met = client.Meet(grid, timeout);
  if (!met) {
    return runtime::ProcessError(kRobotsProgram, met.error().message,
                                 met.error().IsInvalidArgument() ? kExitUsage : kExitFailure);
  }
  // The service is at step T of the maze's change sequence (a loaded
  // policy caught up with it, or an earlier fleet): the obstacles go on
  // from there.
  const int service_start = met->time_step;
  if (service_start > static_cast<int>(steps.size())) {
    return runtime::ProcessError(
        kRobotsProgram, "the service is at time step " + std::to_string(service_start) +
                            " and the maze's change sequence has " + std::to_string(steps.size()) +
                            " steps (give --steps)");
  }
  for (int t = 0; t < service_start; ++t) ApplyChanges(steps[static_cast<size_t>(t)], grid);

  FleetOptions fleet_options;
  fleet_options.robots = static_cast<int>(robots);
  fleet_options.seed = static_cast<uint64_t>(robot_seed);
  fleet_options.goal_count = static_cast<int>(goals);
  fleet_options.delay_probability = delay_prob;
  fleet_options.ignore_conflicts = ignore_conflicts;
  Result<std::unique_ptr<Fleet>> made = Fleet::Create(grid, fleet_options);
  if (!made) return runtime::ProcessError(kRobotsProgram, made.error().message);
  Fleet& planner = **made;
  std::vector<Robot> fleet(static_cast<size_t>(robots));
  for (size_t r = 0; r < fleet.size(); ++r) {
    fleet[r].optimum = planner.StationDistance(planner.robots()[r].cell);
  }

  const std::string source = "robots-" + std::to_string(getpid());
  int64_t latest_version = met->version;
  int service_step = service_start;  // the newest time step heard
  int64_t queries = 0, requeries = 0, blocked = 0, unanswered = 0;
  const auto started = std::chrono::steady_clock::now();
  // Asks for the robots of `who` (at most 64 a request), and keeps the
  // newest version heard.
  auto ask = [&](const std::vector<size_t>& who) -> bool {
    for (size_t first = 0; first < who.size(); first += 64) {
      const size_t last = std::min(who.size(), first + 64);
      std::vector<std::pair<int32_t, int32_t>> starts;
      for (size_t k = first; k < last; ++k) {
        const int cell = planner.robots()[who[k]].cell;
        starts.emplace_back(grid.RowOf(cell), grid.ColOf(cell));
      }
      std::optional<path_reply_t> reply = client.Ask(starts, timeout);
      if (!reply || reply->refused != path_reply_t::ACCEPTED) return false;
      latest_version = std::max(latest_version, reply->version);
      service_step = std::max(service_step, reply->time_step);
      for (size_t k = first; k < last; ++k) {
        Robot& robot = fleet[who[k]];
        const size_t i = k - first;
        queries += 1;
        if (robot.asked) ++requeries;
        robot.asked = true;
        robot.plan.clear();
        robot.next = 1;
        robot.plan_version = reply->version;
        robot.tasks_seen = planner.robots()[who[k]].tasks_done;
        if (reply->status[i] != path_reply_t::REACHED) {
          ++unanswered;
          continue;
        }
        for (int p = 0; p < reply->path_cells[i]; ++p) {
          const size_t at = static_cast<size_t>(reply->path_offset[i] + p);
          robot.plan.push_back(grid.Index(reply->path_rows[at], reply->path_cols[at]));
        }
      }
    }
    return true;
  };

  size_t step_index = static_cast<size_t>(service_start);
  int64_t sequence = 0;
  JointMoveReport checked;
  LatencyHistogram planning;
  std::vector<int> preferred(fleet.size(), -1);
  for (long long tick = 0; tick < ticks; ++tick) {
    int64_t repair_us = 0;
    if (tick > 0 && tick % ticks_per_step == 0 && step_index < steps.size()) {
      const ChangeStep& step = steps[step_index++];
      ApplyChanges(step, grid);
      const auto repair_start = std::chrono::steady_clock::now();
      planner.ApplyChanges(step);
      repair_us = std::chrono::duration_cast<std::chrono::microseconds>(
                      std::chrono::steady_clock::now() - repair_start)
                      .count();
      PublishStep(client, step, grid, *frame, source, ++sequence,
                  static_cast<uint64_t>(met->maze_fingerprint), 0);
      if (!step.changes.empty()) {
        // Wait for this step's own policy (its REPORT: a step that retrains
        // commits an interim policy before it): the fleet then plans on the
        // approach's policy of the step, as run scores it.
        ++service_step;
        std::optional<path_reply_t> probe;
        if (client.ReportArrival(service_step, timeout)) probe = client.Ask({}, timeout);
        if (!probe) {
          return runtime::ProcessError(kRobotsProgram,
                                       "the service did not commit time step " +
                                           std::to_string(service_step) + " within --timeout",
                                       kExitFailure);
        }
        latest_version = std::max(latest_version, probe->version);
        service_step = std::max(service_step, probe->time_step);
      }
    }
    // Robots on their way to a station whose path is missing, walled,
    // older than the newest policy or for an earlier task ask the service.
    std::vector<size_t> needing;
    for (size_t r = 0; r < fleet.size(); ++r) {
      Robot& robot = fleet[r];
      const FleetRobot& state = planner.robots()[r];
      if (!state.to_station) continue;
      const bool no_plan = robot.next >= robot.plan.size() || robot.tasks_seen != state.tasks_done;
      const bool wall = !no_plan && grid.at(robot.plan[robot.next]) == Cell::kObstacle;
      if (no_plan || wall || robot.plan_version < latest_version) needing.push_back(r);
    }
    if (!needing.empty() && !ask(needing)) {
      return runtime::ProcessError(
          kRobotsProgram,
          "no answer from a service of run " + process->run_id + " within --timeout", kExitFailure);
    }
    for (size_t r = 0; r < fleet.size(); ++r) {
      Robot& robot = fleet[r];
      preferred[r] = -1;
      if (!planner.robots()[r].to_station || robot.next >= robot.plan.size()) continue;
      if (grid.at(robot.plan[robot.next]) == Cell::kObstacle) {
        ++blocked;
        robot.plan.clear();
        continue;
      }
      preferred[r] = robot.plan[robot.next];
    }
    const auto plan_start = std::chrono::steady_clock::now();
    const JointMove& move = planner.Tick(preferred);
    planning.Add(repair_us + std::chrono::duration_cast<std::chrono::microseconds>(
                                 std::chrono::steady_clock::now() - plan_start)
                                 .count());
    checked.Add(CheckJointMove(grid, move.before, move.after, move.delayed));
    for (size_t r = 0; r < fleet.size(); ++r) {
      Robot& robot = fleet[r];
      if (preferred[r] < 0) continue;
      if (move.after[r] == preferred[r]) {
        ++robot.next;
      } else if (move.after[r] != move.before[r]) {
        robot.plan.clear();  // pushed off its path: ask again
      }
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (std::optional<std::string> two = client.SecondService()) {
    return runtime::ProcessError(kRobotsProgram, *two, kExitFailure);
  }
  int64_t arrived = 0, ticks_sum = 0, optimum_sum = 0;
  for (size_t r = 0; r < fleet.size(); ++r) {
    const FleetRobot& state = planner.robots()[r];
    if (state.first_done < 0) continue;
    ++arrived;
    ticks_sum += state.first_done;
    optimum_sum += fleet[r].optimum;
  }
  std::printf(
      "{\"robots\":%lld,\"ticks\":%lld,\"arrived\":%lld,\"arrival_rate\":%.4f,"
      "\"ticks_over_optimal\":%.4f,\"tasks\":%lld,\"throughput\":%.4f,\"conflicts\":%lld,"
      "\"overruns\":%lld,\"delays\":%lld,\"blocked_moves\":%lld,\"queries\":%lld,"
      "\"requeries\":%lld,\"not_reached_answers\":%lld,\"queries_per_s\":%.1f,"
      "\"ms_per_tick_p50\":%.3f,\"ms_per_tick_p99\":%.3f,\"seconds\":%.2f,\"version\":%lld}\n",
      robots, ticks, static_cast<long long>(arrived),
      static_cast<double>(arrived) / static_cast<double>(robots),
      optimum_sum > 0 ? static_cast<double>(ticks_sum) / static_cast<double>(optimum_sum) : 0.0,
      static_cast<long long>(planner.tasks_done()),
      static_cast<double>(planner.tasks_done()) / static_cast<double>(ticks),
      static_cast<long long>(checked.conflicts()), static_cast<long long>(planner.overruns()),
      static_cast<long long>(planner.delays()), static_cast<long long>(blocked),
      static_cast<long long>(queries), static_cast<long long>(requeries),
      static_cast<long long>(unanswered),
      seconds > 0 ? static_cast<double>(queries) / seconds : 0.0,
      static_cast<double>(planning.Quantile(0.5)) / 1000.0,
      static_cast<double>(planning.Quantile(0.99)) / 1000.0, seconds,
      static_cast<long long>(latest_version));
  std::fflush(stdout);
  return 0;
}

}  // namespace dynapath::cli
