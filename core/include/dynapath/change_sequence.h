#pragma once
// Obstacle changes over time (SPEC section 1): per time step, the list of
// cells whose code changes, in the order the changes happened.

#include <cstdint>
#include <optional>
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

// The maze a change sequence was made for, as a change file records it:
// 64-bit FNV-1a over rows and cols (4 bytes each, little-endian) and then
// one byte per cell, its code (0 obstacle, 1 free, 2 station), row-major.
// Two mazes of one size with any cell or station different differ.
uint64_t MazeFingerprint(const Grid& grid);
// 16 lower-case hex digits.
std::string FingerprintText(uint64_t fingerprint);

// Change-file format (text, one time step per line), version 2:
//   dynapath-changes 2 <rows> <cols> <steps> <fingerprint>
//   <requested_moves> <n> <cell> <code> <cell> <code> ...
// `fingerprint` is MazeFingerprint of the maze at time step 0 (16 hex
// digits), `cell` the row-major index, `code` 0 (obstacle), 1 (free) or
// 2 (station). Version 1 files (the same without the fingerprint) are read.
std::string ChangesToText(const ChangeSequence& sequence, const Grid& initial);

// What a change file's header says.
struct ChangeFileHeader {
  int version = 0;
  int rows = 0, cols = 0;
  std::optional<uint64_t> fingerprint;  // none in version 1
};
// Parses and checks the sequence against a grid of rows x cols; `header`
// (may be null) gets the header. Memory stays proportional to the text.
Result<ChangeSequence> ChangesFromText(const std::string& text, int rows, int cols,
                                       ChangeFileHeader* header = nullptr);
// Applies the sequence to a copy of `initial`, checking every change against
// the grid as it is then: a change may not create or remove a station, free
// a cell that holds no obstacle, or put an obstacle on one that holds one.
// The error names the time step, the change and the cell.
Status CheckChangesFit(const ChangeSequence& sequence, const Grid& initial);
Status SaveChanges(const ChangeSequence& sequence, const Grid& initial, const std::string& path);
Result<ChangeSequence> LoadChanges(const std::string& path, int rows, int cols,
                                   ChangeFileHeader* header = nullptr);

}  // namespace dynapath
