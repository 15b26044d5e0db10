#pragma once
// How a run's size and threads become its processes' limits: written once
// for every front end (run, experiment, serve).

#include <cstdint>

#include "dynapath/grid.h"

namespace dynapath::app {

// The largest grid a run's buses accept (BusOptions::max_grid_cells): its
// maze's cells, so a message of a larger grid is dropped before it is
// reassembled.
int64_t GridCap(const Grid& maze);
int64_t GridCap(int rows, int cols);

// The threads each of `agents` agents trains on when a run's `threads`
// are split among them (at least one each).
int ThreadsPerAgent(int threads, int agents);

}  // namespace dynapath::app
