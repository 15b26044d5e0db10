#include "protocol/limits.h"

#include <algorithm>

namespace dynapath::protocol {

int64_t LargestMessageBytes(int64_t cells) {
  cells = std::clamp<int64_t>(cells, 1, kMaxGridCells);
  // 2 x 73 bytes per cell for a batch (a code, 8 table values in double
  // under --semantics report, two start counters), plus 1 MiB for headers,
  // strings, the items of many small jobs and shards of small regions.
  return 2 * 73 * cells + (int64_t{1} << 20);
}

FragmentLimits BusFragmentLimits(int64_t cells) {
  FragmentLimits limits;
  limits.max_message_bytes = LargestMessageBytes(cells);
  // Pieces are ~60 KB: their bookkeeping adds well under 1%; 1 MiB covers it.
  limits.max_buffered_bytes = 2 * limits.max_message_bytes + (int64_t{1} << 20);
  limits.max_partials = 64;
  limits.lifetime = 30000;
  return limits;
}

}  // namespace dynapath::protocol
