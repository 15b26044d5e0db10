#include "core/q_table.h"

#include <algorithm>
#include <cassert>

namespace dynapath {

QTable RootQTable::Extract(const Region& region) const {
  QTable node_table(region.cells());
  const size_t span = static_cast<size_t>(region.cols()) * kNumActions;
  for (int r = region.r0; r <= region.r1; ++r) {
    const float* source = table_.row(r * cols_ + region.c0);
    std::copy(source, source + span, node_table.row(region.LocalIndex(r, region.c0)));
  }
  return node_table;
}

void RootQTable::Commit(const Region& region, const QTable& node_table) {
  assert(node_table.cells() == region.cells());
  const size_t span = static_cast<size_t>(region.cols()) * kNumActions;
  for (int r = region.r0; r <= region.r1; ++r) {
    const float* source = node_table.row(region.LocalIndex(r, region.c0));
    std::copy(source, source + span, table_.row(r * cols_ + region.c0));
  }
}

}  // namespace dynapath
