#pragma once
// Reads the maze and change sequence of a run back from an LCM log
// (`dynapath run --log FILE`, or lcm-logger's): the grid_t answers and the
// changes_t answers envsim published. Used by --replay.

#include <cstdint>
#include <string>

#include "dynapath/result.h"
#include "dynapath/scenario.h"

namespace dynapath::protocol {

struct LoggedScenario {
  std::string run_id;
  Scenario scenario;
  std::string size_label, difficulty;
  uint64_t seed = 0;
};

// The first run found in the log (or `run_id` if not empty). Fails with one
// clear message when the file is not an LCM log, holds no maze, misses time
// steps, or holds two different versions of one step.
Result<LoggedScenario> ReadScenarioLog(const std::string& path, const std::string& run_id = "");

}  // namespace dynapath::protocol
