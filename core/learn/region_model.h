#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/learners.h"
#endif
// The in-region MDP a learner trains on (SPEC sections 2 and 6-7): for every
// cell of a region, the actions whose target lies inside the region, where
// each leads and what it pays. Built once per training job from the region's
// cell codes; immutable afterwards and safe to share between threads.

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include <array>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "dynapath/grid.h"
#include "dynapath/mdp.h"
#include "dynapath/region.h"
#include "dynapath/training_job.h"

namespace dynapath {

namespace region_model_internal {
// kActionMasks[bits][a]: 0 when bit a of `bits` is set, -infinity otherwise.
inline constexpr auto kActionMasks = [] {
  std::array<std::array<float, kNumActions>, 256> masks{};
  for (int bits = 0; bits < 256; ++bits) {
    for (int a = 0; a < kNumActions; ++a) {
      masks[bits][a] = (bits >> a) & 1 ? 0.0f : -std::numeric_limits<float>::infinity();
    }
  }
  return masks;
}();
// kActionLists[bits]: the set bits of `bits` in increasing order.
struct ActionList {
  std::array<uint8_t, kNumActions> actions;
  uint8_t count;
};
inline constexpr auto kActionLists = [] {
  std::array<ActionList, 256> lists{};
  for (int bits = 0; bits < 256; ++bits) {
    for (int a = 0; a < kNumActions; ++a) {
      if ((bits >> a) & 1) lists[bits].actions[lists[bits].count++] = static_cast<uint8_t>(a);
    }
  }
  return lists;
}();
}  // namespace region_model_internal

class RegionModel {
 public:
  // `codes`: the region's cell codes, region-local row-major (region.cells()).
  // `grid_rows` x `grid_cols` is the whole grid (0 x 0: the region is the
  // grid); it decides which actions the bootstrap max ranges over.
  RegionModel(const Region& region, const std::vector<uint8_t>& codes, int grid_rows = 0,
              int grid_cols = 0, Bootstrap bootstrap = Bootstrap::kInGrid);
  // The model of a training job.
  explicit RegionModel(const TrainingJob& job);
  // Convenience: the region cut out of a grid.
  RegionModel(const Grid& grid, const Region& region, Bootstrap bootstrap = Bootstrap::kInGrid);

  const Region& region() const { return region_; }
  int cells() const { return region_.cells(); }
  Cell code(int cell) const { return static_cast<Cell>(codes_[cell]); }
  bool is_station(int cell) const { return code(cell) == Cell::kStation; }

  // In-region actions of `cell` in increasing order.
  int action_count(int cell) const {
    return region_model_internal::kActionLists[record_[cell].in_region].count;
  }
  const uint8_t* actions(int cell) const {
    return region_model_internal::kActionLists[record_[cell].in_region].actions.data();
  }

  // The learners' random walk, one dependent load shorter: the number of
  // in-region actions of `cell`, and the cell reached by its `index`-th
  // in-region action (index < in_region_count(cell)). The walk's next cell
  // then waits for two loads (count, then move) instead of four (record,
  // action list, action, offset).
  int in_region_count(int cell) const { return in_region_count_[cell]; }
  int step_target(int cell, int index) const {
    return cell + step_delta_[static_cast<size_t>(cell) * kNumActions + index];
  }

  // Cell reached by action `a` from `cell` (the cell itself when blocked by an
  // obstacle), and its reward. Only meaningful for in-region actions.
  int target(int cell, int a) const {
    // Without a branch: whether a random walk's move is blocked is
    // unpredictable, and a mispredicted branch costs more than the mask.
    const int moves = static_cast<int>((record_[cell].moves >> a) & 1u);
    return cell + (offset_[a] & -moves);
  }
  float reward(int cell, int a) const {
    // By (in region, ends on a station, moves): 0 out of the region, else
    // +100 on a station, -1 for a move, -10 for a bump (no branch: the
    // learners' hot loop).
    static constexpr float kRewards[8] = {0.0f, kBumpReward, 0.0f, kStationReward,
                                          0.0f, kStepReward, 0.0f, kStationReward};
    const CellRecord& record = record_[cell];
    const unsigned index = ((record.in_region >> a) & 1u) | (((record.station >> a) & 1u) << 1) |
                           (((record.moves >> a) & 1u) << 2);
    return kRewards[index];
  }

  // 8 floats: 0 for the in-region actions of `cell`, -infinity for the
  // others, so that max_a (q[a] + mask[a]) is the in-region maximum without
  // branches (the learners' hot loop). Cells with no in-region action (1x1
  // regions) give -infinity.
  const float* action_mask(int cell) const {
    return region_model_internal::kActionMasks[record_[cell].in_region].data();
  }

  // The bootstrap term max_a' Q(s', a') of every update: the maximum of
  // q_row[a] (the cell's 8 values) over the cell's bootstrap actions, i.e.
  // its in-grid actions (Bootstrap::kInGrid), its in-region actions, or all
  // 8 (Bootstrap::kAllStored). V: the table's value type (q_table.h).
  template <typename V>
  V BootstrapMax(int cell, const V* q_row) const {
    const float* mask = region_model_internal::kActionMasks[record_[cell].bootstrap].data();
    // A balanced tree of maxima: m[i] = max(x[i], x[i + 4]), then
    // max(max(m0, m2), max(m1, m3)), each max(x, y) = x < y ? y : x, which is
    // what SSE's _mm_max_ps(y, x) computes (the compiler does not vectorise
    // it by itself: it was about 30 scalar instructions of a learner's step).
#if defined(__SSE__)
    if constexpr (std::is_same_v<V, float>) {
      const __m128 low = _mm_add_ps(_mm_loadu_ps(q_row), _mm_loadu_ps(mask));
      const __m128 high = _mm_add_ps(_mm_loadu_ps(q_row + 4), _mm_loadu_ps(mask + 4));
      const __m128 m = _mm_max_ps(high, low);                                     // m0 m1 m2 m3
      const __m128 halves = _mm_max_ps(_mm_movehl_ps(m, m), m);                   // left right . .
      const __m128 best = _mm_max_ss(_mm_shuffle_ps(halves, halves, 1), halves);  // right vs left
      return _mm_cvtss_f32(best);
    }
#endif
    // The same tree in scalar code (doubles, or no SSE). The masks are 0 or
    // -infinity, exact in either type.
    V m[4];
    for (int i = 0; i < 4; ++i) {
      const V x = q_row[i] + static_cast<V>(mask[i]);
      const V y = q_row[i + 4] + static_cast<V>(mask[i + 4]);
      m[i] = x < y ? y : x;
    }
    const V left = m[0] < m[2] ? m[2] : m[0];
    const V right = m[1] < m[3] ? m[3] : m[1];
    return left < right ? right : left;
  }

  // Non-obstacle cells in increasing order: the possible start cells.
  const std::vector<int>& start_cells() const { return start_cells_; }

  // The region's cell codes, region-local row-major.
  const std::vector<uint8_t>& codes() const { return codes_; }

 private:
  // Everything a step reads about a cell, as 8-bit action masks (4 bytes a
  // cell): a 1000x1000 region's records take 4 MB, where 64-byte records
  // with explicit targets and rewards took 64 MB. Targets are cell +
  // offset_[a] for a move, the cell itself otherwise; rewards follow from
  // the masks (mdp.h).
  struct CellRecord {
    uint8_t in_region;  // bit a: action a stays in the region
    uint8_t bootstrap;  // bit a: action a counts in the bootstrap max
    uint8_t moves;      // bit a: in-region action a moves (its target is no obstacle)
    uint8_t station;    // bit a: in-region action a ends on a station (+100)
  };
  static_assert(sizeof(CellRecord) == 4);

  void Build();

  Region region_;
  int grid_rows_, grid_cols_;
  Bootstrap bootstrap_;
  std::array<int32_t, kNumActions> offset_{};  // region-local index change of each action
  std::vector<uint8_t> codes_;
  std::vector<CellRecord> record_;
  // Per cell: its in-region action count, and target - cell of each of its
  // in-region actions in increasing order (|delta| <= cols + 1 <= 4097 fits
  // 16 bits): 17 bytes a cell, 17 MB at a million cells.
  std::vector<uint8_t> in_region_count_;
  std::vector<int16_t> step_delta_;
  std::vector<int> start_cells_;
};

// Cuts a region's codes out of a grid, region-local row-major.
std::vector<uint8_t> RegionCodes(const Grid& grid, const Region& region);

}  // namespace dynapath
