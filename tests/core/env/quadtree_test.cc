#include "dynapath/quadtree.h"

#include <gtest/gtest.h>

#include <set>

namespace dynapath {
namespace {

void ExpectEveryCellInExactlyOneLeaf(const QuadTree& tree) {
  std::vector<int> owners(static_cast<size_t>(tree.rows()) * tree.cols(), 0);
  for (NodeId leaf : tree.leaves()) {
    const Region& region = tree.node(leaf).region;
    ASSERT_FALSE(region.empty());
    EXPECT_LE(region.rows(), tree.leaf_limit());
    EXPECT_LE(region.cols(), tree.leaf_limit());
    for (int r = region.r0; r <= region.r1; ++r) {
      for (int c = region.c0; c <= region.c1; ++c) {
        ++owners[r * tree.cols() + c];
        EXPECT_EQ(tree.LeafOf(r * tree.cols() + c), leaf);
      }
    }
  }
  for (int count : owners) ASSERT_EQ(count, 1);
}

TEST(QuadTreeTest, ReportShapes) {
  // SPEC 3: 300x300 has 5 levels and 256 leaves; 50x50 has 3 levels and 16.
  const QuadTree big(300, 300);
  EXPECT_EQ(big.level_count(), 5);
  EXPECT_EQ(big.leaves().size(), 256u);
  ExpectEveryCellInExactlyOneLeaf(big);
  const QuadTree medium(50, 50);
  EXPECT_EQ(medium.level_count(), 3);
  EXPECT_EQ(medium.leaves().size(), 16u);
  ExpectEveryCellInExactlyOneLeaf(medium);
  const QuadTree small(20, 20);
  EXPECT_EQ(small.level_count(), 1);
  EXPECT_EQ(small.node_count(), 1);
  EXPECT_TRUE(small.node(0).is_leaf());
  EXPECT_EQ(QuadTree(100, 100).level_count(), 4);
  EXPECT_EQ(QuadTree(200, 200).level_count(), 5);
}

TEST(QuadTreeTest, SplitsAtTheMidpointLikeTheReport) {
  const QuadTree tree(50, 50);
  const QuadNode& root = tree.node(tree.root());
  // mr = mc = (0 + 49) / 2 = 24.
  EXPECT_EQ(tree.node(root.children[0]).region, (Region{0, 24, 0, 24}));
  EXPECT_EQ(tree.node(root.children[1]).region, (Region{0, 24, 25, 49}));
  EXPECT_EQ(tree.node(root.children[2]).region, (Region{25, 49, 0, 24}));
  EXPECT_EQ(tree.node(root.children[3]).region, (Region{25, 49, 25, 49}));
  // 25 rows: (0 + 24) / 2 = 12, so 13 + 12.
  const QuadNode& tl = tree.node(root.children[0]);
  EXPECT_EQ(tree.node(tl.children[0]).region, (Region{0, 12, 0, 12}));
  EXPECT_EQ(tree.node(tl.children[3]).region, (Region{13, 24, 13, 24}));
}

TEST(QuadTreeTest, IdsAreLevelOrderAndLinksConsistent) {
  const QuadTree tree(300, 300);
  int previous_level = 0;
  for (const QuadNode& node : tree.nodes()) {
    EXPECT_GE(node.level, previous_level);
    previous_level = node.level;
    for (NodeId child : node.children) {
      if (child == kNoNode) continue;
      EXPECT_EQ(tree.node(child).parent, node.id);
      EXPECT_EQ(tree.node(child).level, node.level + 1);
      EXPECT_GT(child, node.id);
      EXPECT_TRUE(tree.IsInSubtree(child, node.id));
    }
  }
  EXPECT_EQ(tree.node(tree.root()).parent, kNoNode);
  EXPECT_FALSE(tree.IsInSubtree(tree.root(), tree.leaves().front()));
}

TEST(QuadTreeTest, RectangularAndThinGrids) {
  for (auto [rows, cols] : {std::pair{7, 90}, std::pair{1, 100}, std::pair{45, 21}, std::pair{1, 1},
                            std::pair{21, 1}}) {
    const QuadTree tree(rows, cols);
    SCOPED_TRACE(std::to_string(rows) + "x" + std::to_string(cols));
    ExpectEveryCellInExactlyOneLeaf(tree);
  }
}

TEST(QuadTreeTest, LeafLimitIsAParameter) {
  const QuadTree tree(16, 16, 4);
  EXPECT_EQ(tree.leaves().size(), 16u);
  EXPECT_EQ(tree.level_count(), 3);
  ExpectEveryCellInExactlyOneLeaf(tree);
}

}  // namespace
}  // namespace dynapath
