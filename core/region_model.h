#pragma once
// The in-region MDP a learner trains on (SPEC sections 2 and 6-7): for every
// cell of a region, the actions whose target lies inside the region, where
// each leads and what it pays. Built once per training job from the region's
// cell codes; immutable afterwards and safe to share between threads.

#include <cstdint>
#include <vector>

#include "core/grid.h"
#include "core/mdp.h"
#include "core/region.h"

namespace dynapath {

class RegionModel {
 public:
  // `codes`: the region's cell codes, region-local row-major (region.cells()).
  RegionModel(const Region& region, const std::vector<uint8_t>& codes);
  // Convenience: the region cut out of a grid.
  RegionModel(const Grid& grid, const Region& region);

  const Region& region() const { return region_; }
  int cells() const { return region_.cells(); }
  Cell code(int cell) const { return static_cast<Cell>(codes_[cell]); }
  bool is_station(int cell) const { return code(cell) == Cell::kStation; }

  // In-region actions of `cell` in increasing order.
  int action_count(int cell) const { return action_count_[cell]; }
  const uint8_t* actions(int cell) const { return &actions_[static_cast<size_t>(cell) * kNumActions]; }

  // Cell reached by action `a` from `cell` (the cell itself when blocked by an
  // obstacle), and its reward. Only meaningful for in-region actions.
  int target(int cell, int a) const { return target_[static_cast<size_t>(cell) * kNumActions + a]; }
  float reward(int cell, int a) const { return reward_[static_cast<size_t>(cell) * kNumActions + a]; }

  // Non-obstacle cells in increasing order: the possible start cells.
  const std::vector<int>& start_cells() const { return start_cells_; }

  // The region's cell codes, region-local row-major.
  const std::vector<uint8_t>& codes() const { return codes_; }

 private:
  void Build();

  Region region_;
  std::vector<uint8_t> codes_;
  std::vector<uint8_t> action_count_;
  std::vector<uint8_t> actions_;
  std::vector<int32_t> target_;
  std::vector<float> reward_;
  std::vector<int> start_cells_;
};

// Cuts a region's codes out of a grid, region-local row-major.
std::vector<uint8_t> RegionCodes(const Grid& grid, const Region& region);

}  // namespace dynapath
