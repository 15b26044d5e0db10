#pragma once
// The options that choose a maze and its change sequence, shared by
// `dynapath maze` and `dynapath run`.

#include <spdlog/common.h>

#include <cstdint>
#include <optional>
#include <string>

#include "dynapath/difficulty.h"
#include "dynapath/experiment.h"
#include "dynapath/map_scenario.h"
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

// The scenario options as given on a command line, as text where the
// command line gives words (--difficulty, --stations, --movers): a process's
// options (envsim's) travel so. ParseScenarioOptions reads them into a
// ScenarioSpec.
struct ScenarioOptions {
  std::optional<long long> size, cols, seed, steps;
  std::optional<std::string> difficulty, maze, stations, stations_file, movers, changes, replay;
  bool allow_unreachable = false;
  bool force_changes = false;  // use a change file made for another maze (a warning)
};
void DeclareScenarioOptions(OptionGroup& group, ScenarioOptions& options);

// A scenario, typed: what ResolveScenario builds. A command line's text is
// parsed into it once (ParseScenarioOptions); a study (and the Python
// module) fill it directly. Unset fields take the default their option's
// help names, and some exclude others (replay, maze), as the options do.
struct ScenarioSpec {
  // A generated maze: rows (and columns), difficulty; seed and steps for
  // every maze. Range-checked by ResolveScenario, as the options' values.
  std::optional<long long> size, cols, seed, steps;
  std::optional<Difficulty> difficulty;
  // A maze file, and on it stations and moving obstacles: N or P% of its
  // free cells (from the seed), or the stations of a file.
  std::optional<std::string> maze, stations_file;
  std::optional<CellCount> stations, movers;
  std::optional<std::string> changes;  // a change file instead of generated changes
  std::optional<std::string> replay;   // the maze and changes of an LCM log
  bool allow_unreachable = false;
  bool force_changes = false;
};
// The options' words read once: --difficulty, --stations, --movers (an
// error names the option, "option --stations: expected a count N ...").
Result<ScenarioSpec> ParseScenarioOptions(const ScenarioOptions& options);
// The spec as a command line's options again (envsim's, handed over as
// text): ParseScenarioOptions gives it back.
ScenarioOptions ScenarioOptionsOf(const ScenarioSpec& spec);
// --stations or --movers N|P% (the option `name`, for the error).
Result<CellCount> ParseCellCountOption(const std::string& name, const std::string& text);
// "12" or "0.5%": the shortest text ParseCellCount reads back as `count`.
std::string CellCountText(const CellCount& count);
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
// The scenario of a spec: the maze generated, loaded (with its stations
// and movers placed) or replayed, and its change sequence; every value and
// combination checked, an error naming its option.
Result<ScenarioSetup> ResolveScenario(const ScenarioSpec& spec);
// A command line's: ParseScenarioOptions, then the above.
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
