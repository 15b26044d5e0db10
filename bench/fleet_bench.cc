// The fleet's figures (docs/PERFORMANCE.md, "Robots that see each other"):
// one fleet of fleet.h on a map whose obstacles move, run twice, robots
// blocking each other (PIBT) and with conflicts ignored, every tick checked
// by the validator (fleet_validator.h). Prints one JSON line per mode:
// throughput (tasks per tick), conflicts, ms per tick (map repair and
// planning) p50/p99/max, then the throughput ratio.
//
//   fleet_bench --maze city-1000-1000.map --stations 0.5% --movers 2%
//     --robots 10000 --ticks 1000 --threads 2
//   fleet_bench --size 300 --difficulty hard --robots 1000 --ticks 1000
//
// The map, stations, movers and their moves are drawn exactly as `dynapath
// run` draws them for the same options and --seed; one change step a tick.

#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "dynapath/c_random.h"
#include "dynapath/difficulty.h"
#include "dynapath/fleet.h"
#include "dynapath/fleet_validator.h"
#include "dynapath/latency_histogram.h"
#include "dynapath/map_scenario.h"
#include "dynapath/movingai_map.h"
#include "dynapath/scenario.h"

namespace dynapath {
namespace {

struct Options {
  std::string maze, stations = "0.5%", movers;
  long long size = 300, seed = 1, robots = 1000, ticks = 1000, goals = 32, threads = 1;
  std::string difficulty = "hard";
  double delay = 0.0;
  std::string modes = "both";  // both, pibt, ignore
};

[[noreturn]] void Usage(const std::string& why) {
  std::fprintf(stderr,
               "fleet_bench: %s\n"
               "usage: fleet_bench [--maze FILE --stations N|P%% --movers N|P%% | --size N "
               "--difficulty easy|medium|hard] [--seed S] [--robots N] [--ticks T] [--goal-count G] "
               "[--delay-prob P] [--threads K] [--modes both|pibt|ignore]\n",
               why.c_str());
  std::exit(2);
}

long long Integer(const std::string& name, const char* text, long long low, long long high) {
  char* end = nullptr;
  const long long value = std::strtoll(text, &end, 10);
  if (end == text || *end != '\0' || value < low || value > high) {
    Usage(name + " must be an integer in [" + std::to_string(low) + ", " + std::to_string(high) +
          "], got '" + text + "'");
  }
  return value;
}

Options Parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; i += 2) {
    const std::string name = argv[i];
    if (i + 1 >= argc) Usage(name + " needs a value");
    const char* value = argv[i + 1];
    if (name == "--maze") {
      o.maze = value;
    } else if (name == "--stations") {
      o.stations = value;
    } else if (name == "--movers") {
      o.movers = value;
    } else if (name == "--difficulty") {
      o.difficulty = value;
    } else if (name == "--modes") {
      o.modes = value;
      if (o.modes != "both" && o.modes != "pibt" && o.modes != "ignore") Usage("bad --modes");
    } else if (name == "--size") {
      o.size = Integer(name, value, 2, 4000);
    } else if (name == "--seed") {
      o.seed = Integer(name, value, 0, 2147483647);
    } else if (name == "--robots") {
      o.robots = Integer(name, value, 1, 1000000);
    } else if (name == "--ticks") {
      o.ticks = Integer(name, value, 1, 1000000);
    } else if (name == "--goal-count") {
      o.goals = Integer(name, value, 1, 4096);
    } else if (name == "--threads") {
      o.threads = Integer(name, value, 1, 64);
    } else if (name == "--delay-prob") {
      char* end = nullptr;
      o.delay = std::strtod(value, &end);
      if (end == value || *end != '\0' || !(o.delay >= 0 && o.delay < 1)) {
        Usage("--delay-prob must be in [0, 1)");
      }
    } else {
      Usage("unknown option " + name);
    }
  }
  return o;
}

Scenario Load(const Options& o) {
  Scenario scenario;
  const int steps = static_cast<int>(o.ticks);
  if (o.maze.empty()) {
    Difficulty difficulty = Difficulty::kHard;
    if (o.difficulty == "easy") {
      difficulty = Difficulty::kEasy;
    } else if (o.difficulty == "medium") {
      difficulty = Difficulty::kMedium;
    } else if (o.difficulty != "hard") {
      Usage("bad --difficulty");
    }
    const int size = static_cast<int>(o.size);
    return GenerateScenario(size, size, difficulty, static_cast<unsigned>(o.seed), steps);
  }
  // As runtime/scenario_options.cc: stations, then movers, then their
  // moves, all from one stream seeded with --seed.
  CRandom random(static_cast<uint32_t>(o.seed));
  Result<Grid> grid = LoadMazeFile(o.maze);
  if (!grid) Usage(grid.error().message);
  scenario.grid = std::move(*grid);
  Result<CellCount> stations = ParseCellCount(o.stations);
  if (!stations) Usage(stations.error().message);
  Result<std::vector<int>> placed = PlaceOnFreeCells(
      scenario.grid, stations->Resolve(scenario.grid.Count(Cell::kFree)), Cell::kStation, random);
  if (!placed) Usage(placed.error().message);
  std::vector<int> movers;
  if (!o.movers.empty()) {
    Result<CellCount> count = ParseCellCount(o.movers);
    if (!count) Usage(count.error().message);
    Result<std::vector<int>> cells = PlaceOnFreeCells(
        scenario.grid, count->Resolve(scenario.grid.Count(Cell::kFree)), Cell::kObstacle, random);
    if (!cells) Usage(cells.error().message);
    movers = std::move(*cells);
  }
  scenario.changes = GenerateMoverChanges(scenario.grid, movers, steps, random);
  return scenario;
}

// Runs one mode; returns its throughput.
double RunMode(const Scenario& scenario, const Options& o, bool ignore) {
  FleetOptions options;
  options.robots = static_cast<int>(o.robots);
  options.seed = static_cast<uint64_t>(o.seed);
  options.goal_count = static_cast<int>(o.goals);
  options.delay_probability = o.delay;
  options.ignore_conflicts = ignore;
  options.threads = static_cast<int>(o.threads);
  const auto built = std::chrono::steady_clock::now();
  Result<std::unique_ptr<Fleet>> made = Fleet::Create(scenario.grid, options);
  if (!made) Usage(made.error().message);
  Fleet& fleet = **made;
  const double build_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - built).count();
  Grid world = scenario.grid;
  LatencyHistogram per_tick, repair, cpu;
  auto cpu_now = [] {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<int64_t>(ts.tv_sec) * 1000000 + ts.tv_nsec / 1000;
  };
  JointMoveReport checked;
  int64_t changed_cells = 0;
  for (long long t = 0; t < o.ticks; ++t) {
    const auto start = std::chrono::steady_clock::now();
    const int64_t cpu_start = cpu_now();
    if (t < static_cast<long long>(scenario.changes.steps.size())) {
      const ChangeStep& step = scenario.changes.steps[static_cast<size_t>(t)];
      fleet.ApplyChanges(step);
      for (const CellChange& change : step.changes) world.set(change.cell, change.code);
      changed_cells += static_cast<int64_t>(step.changes.size());
    }
    repair.Add(std::chrono::duration_cast<std::chrono::microseconds>(
                   std::chrono::steady_clock::now() - start)
                   .count());
    const JointMove& move = fleet.Tick();
    per_tick.Add(std::chrono::duration_cast<std::chrono::microseconds>(
                     std::chrono::steady_clock::now() - start)
                     .count());
    cpu.Add(cpu_now() - cpu_start);
    checked.Add(CheckJointMove(world, move.before, move.after, move.delayed));
  }
  const double throughput = static_cast<double>(fleet.tasks_done()) / static_cast<double>(o.ticks);
  std::printf(
      "{\"mode\":\"%s\",\"rows\":%d,\"cols\":%d,\"robots\":%lld,\"goals\":%zu,\"ticks\":%lld,"
      "\"changed_cells\":%lld,\"tasks\":%lld,\"throughput\":%.3f,\"conflicts\":%lld,"
      "\"vertex\":%lld,\"swap\":%lld,\"crossing\":%lld,\"onto_obstacle\":%lld,"
      "\"overruns\":%lld,\"delays\":%lld,\"held\":%lld,\"ms_per_tick_p50\":%.2f,"
      "\"ms_per_tick_p99\":%.2f,\"ms_per_tick_max\":%.2f,\"repair_ms_p50\":%.2f,"
      "\"repair_ms_p99\":%.2f,\"cpu_ms_per_tick_p50\":%.2f,\"cpu_ms_per_tick_p99\":%.2f,"
      "\"build_s\":%.2f,\"threads\":%lld}\n",
      ignore ? "ignore-conflicts" : "pibt", world.rows(), world.cols(), o.robots,
      fleet.goals().size(), o.ticks, static_cast<long long>(changed_cells),
      static_cast<long long>(fleet.tasks_done()), throughput,
      static_cast<long long>(checked.conflicts()), static_cast<long long>(checked.vertex),
      static_cast<long long>(checked.swap), static_cast<long long>(checked.crossing),
      static_cast<long long>(checked.onto_obstacle), static_cast<long long>(fleet.overruns()),
      static_cast<long long>(fleet.delays()), static_cast<long long>(fleet.held()),
      static_cast<double>(per_tick.Quantile(0.5)) / 1000.0,
      static_cast<double>(per_tick.Quantile(0.99)) / 1000.0,
      static_cast<double>(per_tick.max()) / 1000.0,
      static_cast<double>(repair.Quantile(0.5)) / 1000.0,
      static_cast<double>(repair.Quantile(0.99)) / 1000.0,
      static_cast<double>(cpu.Quantile(0.5)) / 1000.0,
      static_cast<double>(cpu.Quantile(0.99)) / 1000.0, build_s, o.threads);
  std::fflush(stdout);
  return throughput;
}

}  // namespace
}  // namespace dynapath

int main(int argc, char** argv) {
  using namespace dynapath;
  const Options o = Parse(argc, argv);
  const Scenario scenario = Load(o);
  double pibt = 0, ignore = 0;
  if (o.modes != "ignore") pibt = RunMode(scenario, o, false);
  if (o.modes != "pibt") ignore = RunMode(scenario, o, true);
  if (o.modes == "both") {
    std::printf("{\"throughput_ratio\":%.4f}\n", ignore > 0 ? pibt / ignore : 0.0);
  }
  return 0;
}
