#include "dynapath/q_table.h"

#include <algorithm>
#include <cassert>

namespace dynapath {

bool QTable::AllZero() const {
  return WithValueType(precision_, [this]<typename V>(V*) {
    const std::vector<V>& values = Values<V>();
    return std::all_of(values.begin(), values.end(), [](V v) { return v == V{0}; });
  });
}

namespace {

// Copies `region`'s rows between a grid-wide table (`cols` columns) and a
// region table, one contiguous span per row.
template <typename V>
void CopyRegion(const Region& region, int cols, const QTable& from, bool from_root, QTable& to) {
  const size_t span = static_cast<size_t>(region.cols()) * kNumActions;
  for (int r = region.r0; r <= region.r1; ++r) {
    const int root_cell = r * cols + region.c0;
    const int node_cell = region.LocalIndex(r, region.c0);
    const V* source = from.Row<V>(from_root ? root_cell : node_cell);
    std::copy(source, source + span, to.Row<V>(from_root ? node_cell : root_cell));
  }
}

}  // namespace

QTable RootQTable::Extract(const Region& region) const {
  QTable node_table(region.cells(), table_.precision());
  WithValueType(table_.precision(), [&]<typename V>(V*) {
    CopyRegion<V>(region, cols_, table_, true, node_table);
  });
  return node_table;
}

void RootQTable::Commit(const Region& region, const QTable& node_table) {
  assert(node_table.cells() == region.cells());
  assert(node_table.precision() == table_.precision());
  WithValueType(table_.precision(), [&]<typename V>(V*) {
    CopyRegion<V>(region, cols_, node_table, false, table_);
  });
}

}  // namespace dynapath
