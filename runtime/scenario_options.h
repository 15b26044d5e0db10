#pragma once
// The options that choose a maze and its change sequence, shared by
// `dynapath maze` and `dynapath run`.

#include <cstdint>
#include <optional>
#include <string>

#include "core/experiment.h"
#include "core/scenario.h"
#include "runtime/option_group.h"

namespace dynapath::runtime {

struct ScenarioSetup {
  Scenario scenario;
  RunLabels labels;
  uint64_t seed = 0;   // the maze seed (also the learners' run seed)
  std::string source;  // how the scenario was obtained, for the log
};

// The scenario options as given: unset ones take the default their help
// names (ResolveScenario), and some exclude others (--replay, --maze).
struct ScenarioOptions {
  std::optional<long long> size, cols, seed, steps;
  std::optional<std::string> difficulty, maze, stations, stations_file, movers, changes, replay;
  bool allow_unreachable = false;
};
void DeclareScenarioOptions(OptionGroup& group, ScenarioOptions& options);
// --seed and --steps alone (`dynapath experiment`: for every maze).
void DeclareSeedAndStepsOptions(OptionGroup& group, std::optional<long long>& seed,
                                std::optional<long long>& steps);
Result<ScenarioSetup> ResolveScenario(const ScenarioOptions& options);

// --log-level, which sets spdlog's level.
struct LogOptions {
  std::string log_level = "info";
};
void DeclareLogOptions(OptionGroup& group, LogOptions& options);
Status ApplyLogLevel(const LogOptions& options);
// "must be trace, debug, info, warn, error or off, got 'x'" unless a level.
Status CheckLogLevel(const std::string& text);

}  // namespace dynapath::runtime
