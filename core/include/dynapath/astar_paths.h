#pragma once
// The A* baselines of SPEC section 8. A* Static computes, at time step 0, a
// shortest 8-connected unit-cost path from every non-obstacle cell to its
// nearest station and never updates it; A* Oracle recomputes them at every
// step. Both use the report's algorithm (one A* search per start without a
// stored path, Chebyshev heuristic toward the nearest station, sub-paths of
// found paths reused) so its cost can be compared with the report's; the BFS
// Oracle (core/include/dynapath/bfs_oracle.h) gives the same lengths in one linear pass.

#include <cstdint>
#include <vector>

#include "dynapath/bfs_oracle.h"
#include "dynapath/grid.h"
#include "dynapath/policy_evaluation.h"
#include "dynapath/stop_token.h"

namespace dynapath {

// One stored path per cell, as a forest of next pointers toward stations.
struct StationPaths {
  // Next cell on the cell's stored path: the cell itself for a station (its
  // path ends there), -1 for obstacles and cells with no path.
  std::vector<int32_t> next;
  // Path length in moves: 0 for stations, kUnreachable for obstacles and
  // cells from which no station can be reached.
  std::vector<int32_t> length;
};

// Computes StationPaths by A*. Keeps its scratch buffers between calls so
// that repeated planning (A* Oracle, every time step) does not allocate.
// Not thread-safe; use one planner per thread.
class AStarPlanner {
 public:
  // Fills `out` for `grid`. Every length equals the BFS Oracle's distance
  // (NearestStationDistances); the stored paths are shortest paths.
  // Once `stop` is requested (checked every 256 searches) it ends early
  // and returns false; the starts not searched then count as unreachable.
  bool ComputeAllPaths(const Grid& grid, StationPaths& out, StopToken stop = nullptr);

  // Number of A* searches and of closed (expanded) cells of the last call,
  // for benchmarks and the cost comparison with the report.
  int64_t searches() const { return searches_; }
  int64_t expansions() const { return expansions_; }

 private:
  struct OpenEntry {
    int32_t f;  // g + h
    int32_t g;  // moves from the start
    int32_t cell;
  };

  // One A* search from `start` (no stored path yet); stores its path, or marks
  // every closed cell unreachable when no station can be reached.
  void Search(const Grid& grid, int start, StationPaths& out);

  std::vector<int32_t> heuristic_;  // Chebyshev distance to the nearest station
  std::vector<int32_t> queue_;      // breadth-first queue of the heuristic
  std::vector<int32_t> g_;          // valid where seen_stamp_ == generation_
  std::vector<int32_t> parent_;     // idem
  std::vector<uint32_t> seen_stamp_;
  std::vector<uint32_t> closed_stamp_;
  std::vector<int32_t> closed_;  // cells closed by the current search
  std::vector<OpenEntry> open_;  // binary heap ordered by OpenAfter in the .cc
  uint32_t generation_ = 0;
  int64_t searches_ = 0;
  int64_t expansions_ = 0;
};

// A* Static scoring (SPEC section 8): every non-obstacle cell of `current` is
// a start; it succeeds when `paths` (computed on an earlier grid of the same
// size) stores a path for it and no cell of that path, the start included, is
// an obstacle in `current`, and the path's last cell is still a station
// (stations never change in generated scenarios; this only matters for loaded
// change files). Its length is the stored length. Linear in the grid size.
PolicyScore ScoreStoredPaths(const Grid& current, const StationPaths& paths);

// Oracle scoring of exact distances (BFS Oracle, A* Oracle): every
// non-obstacle cell is a start and succeeds when its distance is not
// kUnreachable; its length is the distance.
PolicyScore ScoreDistances(const Grid& grid, const std::vector<int32_t>& distance);

}  // namespace dynapath
