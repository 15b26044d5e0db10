#pragma once
// A scenario is what every approach of one run is evaluated on: the maze at
// time step 0 and its change sequence. The paper-compatible generator draws
// both from one C-library random stream, exactly as the report's runs did.

#include <string>

#include "dynapath/change_sequence.h"
#include "dynapath/difficulty.h"
#include "dynapath/grid.h"

namespace dynapath {

class CRandom;

struct Scenario {
  Grid grid;               // the maze at time step 0
  ChangeSequence changes;  // changes of time steps 1..T
};

// Draws a maze (SPEC section 1) from `random`.
Grid GenerateMaze(int rows, int cols, const CellProbabilities& probabilities, CRandom& random);

// Moves in one time step, 1 to 10, with the report's skew (90% one move).
int DrawMoveCount(CRandom& random);
// One requested move of SPEC 1: picks one of `candidates` (obstacle cells)
// with rand() % count, then one of its free in-grid neighbours in the order
// N, NE, ..., NW with rand() % count, if any; moves it in `grid`, in
// `candidates` (in place) and records both changed cells in `step`.
void MoveOneObstacle(Grid& grid, std::vector<int>& candidates, CRandom& random, ChangeStep& step);

// Draws `steps` time steps of obstacle moves, starting from `grid`, from `random`.
ChangeSequence GenerateChanges(const Grid& grid, int steps, CRandom& random);

// srand(seed); maze; then the change sequence from the same stream.
// `steps` < 0 means the report's 2 x rows.
Scenario GenerateScenario(int rows, int cols, Difficulty difficulty, unsigned seed, int steps = -1);

// Number of time steps the report simulates for a maze: 2 x rows.
inline int ReportTimeSteps(int rows) { return 2 * rows; }

}  // namespace dynapath
