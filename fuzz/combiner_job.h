#pragma once
// The federated job of fuzz/round_combiner_fuzz.cc (and of its seeds,
// tests/protocol/fuzz_seeds.cc): a 10x10 map, 4 learners, two agents.

#include "core/learn/fedasynq.h"
#include "core/learn/region_model.h"
#include "dynapath/grid.h"
#include "protocol/round_combiner.h"

namespace dynapath::fuzz {

inline constexpr const char* kCombinerMap =
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

inline TrainingJob CombinerTrainingJob(Averaging averaging) {
  static const Grid grid = *GridFromText(kCombinerMap);
  TrainingJob job;
  job.node = 0;
  job.region = Region{0, grid.rows() - 1, 0, grid.cols() - 1};
  job.codes = RegionCodes(grid, job.region);
  job.warm_start = QTable(job.region.cells());
  job.seed = 17;
  job.kind = LearnerKind::kFedAsynQ;
  job.federated.averaging = averaging;
  job.federated.learners = 4;
  return job;
}

inline protocol::RoundCombiner::Job CombinerJob(const TrainingJob& job) {
  return protocol::RoundCombiner::Job::From(0, job);
}

// Agent 1 hosts learners 0 and 1, agent 2 learners 2 and 3.
inline protocol::RoundCombiner::Items CombinerItems() {
  return {{1, {{0, 0}, {0, 1}}}, {2, {{0, 2}, {0, 3}}}};
}

}  // namespace dynapath::fuzz
