// dynapath robots: a simulated fleet in closed loop with a running
// `dynapath serve` (docs/howto/SERVICE.md). N robots at seeded free cells
// each ask the service for a path and move one cell per tick along it; the
// obstacles move per the maze's change sequence, published to the service
// as live updates; a robot asks again when its next cell became an
// obstacle or a newer policy was committed. Reports arrivals, ticks
// against each robot's exact optimum, blocked moves, queries.

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "dynapath/bfs_oracle.h"
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

struct Robot {
  int cell = 0;
  int optimum = 0;        // exact distance at the start (tick 0)
  std::vector<int> plan;  // cells from the current one on; empty: none
  size_t next = 0;        // index of the next cell in `plan`
  int64_t plan_version = 0;
  int arrived_at = -1;  // tick of arrival
  bool asked = false;
};

}  // namespace

int RobotsCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "A simulated fleet in closed loop with a running `dynapath serve`: --robots N\n"
      "robots start at seeded free cells that can reach a station, ask the service for\n"
      "a path and move one cell per tick along it. Every --ticks-per-step ticks the\n"
      "obstacles move by the maze's next change step, which this command publishes to\n"
      "the service as an update and waits for its commit; a robot asks again when its\n"
      "next cell became an obstacle (a blocked move) or its plan comes from an older\n"
      "policy. Robots do not block each other. The maze options must be the service's\n"
      "(its maze fingerprint is checked first); the obstacles start from the service's\n"
      "current step of the maze's change sequence.\n"
      "Prints one JSON line: robots, arrived, arrival_rate, ticks_over_optimal (ticks\n"
      "of the arrived robots over their exact optimum at tick 0), blocked_moves,\n"
      "queries, requeries, queries_per_s.",
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
  group.Option("--robot-seed", robot_seed, "S", "seed of the robots' start cells");
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
  if (!(timeout > 0 && timeout <= 3600)) {
    return runtime::ProcessError(kRobotsProgram, "--timeout must be between 0 and 3600 seconds");
  }
  Result<runtime::ProcessSetup> process = runtime::ResolveProcessOptions(process_options, true);
  if (!process) return runtime::ProcessError(kRobotsProgram, process.error().message);
  Result<runtime::ScenarioSetup> setup = runtime::ResolveScenario(scenario);
  if (!setup) return runtime::ProcessError(kRobotsProgram, setup.error().message);
  Grid grid = setup->scenario.grid;
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

  // Starts: free cells that can reach a station at tick 0.
  std::vector<int32_t> distance, queue;
  NearestStationDistances(grid, distance, queue);
  std::vector<int> candidates;
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (grid.at(cell) == Cell::kFree && distance[cell] > 0) candidates.push_back(cell);
  }
  if (candidates.empty()) {
    return runtime::ProcessError(kRobotsProgram, "no free cell of the maze reaches a station", 1);
  }
  std::mt19937_64 random(static_cast<uint64_t>(robot_seed));
  std::uniform_int_distribution<size_t> pick(0, candidates.size() - 1);
  std::vector<Robot> fleet(static_cast<size_t>(robots));
  for (Robot& robot : fleet) {
    robot.cell = candidates[pick(random)];
    robot.optimum = distance[robot.cell];
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
        const int cell = fleet[who[k]].cell;
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
  for (long long tick = 0; tick < ticks; ++tick) {
    if (tick > 0 && tick % ticks_per_step == 0 && step_index < steps.size()) {
      const ChangeStep& step = steps[step_index++];
      ApplyChanges(step, grid);
      obstacle_update_t update = protocol::UpdateToMessage(
          step, grid.cols(), source, ++sequence, static_cast<uint64_t>(met->maze_fingerprint));
      update.run_id = process->run_id;
      client.bus().Publish(protocol::channel::kMapUpdates, update);
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
    std::vector<size_t> needing;
    for (size_t r = 0; r < fleet.size(); ++r) {
      Robot& robot = fleet[r];
      if (robot.arrived_at >= 0) continue;
      const bool no_plan = robot.next >= robot.plan.size();
      const bool wall = !no_plan && grid.at(robot.plan[robot.next]) == Cell::kObstacle;
      if (no_plan || wall || robot.plan_version < latest_version) needing.push_back(r);
    }
    if (!needing.empty() && !ask(needing)) {
      return runtime::ProcessError(
          kRobotsProgram,
          "no answer from a service of run " + process->run_id + " within --timeout", kExitFailure);
    }
    for (Robot& robot : fleet) {
      if (robot.arrived_at >= 0 || robot.next >= robot.plan.size()) continue;
      const int next = robot.plan[robot.next];
      if (grid.at(next) == Cell::kObstacle) {
        ++blocked;
        robot.plan.clear();
        continue;
      }
      robot.cell = next;
      ++robot.next;
      if (grid.at(robot.cell) == Cell::kStation) robot.arrived_at = static_cast<int>(tick) + 1;
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (std::optional<std::string> two = client.SecondService()) {
    return runtime::ProcessError(kRobotsProgram, *two, kExitFailure);
  }
  int64_t arrived = 0, ticks_sum = 0, optimum_sum = 0;
  for (const Robot& robot : fleet) {
    if (robot.arrived_at < 0) continue;
    ++arrived;
    ticks_sum += robot.arrived_at;
    optimum_sum += robot.optimum;
  }
  std::printf(
      "{\"robots\":%lld,\"ticks\":%lld,\"arrived\":%lld,\"arrival_rate\":%.4f,"
      "\"ticks_over_optimal\":%.4f,\"blocked_moves\":%lld,\"queries\":%lld,\"requeries\":%lld,"
      "\"not_reached_answers\":%lld,\"queries_per_s\":%.1f,\"seconds\":%.2f,\"version\":%lld}\n",
      robots, ticks, static_cast<long long>(arrived),
      static_cast<double>(arrived) / static_cast<double>(robots),
      optimum_sum > 0 ? static_cast<double>(ticks_sum) / static_cast<double>(optimum_sum) : 0.0,
      static_cast<long long>(blocked), static_cast<long long>(queries),
      static_cast<long long>(requeries), static_cast<long long>(unanswered),
      seconds > 0 ? static_cast<double>(queries) / seconds : 0.0, seconds,
      static_cast<long long>(latest_version));
  std::fflush(stdout);
  return 0;
}

}  // namespace dynapath::cli
