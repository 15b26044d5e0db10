#include "core/eval/incremental_policy_evaluation.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "core/plan/learning_planner.h"
#include "dynapath/experiment.h"
#include "dynapath/local_trainer.h"
#include "dynapath/mdp.h"
#include "dynapath/policy_evaluation.h"
#include "dynapath/quadtree.h"
#include "dynapath/scenario.h"
#include "dynapath/thread_pool.h"
#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

using test_grids::RandomGrid;

// Values from a small set half of the time, so ties (which rank the higher
// action first) are common.
void RandomiseRegion(QTable& table, const Grid& grid, const Region& region, std::mt19937& random) {
  const bool coarse = random() % 2 == 0;
  for (int r = region.r0; r <= region.r1; ++r) {
    for (int c = region.c0; c <= region.c1; ++c) {
      float* q = table.row(grid.Index(r, c));
      for (int a = 0; a < 8; ++a) {
        q[a] = coarse ? static_cast<float>(random() % 3)
                      : static_cast<float>(random() % 20001) / 100.0f - 100.0f;
      }
    }
  }
}

// Steers a region's table towards the stations (minus the BFS distance of the
// target, plus noise), so long successful paths exist and the depth bound
// rows + cols matters.
void GuideRegion(QTable& table, const Grid& grid, const Region& region, std::mt19937& random) {
  const std::vector<int32_t> distance = test_grids::Distances(grid);
  for (int r = region.r0; r <= region.r1; ++r) {
    for (int c = region.c0; c <= region.c1; ++c) {
      float* q = table.row(grid.Index(r, c));
      for (int a = 0; a < 8; ++a) {
        const int tr = r + kActionRowOffset[a], tc = c + kActionColOffset[a];
        const int32_t d = grid.InBounds(tr, tc) ? distance[grid.Index(tr, tc)] : -1;
        q[a] = (d < 0 ? -1000.0f : -static_cast<float>(d)) + static_cast<float>(random() % 3);
      }
    }
  }
}

void ExpectSameAsFullEvaluation(IncrementalPolicyEvaluation& incremental, const QuadTree& tree,
                                const Grid& grid, const QTable& table, const std::string& where) {
  PolicyEvaluator evaluator;
  PolicyDepths full;
  evaluator.Evaluate(grid, table, full);
  ASSERT_EQ(incremental.Depths(grid, table), full.depth) << where;
  const std::vector<int32_t>& successors = incremental.Successors(grid, table);
  for (int cell = 0; cell < grid.size(); ++cell) {
    int best, second;
    TopTwoActions(grid, cell, table, best, second);
    const auto target = [&](int a) {
      return a < 0 ? -1
                   : grid.Index(grid.RowOf(cell) + kActionRowOffset[a],
                                grid.ColOf(cell) + kActionColOffset[a]);
    };
    ASSERT_EQ(successors[2 * cell], target(best)) << where << " cell " << cell;
    ASSERT_EQ(successors[2 * cell + 1], target(second)) << where << " cell " << cell;
  }
  for (NodeId node = 0; node < tree.node_count(); ++node) {
    const PolicyScore expected = ScoreRegion(grid, full, tree.node(node).region);
    const PolicyScore& score = incremental.Score(grid, table, node);
    ASSERT_EQ(score.starts, expected.starts) << where << " node " << node;
    ASSERT_EQ(score.successes, expected.successes) << where << " node " << node;
    ASSERT_EQ(score.total_length, expected.total_length) << where << " node " << node;
  }
}

TEST(IncrementalPolicyEvaluationTest, EqualsFullEvaluationUnderEditsAndRetraining) {
  std::mt19937 random(5);
  for (int trial = 0; trial < 30; ++trial) {
    const int rows = 1 + static_cast<int>(random() % 30),
              cols = 1 + static_cast<int>(random() % 30);
    Grid grid = RandomGrid(rows, cols, static_cast<int>(random() % 400),
                           1 + static_cast<int>(random() % 20), random);
    const QuadTree tree(rows, cols, 2 + static_cast<int>(random() % 8));
    QTable table(grid.size());
    GuideRegion(table, grid, tree.node(tree.root()).region, random);
    IncrementalPolicyEvaluation incremental;
    incremental.Reset(tree);
    ExpectSameAsFullEvaluation(incremental, tree, grid, table, "initial");
    for (int step = 1; step <= 40; ++step) {
      const std::string where = "trial " + std::to_string(trial) + " step " + std::to_string(step);
      // The environment's changes, then (sometimes) a few retrained nodes,
      // queried in between as the retraining strategy does.
      std::vector<int> changed;
      const int count = 1 + static_cast<int>(random() % 10);
      for (int k = 0; k < count; ++k) {
        const int cell = static_cast<int>(random() % grid.size());
        const int v = static_cast<int>(random() % 100);
        grid.set(cell, v < 50 ? Cell::kObstacle : v < 95 ? Cell::kFree : Cell::kStation);
        changed.push_back(cell);
      }
      incremental.GridChanged(changed);
      ExpectSameAsFullEvaluation(incremental, tree, grid, table, where + " after changes");
      const int retrained = static_cast<int>(random() % 3);
      for (int k = 0; k < retrained; ++k) {
        const NodeId node = static_cast<NodeId>(random() % tree.node_count());
        const Region& region = tree.node(node).region;
        if (random() % 2 == 0) {
          GuideRegion(table, grid, region, random);
        } else {
          RandomiseRegion(table, grid, region, random);
        }
        incremental.TableChanged(region);
        ExpectSameAsFullEvaluation(incremental, tree, grid, table, where + " after retraining");
      }
      if (HasFatalFailure()) return;
    }
  }
}

TEST(IncrementalPolicyEvaluationTest, DepthBoundIsKeptExactly) {
  // A 1x12 corridor whose policy walks west: the far end needs depth 11 <
  // 13 (rows + cols); a station moved further away pushes starts past it.
  Grid grid(1, 12);
  grid.set(0, 0, Cell::kStation);
  const QuadTree tree(1, 12, 4);
  QTable table(grid.size());
  for (int cell = 0; cell < grid.size(); ++cell) {
    table.row(cell)[6] = 10.0f;  // W best, then E (ties to the higher index)
  }
  IncrementalPolicyEvaluation incremental;
  incremental.Reset(tree);
  ExpectSameAsFullEvaluation(incremental, tree, grid, table, "corridor");
  EXPECT_EQ(incremental.Depths(grid, table)[11], 11);
  grid.set(0, 0, Cell::kFree);
  incremental.GridChanged({0});
  ExpectSameAsFullEvaluation(incremental, tree, grid, table, "no station");
  EXPECT_EQ(incremental.Score(grid, table, tree.root()).successes, 0);
}

TEST(IncrementalPolicyEvaluationTest, SnakeLongerThanTheBoundOpensAndCloses) {
  // A serpentine corridor: the far end is 26 moves from the station, more
  // than rows + cols = 12, so it fails; a shortcut makes it succeed, closing
  // the shortcut makes it fail again.
  Grid grid = test_grids::FromText(
      "C......\n"
      "######.\n"
      ".......\n"
      ".######\n"
      ".......\n");
  const QuadTree tree(5, 7, 3);
  std::mt19937 random(3);
  QTable table(grid.size());
  GuideRegion(table, grid, tree.node(tree.root()).region, random);
  IncrementalPolicyEvaluation incremental;
  incremental.Reset(tree);
  ExpectSameAsFullEvaluation(incremental, tree, grid, table, "snake");
  EXPECT_EQ(incremental.Depths(grid, table)[grid.Index(4, 6)], kNoPath);
  for (int cell : {grid.Index(1, 0), grid.Index(3, 6)}) {
    grid.set(cell, Cell::kFree);
    incremental.GridChanged({cell});
    ExpectSameAsFullEvaluation(incremental, tree, grid, table, "shortcut");
  }
  GuideRegion(table, grid, tree.node(tree.root()).region, random);
  incremental.TableChanged(tree.node(tree.root()).region);
  ExpectSameAsFullEvaluation(incremental, tree, grid, table, "retrained");
  EXPECT_NE(incremental.Depths(grid, table)[grid.Index(4, 6)], kNoPath);
  grid.set(1, 0, Cell::kObstacle);
  grid.set(3, 6, Cell::kObstacle);
  incremental.GridChanged({grid.Index(1, 0), grid.Index(3, 6)});
  ExpectSameAsFullEvaluation(incremental, tree, grid, table, "closed again");
  EXPECT_EQ(incremental.Depths(grid, table)[grid.Index(4, 6)], kNoPath);
}

// The learning planner's figures at every step equal a full evaluation of
// its root table (the planner evaluates incrementally).
TEST(IncrementalPolicyEvaluationTest, LearningPlannerMatchesFullEvaluationEveryStep) {
  ThreadPool pool(2);
  LocalTrainer trainer(pool);
  const Scenario scenario = GenerateScenario(24, 24, Difficulty::kHard, 52, 30);
  for (Approach approach : {Approach::kFedAsynQEqAvg, Approach::kOnlyTrainLeafNodes}) {
    PlannerOptions options;
    options.run_seed = 9;
    options.leaf_limit = 6;
    int checked = 0;
    RunApproach(scenario, approach, options, &trainer, {"24", "Hard"}, SteadyClock(),
                [&](const StepView& view) {
                  auto& planner = dynamic_cast<LearningPlanner&>(view.planner);
                  PolicyEvaluator evaluator;
                  PolicyDepths full;
                  evaluator.Evaluate(view.grid, planner.root().table(), full);
                  const PolicyScore expected = ScoreGrid(view.grid, full);
                  const PolicyScore score = planner.Evaluate(view.grid);
                  EXPECT_EQ(score.successes, expected.successes);
                  EXPECT_EQ(score.total_length, expected.total_length);
                  EXPECT_EQ(score.starts, expected.starts);
                  // The picture's actions (read back from the evaluation's
                  // successors) are the table's two best.
                  PolicyPicture picture;
                  ASSERT_TRUE(planner.Picture(view.grid, picture));
                  EXPECT_EQ(picture.depth, full.depth);
                  for (int cell = 0; cell < view.grid.size(); ++cell) {
                    const Cell code = view.grid.at(cell);
                    int best = -1, second = -1;
                    if (code == Cell::kFree) {
                      TopTwoActions(view.grid, cell, planner.root().table(), best, second);
                    }
                    ASSERT_EQ(picture.actions[cell], best) << "cell " << cell;
                    ASSERT_EQ(picture.second[cell], second) << "cell " << cell;
                    ASSERT_EQ(picture.reaches[cell], code == Cell::kObstacle       ? -1
                                                     : full.depth[cell] == kNoPath ? 0
                                                                                   : 1);
                  }
                  ++checked;
                });
    EXPECT_EQ(checked, 31);
  }
}

}  // namespace
}  // namespace dynapath
