#pragma once
// Obstacle changes over time (SPEC section 1): per time step, the list of
// cells whose code changes, in the order the changes happened.

#include <cstdint>
#include <string>
#include <vector>

#include "dynapath/grid.h"
#include "dynapath/result.h"

namespace dynapath {

struct CellChange {
  int cell;   // row-major index in the grid
  Cell code;  // the cell's new code
  bool operator==(const CellChange&) const = default;
};

struct ChangeStep {
  // Obstacle moves the generator asked for (the report's NumChanges column);
  // a move is skipped when the chosen obstacle has no free neighbour.
  int requested_moves = 0;
  std::vector<CellChange> changes;
  bool operator==(const ChangeStep&) const = default;
};

struct ChangeSequence {
  std::vector<ChangeStep> steps;
  bool operator==(const ChangeSequence&) const = default;
};

// Applies one step's changes to `grid` in order.
void ApplyChanges(const ChangeStep& step, Grid& grid);

// Change-file format (text, one time step per line):
//   dynapath-changes 1 <rows> <cols> <steps>
//   <requested_moves> <n> <cell> <code> <cell> <code> ...
// `cell` is the row-major index, `code` 0 (obstacle), 1 (free) or 2 (station).
std::string ChangesToText(const ChangeSequence& sequence, int rows, int cols);
// Parses and checks the sequence against a grid of rows x cols.
Result<ChangeSequence> ChangesFromText(const std::string& text, int rows, int cols);
Status SaveChanges(const ChangeSequence& sequence, int rows, int cols, const std::string& path);
Result<ChangeSequence> LoadChanges(const std::string& path, int rows, int cols);

}  // namespace dynapath
