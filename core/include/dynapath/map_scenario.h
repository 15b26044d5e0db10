#pragma once
// Scenarios on loaded maps: stations placed on a map that has
// none, and moving obstacles ("movers") among static walls. Everything is
// drawn from one C-library stream seeded with the run's seed, so a seed
// gives the same stations, movers and moves in every mode.
//
// The report's own mazes do not use this: their generator (scenario.h), in
// which every obstacle may move, stays exactly as it was.

#include <string>
#include <string_view>
#include <vector>

#include "dynapath/c_random.h"
#include "dynapath/change_sequence.h"
#include "dynapath/grid.h"
#include "dynapath/result.h"

namespace dynapath {

// A count of cells: "N" or a percentage of the free cells "P%" (rounded,
// at least 1 when P > 0).
struct CellCount {
  long long count = 0;
  double percent = -1.0;  // >= 0 when given as a percentage
  int Resolve(int free_cells) const;
};
Result<CellCount> ParseCellCount(const std::string& text);

// Turns `count` free cells, drawn uniformly from `random`, into `code`;
// returns them in drawing order. Error when there are fewer free cells.
Result<std::vector<int>> PlaceOnFreeCells(Grid& grid, int count, Cell code, CRandom& random);

// Station file: one "row col" per line (0-based), blank lines and lines
// starting with '#' ignored. Every cell must be inside the map and passable.
// Bytes in, so it can be fuzzed; at most one station per cell.
Result<std::vector<int>> ParseStationsFile(std::string_view bytes, const Grid& grid);
Result<std::vector<int>> LoadStationsFile(const std::string& path, const Grid& grid);

// `steps` time steps in which only `movers` move (walls never do), with the
// report's distribution of moves per step (1 to 10, same skew) and its
// neighbour rule (a mover steps to one of its free 8-neighbours, chosen
// uniformly; a mover without one skips its move). Without movers every step
// is empty (0 moves requested).
ChangeSequence GenerateMoverChanges(const Grid& initial, std::vector<int> movers, int steps,
                                    CRandom& random);

}  // namespace dynapath
