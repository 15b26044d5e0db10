#pragma once
// Grid helpers shared by the tests of core/.

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "dynapath/bfs_oracle.h"
#include "dynapath/grid.h"

namespace dynapath::test_grids {

// Parses a maze text; a parse error fails the calling test.
inline Grid FromText(const std::string& text) {
  Result<Grid> grid = GridFromText(text);
  EXPECT_TRUE(grid.ok());
  return grid.ok() ? grid.value() : Grid(1, 1);
}

// BFS distances to the nearest station (kUnreachable where none).
inline std::vector<int32_t> Distances(const Grid& grid) {
  std::vector<int32_t> distance, queue;
  NearestStationDistances(grid, distance, queue);
  return distance;
}

// Obstacles and stations with the given per-mille probabilities; integer
// arithmetic on mt19937 output so the grids are the same on every platform.
inline Grid RandomGrid(int rows, int cols, int obstacle_per_mille, int station_per_mille,
                       std::mt19937& random) {
  Grid grid(rows, cols);
  for (int cell = 0; cell < grid.size(); ++cell) {
    const int v = static_cast<int>(random() % 1000);
    if (v < obstacle_per_mille) {
      grid.set(cell, Cell::kObstacle);
    } else if (v < obstacle_per_mille + station_per_mille) {
      grid.set(cell, Cell::kStation);
    }
  }
  return grid;
}

}  // namespace dynapath::test_grids
