#include "core/plan/incremental_oracle.h"

#include <memory>

#include "core/plan/approach_registry.h"
#include "dynapath/astar_paths.h"

namespace dynapath {

StepDetails IncrementalOraclePlanner::Initialize(const Grid& grid) {
  distances_.Build(GridMoves(grid), /*limit=*/0);
  codes_ = grid.codes();
  marked_.assign(codes_.size(), 0);
  score_ = ScoreDistances(grid, distances_.values());
  return {};
}

void IncrementalOraclePlanner::Count(Cell code, int32_t distance, int sign) {
  if (code == Cell::kObstacle) return;
  score_.starts += sign;
  if (distance != DynamicDistances::kNone) {
    score_.successes += sign;
    score_.total_length += sign * static_cast<int64_t>(distance);
  }
}

StepDetails IncrementalOraclePlanner::Adapt(const Grid& grid,
                                            const std::vector<int>& changed_cells) {
  // Take out the old part of every changed cell, repair, take out the old
  // part of every other cell whose distance changed, then put back the new
  // part of all of them.
  touched_.clear();
  for (int cell : changed_cells) {
    if (marked_[cell]) continue;
    marked_[cell] = 1;
    touched_.push_back(cell);
    Count(static_cast<Cell>(codes_[cell]), distances_.value(cell), -1);
  }
  distances_.Repair(GridMoves(grid), changed_cells);
  for (const DynamicDistances::ValueChange& change : distances_.changes()) {
    if (marked_[change.node]) continue;
    marked_[change.node] = 1;
    touched_.push_back(change.node);
    Count(static_cast<Cell>(codes_[change.node]), change.old_value, -1);
  }
  for (int cell : touched_) {
    marked_[cell] = 0;
    codes_[cell] = static_cast<uint8_t>(grid.at(cell));
    Count(grid.at(cell), distances_.value(cell), +1);
  }
  return {};
}

PolicyScore IncrementalOraclePlanner::Evaluate(const Grid& /*grid*/) { return score_; }

// Factory of core/include/dynapath/approach_list.h.
std::unique_ptr<Planner> MakeIncrementalOraclePlanner(const ApproachSpec&, const PlannerOptions&,
                                                      Trainer*) {
  return std::make_unique<IncrementalOraclePlanner>();
}

}  // namespace dynapath
