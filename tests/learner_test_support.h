#pragma once
// Shared by the learner tests: hand-made maps (a 10x10 and a 20x20 maze with
// walls and two stations, where every free cell can reach a station) and the
// measure of a trained policy against the BFS oracle.

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "core/learn/region_model.h"
#include "dynapath/bfs_oracle.h"
#include "dynapath/grid.h"
#include "dynapath/policy_evaluation.h"
#include "dynapath/q_table.h"
#include "dynapath/scenario.h"
#include "dynapath/training_job.h"
#include "tests/grid_test_support.h"

namespace dynapath::test_maps {

// Under a sanitizer (GCC's ASan or TSan build) the tests' own reference
// learners are compiled at -O0 and instrumented, ten times slower than in
// the release build: the heaviest property tests take fewer cases of the
// same kinds there.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

// Hand-made maps: walls, two stations, and (20x20) two enclosed pockets that
// no policy can get out of.
inline constexpr const char* kMap10 =
    "..........\n"
    "..#####...\n"
    "......#...\n"
    ".C....#...\n"
    "......#...\n"
    "###...#...\n"
    "......#.C.\n"
    "..#.......\n"
    "..#.......\n"
    "..#.......\n";
inline constexpr const char* kMap20 =
    "....................\n"
    ".C.....#............\n"
    ".......#............\n"
    ".......#.....####...\n"
    ".......#.....#..#...\n"
    ".......#.....#..#...\n"
    ".......#.....####...\n"
    ".......#............\n"
    ".......#............\n"
    ".......######.......\n"
    "....................\n"
    "..............#.....\n"
    "..............#.....\n"
    "....########..#.....\n"
    "..............#.....\n"
    "..............#...C.\n"
    "..............#.....\n"
    ".....###......#.....\n"
    ".....#.#............\n"
    ".....###............\n";

// How well the top-2 policy of `table` (SPEC 4) does against the BFS oracle:
// the fraction of the starts that can reach a station from which it reaches
// one, and its mean path length over those successes relative to the optimal.
struct PolicyQuality {
  double reachable_success = 0;
  double length_ratio = 0;
};

inline PolicyQuality Quality(const Grid& grid, const QTable& table) {
  std::vector<int32_t> distance, queue;
  NearestStationDistances(grid, distance, queue);
  PolicyEvaluator evaluator;
  PolicyDepths depths;
  evaluator.Evaluate(grid, table, depths);
  int reachable = 0, succeeded = 0;
  int64_t length = 0, optimal = 0;
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (distance[cell] == kUnreachable) continue;
    ++reachable;
    if (depths.depth[cell] == kNoPath) continue;
    ++succeeded;
    length += depths.depth[cell];
    optimal += distance[cell];
  }
  return {static_cast<double>(succeeded) / reachable,
          optimal == 0 ? 1.0 : static_cast<double>(length) / static_cast<double>(optimal)};
}

// Same precision, same size, same bits.
inline bool BytesEqual(const QTable& a, const QTable& b) {
  if (a.precision() != b.precision() || a.size() != b.size()) return false;
  return a.precision() == QPrecision::kFloat
             ? std::memcmp(a.values().data(), b.values().data(), a.size() * sizeof(float)) == 0
             : std::memcmp(a.wide_values().data(), b.wide_values().data(),
                           a.size() * sizeof(double)) == 0;
}

inline Grid MapFromText(const char* text) { return test_grids::FromText(text); }

// One job of `kind` over the whole grid (node 0), from an all-zero table,
// with the learners' default options.
inline TrainingJob WholeGridJob(const Grid& grid, LearnerKind kind, uint64_t seed) {
  TrainingJob job;
  job.node = 0;
  job.region = Region{0, grid.rows() - 1, 0, grid.cols() - 1};
  job.codes = RegionCodes(grid, job.region);
  job.warm_start = QTable(job.region.cells());
  job.seed = seed;
  job.kind = kind;
  return job;
}

// The grids every learner must learn on: the two hand-made maps and the
// report's easy and hard 20x20 mazes.
struct LearningCase {
  std::string name;
  Grid grid;
};

inline std::vector<LearningCase> LearningCases() {
  return {{"Map10", MapFromText(kMap10)},
          {"Map20", MapFromText(kMap20)},
          {"Easy20", GenerateScenario(20, 20, Difficulty::kEasy, 50, 0).grid},
          {"Hard20", GenerateScenario(20, 20, Difficulty::kHard, 52, 0).grid}};
}

}  // namespace dynapath::test_maps
