#include "dynapath/astar_paths.h"

#include <algorithm>
#include <cassert>

#include "dynapath/mdp.h"

namespace dynapath {
namespace {

// Length of a cell whose search has not run yet (never left in the output).
constexpr int32_t kUndecided = -2;

// Heap order of the open list: lowest f first; among equal f the deeper entry
// (higher g, so lower h: closer to a station by the heuristic) first, which
// keeps the usual A* tie-break that walks straight toward the goal; then the
// lower cell index, so the search and the stored paths are deterministic.
// Returns true when `a` is popped after `b` (std::push_heap builds a max-heap).
struct OpenAfter {
  template <class Entry>
  bool operator()(const Entry& a, const Entry& b) const {
    if (a.f != b.f) return a.f > b.f;
    if (a.g != b.g) return a.g < b.g;
    return a.cell > b.cell;
  }
};

}  // namespace

bool AStarPlanner::ComputeAllPaths(const Grid& grid, StationPaths& out, StopToken stop) {
  const int n = grid.size();
  const int rows = grid.rows(), cols = grid.cols();
  const size_t size = static_cast<size_t>(n);
  out.next.assign(size, -1);
  out.length.assign(size, kUndecided);
  searches_ = 0;
  expansions_ = 0;

  // The heuristic: h(cell) = min over stations of max(|dr|, |dc|). On a grid
  // without obstacles the 8-connected distance between two cells is their
  // Chebyshev distance, so one multi-source breadth-first search from all
  // stations that ignores obstacles gives h for every cell in linear time.
  heuristic_.assign(size, -1);
  queue_.resize(size);
  size_t head = 0, tail = 0;
  for (int cell = 0; cell < n; ++cell) {
    switch (grid.at(cell)) {
      case Cell::kObstacle:
        out.length[cell] = kUnreachable;
        break;
      case Cell::kStation:
        out.length[cell] = 0;
        out.next[cell] = cell;
        heuristic_[cell] = 0;
        queue_[tail++] = cell;
        break;
      case Cell::kFree:
        break;
    }
  }
  if (tail == 0) {
    // No station at all: nothing is reachable (and h is undefined).
    std::fill(out.length.begin(), out.length.end(), kUnreachable);
    return true;
  }
  while (head < tail) {
    const int cell = queue_[head++];
    const int row = cell / cols, col = cell % cols;
    for (int a = 0; a < kNumActions; ++a) {
      const int r = row + kActionRowOffset[a], c = col + kActionColOffset[a];
      if (r < 0 || r >= rows || c < 0 || c >= cols) continue;
      const int neighbour = r * cols + c;
      if (heuristic_[neighbour] >= 0) continue;
      heuristic_[neighbour] = heuristic_[cell] + 1;
      queue_[tail++] = neighbour;
    }
  }

  // Generation stamps make the per-search state valid only where stamped with
  // the current search's generation, so no grid-sized array is cleared per
  // search. A new grid size restarts the stamps.
  if (seen_stamp_.size() != size) {
    g_.assign(size, 0);
    parent_.assign(size, -1);
    seen_stamp_.assign(size, 0);
    closed_stamp_.assign(size, 0);
    generation_ = 0;
  }

  // The report's loop: every start in row-major order that no earlier search
  // has decided gets its own search.
  // One search can cover a whole map (17 s per step at 1024x1024 in all), so
  // a stop request is checked every 256 searches.
  for (int start = 0; start < n; ++start) {
    if (out.length[start] != kUndecided) continue;
    if ((searches_ & 255) == 0 && StopRequested(stop)) {
      for (int cell = start; cell < n; ++cell) {
        if (out.length[cell] == kUndecided) out.length[cell] = kUnreachable;
      }
      return false;
    }
    Search(grid, start, out);
  }
  return true;
}

void AStarPlanner::Search(const Grid& grid, int start, StationPaths& out) {
  const int rows = grid.rows(), cols = grid.cols();
  if (++generation_ == 0) {
    // Wrapped after 2^32 searches: old stamps could alias the new generation.
    std::fill(seen_stamp_.begin(), seen_stamp_.end(), 0u);
    std::fill(closed_stamp_.begin(), closed_stamp_.end(), 0u);
    generation_ = 1;
  }
  const uint32_t generation = generation_;
  ++searches_;
  open_.clear();
  closed_.clear();

  seen_stamp_[start] = generation;
  g_[start] = 0;
  parent_[start] = -1;
  open_.push_back({heuristic_[start], 0, start});
  int goal = -1;
  while (!open_.empty()) {
    std::pop_heap(open_.begin(), open_.end(), OpenAfter{});
    const OpenEntry entry = open_.back();
    open_.pop_back();
    const int cell = entry.cell;
    // A cell may sit in the heap several times (no decrease-key); the first
    // pop is the one with the smallest g.
    if (closed_stamp_[cell] == generation) continue;
    closed_stamp_[cell] = generation;
    closed_.push_back(cell);
    ++expansions_;
    // h is consistent (|h(u) - h(v)| <= 1 = cost(u, v) for neighbours, as
    // the Chebyshev distance to a fixed station changes by at most 1 per
    // 8-connected move, and so does a minimum of such distances), so a cell's
    // g is final when it is closed and the first station closed is a nearest
    // one: that is the goal test.
    if (grid.at(cell) == Cell::kStation) {
      goal = cell;
      break;
    }
    const int row = cell / cols, col = cell % cols;
    const int32_t next_g = entry.g + 1;
    for (int a = 0; a < kNumActions; ++a) {
      // A diagonal move is allowed whatever the two side cells are (SPEC 2).
      const int r = row + kActionRowOffset[a], c = col + kActionColOffset[a];
      if (r < 0 || r >= rows || c < 0 || c >= cols) continue;
      const int neighbour = r * cols + c;
      if (grid.at(neighbour) == Cell::kObstacle || closed_stamp_[neighbour] == generation) continue;
      if (seen_stamp_[neighbour] == generation && g_[neighbour] <= next_g) continue;
      seen_stamp_[neighbour] = generation;
      g_[neighbour] = next_g;
      parent_[neighbour] = cell;
      open_.push_back({next_g + heuristic_[neighbour], next_g, neighbour});
      std::push_heap(open_.begin(), open_.end(), OpenAfter{});
    }
  }

  if (goal < 0) {
    // The heap ran dry: the search closed the whole 8-connected component of
    // `start` (moves are symmetric) and found no station in it, so every cell
    // it closed is unreachable too. Exact, and it spares those cells their
    // own (equally fruitless) searches.
    for (int cell : closed_) out.length[cell] = kUnreachable;
    return;
  }

  // Store the path for the start and every cell on it. A suffix of a
  // shortest path to a nearest station is itself one: for a cell v at i moves
  // from `start` on a path of length d(start), the suffix gives
  // d(v) <= d(start) - i, and d(start) <= i + d(v) because one can walk to v
  // and on to v's nearest station; so d(v) = d(start) - i. A cell that already
  // has a stored path (an earlier search crossed it) keeps it: both are
  // shortest, and the pointers of the cells behind it stay consistent.
  const int32_t total = g_[goal];
  int child = goal;
  for (int cell = parent_[goal]; cell >= 0; child = cell, cell = parent_[cell]) {
    if (out.length[cell] != kUndecided) continue;
    out.length[cell] = total - g_[cell];
    out.next[cell] = child;
  }
}

PolicyScore ScoreStoredPaths(const Grid& current, const StationPaths& paths) {
  const int n = current.size();
  assert(paths.next.size() == static_cast<size_t>(n) && paths.length.size() == paths.next.size());
  // Whether the stored path from a cell is still open in `current`. A cell's
  // answer is its next cell's answer unless the cell itself is blocked, so
  // each cell is resolved once (memoised walk): linear overall.
  enum : uint8_t { kUnknown = 0, kOpen = 1, kBlocked = 2 };
  std::vector<uint8_t> status(static_cast<size_t>(n), kUnknown);
  std::vector<int32_t> walk;
  PolicyScore score;
  for (int start = 0; start < n; ++start) {
    if (current.at(start) == Cell::kObstacle) continue;
    ++score.starts;
    if (paths.length[start] < 0) continue;
    int cell = start;
    while (status[cell] == kUnknown) {
      if (current.at(cell) == Cell::kObstacle || paths.next[cell] < 0) {
        status[cell] = kBlocked;
      } else if (paths.length[cell] == 0) {
        status[cell] = current.at(cell) == Cell::kStation ? kOpen : kBlocked;
      } else {
        walk.push_back(cell);
        cell = paths.next[cell];
      }
    }
    for (int visited : walk) status[visited] = status[cell];
    walk.clear();
    if (status[start] == kOpen) {
      ++score.successes;
      score.total_length += paths.length[start];
    }
  }
  return score;
}

PolicyScore ScoreDistances(const Grid& grid, const std::vector<int32_t>& distance) {
  PolicyScore score;
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (grid.at(cell) == Cell::kObstacle) continue;
    ++score.starts;
    if (distance[cell] != kUnreachable) {
      ++score.successes;
      score.total_length += distance[cell];
    }
  }
  return score;
}

}  // namespace dynapath
