#include "runtime/scenario_options.h"

#include <spdlog/spdlog.h>

#include <charconv>
#include <optional>
#include <vector>

#include "dynapath/bfs_oracle.h"
#include "dynapath/c_random.h"
#include "dynapath/limits.h"
#include "dynapath/map_scenario.h"
#include "dynapath/movingai_map.h"
#include "dynapath/text_util.h"
#include "protocol/log_scenario.h"

namespace dynapath::runtime {

namespace {
constexpr long long kDefaultSize = 20;
constexpr Difficulty kDefaultDifficulty = Difficulty::kEasy;
}  // namespace

const WordTable<Difficulty>& DifficultyWords() {
  // The result files' names ("Easy") in lower case, so the two cannot drift.
  static const WordTable<Difficulty> words = [] {
    std::vector<WordTable<Difficulty>::Word> list;
    for (Difficulty difficulty : kAllDifficulties) {
      list.push_back({ToLower(DifficultyName(difficulty)), difficulty});
    }
    return WordTable<Difficulty>(std::move(list), WordTable<Difficulty>::Case::kIgnored);
  }();
  return words;
}

// "warehouse-10-20-10-2-1" for ".../warehouse-10-20-10-2-1.map": the file's
// name without ".map", with characters that would break a CSV field replaced.
std::string MapLabel(const std::string& path) {
  std::string name = path.substr(path.find_last_of('/') + 1);
  const std::string lower = ToLower(name);
  for (const std::string suffix : {".map", ".yaml", ".yml", ".txt"}) {
    if (name.size() > suffix.size() &&
        lower.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      name.resize(name.size() - suffix.size());
      break;
    }
  }
  for (char& ch : name) {
    if (ch == ',' || ch == '"' || ch == '\n' || ch == '\r') ch = '_';
  }
  return name.empty() ? "Custom" : name;
}

void DeclareSeedAndStepsOptions(OptionGroup& group, std::optional<long long>& seed,
                                std::optional<long long>& steps) {
  group.Option("--seed", seed, "S", "seed of the maze and change sequence (C-library stream)",
               "the report's: 50 + difficulty index");
  group.Option("--steps", steps, "T", "number of time steps", "2 x rows, the report's");
}

void DeclareMapPopulationOptions(OptionGroup& group, std::optional<std::string>& stations,
                                 std::optional<std::string>& movers) {
  group.Option("--stations", stations, "N|P%",
               "on a loaded map: place N stations (or P% of the free cells) from the seed");
  group.Option("--movers", movers, "N|P%",
               "on a loaded map: N moving obstacles (or P% of the free cells) from the seed; "
               "only they move");
}

void DeclareScenarioOptions(OptionGroup& group, ScenarioOptions& o) {
  group.Option("--size", o.size, "N", "maze rows (and columns unless --cols)",
               std::to_string(kDefaultSize));
  group.Option("--cols", o.cols, "M", "maze columns, for rectangular mazes", "--size");
  group.Option("--difficulty", o.difficulty, "D", DifficultyWords().List(),
               DifficultyWords().Name(kDefaultDifficulty));
  DeclareSeedAndStepsOptions(group, o.seed, o.steps);
  group.Option("--maze", o.maze, "FILE",
               "load the maze from a file instead: a MovingAI map (.map, walls never move), "
               "a ROS map_server map (.yaml/.yml naming a PGM; walls never move) or the text "
               "format ('#', '.', 'C', every obstacle may move)");
  DeclareMapPopulationOptions(group, o.stations, o.movers);
  group.Option("--stations-file", o.stations_file, "FILE",
               "with --maze: stations from a file, 'row col' per line");
  group.Option("--changes", o.changes, "FILE",
               "load the change sequence from a change file instead (dynapath maze "
               "--save-changes; it must be made for this maze)");
  group.Flag("--force-changes", o.force_changes,
             "use --changes although the file records another maze's fingerprint (a warning; "
             "every change is still checked against the grid)");
  group.Option("--replay", o.replay, "LOG",
               "re-issue the maze and change sequence recorded in an LCM log (--log)");
  group.Flag("--allow-unreachable", o.allow_unreachable,
             "run a maze where no free cell reaches a station (else an error)");
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

// --replay sets the maze and changes: no other scenario option may be given
// (the options as given, or the spec: the same fields).
template <typename Given>
Status CheckReplayAlone(const Given& o) {
  const std::pair<const char*, bool> others[] = {{"size", o.size.has_value()},
                                                 {"cols", o.cols.has_value()},
                                                 {"difficulty", o.difficulty.has_value()},
                                                 {"seed", o.seed.has_value()},
                                                 {"steps", o.steps.has_value()},
                                                 {"maze", o.maze.has_value()},
                                                 {"changes", o.changes.has_value()},
                                                 {"stations", o.stations.has_value()},
                                                 {"stations-file", o.stations_file.has_value()},
                                                 {"movers", o.movers.has_value()}};
  for (const auto& [other, given] : others) {
    if (given) {
      return Error{
          std::string("--replay sets the maze and changes: do not combine it with --") + other,
          Error::Code::kInvalidArgument, other};
    }
  }
  return Ok{};
}

Result<ScenarioSetup> ReplayScenario(const ScenarioSpec& o) {
  if (Status alone = CheckReplayAlone(o); !alone) return alone.error();
  Result<protocol::LoggedScenario> logged = protocol::ReadScenarioLog(*o.replay);
  if (!logged) return logged.error();
  ScenarioSetup setup;
  setup.scenario = std::move(logged->scenario);
  setup.labels.size_label = logged->size_label;
  setup.labels.difficulty_label = logged->difficulty;
  setup.seed = logged->seed;
  setup.source = "replayed from " + *o.replay + " (run " + logged->run_id + ")";
  return setup;
}

// "option --NAME: MESSAGE", a bad value of option NAME.
Error OfOption(const std::string& name, const Error& error) {
  return Error{"option --" + name + ": " + error.message, Error::Code::kInvalidArgument, name};
}

// --stations N|P% on a loaded maze. A MovingAI map has no stations of its
// own, so there a count that places none (0, 0%, a percentage rounding to
// no cell) is an error of its own rather than "the map has no stations".
Status PlaceStations(const CellCount& count, bool movingai, Grid& grid, CRandom& random) {
  const int cells = count.Resolve(grid.Count(Cell::kFree));
  if (movingai && cells == 0) {
    return Error::Option("stations", "must place at least 1 station on a MovingAI map, got '" +
                                         CellCountText(count) + "' (" +
                                         std::to_string(grid.Count(Cell::kFree)) + " free cells)");
  }
  Result<std::vector<int>> placed = PlaceOnFreeCells(grid, cells, Cell::kStation, random);
  if (!placed) return OfOption("stations", placed.error());
  return Ok{};
}

// Stations and movers of a loaded maze, drawn from `random`;
// `movers` gets the movers' cells (empty when --movers is not given).
Status PlaceOnMap(const ScenarioSpec& o, bool movingai, Grid& grid, CRandom& random,
                  std::optional<std::vector<int>>& movers) {
  if (o.stations && o.stations_file) {
    return Error{"give --stations or --stations-file, not both"};
  }
  if (o.stations_file) {
    Result<std::vector<int>> stations = LoadStationsFile(*o.stations_file, grid);
    if (!stations) return stations.error();
    for (int cell : *stations) grid.set(cell, Cell::kStation);
  } else if (o.stations) {
    if (Status placed = PlaceStations(*o.stations, movingai, grid, random); !placed) return placed;
  }
  // A text maze without stations stays allowed (nothing reaches a station),
  // as before; a map without them is almost surely a forgotten option.
  if (movingai && grid.Count(Cell::kStation) == 0) {
    return Error{
        "a MovingAI map has no stations: give --stations N (or P%) or --stations-file FILE"};
  }
  if (o.movers) {
    Result<std::vector<int>> placed =
        PlaceOnFreeCells(grid, o.movers->Resolve(grid.Count(Cell::kFree)), Cell::kObstacle, random);
    if (!placed) return OfOption("movers", placed.error());
    movers = std::move(*placed);
  } else if (movingai) {
    movers.emplace();  // a map's walls never move
  }
  return Ok{};
}

// A loaded change file against the maze it is used with: the maze it
// records (refused when it differs, unless `force`), then every change
// against the grid as it is applied (always).
Status CheckChangeFile(const std::string& path, const ChangeFileHeader& header,
                       const ChangeSequence& changes, const Grid& grid, bool force) {
  const uint64_t ours = MazeFingerprint(grid);
  if (!header.fingerprint) {
    spdlog::warn(
        "{}: a version {} change file records no maze fingerprint: it is not checked against "
        "the maze (every change still is); save it again with dynapath maze --save-changes",
        path, header.version);
  } else if (*header.fingerprint != ours) {
    const std::string differs = path + " was made for the maze of fingerprint " +
                                FingerprintText(*header.fingerprint) + ", this maze's is " +
                                FingerprintText(ours);
    if (!force) {
      return Error(differs +
                       " (another seed, maze file or stations?); --force-changes uses it "
                       "anyway",
                   Error::Code::kInvalidArgument, "changes");
    }
    spdlog::warn("{}: using it anyway (--force-changes)", differs);
  }
  if (Status fits = CheckChangesFit(changes, grid); !fits) {
    return fits.error().Prefixed(path + ": ");
  }
  return Ok{};
}

}  // namespace

Result<CellCount> ParseCellCountOption(const std::string& name, const std::string& text) {
  Result<CellCount> count = ParseCellCount(text);
  if (!count) return OfOption(name, count.error());
  return count;
}

std::string CellCountText(const CellCount& count) {
  if (count.percent < 0.0) return std::to_string(count.count);
  char text[64];
  const auto written = std::to_chars(text, text + sizeof text, count.percent);  // shortest
  return std::string(text, written.ptr) + "%";
}

Result<ScenarioSpec> ParseScenarioOptions(const ScenarioOptions& o) {
  // With --replay the other options' values are not read: giving one is
  // the error.
  if (o.replay) {
    if (Status alone = CheckReplayAlone(o); !alone) return alone.error();
  }
  ScenarioSpec spec;
  spec.size = o.size;
  spec.cols = o.cols;
  spec.seed = o.seed;
  spec.steps = o.steps;
  if (o.difficulty) {
    Result<Difficulty> difficulty = DifficultyWords().ParseOption("difficulty", *o.difficulty);
    if (!difficulty) return difficulty.error();
    spec.difficulty = *difficulty;
  }
  spec.maze = o.maze;
  spec.stations_file = o.stations_file;
  if (o.stations) {
    Result<CellCount> stations = ParseCellCountOption("stations", *o.stations);
    if (!stations) return stations.error();
    spec.stations = *stations;
  }
  if (o.movers) {
    Result<CellCount> movers = ParseCellCountOption("movers", *o.movers);
    if (!movers) return movers.error();
    spec.movers = *movers;
  }
  spec.changes = o.changes;
  spec.replay = o.replay;
  spec.allow_unreachable = o.allow_unreachable;
  spec.force_changes = o.force_changes;
  return spec;
}

ScenarioOptions ScenarioOptionsOf(const ScenarioSpec& spec) {
  ScenarioOptions o;
  o.size = spec.size;
  o.cols = spec.cols;
  o.seed = spec.seed;
  o.steps = spec.steps;
  if (spec.difficulty) o.difficulty = DifficultyWords().Name(*spec.difficulty);
  o.maze = spec.maze;
  o.stations_file = spec.stations_file;
  if (spec.stations) o.stations = CellCountText(*spec.stations);
  if (spec.movers) o.movers = CellCountText(*spec.movers);
  o.changes = spec.changes;
  o.replay = spec.replay;
  o.allow_unreachable = spec.allow_unreachable;
  o.force_changes = spec.force_changes;
  return o;
}

Result<ScenarioSetup> ResolveScenario(const ScenarioOptions& options) {
  Result<ScenarioSpec> spec = ParseScenarioOptions(options);
  if (!spec) return spec.error();
  return ResolveScenario(*spec);
}

Result<ScenarioSetup> ResolveScenario(const ScenarioSpec& o) {
  if (o.replay) return ReplayScenario(o);
  constexpr long long kMaxSide = kMaxGridSide;
  ScenarioSetup setup;
  const Difficulty difficulty = o.difficulty.value_or(kDefaultDifficulty);
  Result<long long> seed = InRange("seed", o.seed, ReportSeed(difficulty), 0, kMaxSeed);
  if (!seed) return seed.error();
  setup.seed = static_cast<uint64_t>(*seed);
  CRandom random(static_cast<uint32_t>(*seed));
  std::optional<std::vector<int>> movers;  // set: only these obstacles move

  if (o.maze) {
    if (o.size || o.cols) {
      return Error{"--maze sets the maze size: do not combine it with --size or --cols"};
    }
    bool movingai = false;
    Result<Grid> grid = LoadMazeFile(*o.maze, &movingai);
    if (!grid) return grid.error();
    setup.scenario.grid = std::move(*grid);
    Status placed = PlaceOnMap(o, movingai, setup.scenario.grid, random, movers);
    if (!placed) return placed.error();
    // A loaded maze (a map or a text maze) is told apart in result files by
    // its file name: mazes of one size differ.
    setup.labels.difficulty_label = o.difficulty ? DifficultyName(difficulty) : MapLabel(*o.maze);
    setup.source = "maze file " + *o.maze;
  } else {
    const std::pair<const char*, bool> map_options[] = {
        {"stations", o.stations.has_value()},
        {"stations-file", o.stations_file.has_value()},
        {"movers", o.movers.has_value()}};
    for (const auto& [map_only, given] : map_options) {
      if (given) {
        return Error{std::string("--") + map_only +
                         " is for loaded maps (--maze); the report's mazes keep their generator",
                     Error::Code::kInvalidArgument, map_only};
      }
    }
    Result<long long> rows = InRange("size", o.size, kDefaultSize, 1, kMaxSide);
    if (!rows) return rows.error();
    Result<long long> cols = InRange("cols", o.cols, *rows, 1, kMaxSide);
    if (!cols) return cols.error();
    setup.scenario.grid = GenerateMaze(static_cast<int>(*rows), static_cast<int>(*cols),
                                       ProbabilitiesOf(difficulty), random);
    setup.labels.difficulty_label = DifficultyName(difficulty);
    setup.source = "generated, seed " + std::to_string(*seed);
  }
  const Grid& grid = setup.scenario.grid;
  setup.labels.size_label = SizeLabel(grid.rows(), grid.cols());
  if (Status reachable = CheckStationReachable(grid); !reachable) {
    if (!o.allow_unreachable) {
      return Error{reachable.error().message + " (--allow-unreachable runs it anyway)"};
    }
    spdlog::warn("{}: running it anyway (--allow-unreachable)", reachable.error().message);
  }

  Result<long long> steps = InRange("steps", o.steps, ReportTimeSteps(grid.rows()), 0, kMaxSteps);
  if (!steps) return steps.error();
  if (o.changes) {
    ChangeFileHeader header;
    Result<ChangeSequence> changes = LoadChanges(*o.changes, grid.rows(), grid.cols(), &header);
    if (!changes) return changes.error();
    if (Status fits = CheckChangeFile(*o.changes, header, *changes, grid, o.force_changes); !fits) {
      return fits.error();
    }
    setup.scenario.changes = std::move(*changes);
    if (o.steps) {
      if (*steps > static_cast<long long>(setup.scenario.changes.steps.size())) {
        return Error{"--steps " + std::to_string(*steps) + " is more than the " +
                         std::to_string(setup.scenario.changes.steps.size()) +
                         " time steps of the change file",
                     Error::Code::kInvalidArgument, "steps"};
      }
      setup.scenario.changes.steps.resize(static_cast<size_t>(*steps));
    }
    setup.source += ", changes from " + *o.changes;
  } else {
    // Right after the maze, from the same stream, as the report's runs did
    // (a loaded maze starts a fresh stream from the seed).
    setup.scenario.changes =
        movers ? GenerateMoverChanges(grid, *movers, static_cast<int>(*steps), random)
               : GenerateChanges(grid, static_cast<int>(*steps), random);
  }
  return setup;
}

const WordTable<spdlog::level::level_enum>& LogLevelWords() {
  using namespace spdlog::level;
  // spdlog::level::from_str's spellings; its long and short aliases stay
  // accepted without being offered.
  static const WordTable<level_enum> words({{"trace", trace},
                                            {"debug", debug},
                                            {"info", info},
                                            {"warn", warn},
                                            {"error", err},
                                            {"off", off},
                                            {"warning", warn, false},
                                            {"err", err, false},
                                            {"critical", critical, false}});
  return words;
}

void DeclareLogOptions(OptionGroup& group, LogOptions& options) {
  group.Option("--log-level", options.log_level, "LEVEL", LogLevelWords().List());
}

Status CheckLogLevel(const std::string& text) { return LogLevelWords().Check(text); }

Status ApplyLogLevel(const LogOptions& options) {
  Result<spdlog::level::level_enum> level =
      LogLevelWords().ParseOption("log-level", options.log_level);
  if (!level) return level.error();
  spdlog::set_level(*level);
  return Ok{};
}

}  // namespace dynapath::runtime
