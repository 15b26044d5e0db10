#include "dynapath/grid.h"

#include <algorithm>
#include <sstream>

#include "dynapath/limits.h"
#include "dynapath/text_file.h"

namespace dynapath {

char CellChar(Cell cell) {
  switch (cell) {
    case Cell::kObstacle:
      return '#';
    case Cell::kFree:
      return '.';
    case Cell::kStation:
      return 'C';
  }
  return '?';
}

Grid::Grid(int rows, int cols, Cell fill)
    : rows_(rows),
      cols_(cols),
      cells_(static_cast<size_t>(rows) * cols, static_cast<uint8_t>(fill)) {}

int Grid::Count(Cell cell) const {
  return static_cast<int>(std::count(cells_.begin(), cells_.end(), static_cast<uint8_t>(cell)));
}

std::string GridToText(const Grid& grid) {
  std::string text;
  text.reserve(static_cast<size_t>(grid.rows()) * (grid.cols() + 1));
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) text.push_back(CellChar(grid.at(r, c)));
    text.push_back('\n');
  }
  return text;
}

Result<Grid> GridFromText(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == ';') continue;
    for (size_t i = 0; i < line.size(); ++i) {
      const char ch = line[i];
      if (ch != '#' && ch != '.' && ch != 'C') {
        return Error::Corrupt("line " + std::to_string(line_number) + ", column " +
                              std::to_string(i + 1) + ": unexpected character '" +
                              std::string(1, ch) + "' (expected '#', '.' or 'C')");
      }
    }
    if (!lines.empty() && line.size() != lines.front().size()) {
      return Error::Corrupt("line " + std::to_string(line_number) + " has " +
                            std::to_string(line.size()) + " cells, the first row has " +
                            std::to_string(lines.front().size()));
    }
    lines.push_back(line);
  }
  if (lines.empty()) return Error::Corrupt("the maze has no rows");
  constexpr size_t kMaxSide = kMaxGridSide;
  if (lines.size() > kMaxSide || lines.front().size() > kMaxSide) {
    return Error::Corrupt("the maze is larger than " + std::to_string(kMaxGridSide) +
                          " cells on a side");
  }
  Grid grid(static_cast<int>(lines.size()), static_cast<int>(lines.front().size()));
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) {
      const char ch = lines[r][c];
      grid.set(r, c, ch == '#' ? Cell::kObstacle : ch == 'C' ? Cell::kStation : Cell::kFree);
    }
  }
  return grid;
}

Status SaveGrid(const Grid& grid, const std::string& path) {
  return WriteTextFileAtomically(path, GridToText(grid));
}

Result<Grid> LoadGrid(const std::string& path) {
  Result<std::string> text = ReadTextFile(path);
  if (!text) return text.error();
  Result<Grid> grid = GridFromText(*text);
  if (!grid) return grid.error().Prefixed(path + ": ");
  return grid;
}

}  // namespace dynapath
