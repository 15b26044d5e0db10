// Goal paths on a changing map, in process (no LCM): GoalPlanner's latency
// and memory, its exactness against a fresh breadth-first search, beside a
// from-scratch A* on the same queries. docs/PERFORMANCE.md#goal-paths.
//
//   goal_paths_latency MAP [--warmup W] [--seconds S] [--rate Q] [--updates U]
//                      [--change-permille P] [--hot-goals H] [--hot-share F]
//                      [--cache-mb M] [--check N] [--astar-queries K] [--seed X]
//                      [--background B] [--settle 0|1] [--hot-after A]
//                      [--landmarks L] [--active-landmarks AL] [--drop-costly 0|1]
//
// Simulated time: S seconds of Q queries a second with U map updates a
// second, each moving obstacles (SPEC's movers: an obstacle to a free
// neighbour) until P per mille of the free cells changed. A query's start
// is a random free cell; its goal, with probability F, one of H fixed goals
// (the most asked), else a random free cell. Each query is timed alone
// (steady_clock around Plan, lazy field repairs included): service time,
// not queueing. W simulated seconds before are run the same way but not
// measured (the hot goals' fields are built then; with --settle 1 the
// builder thread's queued fields are then waited for, so the measured part
// starts with the fields it was asked for). B: 1 (the default) makes fields on
// the planner's builder thread, 0 on the query thread, at the miss that
// makes a goal hot. A, L, AL and --drop-costly set GoalPlannerOptions'
// hot_after, landmarks, active_landmarks and drop_costly_fields (defaults
// 2, 8, 4, 1). The first N answers are checked against a fresh
// search on that update's grid; K queries are answered again by a planner without fields (A* from
// scratch every time).

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "dynapath/goal_paths.h"
#include "dynapath/movingai_map.h"

namespace {

using dynapath::Cell;
using dynapath::GoalPath;
using dynapath::GoalPlanner;
using dynapath::GoalPlannerOptions;
using dynapath::Grid;

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))];
}

void Print(const char* what, const std::vector<double>& us) {
  std::printf("%-34s n=%-7zu p50 %8.3f ms  p99 %8.3f ms  max %8.3f ms\n", what, us.size(),
              Percentile(us, 0.5) / 1000, Percentile(us, 0.99) / 1000,
              us.empty() ? 0.0 : *std::max_element(us.begin(), us.end()) / 1000);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') {
    std::fprintf(stderr, "usage: goal_paths_latency MAP [options] (see the source's header)\n");
    return 2;
  }
  double warmup = 0, seconds = 10, rate = 10000, updates_per_second = 10, change_permille = 1,
         hot_share = 0.9;
  int hot_goals = 1000, check = 10000, astar_queries = 10000;
  double cache_mb = 256;
  unsigned seed = 1;
  int background = 1, settle = 0, hot_after = 2;
  int landmarks = 8, active_landmarks = 4, drop_costly = 1;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string o = argv[i];
    const double v = std::atof(argv[i + 1]);
    if (o == "--seconds")
      seconds = v;
    else if (o == "--warmup")
      warmup = v;
    else if (o == "--rate")
      rate = v;
    else if (o == "--updates")
      updates_per_second = v;
    else if (o == "--change-permille")
      change_permille = v;
    else if (o == "--hot-goals")
      hot_goals = static_cast<int>(v);
    else if (o == "--hot-share")
      hot_share = v;
    else if (o == "--cache-mb")
      cache_mb = v;
    else if (o == "--check")
      check = static_cast<int>(v);
    else if (o == "--astar-queries")
      astar_queries = static_cast<int>(v);
    else if (o == "--background")
      background = static_cast<int>(v);
    else if (o == "--drop-costly")
      drop_costly = static_cast<int>(v);
    else if (o == "--landmarks")
      landmarks = static_cast<int>(v);
    else if (o == "--active-landmarks")
      active_landmarks = static_cast<int>(v);
    else if (o == "--hot-after")
      hot_after = static_cast<int>(v);
    else if (o == "--settle")
      settle = static_cast<int>(v);
    else if (o == "--seed")
      seed = static_cast<unsigned>(v);
    else {
      std::fprintf(stderr, "unknown option %s\n", o.c_str());
      return 2;
    }
  }
  dynapath::Result<Grid> loaded = dynapath::LoadMazeFile(argv[1]);
  if (!loaded) {
    std::fprintf(stderr, "%s\n", loaded.error().message.c_str());
    return 2;
  }
  Grid grid = *loaded;
  std::mt19937_64 random(seed);
  auto free_cell = [&] {
    for (;;) {
      const int c = static_cast<int>(random() % static_cast<uint64_t>(grid.size()));
      if (grid.at(c) != Cell::kObstacle) return c;
    }
  };
  const int free_cells = grid.size() - grid.Count(Cell::kObstacle);
  const int changes_per_update = std::max(1, static_cast<int>(free_cells * change_permille / 1000));
  std::vector<int> goals;
  for (int k = 0; k < hot_goals; ++k) goals.push_back(free_cell());
  std::printf(
      "map %s: %dx%d, %d free cells; %.0f queries/s, %.0f updates/s of %d changed cells "
      "(%.2f per mille of the free cells); %d hot goals take %.0f%% of the queries; "
      "cache %.0f MB\n",
      argv[1], grid.rows(), grid.cols(), free_cells, rate, updates_per_second, changes_per_update,
      change_permille, hot_goals, hot_share * 100, cache_mb);

  GoalPlannerOptions options;
  options.cache_bytes = static_cast<size_t>(cache_mb * 1024 * 1024);
  options.background_builds = background != 0;
  options.hot_after = hot_after;
  options.landmarks = landmarks;
  options.drop_costly_fields = drop_costly != 0;
  options.active_landmarks = active_landmarks;
  GoalPlanner planner(options);
  GoalPlannerOptions no_fields;
  no_fields.cache_bytes = 0;
  GoalPlanner astar(no_fields);
  planner.Update(std::make_shared<const Grid>(grid), {});
  astar.Update(std::make_shared<const Grid>(grid), {});

  using Clock = std::chrono::steady_clock;
  const auto micros = [](Clock::duration d) {
    return std::chrono::duration<double, std::micro>(d).count();
  };
  const int64_t warm = static_cast<int64_t>(warmup * rate);
  const int64_t queries = warm + static_cast<int64_t>(seconds * rate);
  const int64_t per_update = std::max<int64_t>(1, static_cast<int64_t>(rate / updates_per_second));
  std::vector<double> hot_us, other_us, all_us, astar_hot_us, astar_other_us, update_us;
  std::vector<bool> by_field;
  std::vector<double> expanded_per_search, search_repairing_us, search_plain_us;
  int64_t checked = 0, wrong = 0, reached = 0;
  double busy_us = 0;
  std::vector<int> obstacles;
  for (int c = 0; c < grid.size(); ++c) {
    if (grid.at(c) == Cell::kObstacle) obstacles.push_back(c);
  }
  for (int64_t i = 0; i < queries; ++i) {
    const int64_t q = i - warm;  // negative: warming up, not measured
    if (q == 0 && settle != 0) {
      const auto s0 = Clock::now();
      planner.WaitForBuilds();
      std::printf("settled: waited %.1f s for the builder's %lld queued fields\n",
                  micros(Clock::now() - s0) / 1e6, static_cast<long long>(planner.stats().queued));
    }
    if (i > 0 && i % per_update == 0) {
      // Movers: an obstacle to a free neighbour, until enough cells changed.
      std::vector<int> changed;
      while (static_cast<int>(changed.size()) < changes_per_update && !obstacles.empty()) {
        const size_t k = random() % obstacles.size();
        const int from = obstacles[k];
        const int r = grid.RowOf(from) + static_cast<int>(random() % 3) - 1;
        const int c = grid.ColOf(from) + static_cast<int>(random() % 3) - 1;
        if (!grid.InBounds(r, c) || grid.at(r, c) != Cell::kFree) continue;
        grid.set(from, Cell::kFree);
        grid.set(r, c, Cell::kObstacle);
        obstacles[k] = grid.Index(r, c);
        changed.push_back(from);
        changed.push_back(grid.Index(r, c));
      }
      auto shared = std::make_shared<const Grid>(grid);
      const auto t0 = Clock::now();
      planner.Update(shared, changed);
      if (q >= 0) {
        update_us.push_back(micros(Clock::now() - t0));
        busy_us += update_us.back();
      }
      astar.Update(shared, changed);
    }
    const int start = free_cell();
    const bool hot = std::uniform_real_distribution<double>(0, 1)(random) < hot_share;
    int goal = hot ? goals[random() % goals.size()] : free_cell();
    if (grid.at(goal) == Cell::kObstacle) goal = free_cell();  // a mover covered it
    const int sr = grid.RowOf(start), sc = grid.ColOf(start);
    const int gr = grid.RowOf(goal), gc = grid.ColOf(goal);
    const int64_t expanded_before = planner.stats().expanded;
    const int64_t repairs_before = planner.stats().repairs;
    const auto t0 = Clock::now();
    const GoalPath path = planner.Plan(sr, sc, gr, gc);
    const double us = micros(Clock::now() - t0);
    if (q < 0) continue;
    busy_us += us;
    (hot ? hot_us : other_us).push_back(us);
    all_us.push_back(us);
    by_field.push_back(path.source == dynapath::GoalSource::kField);
    if (path.source == dynapath::GoalSource::kSearch) {
      expanded_per_search.push_back(
          static_cast<double>(planner.stats().expanded - expanded_before) * 1000);
      (planner.stats().repairs != repairs_before ? search_repairing_us : search_plain_us)
          .push_back(us);
    }
    if (path.status == dynapath::GoalStatus::kReached) ++reached;
    if (q < astar_queries) {
      const auto t1 = Clock::now();
      const GoalPath baseline = astar.Plan(sr, sc, gr, gc);
      (hot ? astar_hot_us : astar_other_us).push_back(micros(Clock::now() - t1));
      if (baseline.cost != path.cost) ++wrong;
    }
    if (q < check) {
      ++checked;
      if (dynapath::FreshGoalDistance(grid, start, goal) != path.cost) ++wrong;
    }
  }
  const dynapath::GoalCacheStats& s = planner.stats();
  std::printf("after %.1f s of warm-up: ", warmup);
  std::printf(
      "queries %lld (%lld reached), updates %zu; checked against a fresh BFS: %lld, "
      "answers that differ (from the BFS or the A*): %lld\n",
      static_cast<long long>(queries - warm), static_cast<long long>(reached), update_us.size(),
      static_cast<long long>(checked), static_cast<long long>(wrong));
  std::vector<double> field_us, search_us;
  for (size_t k = 0; k < all_us.size(); ++k)
    (by_field[k] ? field_us : search_us).push_back(all_us[k]);
  Print("goal planner, the hot goals", hot_us);
  Print("goal planner, other goals", other_us);
  Print("goal planner, every query", all_us);
  Print("goal planner, answered by a field", field_us);
  Print("goal planner, answered by search", search_us);
  Print("  searches that repaired landmarks", search_repairing_us);
  Print("  searches that did not", search_plain_us);
  std::printf(
      "cells expanded per search (in thousands): p50 %.1f, p99 %.1f, max %.1f\n",
      Percentile(expanded_per_search, 0.5) / 1e6, Percentile(expanded_per_search, 0.99) / 1e6,
      expanded_per_search.empty()
          ? 0.0
          : *std::max_element(expanded_per_search.begin(), expanded_per_search.end()) / 1e6);
  Print("A* from scratch, the hot goals", astar_hot_us);
  Print("A* from scratch, other goals", astar_other_us);
  Print("goal planner Update (log a batch)", update_us);
  std::printf("one core busy %.1f%% of the simulated %.0f s (queries + updates)\n",
              busy_us / (seconds * 1e6) * 100, seconds);
  std::printf(
      "cache: %lld hits, %lld misses, %lld builds (%lld on the builder thread, %lld wide), "
      "%lld evictions, %lld repairs, %lld dropped as dearer than searching (%lld not made), "
      "%lld rebuilds; %lld A* searches (%.0f cells expanded each), %lld landmarks, "
      "%lld proved unreachable\n",
      static_cast<long long>(s.hits), static_cast<long long>(s.misses),
      static_cast<long long>(s.builds), static_cast<long long>(s.queued),
      static_cast<long long>(s.widened), static_cast<long long>(s.evictions),
      static_cast<long long>(s.repairs), static_cast<long long>(s.dropped_costly),
      static_cast<long long>(s.not_made_costly), static_cast<long long>(s.rebuilds),
      static_cast<long long>(s.searches),
      s.searches ? static_cast<double>(s.expanded) / static_cast<double>(s.searches) : 0.0,
      static_cast<long long>(s.landmarks), static_cast<long long>(s.proved_unreachable));
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf(
      "fields: %lld now (%lld being made), %lld indexed cells, %.1f MB now, peak %.1f MB, cap "
      "%.1f MB; process max RSS %.1f MB\n",
      static_cast<long long>(s.fields), static_cast<long long>(s.pending),
      static_cast<long long>(s.indexed_cells), static_cast<double>(s.bytes) / 1048576.0,
      static_cast<double>(s.peak_bytes) / 1048576.0, static_cast<double>(s.cap_bytes) / 1048576.0,
      static_cast<double>(usage.ru_maxrss) / 1024.0);
  return wrong == 0 ? 0 : 1;
}
