// --semantics report (docs/concepts/DECISIONS.md, "The report code's semantics"):
// (a) the bootstrap max over all 8 stored values, whose never-updated
// off-grid entries (0) make a "phantom exit" at the outer wall; (b) a node
// other than the root trained for the first time starts from zeros unless
// an ancestor was trained (then it keeps the copy); the report code's
// single-agent details (SPEC 11: station starts that step, uniform starts,
// one step fewer, replay and convergence checks from episode 501, the first
// check against the starting table), on hand-made grids with exact values.
// Each checked to happen under the switch only.

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <vector>

#include "core/learn/region_model.h"
#include "core/learn/single_agent_learner.h"
#include "core/plan/learning_planner.h"
#include "dynapath/mdp.h"
#include "dynapath/parameters.h"
#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

TEST(ReportSemanticsTest, BootstrapMaxOverAllStoredValuesSeesTheOffGridZeros) {
  const Grid grid(4, 4);
  // Corner 0 of the whole grid: only E, SE, S (2, 3, 4) are in the grid. Its
  // off-grid entries were never updated, so they hold 0.
  const float corner[kNumActions] = {0, 0, -3, -7, -2, 0, 0, 0};
  EXPECT_EQ(RegionModel(grid, Region{0, 3, 0, 3}, Bootstrap::kInGrid).BootstrapMax(0, corner),
            -2.0f);
  EXPECT_EQ(RegionModel(grid, Region{0, 3, 0, 3}, Bootstrap::kAllStored).BootstrapMax(0, corner),
            0.0f);
  // In a region, the out-of-region in-grid entries count under both rules
  // (they hold the node's table's values), the in-region rule leaves them out.
  const Region quarter{2, 3, 2, 3};  // grid cells (2..3, 2..3); local 0 = grid (2,2)
  const float row[kNumActions] = {5, -1, -1, -1, -1, -1, -1, -1};
  EXPECT_EQ(RegionModel(grid, quarter, Bootstrap::kInGrid).BootstrapMax(0, row), 5.0f);
  EXPECT_EQ(RegionModel(grid, quarter, Bootstrap::kAllStored).BootstrapMax(0, row), 5.0f);
  EXPECT_EQ(RegionModel(grid, quarter, Bootstrap::kInRegion).BootstrapMax(0, row), -1.0f);
  // The actions the learner takes do not change.
  const RegionModel all(grid, quarter, Bootstrap::kAllStored);
  const RegionModel in_grid(grid, quarter, Bootstrap::kInGrid);
  for (int cell = 0; cell < all.cells(); ++cell) {
    ASSERT_EQ(all.action_count(cell), in_grid.action_count(cell));
    for (int i = 0; i < all.action_count(cell); ++i) {
      EXPECT_EQ(all.actions(cell)[i], in_grid.actions(cell)[i]);
    }
  }
}

// Largest in-grid value of a cell: the value the top-2 policy sees.
float BestInGrid(const Grid& grid, const QTable& table, int cell) {
  const int row = cell / grid.cols(), col = cell % grid.cols();
  float best = -1e30f;
  for (int a = 0; a < kNumActions; ++a) {
    if (grid.InBounds(row + kActionRowOffset[a], col + kActionColOffset[a])) {
      best = std::max(best, table.row(cell)[a]);
    }
  }
  return best;
}

TEST(ReportSemanticsTest, PhantomExitAppearsAtTheOuterWallOnlyUnderTheSwitch) {
  // No station: every true value is negative (towards -1 / (1 - 0.9) = -10).
  // With the off-grid zeros in the max, a step along the outer wall is worth
  // -1 + 0.9 * 0: the wall looks like an exit.
  const Grid grid(7, 7);
  TrainingJob job;
  job.node = 0;
  job.region = Region{0, 6, 0, 6};
  job.codes = RegionCodes(grid, job.region);
  job.seed = 11;
  job.kind = LearnerKind::kSingleAgent;
  job.bootstrap = Bootstrap::kInGrid;
  const TrainingResult ours = TrainSingleAgent(job);
  job.bootstrap = Bootstrap::kAllStored;
  const TrainingResult report = TrainSingleAgent(job);
  // Under the switch a cell d steps from the wall is worth what d steps to
  // the wall and one along it are: -1 for d = 0 and 1 (a step onto or along
  // the wall, whose max is the phantom 0), then -1 + 0.9 * (value at d - 1).
  const float phantom[4] = {-1.0f, -1.0f, -1.9f, -2.71f};
  for (int cell = 0; cell < grid.size(); ++cell) {
    const int row = cell / 7, col = cell % 7;
    const int d = std::min({row, col, 6 - row, 6 - col});
    EXPECT_LT(BestInGrid(grid, ours.table, cell), -3.0f) << cell;
    EXPECT_NEAR(BestInGrid(grid, report.table, cell), phantom[d], 0.2f) << cell;
  }
  // The off-grid entries themselves are never written.
  for (int a = 0; a < kNumActions; ++a) {
    if (!grid.InBounds(kActionRowOffset[a], kActionColOffset[a])) {
      EXPECT_EQ(report.table.row(0)[a], 0.0f);
    }
  }
}

// Records the warm start of every job and commits a table of node + 1
// everywhere (no station is ever reached: every trained node stays below
// 0.9, so escalation climbs to the root).
class RecordingTrainer : public Trainer {
 public:
  TrainingStats Train(const std::vector<NodeId>& nodes, const std::vector<uint64_t>& seeds,
                      const LearnerConfig& config, const QuadTree& tree, const Grid& grid,
                      RootQTable& root) override {
    bootstrap = config.bootstrap;
    for (size_t i = 0; i < nodes.size(); ++i) {
      const TrainingJob job = MakeTrainingJob(nodes[i], seeds[i], config, tree, grid, root);
      precisions.push_back(job.precision);
      warm_starts[nodes[i]].push_back(job.warm_start);
    }
    for (NodeId node : nodes) {
      QTable table(tree.node(node).region.cells(), root.precision());
      WithValueType(root.precision(), [&]<typename V>(V*) {
        std::fill(table.Values<V>().begin(), table.Values<V>().end(), static_cast<V>(node + 1));
      });
      root.Commit(tree.node(node).region, table);
    }
    return {static_cast<int64_t>(nodes.size()), 0};
  }
  std::map<NodeId, std::vector<QTable>> warm_starts;
  std::vector<QPrecision> precisions;  // of every job
  Bootstrap bootstrap = Bootstrap::kInRegion;
};

// Every value of `table` in double (exact for either precision).
std::vector<double> Values(const QTable& table) {
  std::vector<double> values(table.size());
  for (size_t i = 0; i < values.size(); ++i) values[i] = table.value(i);
  return values;
}

bool AllEqual(const QTable& table, double value) {
  const std::vector<double> values = Values(table);
  return std::all_of(values.begin(), values.end(), [value](double v) { return v == value; });
}

TEST(ReportSemanticsTest, FirstTrainedNodeStartsFromZerosOnlyUnderTheSwitch) {
  // 16x16, leaves of 4x4: root 0, nodes 1-4 (8x8), leaves 5-20.
  const Grid grid(16, 16);
  for (const Semantics semantics : {Semantics::kOurs, Semantics::kReport}) {
    SCOPED_TRACE(semantics == Semantics::kReport ? "report" : "ours");
    PlannerOptions options;
    options.leaf_limit = 4;
    options.semantics = semantics;
    RecordingTrainer trainer;
    LearningPlanner planner(Approach::kSingleAgent, options, trainer);
    planner.Initialize(grid);
    EXPECT_EQ(trainer.bootstrap,
              semantics == Semantics::kReport ? Bootstrap::kAllStored : Bootstrap::kInGrid);
    ASSERT_EQ(planner.tree().node_count(), 21);
    // Leaves first: from the all-zero root under both.
    for (NodeId leaf : planner.tree().leaves()) {
      ASSERT_EQ(trainer.warm_starts[leaf].size(), 1u);
      EXPECT_TRUE(AllEqual(trainer.warm_starts[leaf][0], 0.0f));
    }
    // The 8x8 nodes' first training: their children's values (ours), or
    // zeros (report).
    for (NodeId node = 1; node <= 4; ++node) {
      ASSERT_EQ(trainer.warm_starts[node].size(), 1u);
      const QTable& warm = trainer.warm_starts[node][0];
      if (semantics == Semantics::kReport) {
        EXPECT_TRUE(AllEqual(warm, 0.0f));
      } else {
        // Its four leaves (ids 5..20) committed leaf + 1 >= 6.
        const std::vector<double> v = Values(warm);
        EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](double x) { return x >= 6.0; }));
      }
    }
    // The root has a table from the start, kept in sync: it starts from the
    // values of the 8x8 nodes under both.
    ASSERT_EQ(trainer.warm_starts[0].size(), 1u);
    const std::vector<double> root_warm = Values(trainer.warm_starts[0][0]);
    EXPECT_TRUE(std::all_of(root_warm.begin(), root_warm.end(),
                            [](double x) { return x >= 2.0 && x <= 5.0; }));
    // The report code's tables are double; ours float.
    const QPrecision expected =
        semantics == Semantics::kReport ? QPrecision::kDouble : QPrecision::kFloat;
    EXPECT_TRUE(std::all_of(trainer.precisions.begin(), trainer.precisions.end(),
                            [expected](QPrecision p) { return p == expected; }));
    for (const auto& [node, tables] : trainer.warm_starts) {
      for (const QTable& table : tables) EXPECT_EQ(table.precision(), expected) << node;
    }
    // A second training of a node warm-starts from its values under both.
    trainer.warm_starts.clear();
    Grid changed = grid;
    changed.set(0, Cell::kObstacle);
    planner.Adapt(changed, {0});
    ASSERT_FALSE(trainer.warm_starts[5].empty());
    EXPECT_TRUE(AllEqual(trainer.warm_starts[5][0], 1.0f));  // the root's values
  }
}


// A single-agent job over the whole of a hand-made grid, with the report's
// double tables; `report`: --semantics report's bootstrap (and with it the
// report code's learner rules) and parameter values.
TrainingJob ReportJob(const char* text, bool report, uint64_t seed = 5) {
  const Grid grid = test_grids::FromText(text);
  TrainingJob job;
  job.node = 0;
  job.region = Region{0, grid.rows() - 1, 0, grid.cols() - 1};
  job.codes = RegionCodes(grid, job.region);
  job.precision = QPrecision::kDouble;
  job.seed = seed;
  job.kind = LearnerKind::kSingleAgent;
  if (report) {
    PlannerOptions options;
    ApplyReportPreset(options);
    job.single_agent = options.single_agent;
    job.bootstrap = Bootstrap::kAllStored;
  }
  return job;
}

// n updates of a blocked move on a station: v <- v + 0.4 (100 + 0.9 v - v),
// in the learner's own arithmetic (its row's max is this value: the other
// entries are 0 and v > 0).
double BlockedStationValue(int n) {
  double v = 0;
  for (int i = 0; i < n; ++i) {
    v = v + kLearningRateOf<double> *
                (static_cast<double>(kStationReward) + kDiscountOf<double> * v - v);
  }
  return v;
}

TEST(ReportSemanticsTest, StationStartTakesAStepAndItsRowGrowsUnderABlockedMove) {
  // "C#": the only start is the station, its only in-region move (E) is
  // blocked. Report: every episode takes that step, stays, earns +100 and
  // ends, so Q(C, E) follows BlockedStationValue exactly (no replay before
  // episode 501). Ours: a station start is an immediate success, no step.
  for (const bool report : {false, true}) {
    SCOPED_TRACE(report ? "report" : "ours");
    TrainingJob job = ReportJob("C#\n", report);
    job.single_agent.max_episodes = 30;
    const TrainingResult result = TrainSingleAgent(job);
    EXPECT_EQ(result.episodes_or_rounds, 30);
    EXPECT_EQ(result.steps, report ? 30 : 0);
    const std::vector<double> v = Values(result.table);
    for (size_t i = 0; i < v.size(); ++i) {
      const bool east_of_station = i == 2;  // cell 0, action E
      EXPECT_EQ(v[i], report && east_of_station ? BlockedStationValue(30) : 0.0) << i;
    }
  }
  EXPECT_EQ(BlockedStationValue(1), 40.0);
  // Trained to convergence the row reaches 100 / (1 - 0.9) = 1000. The
  // checks (before episodes 501, 551, ...) start against the zero table, so
  // the first is not quiet and the 21st quiet one is before episode 1551.
  const TrainingResult converged = TrainSingleAgent(ReportJob("C#\n", true));
  EXPECT_NEAR(converged.table.value(2), 1000.0, 1e-9);
  EXPECT_EQ(converged.episodes_or_rounds, 1551);
  EXPECT_EQ(converged.steps, 1551);
}

TEST(ReportSemanticsTest, StationStartThatMovesOffGoesOnAndTheStationRowIsLearned) {
  // "C.": from the station the only move is E, onto the free cell (-1), and
  // the episode goes on: back W onto the station (+100) ends it. Report:
  // Q(C, E) = -1 + 0.9 Q(., W) is learned and positive. Ours: the station
  // row is never updated and stays 0.
  for (const bool report : {false, true}) {
    SCOPED_TRACE(report ? "report" : "ours");
    TrainingJob job = ReportJob("C.\n", report);
    job.single_agent.max_episodes = 200;
    const TrainingResult result = TrainSingleAgent(job);
    const double station_east = result.table.value(0 * kNumActions + 2);
    const double free_west = result.table.value(1 * kNumActions + 6);
    EXPECT_GT(free_west, 99.0);
    if (report) {
      EXPECT_GT(station_east, 0.0);
    } else {
      EXPECT_EQ(station_east, 0.0);
    }
  }
}

TEST(ReportSemanticsTest, EpisodesHaveOneStepFewer) {
  // No station in "....": every episode runs to the cap, region rows + cols
  // steps (ours, 5) or one fewer (report, 4).
  for (const bool report : {false, true}) {
    TrainingJob job = ReportJob("....\n", report);
    job.single_agent.max_episodes = 10;
    EXPECT_EQ(TrainSingleAgent(job).steps, report ? 40 : 50);
  }
}

TEST(ReportSemanticsTest, ReplayAndConvergenceChecksStartAfterEpisode500) {
  const std::vector<Parameter>& parameters = Parameters();
  for (size_t i = 0; i < parameters.size(); ++i) {
    if (parameters[i].name == "replay-start-episode" ||
        parameters[i].name == "convergence-start-episode") {
      EXPECT_EQ(parameters[i].default_value, 500.0);
      EXPECT_EQ(parameters[i].report_value, 501.0);
    }
  }
  // Replay: episodes 0..500 of the report's learner replay nothing (the
  // same table as with no replay at all); episode 501 does.
  constexpr const char* kMaze = "C..#\n.#..\n...C\n#...\n";
  for (const int episodes : {501, 502}) {
    TrainingJob job = ReportJob(kMaze, true, 7);
    job.single_agent.max_episodes = episodes;
    job.single_agent.convergence_start_episode = 100000;
    const TrainingResult replayed = TrainSingleAgent(job);
    job.single_agent.replay_batch = 0;
    const TrainingResult plain = TrainSingleAgent(job);
    EXPECT_EQ(Values(replayed.table) == Values(plain.table), episodes == 501) << episodes;
  }
  // Convergence, on a one-cell region (no step, the table never changes):
  // ours snapshots before episode 500 and is quiet at 550, ..., 1550; the
  // report compares with the starting table before episode 501 (quiet) and
  // stops at its 21st quiet check, before episode 1501.
  EXPECT_EQ(TrainSingleAgent(ReportJob(".\n", false)).episodes_or_rounds, 1550);
  EXPECT_EQ(TrainSingleAgent(ReportJob(".\n", true)).episodes_or_rounds, 1501);
  TrainingJob preset_only = ReportJob(".\n", true);
  preset_only.bootstrap = Bootstrap::kInGrid;  // the report's numbers, our rules
  EXPECT_EQ(TrainSingleAgent(preset_only).episodes_or_rounds, 1551);
}

TEST(ReportSemanticsTest, FirstTrainedChildOfATrainedAncestorKeepsItsCopy) {
  // 16x16, leaves of 4x4: root 0, nodes 1-4 (8x8: TL, TR, BL, BR), leaves
  // 5-20. Column 0 is all stations and the constant tables of
  // RecordingTrainer send every start W or NW (ties go to the higher
  // actions), so the bottom half succeeds; a wall at column 1 of the top
  // half makes its starts fail. Initial training: all leaves, then nodes 1
  // and 2 (top half, from zeros under the switch: no ancestor trained yet),
  // then the root; nodes 3 and 4 stay untrained. Then column 0 of rows 8-11
  // turns to obstacles: that leaf falls to 0.5, is retrained, and node 3 is
  // trained for the first time, after its ancestor (the root) was: under
  // both semantics it starts from the root's values over its region.
  Grid grid(16, 16);
  for (int r = 0; r < 16; ++r) grid.set(grid.Index(r, 0), Cell::kStation);
  for (int r = 0; r < 8; ++r) grid.set(grid.Index(r, 1), Cell::kObstacle);
  for (const Semantics semantics : {Semantics::kOurs, Semantics::kReport}) {
    SCOPED_TRACE(semantics == Semantics::kReport ? "report" : "ours");
    PlannerOptions options;
    options.leaf_limit = 4;
    options.semantics = semantics;
    RecordingTrainer trainer;
    LearningPlanner planner(Approach::kSingleAgent, options, trainer);
    planner.Initialize(grid);
    ASSERT_EQ(planner.tree().node_count(), 21);
    for (NodeId node : {0, 1, 2}) ASSERT_EQ(trainer.warm_starts[node].size(), 1u) << node;
    ASSERT_TRUE(trainer.warm_starts[3].empty());
    ASSERT_TRUE(trainer.warm_starts[4].empty());
    for (NodeId node : {1, 2}) {
      const QTable& warm = trainer.warm_starts[node][0];
      if (semantics == Semantics::kReport) {
        EXPECT_TRUE(AllEqual(warm, 0.0)) << node;
      } else {
        EXPECT_FALSE(AllEqual(warm, 0.0)) << node;
      }
    }
    trainer.warm_starts.clear();
    Grid changed = grid;
    std::vector<int> cells;
    for (int r = 8; r < 12; ++r) {
      cells.push_back(grid.Index(r, 0));
      changed.set(cells.back(), Cell::kObstacle);
    }
    const NodeId leaf = planner.tree().LeafOf(grid.Index(8, 0));
    planner.Adapt(changed, cells);
    ASSERT_EQ(trainer.warm_starts[leaf].size(), 1u);
    ASSERT_EQ(trainer.warm_starts[3].size(), 1u);
    // The root committed 1 everywhere, then the leaf its own id + 1.
    const Region& region = planner.tree().node(3).region;
    const Region& leaf_region = planner.tree().node(leaf).region;
    const QTable& warm = trainer.warm_starts[3][0];
    for (int cell = 0; cell < region.cells(); ++cell) {
      const int r = region.r0 + cell / region.cols(), c = region.c0 + cell % region.cols();
      const bool in_leaf = r >= leaf_region.r0 && r <= leaf_region.r1 && c >= leaf_region.c0 &&
                           c <= leaf_region.c1;
      for (int a = 0; a < kNumActions; ++a) {
        ASSERT_EQ(warm.value(static_cast<size_t>(cell) * kNumActions + a),
                  in_leaf ? leaf + 1.0 : 1.0)
            << cell << " " << a;
      }
    }
  }
}

}  // namespace
}  // namespace dynapath
