#pragma once
// The hierarchical decomposition of SPEC section 3: a quadtree whose nodes
// cover rectangles of the grid. Immutable once built.

#include <array>
#include <vector>

#include "dynapath/region.h"

namespace dynapath {

using NodeId = int;
inline constexpr NodeId kNoNode = -1;

struct QuadNode {
  NodeId id = kNoNode;
  NodeId parent = kNoNode;
  int level = 0;  // 0 = root
  Region region;
  // TL, TR, BL, BR; a child is kNoNode when its rectangle would be empty
  // (a 1-cell-thin side of a rectangular grid) or for a leaf.
  std::array<NodeId, 4> children{kNoNode, kNoNode, kNoNode, kNoNode};
  bool is_leaf() const {
    return children[0] == kNoNode && children[1] == kNoNode && children[2] == kNoNode &&
           children[3] == kNoNode;
  }
};

class QuadTree {
 public:
  // 20: the report's largest leaf side.
  static constexpr int kDefaultLeafLimit = 20;

  // Splits nodes larger than `leaf_limit` in either dimension. Node ids are
  // given level by level (breadth-first, children in TL, TR, BL, BR order), so
  // "node id order" is also "level order", root first.
  QuadTree(int rows, int cols, int leaf_limit = kDefaultLeafLimit);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  int leaf_limit() const { return leaf_limit_; }
  int node_count() const { return static_cast<int>(nodes_.size()); }
  int level_count() const { return level_count_; }
  NodeId root() const { return 0; }
  const QuadNode& node(NodeId id) const { return nodes_[id]; }
  const std::vector<QuadNode>& nodes() const { return nodes_; }
  // Leaves in node-id order.
  const std::vector<NodeId>& leaves() const { return leaves_; }

  // The leaf containing grid cell `cell` (row-major index).
  NodeId LeafOf(int cell) const { return leaf_of_cell_[cell]; }
  // True when `descendant` is `ancestor` or lies below it.
  bool IsInSubtree(NodeId descendant, NodeId ancestor) const;

 private:
  int rows_, cols_, leaf_limit_;
  int level_count_ = 1;
  std::vector<QuadNode> nodes_;
  std::vector<NodeId> leaves_;
  std::vector<NodeId> leaf_of_cell_;
};

}  // namespace dynapath
