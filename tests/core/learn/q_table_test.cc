#include "dynapath/q_table.h"

#include <gtest/gtest.h>

#include <random>

#include "dynapath/quadtree.h"

namespace dynapath {
namespace {

TEST(QTableTest, ExtractAndCommitABlock) {
  RootQTable root(4, 5);
  const Region region{1, 2, 2, 4};
  QTable block(region.cells());
  for (size_t i = 0; i < block.values().size(); ++i) block.values()[i] = static_cast<float>(i + 1);
  root.Commit(region, block);
  EXPECT_EQ(root.Extract(region), block);
  // Cell (2, 3) is local (1, 1) -> local index 4.
  EXPECT_EQ(root.table().row(2 * 5 + 3)[0], block.row(4)[0]);
  // Outside the region nothing changed.
  EXPECT_EQ(root.table().row(0)[0], 0.0f);
  EXPECT_EQ(root.table().row(1 * 5 + 1)[7], 0.0f);
}

// The spec's model: every node owns a table; training a node copies its
// values into all ancestors and all descendants. Our root-only store must
// give every node the same table as that model, after any training sequence.
TEST(QTableTest, RootStoreEqualsExplicitPerNodePropagation) {
  const QuadTree tree(37, 45, 6);
  std::vector<QTable> per_node;
  for (const QuadNode& node : tree.nodes()) per_node.emplace_back(node.region.cells());
  RootQTable root(tree.rows(), tree.cols());
  std::mt19937 random(5);

  auto copy_overlap = [&](const QTable& source, const Region& from, QTable& target,
                          const Region& to) {
    for (int r = std::max(from.r0, to.r0); r <= std::min(from.r1, to.r1); ++r) {
      for (int c = std::max(from.c0, to.c0); c <= std::min(from.c1, to.c1); ++c) {
        std::copy(source.row(from.LocalIndex(r, c)),
                  source.row(from.LocalIndex(r, c)) + kNumActions, target.row(to.LocalIndex(r, c)));
      }
    }
  };

  for (int training = 0; training < 200; ++training) {
    const NodeId node = static_cast<NodeId>(random() % tree.node_count());
    const Region& region = tree.node(node).region;
    // Both models warm-start the node from its current table.
    ASSERT_EQ(root.Extract(region), per_node[node]);
    // "Training": new values that depend on the warm start.
    QTable trained = per_node[node];
    for (float& value : trained.values()) value = value * 0.5f + static_cast<float>(random() % 100);
    per_node[node] = trained;
    for (const QuadNode& other : tree.nodes()) {
      if (other.id != node &&
          (tree.IsInSubtree(node, other.id) || tree.IsInSubtree(other.id, node))) {
        copy_overlap(trained, region, per_node[other.id], other.region);
      }
    }
    root.Commit(region, trained);
    for (const QuadNode& other : tree.nodes()) {
      ASSERT_EQ(root.Extract(other.region), per_node[other.id]) << "node " << other.id;
    }
  }
}

}  // namespace
}  // namespace dynapath
