#pragma once
// Flat Q-tables: `cells x 8` floats, row-major by cell then action.

#include <span>
#include <vector>

#include "core/mdp.h"
#include "core/region.h"

namespace dynapath {

class QTable {
 public:
  QTable() = default;
  explicit QTable(int cells) : values_(static_cast<size_t>(cells) * kNumActions, 0.0f) {}

  int cells() const { return static_cast<int>(values_.size() / kNumActions); }
  float* row(int cell) { return values_.data() + static_cast<size_t>(cell) * kNumActions; }
  const float* row(int cell) const {
    return values_.data() + static_cast<size_t>(cell) * kNumActions;
  }
  std::vector<float>& values() { return values_; }
  const std::vector<float>& values() const { return values_; }

  bool operator==(const QTable&) const = default;

 private:
  std::vector<float> values_;
};

// The root table of SPEC section 3: the policy in force everywhere.
//
// The spec keeps one table per quadtree node and, after training a node,
// copies its values into all ancestors and all descendants. Nodes that
// overlap a node are exactly its ancestors and descendants, so after every
// such copy each node's table equals the root table restricted to the node's
// region: the per-node tables are views of the root. This class stores only
// the root, and "propagation" is the write of a node's block into it
// (tests/q_table_test.cc checks the equivalence against explicit copies).
class RootQTable {
 public:
  RootQTable(int rows, int cols) : rows_(rows), cols_(cols), table_(rows * cols) {}

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  const QTable& table() const { return table_; }
  QTable& table() { return table_; }

  // The node's table: the root's values over `region`, cells in region order.
  QTable Extract(const Region& region) const;
  // Trains-then-propagates: the node's new table replaces the root's values
  // over `region` (and so every ancestor's and descendant's view of it).
  void Commit(const Region& region, const QTable& node_table);

 private:
  int rows_, cols_;
  QTable table_;
};

}  // namespace dynapath
