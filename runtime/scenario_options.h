#pragma once
// The options that choose a maze and its change sequence, shared by
// `dynapath maze` and `dynapath run`.

#include <cstdint>
#include <string>

#include "core/experiment.h"
#include "core/scenario.h"
#include "runtime/arg_parser.h"

namespace dynapath::runtime {

struct ScenarioSetup {
  Scenario scenario;
  RunLabels labels;
  uint64_t seed = 0;   // the maze seed (also the learners' run seed)
  std::string source;  // how the scenario was obtained, for the log
};

void AddScenarioOptions(ArgParser& parser);
// Their names (for the launcher to forward them to envsim).
const std::vector<std::string>& ScenarioOptionNames();
Result<ScenarioSetup> ResolveScenario(const ArgParser& parser);

// Sets spdlog's level from --log-level (and adds that option).
void AddLogLevelOption(ArgParser& parser);
Status ApplyLogLevel(const ArgParser& parser);

}  // namespace dynapath::runtime
