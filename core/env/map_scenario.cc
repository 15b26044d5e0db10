#include "dynapath/map_scenario.h"

#include <array>
#include <charconv>
#include <cmath>

#include "dynapath/mdp.h"
#include "dynapath/scenario.h"
#include "dynapath/text_file.h"
#include "dynapath/text_util.h"

namespace dynapath {

int CellCount::Resolve(int free_cells) const {
  if (percent < 0.0) return static_cast<int>(count);
  if (percent == 0.0) return 0;
  const long long n = std::llround(percent / 100.0 * free_cells);
  return static_cast<int>(n < 1 ? 1 : n);
}

Result<CellCount> ParseCellCount(const std::string& text) {
  const std::string t = Trim(text);
  CellCount result;
  if (!t.empty() && t.back() == '%') {
    const std::string number = t.substr(0, t.size() - 1);
    char* end = nullptr;
    const double percent = std::strtod(number.c_str(), &end);
    if (number.empty() || end != number.c_str() + number.size() || !(percent >= 0.0) ||
        percent > 100.0) {
      return Error{"expected a count N or a percentage P% (0 to 100), got '" + text + "'"};
    }
    result.percent = percent;
    return result;
  }
  long long count = 0;
  const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), count);
  if (t.empty() || error != std::errc{} || end != t.data() + t.size() || count < 0 ||
      count > 100'000'000) {
    return Error{"expected a count N or a percentage P% (0 to 100), got '" + text + "'"};
  }
  result.count = count;
  return result;
}

Result<std::vector<int>> PlaceOnFreeCells(Grid& grid, int count, Cell code, CRandom& random) {
  std::vector<int> free;
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (grid.at(cell) == Cell::kFree) free.push_back(cell);
  }
  if (count > static_cast<int>(free.size())) {
    return Error{"asked for " + std::to_string(count) + " cells, the map has only " +
                 std::to_string(free.size()) + " free cells"};
  }
  // Partial Fisher-Yates over the row-major list of free cells.
  std::vector<int> placed;
  placed.reserve(static_cast<size_t>(count));
  for (int k = 0; k < count; ++k) {
    const size_t remaining = free.size() - static_cast<size_t>(k);
    const size_t pick = static_cast<size_t>(k) + static_cast<size_t>(random.Next()) % remaining;
    std::swap(free[static_cast<size_t>(k)], free[pick]);
    placed.push_back(free[static_cast<size_t>(k)]);
    grid.set(placed.back(), code);
  }
  return placed;
}

Result<std::vector<int>> ParseStationsFile(std::string_view bytes, const Grid& grid) {
  std::vector<int> stations;
  std::vector<uint8_t> seen(static_cast<size_t>(grid.size()), 0);
  size_t pos = 0;
  int number = 0;
  while (pos < bytes.size()) {
    const size_t end = bytes.find('\n', pos);
    std::string_view line =
        bytes.substr(pos, (end == std::string_view::npos ? bytes.size() : end) - pos);
    pos = end == std::string_view::npos ? bytes.size() : end + 1;
    ++number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    // Spaces and tabs separate and surround the two numbers, in any amount.
    auto blank = [](char c) { return c == ' ' || c == '\t'; };
    while (!line.empty() && blank(line.front())) line.remove_prefix(1);
    while (!line.empty() && blank(line.back())) line.remove_suffix(1);
    if (line.empty() || line[0] == '#') continue;
    const std::string where = "line " + std::to_string(number) + ": ";
    int row = 0, col = 0;
    const char* stop = line.data() + line.size();
    auto [after_row, e1] = std::from_chars(line.data(), stop, row);
    if (e1 != std::errc{} || after_row == stop || !blank(*after_row)) {
      return Error::Corrupt(where + "expected 'row col'");
    }
    const char* col_start = after_row;
    while (col_start != stop && blank(*col_start)) ++col_start;
    auto [after_col, e2] = std::from_chars(col_start, stop, col);
    if (e2 != std::errc{} || after_col != stop) return Error::Corrupt(where + "expected 'row col'");
    if (!grid.InBounds(row, col)) {
      return Error::Corrupt(where + "(" + std::to_string(row) + ", " + std::to_string(col) +
                            ") is outside the " + std::to_string(grid.rows()) + "x" +
                            std::to_string(grid.cols()) + " map");
    }
    const int cell = grid.Index(row, col);
    if (grid.at(cell) == Cell::kObstacle) {
      return Error::Corrupt(where + "(" + std::to_string(row) + ", " + std::to_string(col) +
                            ") is an obstacle");
    }
    if (seen[cell]) return Error::Corrupt(where + "station given twice");
    seen[cell] = 1;
    stations.push_back(cell);
  }
  if (stations.empty()) return Error::Corrupt("no station in the station file");
  return stations;
}

Result<std::vector<int>> LoadStationsFile(const std::string& path, const Grid& grid) {
  Result<std::string> text = ReadTextFile(path);
  if (!text) return text.error();
  Result<std::vector<int>> stations = ParseStationsFile(*text, grid);
  if (!stations) return stations.error().Prefixed(path + ": ");
  return stations;
}

ChangeSequence GenerateMoverChanges(const Grid& initial, std::vector<int> movers, int steps,
                                    CRandom& random) {
  Grid grid = initial;
  ChangeSequence sequence;
  sequence.steps.resize(static_cast<size_t>(steps));
  if (movers.empty()) return sequence;  // nothing can move: no draws, no moves
  for (ChangeStep& step : sequence.steps) {
    step.requested_moves = DrawMoveCount(random);
    for (int move = 0; move < step.requested_moves && !movers.empty(); ++move) {
      MoveOneObstacle(grid, movers, random, step);
    }
  }
  return sequence;
}

}  // namespace dynapath
