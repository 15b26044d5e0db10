#include "dynapath/bfs_oracle.h"

#include "dynapath/mdp.h"

namespace dynapath {

void NearestStationDistances(const Grid& grid, std::vector<int32_t>& distance,
                             std::vector<int32_t>& queue) {
  const int rows = grid.rows(), cols = grid.cols();
  distance.assign(static_cast<size_t>(grid.size()), kUnreachable);
  queue.resize(static_cast<size_t>(grid.size()));
  size_t head = 0, tail = 0;
  for (int i = 0; i < grid.size(); ++i) {
    if (grid.at(i) == Cell::kStation) {
      distance[i] = 0;
      queue[tail++] = i;
    }
  }
  // Moves are symmetric (a diagonal move ignores the two side cells), so the
  // search from the stations over reversed moves is the search over moves.
  while (head < tail) {
    const int cell = queue[head++];
    const int row = cell / cols, col = cell % cols;
    const int32_t next_distance = distance[cell] + 1;
    for (int a = 0; a < kNumActions; ++a) {
      const int r = row + kActionRowOffset[a], c = col + kActionColOffset[a];
      if (r < 0 || r >= rows || c < 0 || c >= cols) continue;
      const int neighbour = r * cols + c;
      if (distance[neighbour] != kUnreachable || grid.at(neighbour) == Cell::kObstacle) continue;
      distance[neighbour] = next_distance;
      queue[tail++] = neighbour;
    }
  }
}

}  // namespace dynapath
