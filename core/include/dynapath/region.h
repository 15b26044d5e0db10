#pragma once
// An inclusive rectangle of grid cells, rows r0..r1 and cols c0..c1.

namespace dynapath {

struct Region {
  int r0 = 0, r1 = -1, c0 = 0, c1 = -1;

  int rows() const { return r1 - r0 + 1; }
  int cols() const { return c1 - c0 + 1; }
  int cells() const { return rows() * cols(); }
  bool empty() const { return r1 < r0 || c1 < c0; }
  bool Contains(int row, int col) const { return row >= r0 && row <= r1 && col >= c0 && col <= c1; }
  // Row-major index of (row, col) inside the region.
  int LocalIndex(int row, int col) const { return (row - r0) * cols() + (col - c0); }
  bool operator==(const Region&) const = default;
};

}  // namespace dynapath
