#include "runtime/scenario_options.h"

#include <spdlog/spdlog.h>

#include <optional>
#include <vector>

#include "core/bfs_oracle.h"
#include "core/c_random.h"
#include "core/limits.h"
#include "core/map_scenario.h"
#include "core/movingai_map.h"
#include "lcmtypes/protocol/log_scenario.h"

namespace dynapath::runtime {

void AddScenarioOptions(ArgParser& parser) {
  parser.AddOption("size", "N", "maze rows (and columns unless --cols)", "20");
  parser.AddOption("cols", "M", "maze columns, for rectangular mazes", "--size");
  parser.AddOption("difficulty", "D", "easy, medium or hard", "easy");
  parser.AddOption("seed", "S", "seed of the maze and change sequence (C-library stream)",
                   "the report's: 50 + difficulty index");
  parser.AddOption("steps", "T", "number of time steps", "2 x rows, the report's");
  parser.AddOption("maze", "FILE",
                   "load the maze from a file instead: a MovingAI map (.map, walls never move) "
                   "or the text format ('#', '.', 'C', every obstacle may move)");
  parser.AddOption("stations", "N|P%",
                   "with --maze: place N stations (or P% of the free cells) from the seed");
  parser.AddOption("stations-file", "FILE",
                   "with --maze: stations from a file, 'row col' per line");
  parser.AddOption("movers", "N|P%",
                   "with --maze: N moving obstacles (or P% of the free cells) from the seed; "
                   "only they move");
  parser.AddOption("changes", "FILE", "load the change sequence from a change file instead");
  parser.AddOption("replay", "LOG",
                   "re-issue the maze and change sequence recorded in an LCM log (--log)");
  parser.AddFlag("allow-unreachable",
                 "run a maze where no free cell reaches a station (else an error)");
}

const std::vector<std::string>& ScenarioOptionNames() {
  static const std::vector<std::string> names = {
      "size",    "cols",   "difficulty",        "seed",     "steps",         "maze",
      "changes", "replay", "allow-unreachable", "stations", "stations-file", "movers"};
  return names;
}

namespace {

// A maze where no free cell reaches a station has nothing to learn: every
// approach scores 0. Checked at time step 0.
Status CheckStationReachable(const Grid& grid) {
  bool station = false;
  for (int r = 0; r < grid.rows() && !station; ++r) {
    for (int c = 0; c < grid.cols() && !station; ++c) station = grid.at(r, c) == Cell::kStation;
  }
  if (!station) return Error{"the maze has no station ('C')"};
  std::vector<int32_t> distance, queue;
  NearestStationDistances(grid, distance, queue);
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) {
      if (grid.at(r, c) == Cell::kFree &&
          distance[static_cast<size_t>(r) * grid.cols() + c] != kUnreachable) {
        return Ok{};
      }
    }
  }
  return Error{"no free cell of the maze reaches a station"};
}

Result<ScenarioSetup> ReplayScenario(const ArgParser& parser) {
  for (const char* other : {"size", "cols", "difficulty", "seed", "steps", "maze", "changes",
                            "stations", "stations-file", "movers"}) {
    if (parser.Has(other)) {
      return Error{std::string("--replay sets the maze and changes: do not combine it with --") +
                   other};
    }
  }
  Result<protocol::LoggedScenario> logged = protocol::ReadScenarioLog(parser.Get("replay"));
  if (!logged) return logged.error();
  ScenarioSetup setup;
  setup.scenario = std::move(logged->scenario);
  setup.labels.size_label = logged->size_label;
  setup.labels.difficulty_label = logged->difficulty;
  setup.seed = logged->seed;
  setup.source = "replayed from " + parser.Get("replay") + " (run " + logged->run_id + ")";
  return setup;
}

// "warehouse-10-20-10-2-1" for ".../warehouse-10-20-10-2-1.map": the file's
// name without ".map", with characters that would break a CSV field replaced.
std::string MapLabel(const std::string& path) {
  std::string name = path.substr(path.find_last_of('/') + 1);
  if (name.size() > 4 && name.compare(name.size() - 4, 4, ".map") == 0)
    name.resize(name.size() - 4);
  for (char& ch : name) {
    if (ch == ',' || ch == '"' || ch == '\n' || ch == '\r') ch = '_';
  }
  return name.empty() ? "Custom" : name;
}

// Stations and movers of a loaded maze (issue 11), drawn from `random`;
// `movers` gets the movers' cells (empty when --movers is not given).
Status PlaceOnMap(const ArgParser& parser, bool movingai, Grid& grid, CRandom& random,
                  std::optional<std::vector<int>>& movers) {
  if (parser.Has("stations") && parser.Has("stations-file")) {
    return Error{"give --stations or --stations-file, not both"};
  }
  if (parser.Has("stations-file")) {
    Result<std::vector<int>> stations = LoadStationsFile(parser.Get("stations-file"), grid);
    if (!stations) return stations.error();
    for (int cell : *stations) grid.set(cell, Cell::kStation);
  } else if (parser.Has("stations")) {
    Result<CellCount> count = ParseCellCount(parser.Get("stations"));
    if (!count) return Error{"option --stations: " + count.error().message};
    Result<std::vector<int>> placed =
        PlaceOnFreeCells(grid, count->Resolve(grid.Count(Cell::kFree)), Cell::kStation, random);
    if (!placed) return Error{"option --stations: " + placed.error().message};
  }
  // A text maze without stations stays allowed (nothing reaches a station),
  // as before; a map without them is almost surely a forgotten option.
  if (movingai && grid.Count(Cell::kStation) == 0) {
    return Error{
        "a MovingAI map has no stations: give --stations N (or P%) or --stations-file FILE"};
  }
  if (parser.Has("movers")) {
    Result<CellCount> count = ParseCellCount(parser.Get("movers"));
    if (!count) return Error{"option --movers: " + count.error().message};
    Result<std::vector<int>> placed =
        PlaceOnFreeCells(grid, count->Resolve(grid.Count(Cell::kFree)), Cell::kObstacle, random);
    if (!placed) return Error{"option --movers: " + placed.error().message};
    movers = std::move(*placed);
  } else if (movingai) {
    movers.emplace();  // a map's walls never move
  }
  return Ok{};
}

}  // namespace

Result<ScenarioSetup> ResolveScenario(const ArgParser& parser) {
  if (parser.Has("replay")) return ReplayScenario(parser);
  constexpr long long kMaxSide = kMaxGridSide;
  ScenarioSetup setup;
  std::optional<Difficulty> difficulty = Difficulty::kEasy;
  if (parser.Has("difficulty")) {
    difficulty = ParseDifficulty(parser.Get("difficulty"));
    if (!difficulty) {
      return Error{"option --difficulty must be easy, medium or hard, got '" +
                   parser.Get("difficulty") + "'"};
    }
  }
  Result<long long> seed = parser.GetInt("seed", ReportSeed(*difficulty), 0, 4294967295LL);
  if (!seed) return seed.error();
  setup.seed = static_cast<uint64_t>(*seed);
  CRandom random(static_cast<uint32_t>(*seed));
  std::optional<std::vector<int>> movers;  // set: only these obstacles move

  if (parser.Has("maze")) {
    if (parser.Has("size") || parser.Has("cols")) {
      return Error{"--maze sets the maze size: do not combine it with --size or --cols"};
    }
    bool movingai = false;
    Result<Grid> grid = LoadMazeFile(parser.Get("maze"), &movingai);
    if (!grid) return grid.error();
    setup.scenario.grid = std::move(*grid);
    Status placed = PlaceOnMap(parser, movingai, setup.scenario.grid, random, movers);
    if (!placed) return placed.error();
    // A map is told apart in result files by its name (maps of one size
    // differ); a text maze keeps "Custom".
    setup.labels.difficulty_label = parser.Has("difficulty") ? DifficultyName(*difficulty)
                                    : movingai               ? MapLabel(parser.Get("maze"))
                                                             : "Custom";
    setup.source = "maze file " + parser.Get("maze");
  } else {
    for (const char* map_only : {"stations", "stations-file", "movers"}) {
      if (parser.Has(map_only)) {
        return Error{std::string("--") + map_only +
                     " is for loaded maps (--maze); the report's mazes keep their generator"};
      }
    }
    Result<long long> rows = parser.GetInt("size", 20, 1, kMaxSide);
    if (!rows) return rows.error();
    Result<long long> cols = parser.GetInt("cols", *rows, 1, kMaxSide);
    if (!cols) return cols.error();
    setup.scenario.grid = GenerateMaze(static_cast<int>(*rows), static_cast<int>(*cols),
                                       ProbabilitiesOf(*difficulty), random);
    setup.labels.difficulty_label = DifficultyName(*difficulty);
    setup.source = "generated, seed " + std::to_string(*seed);
  }
  const Grid& grid = setup.scenario.grid;
  setup.labels.size_label = SizeLabel(grid.rows(), grid.cols());
  if (Status reachable = CheckStationReachable(grid); !reachable) {
    if (!parser.Has("allow-unreachable")) {
      return Error{reachable.error().message + " (--allow-unreachable runs it anyway)"};
    }
    spdlog::warn("{}: running it anyway (--allow-unreachable)", reachable.error().message);
  }

  Result<long long> steps = parser.GetInt("steps", ReportTimeSteps(grid.rows()), 0, 1'000'000);
  if (!steps) return steps.error();
  if (parser.Has("changes")) {
    Result<ChangeSequence> changes = LoadChanges(parser.Get("changes"), grid.rows(), grid.cols());
    if (!changes) return changes.error();
    setup.scenario.changes = std::move(*changes);
    if (parser.Has("steps")) {
      if (*steps > static_cast<long long>(setup.scenario.changes.steps.size())) {
        return Error{"--steps " + std::to_string(*steps) + " is more than the " +
                     std::to_string(setup.scenario.changes.steps.size()) +
                     " time steps of the change file"};
      }
      setup.scenario.changes.steps.resize(static_cast<size_t>(*steps));
    }
    setup.source += ", changes from " + parser.Get("changes");
  } else {
    // Right after the maze, from the same stream, as the report's runs did
    // (a loaded maze starts a fresh stream from the seed).
    setup.scenario.changes =
        movers ? GenerateMoverChanges(grid, *movers, static_cast<int>(*steps), random)
               : GenerateChanges(grid, static_cast<int>(*steps), random);
  }
  return setup;
}

void AddLogLevelOption(ArgParser& parser) {
  parser.AddOption("log-level", "LEVEL", "trace, debug, info, warn, error or off", "info");
}

Status ApplyLogLevel(const ArgParser& parser) {
  const std::string name = parser.Get("log-level", "info");
  const spdlog::level::level_enum level = spdlog::level::from_str(name);
  if (level == spdlog::level::off && name != "off") {
    return Error{"option --log-level must be trace, debug, info, warn, error or off, got '" + name +
                 "'"};
  }
  spdlog::set_level(level);
  return Ok{};
}

}  // namespace dynapath::runtime
