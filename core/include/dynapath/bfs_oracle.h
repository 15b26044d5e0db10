#pragma once
// BFS Oracle (SPEC section 8): the exact distance from every cell to its
// nearest station, by one multi-source breadth-first search from all stations
// over free 8-connected moves. Linear in the number of cells.

#include <cstdint>
#include <vector>

#include "dynapath/grid.h"

namespace dynapath {

inline constexpr int32_t kUnreachable = -1;

// Distance in moves from each cell to its nearest station; kUnreachable for
// obstacles and for cells with no path. `queue` is scratch space, reused
// between calls to avoid allocation.
void NearestStationDistances(const Grid& grid, std::vector<int32_t>& distance,
                             std::vector<int32_t>& queue);

}  // namespace dynapath
