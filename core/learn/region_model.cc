#include "core/learn/region_model.h"

#include <cassert>
#include <stdexcept>

namespace dynapath {

RegionModel::RegionModel(const Region& region, const std::vector<uint8_t>& codes, int grid_rows,
                         int grid_cols, Bootstrap bootstrap)
    : region_(region),
      grid_rows_(grid_rows > 0 ? grid_rows : region.r1 + 1),
      grid_cols_(grid_cols > 0 ? grid_cols : region.c1 + 1),
      bootstrap_(bootstrap),
      codes_(codes) {
  assert(static_cast<int>(codes_.size()) == region_.cells());
  Build();
}

RegionModel::RegionModel(const TrainingJob& job)
    : RegionModel(job.region, job.codes, job.grid_rows, job.grid_cols, job.bootstrap) {}

RegionModel::RegionModel(const Grid& grid, const Region& region, Bootstrap bootstrap)
    : RegionModel(region, RegionCodes(grid, region), grid.rows(), grid.cols(), bootstrap) {}

void RegionModel::Build() {
  const int rows = region_.rows(), cols = region_.cols();
  const int n = region_.cells();
  for (int a = 0; a < kNumActions; ++a)
    offset_[a] = kActionRowOffset[a] * cols + kActionColOffset[a];
  record_.assign(static_cast<size_t>(n), CellRecord{});
  start_cells_.clear();
  in_region_count_.assign(static_cast<size_t>(n), 0);
  step_delta_.assign(static_cast<size_t>(n) * kNumActions, 0);
  for (int cell = 0; cell < n; ++cell) {
    CellRecord& record = record_[cell];
    const int row = cell / cols, col = cell % cols;
    for (int a = 0; a < kNumActions; ++a) {
      const uint8_t bit = static_cast<uint8_t>(1 << a);
      const int r = row + kActionRowOffset[a], c = col + kActionColOffset[a];
      const int grid_r = region_.r0 + r, grid_c = region_.c0 + c;
      const bool in_grid = grid_r >= 0 && grid_r < grid_rows_ && grid_c >= 0 && grid_c < grid_cols_;
      if (bootstrap_ == Bootstrap::kAllStored || (in_grid && bootstrap_ == Bootstrap::kInGrid)) {
        record.bootstrap |= bit;
      }
      if (r < 0 || r >= rows || c < 0 || c >= cols) continue;
      record.in_region |= bit;
      record.bootstrap |= bit;
      const int next = r * cols + c;
      const bool blocked = static_cast<Cell>(codes_[next]) == Cell::kObstacle;
      if (!blocked) record.moves |= bit;
      // +100 when the cell the agent ends on is a station, even if it stayed.
      if (static_cast<Cell>(codes_[blocked ? cell : next]) == Cell::kStation) record.station |= bit;
    }
    if (static_cast<Cell>(codes_[cell]) != Cell::kObstacle) start_cells_.push_back(cell);
    const auto& list = region_model_internal::kActionLists[record.in_region];
    in_region_count_[cell] = list.count;
    for (int i = 0; i < list.count; ++i) {
      step_delta_[static_cast<size_t>(cell) * kNumActions + i] =
          static_cast<int16_t>(target(cell, list.actions[i]) - cell);
    }
  }
}

std::vector<uint8_t> RegionCodes(const Grid& grid, const Region& region) {
  if (region.empty()) return {};
  // Regions are quadtree nodes of this grid (MakeTrainingJob) or were
  // validated against their grid on arrival (protocol/validate.cc).
  assert(grid.InBounds(region.r0, region.c0) && grid.InBounds(region.r1, region.c1));
  std::vector<uint8_t> codes;
  codes.reserve(static_cast<size_t>(region.cells()));
  const std::vector<uint8_t>& all = grid.codes();
  for (int r = region.r0; r <= region.r1; ++r) {
    const auto first = all.begin() + grid.Index(r, region.c0);
    codes.insert(codes.end(), first, first + region.cols());
  }
  return codes;
}

}  // namespace dynapath
