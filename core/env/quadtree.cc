#include "dynapath/quadtree.h"

#include <algorithm>

namespace dynapath {
namespace {

// Children stay kNoNode (an aggregate initialiser with "{}" would zero them).
QuadNode MakeNode(NodeId id, NodeId parent, int level, const Region& region) {
  QuadNode node;
  node.id = id;
  node.parent = parent;
  node.level = level;
  node.region = region;
  return node;
}

}  // namespace

QuadTree::QuadTree(int rows, int cols, int leaf_limit)
    : rows_(rows), cols_(cols), leaf_limit_(std::max(1, leaf_limit)) {
  nodes_.push_back(MakeNode(0, kNoNode, 0, Region{0, rows - 1, 0, cols - 1}));
  // Breadth-first: nodes_ doubles as the queue.
  for (size_t next = 0; next < nodes_.size(); ++next) {
    const Region region = nodes_[next].region;
    if (region.rows() <= leaf_limit_ && region.cols() <= leaf_limit_) continue;
    const int mr = (region.r0 + region.r1) / 2;
    const int mc = (region.c0 + region.c1) / 2;
    const std::array<Region, 4> quarters = {
        Region{region.r0, mr, region.c0, mc}, Region{region.r0, mr, mc + 1, region.c1},
        Region{mr + 1, region.r1, region.c0, mc}, Region{mr + 1, region.r1, mc + 1, region.c1}};
    for (int q = 0; q < 4; ++q) {
      if (quarters[q].empty()) continue;
      const NodeId id = static_cast<NodeId>(nodes_.size());
      const int level = nodes_[next].level + 1;
      nodes_[next].children[q] = id;
      nodes_.push_back(MakeNode(id, static_cast<NodeId>(next), level, quarters[q]));
      level_count_ = std::max(level_count_, level + 1);
    }
  }
  leaf_of_cell_.assign(static_cast<size_t>(rows) * cols, kNoNode);
  for (const QuadNode& n : nodes_) {
    if (!n.is_leaf()) continue;
    leaves_.push_back(n.id);
    for (int r = n.region.r0; r <= n.region.r1; ++r) {
      for (int c = n.region.c0; c <= n.region.c1; ++c) leaf_of_cell_[r * cols + c] = n.id;
    }
  }
}

bool QuadTree::IsInSubtree(NodeId descendant, NodeId ancestor) const {
  for (NodeId n = descendant; n != kNoNode; n = nodes_[n].parent) {
    if (n == ancestor) return true;
  }
  return false;
}

}  // namespace dynapath
