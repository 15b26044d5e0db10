#include "app/resources.h"

#include <algorithm>

namespace dynapath::app {

int64_t GridCap(int rows, int cols) { return static_cast<int64_t>(rows) * cols; }

int64_t GridCap(const Grid& maze) { return GridCap(maze.rows(), maze.cols()); }

int ThreadsPerAgent(int threads, int agents) { return std::max(1, threads / std::max(1, agents)); }

}  // namespace dynapath::app
