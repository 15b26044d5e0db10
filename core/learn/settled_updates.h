#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/learners.h"
#endif
// Which Q-learning updates of a region are known to be no-ops, so that the
// single-agent learner's experience replay can skip them (SPEC section 6:
// 64 replayed updates after every real step, most of them re-applying an
// update that no longer changes anything).
//
// An update of entry s * 8 + a is a pure function of Q(s, a) and of the row
// Q(s', .) of its target s' (the reward is fixed). Once an application left
// Q(s, a) bit for bit unchanged, it is *settled*: applying it again changes
// nothing until Q(s, a) or a value of row s' is written. Only updates write
// values, and an update that changes Q(s, a) unsettles every entry whose
// target is s (RowChanged). Skipping settled updates therefore leaves the
// table exactly as applying them would.
//
// It also counts the entries of the replay buffer that are not settled: when
// there are none, a whole replay batch is a no-op and only the random draws
// that would have picked its entries need to be made.

#include <cstdint>
#include <vector>

#include "core/learn/region_model.h"

namespace dynapath {

class SettledUpdates {
 public:
  // Every entry starts unsettled (the table is new to the learner).
  explicit SettledUpdates(const RegionModel& model);

  bool settled(uint32_t entry) const { return settled_[entry] != 0; }
  // Its last application left the value unchanged.
  void MarkSettled(uint32_t entry) {
    if (settled_[entry]) return;
    settled_[entry] = 1;
    if (in_buffer_[entry] != 0) --unsettled_in_buffer_;
  }
  // A value of row `cell` changed: the updates reading it may change again.
  void RowChanged(int cell) {
    for (int32_t i = first_[cell]; i < first_[cell + 1]; ++i) {
      const uint32_t entry = predecessors_[i];
      if (!settled_[entry]) continue;
      settled_[entry] = 0;
      if (in_buffer_[entry] != 0) ++unsettled_in_buffer_;
    }
  }
  // The replay buffer gained / lost one copy of `entry`.
  void Added(uint32_t entry) {
    if (in_buffer_[entry]++ == 0 && !settled_[entry]) ++unsettled_in_buffer_;
  }
  void Removed(uint32_t entry) {
    if (--in_buffer_[entry] == 0 && !settled_[entry]) --unsettled_in_buffer_;
  }
  // True when every entry in the replay buffer is settled.
  bool BufferSettled() const { return unsettled_in_buffer_ == 0; }

 private:
  // uint32_t, not uint8_t: a char store may alias anything, which would keep
  // the learner's generator state in memory instead of registers.
  std::vector<uint32_t> settled_;       // per entry
  std::vector<uint32_t> in_buffer_;     // per entry: copies in the replay buffer
  std::vector<int32_t> first_;          // per cell + 1: CSR offsets into predecessors_
  std::vector<uint32_t> predecessors_;  // entries (in-region actions) by target cell
  int64_t unsettled_in_buffer_ = 0;     // distinct entries
};

}  // namespace dynapath
