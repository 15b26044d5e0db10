// --semantics report (docs/concepts/DECISIONS.md, "Learning"): (a) the bootstrap max
// over all 8 stored values, whose never-updated off-grid entries (0) make a
// "phantom exit" at the outer wall; (b) a node other than the root trained
// for the first time starts from zeros. Each checked to happen under the
// switch only.

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <vector>

#include "core/plan/learning_planner.h"
#include "dynapath/region_model.h"
#include "dynapath/single_agent_learner.h"
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

}  // namespace
}  // namespace dynapath
