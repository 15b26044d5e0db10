#pragma once
// Flat Q-tables: `cells x 8` values, row-major by cell then action.
//
// Values are stored as float (our semantics) or as double (`--semantics
// report`: the report's code keeps its tables in double, SPEC section 10, and
// which action values tie exactly, and so which path wins, depends on it).
// A table has one precision for its life; learners and evaluators are
// templates over the value type and pick theirs once per job or call.

#include <cassert>
#include <cstddef>
#include <vector>

#include "dynapath/mdp.h"
#include "dynapath/region.h"

namespace dynapath {

enum class QPrecision { kFloat, kDouble };

// The value type of a precision, and back.
template <typename V>
inline constexpr QPrecision kPrecisionOf = QPrecision::kFloat;
template <>
inline constexpr QPrecision kPrecisionOf<double> = QPrecision::kDouble;

// Of a pair of float and double containers (a table's storage, a shard's
// values, scratch), the one of value type V; const-ness follows the pair.
template <typename V, typename Narrow, typename Wide>
auto& OfValueType(Narrow& narrow, Wide& wide) {
  if constexpr (kPrecisionOf<V> == QPrecision::kFloat) {
    return narrow;
  } else {
    return wide;
  }
}

class QTable {
 public:
  QTable() = default;
  explicit QTable(int cells, QPrecision precision = QPrecision::kFloat) : precision_(precision) {
    const size_t size = static_cast<size_t>(cells) * kNumActions;
    if (precision == QPrecision::kFloat) {
      values_.assign(size, 0.0f);
    } else {
      wide_values_.assign(size, 0.0);
    }
  }

  QPrecision precision() const { return precision_; }
  // Number of entries (cells x 8).
  size_t size() const {
    return precision_ == QPrecision::kFloat ? values_.size() : wide_values_.size();
  }
  int cells() const { return static_cast<int>(size() / kNumActions); }

  // The float storage (float tables only).
  float* row(int cell) { return Row<float>(cell); }
  const float* row(int cell) const { return Row<float>(cell); }
  std::vector<float>& values() {
    assert(precision_ == QPrecision::kFloat);
    return values_;
  }
  const std::vector<float>& values() const {
    assert(precision_ == QPrecision::kFloat);
    return values_;
  }
  // The double storage (double tables only).
  std::vector<double>& wide_values() {
    assert(precision_ == QPrecision::kDouble);
    return wide_values_;
  }
  const std::vector<double>& wide_values() const {
    assert(precision_ == QPrecision::kDouble);
    return wide_values_;
  }

  // The storage of value type V, which must be the table's.
  template <typename V>
  std::vector<V>& Values() {
    assert(precision_ == kPrecisionOf<V>);
    return OfValueType<V>(values_, wide_values_);
  }
  template <typename V>
  const std::vector<V>& Values() const {
    assert(precision_ == kPrecisionOf<V>);
    return OfValueType<V>(values_, wide_values_);
  }
  template <typename V>
  V* Row(int cell) {
    return Values<V>().data() + static_cast<size_t>(cell) * kNumActions;
  }
  template <typename V>
  const V* Row(int cell) const {
    return Values<V>().data() + static_cast<size_t>(cell) * kNumActions;
  }

  // Value of one entry, in double (exact for either precision).
  double value(size_t entry) const {
    return precision_ == QPrecision::kFloat ? values_[entry] : wide_values_[entry];
  }
  // Whether every value is 0.
  bool AllZero() const;

  bool operator==(const QTable&) const = default;

 private:
  QPrecision precision_ = QPrecision::kFloat;
  std::vector<float> values_;        // float tables
  std::vector<double> wide_values_;  // double tables
};

// Calls f(static_cast<V*>(nullptr)) with V the value type of `precision`:
// the one place a run-time precision becomes a template argument.
template <typename F>
decltype(auto) WithValueType(QPrecision precision, F&& f) {
  if (precision == QPrecision::kFloat) return f(static_cast<float*>(nullptr));
  return f(static_cast<double*>(nullptr));
}

// The root table of SPEC section 3: the policy in force everywhere.
//
// The spec keeps one table per quadtree node and, after training a node,
// copies its values into all ancestors and all descendants. Nodes that
// overlap a node are exactly its ancestors and descendants, so after every
// such copy each node's table equals the root table restricted to the node's
// region: the per-node tables are views of the root. This class stores only
// the root, and "propagation" is the write of a node's block into it
// (tests/core/learn/q_table_test.cc checks the equivalence against explicit copies).
class RootQTable {
 public:
  RootQTable(int rows, int cols, QPrecision precision = QPrecision::kFloat)
      : rows_(rows), cols_(cols), table_(rows * cols, precision) {}

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  QPrecision precision() const { return table_.precision(); }
  const QTable& table() const { return table_; }
  QTable& table() { return table_; }

  // The node's table: the root's values over `region`, cells in region order.
  QTable Extract(const Region& region) const;
  // Trains-then-propagates: the node's new table (of the root's precision)
  // replaces the root's values over `region` (and so every ancestor's and
  // descendant's view of it).
  void Commit(const Region& region, const QTable& node_table);

 private:
  int rows_, cols_;
  QTable table_;
};

}  // namespace dynapath
