#include "dynapath/fleet_validator.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <unordered_map>
#include <utility>

namespace dynapath {

void JointMoveReport::Add(const JointMoveReport& other) {
  out_of_bounds += other.out_of_bounds;
  onto_obstacle += other.onto_obstacle;
  not_adjacent += other.not_adjacent;
  vertex += other.vertex;
  swap += other.swap;
  crossing += other.crossing;
  delay += other.delay;
  overrun += other.overrun;
}

JointMoveReport CheckJointMove(const Grid& grid, const std::vector<int>& before,
                               const std::vector<int>& after, const std::vector<uint8_t>& delayed) {
  JointMoveReport report;
  const size_t n = std::min(before.size(), after.size());
  report.out_of_bounds += static_cast<int64_t>(std::max(before.size(), after.size()) - n);
  auto inside = [&](int cell) { return cell >= 0 && cell < grid.size(); };
  // Moves by (from, to) pair, for swaps and crossings, over robots whose
  // both cells are inside the grid.
  std::map<std::pair<int, int>, int64_t> moves;
  std::unordered_map<int, int64_t> ends;
  for (size_t i = 0; i < n; ++i) {
    const int from = before[i], to = after[i];
    if (!inside(from) || !inside(to)) {
      ++report.out_of_bounds;
      continue;
    }
    if (++ends[to] > 1) ++report.vertex;
    if (from == to) {
      if (grid.at(to) == Cell::kObstacle) ++report.overrun;
      continue;
    }
    if (i < delayed.size() && delayed[i]) ++report.delay;
    if (grid.at(to) == Cell::kObstacle) ++report.onto_obstacle;
    const int dr = grid.RowOf(to) - grid.RowOf(from);
    const int dc = grid.ColOf(to) - grid.ColOf(from);
    if (std::abs(dr) > 1 || std::abs(dc) > 1) ++report.not_adjacent;
    moves[{from, to}] += 1;
  }
  for (const auto& [move, count] : moves) {
    const auto [from, to] = move;
    // Each swapping pair is seen from both ends: count it from the lower.
    if (from < to) {
      auto back = moves.find({to, from});
      if (back != moves.end()) report.swap += std::min(count, back->second);
    }
    const int fr = grid.RowOf(from), fc = grid.ColOf(from);
    const int tr = grid.RowOf(to), tc = grid.ColOf(to);
    if (std::abs(tr - fr) != 1 || std::abs(tc - fc) != 1) continue;
    // The other diagonal of the square, in either direction; counted from
    // the move whose origin is the smaller index.
    const int a = grid.Index(fr, tc), b = grid.Index(tr, fc);
    for (const auto& other : {std::pair{a, b}, std::pair{b, a}}) {
      auto crossing = moves.find(other);
      if (crossing != moves.end() && from < other.first)
        report.crossing += count * crossing->second;
    }
  }
  return report;
}

}  // namespace dynapath
