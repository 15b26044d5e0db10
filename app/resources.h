#pragma once
// How a run's size and threads become its processes' limits, and the
// errors of options: written once for every front end (run, experiment,
// serve).

#include <cstdint>
#include <string>

#include "dynapath/grid.h"
#include "dynapath/result.h"

namespace dynapath::app {

// The largest grid a run's buses accept (BusOptions::max_grid_cells): its
// maze's cells, so a message of a larger grid is dropped before it is
// reassembled.
int64_t GridCap(const Grid& maze);
int64_t GridCap(int rows, int cols);

// The threads each of `agents` agents trains on when a run's `threads`
// are split among them (at least one each).
int ThreadsPerAgent(int threads, int agents);

// An error of the options, about `option` (without "--"; Error::subject):
// a front end prints `message` and exits 2.
inline Error OptionError(std::string message, std::string option = {}) {
  return Error(std::move(message), Error::Code::kInvalidArgument, std::move(option));
}

}  // namespace dynapath::app
