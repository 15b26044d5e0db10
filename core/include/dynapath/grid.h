#pragma once
// The environment: a rows x cols grid of cells, stored row-major.

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "dynapath/result.h"

namespace dynapath {

// Cell codes of SPEC section 1; the numeric values are part of the file and
// message formats.
enum class Cell : uint8_t { kObstacle = 0, kFree = 1, kStation = 2 };

// Text form of a cell: '#', '.', 'C'.
char CellChar(Cell cell);

class Grid {
 public:
  Grid() = default;
  // A grid of the given size, every cell `fill`. rows, cols >= 1.
  Grid(int rows, int cols, Cell fill = Cell::kFree);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  int size() const { return rows_ * cols_; }

  int Index(int row, int col) const { return row * cols_ + col; }
  int RowOf(int index) const { return index / cols_; }
  int ColOf(int index) const { return index % cols_; }
  bool InBounds(int row, int col) const {
    return row >= 0 && row < rows_ && col >= 0 && col < cols_;
  }

  Cell at(int index) const { return static_cast<Cell>(cells_[index]); }
  Cell at(int row, int col) const { return at(Index(row, col)); }
  void set(int index, Cell cell) { cells_[index] = static_cast<uint8_t>(cell); }
  void set(int row, int col, Cell cell) { set(Index(row, col), cell); }

  // Raw codes, row-major (for messages and hashing).
  const std::vector<uint8_t>& codes() const { return cells_; }

  // Number of cells holding `cell`.
  int Count(Cell cell) const;

  bool operator==(const Grid& other) const = default;

 private:
  int rows_ = 0;
  int cols_ = 0;
  std::vector<uint8_t> cells_;
};

// Text format: one line per row of '#', '.', 'C'; all rows the same length;
// blank lines and lines starting with ';' are ignored.
std::string GridToText(const Grid& grid);
Result<Grid> GridFromText(const std::string& text);
Status SaveGrid(const Grid& grid, const std::string& path);
Result<Grid> LoadGrid(const std::string& path);

}  // namespace dynapath
