#include "core/plan/convq_planner.h"

#include <array>

#include "core/plan/approach_registry.h"
#include "core/plan/learning_planner.h"
#include "dynapath/mdp.h"

namespace dynapath {

ConvQPlanner::ConvQPlanner(const ConvQModel& model, int leaf_limit)
    : leaf_limit_(leaf_limit), values_(model) {}

// Factory of core/include/dynapath/approach_list.h.
std::unique_ptr<Planner> MakeConvQPlanner(const ApproachSpec&, const PlannerOptions& options,
                                          Trainer*) {
  const ConvQModel& model = options.convq_model ? *options.convq_model : ShippedConvQModel();
  return std::make_unique<ConvQPlanner>(model, options.leaf_limit);
}

void ConvQPlanner::UpdateRows(const Grid& grid, const std::vector<int>& cells, bool all) {
  if (all) {
    for (int cell = 0; cell < grid.size(); ++cell) {
      values_.ActionValues(grid, cell, table_.Row<double>(cell));
    }
    return;
  }
  rows_.clear();
  const auto add = [&](int cell) {
    if (marked_[static_cast<size_t>(cell)]) return;
    marked_[static_cast<size_t>(cell)] = 1;
    rows_.push_back(cell);
  };
  for (int cell : cells) {
    add(cell);
    const int row = grid.RowOf(cell), col = grid.ColOf(cell);
    for (int a = 0; a < kNumActions; ++a) {
      const int r = row + kActionRowOffset[a], c = col + kActionColOffset[a];
      if (grid.InBounds(r, c)) add(grid.Index(r, c));
    }
  }
  for (int cell : rows_) {
    marked_[static_cast<size_t>(cell)] = 0;
    values_.ActionValues(grid, cell, table_.Row<double>(cell));
    const int row = grid.RowOf(cell), col = grid.ColOf(cell);
    evaluation_.TableChanged(Region{row, row, col, col});
  }
}

StepDetails ConvQPlanner::Initialize(const Grid& grid) {
  tree_ = std::make_unique<QuadTree>(grid.rows(), grid.cols(), leaf_limit_);
  table_ = QTable(grid.size(), QPrecision::kDouble);
  marked_.assign(static_cast<size_t>(grid.size()), 0);
  values_.Solve(grid);
  UpdateRows(grid, {}, /*all=*/true);
  evaluation_.Reset(*tree_);
  return {};
}

StepDetails ConvQPlanner::Adapt(const Grid& grid, const std::vector<int>& changed_cells) {
  evaluation_.GridChanged(changed_cells);
  values_.Repair(grid, changed_cells);
  UpdateRows(grid, values_.touched(), /*all=*/false);
  return {};
}

PolicyScore ConvQPlanner::Evaluate(const Grid& grid) {
  return evaluation_.Score(grid, table_, tree_->root());
}

bool ConvQPlanner::Picture(const Grid& grid, PolicyPicture& picture) {
  const std::vector<int32_t>& depth = evaluation_.Depths(grid, table_);
  PictureFromSuccessors(grid, depth, evaluation_.Successors(grid, table_), picture);
  return true;
}

}  // namespace dynapath
