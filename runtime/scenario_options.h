#pragma once
// The options that choose a maze and its change sequence, shared by
// `dynapath maze` and `dynapath run`.

#include <spdlog/common.h>

#include <cstdint>
#include <optional>
#include <string>

#include "dynapath/experiment.h"
#include "dynapath/scenario.h"
#include "runtime/option_group.h"
#include "runtime/word_table.h"

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
  bool force_changes = false;  // use a change file made for another maze (a warning)
};
void DeclareScenarioOptions(OptionGroup& group, ScenarioOptions& options);
// The words of --difficulty, any case (the result files' names, lower case).
const WordTable<Difficulty>& DifficultyWords();
// Bounds of --seed (the C-library stream's 32-bit seed) and --steps, for
// every command that takes them.
inline constexpr long long kMaxSeed = 4294967295LL;
inline constexpr long long kMaxSteps = 1'000'000;

// --stations and --movers (also a study's, for its maps).
void DeclareMapPopulationOptions(OptionGroup& group, std::optional<std::string>& stations,
                                 std::optional<std::string>& movers);
// "warehouse-10-20-10-2-1" for ".../warehouse-10-20-10-2-1.map": how result
// files label a map run (its Difficulty column).
std::string MapLabel(const std::string& path);
// --seed and --steps alone (`dynapath experiment`: for every maze).
void DeclareSeedAndStepsOptions(OptionGroup& group, std::optional<long long>& seed,
                                std::optional<long long>& steps);
Result<ScenarioSetup> ResolveScenario(const ScenarioOptions& options);

// The words of --log-level: spdlog's names, of which the help lists six.
const WordTable<spdlog::level::level_enum>& LogLevelWords();
// --log-level, which sets spdlog's level.
struct LogOptions {
  std::string log_level = LogLevelWords().Name(spdlog::level::info);
};
void DeclareLogOptions(OptionGroup& group, LogOptions& options);
Status ApplyLogLevel(const LogOptions& options);
// "must be trace, debug, info, warn, error or off, got 'x'" unless a level.
Status CheckLogLevel(const std::string& text);

}  // namespace dynapath::runtime
