#include "study/study_plan.h"

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "dynapath/experiment.h"
#include "dynapath/limits.h"
#include "dynapath/map_scenario.h"
#include "dynapath/movingai_map.h"
#include "dynapath/parameters.h"
#include "dynapath/scenario.h"
#include "dynapath/text_file.h"
#include "dynapath/text_util.h"

namespace dynapath::study {
namespace {

constexpr int kMaxSize = kMaxGridSide;

// The report's study: the defaults of --sizes, --difficulties and
// --approaches, shown in --help and resolved like given values.
constexpr const char* kDefaultSizes = "20,50,100,200,300";
constexpr const char* kDefaultDifficulties = "easy,medium,hard";
constexpr const char* kAllApproaches = "all";

// One item of --sizes, a decimal integer from 2 to kMaxSize, '+' allowed (a
// maze size is the study's own option: `dynapath run` takes --size N alone).
std::optional<int> SizeOf(std::string_view item) {
  if (!item.empty() && item.front() == '+') item.remove_prefix(1);
  int size = 0;
  const char* end = item.data() + item.size();
  const auto [last, error] = std::from_chars(item.data(), end, size);
  if (item.empty() || error != std::errc() || last != end || size < 2 || size > kMaxSize) {
    return std::nullopt;
  }
  return size;
}

std::string LowerDifficulty(Difficulty difficulty) { return ToLower(DifficultyName(difficulty)); }

// The index of parameter `name` in Parameters(), or none.
std::optional<size_t> ParameterIndex(const std::string& name) {
  const std::vector<Parameter>& parameters = Parameters();
  for (size_t i = 0; i < parameters.size(); ++i) {
    if (parameters[i].name == name) return i;
  }
  return std::nullopt;
}

bool IsParameter(const std::string& name) { return ParameterIndex(name).has_value(); }

// Two maps of one study must be two files with two labels: a map's label
// (runtime::MapLabel, its file name) names its run directory and its rows'
// Difficulty column, so two maps named alike would overwrite each other's
// runs and give identical result rows. Both paths exist (they were read).
Status CheckDistinctMaps(const std::string& first, const std::string& second) {
  namespace fs = std::filesystem;
  if (first == second) return Error{"map " + second + " is given twice"};
  std::error_code error;
  if (fs::equivalent(first, second, error)) {
    return Error{"maps " + first + " and " + second + " are the same file"};
  }
  const std::string label = runtime::MapLabel(first);
  if (label == runtime::MapLabel(second)) {
    return Error{"maps " + first + " and " + second + " have the same name '" + label +
                 "' (their runs and result rows would be mixed up); rename one"};
  }
  return Ok{};
}

// An item of --maps: "PATH" or "MAP:STATIONS_FILE" (that map's stations
// from a file, 'row col' per line, instead of --stations): split at the
// last ':' unless the whole item names an existing file or folder.
struct MapItem {
  std::string map, stations_file;
};
MapItem SplitMapItem(const std::string& item) {
  const size_t colon = item.rfind(':');
  std::error_code error;
  if (colon == std::string::npos || colon + 1 == item.size() ||
      std::filesystem::exists(item, error)) {
    return MapItem{item, ""};
  }
  return MapItem{item.substr(0, colon), item.substr(colon + 1)};
}

// A study file's relative map paths are relative to the file's folder, as
// users expect of a config file (the map folder can travel with it); the
// command line's stay relative to the working directory. `out` is not a
// path to read, so it stays as given.
std::vector<std::string> MapsRelativeToFile(std::vector<std::string> items,
                                            const std::string& file_name) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::path(file_name).parent_path();
  if (folder.empty()) return items;  // the file is in the working directory
  auto relative = [&](const std::string& path) {
    return !path.empty() && fs::path(path).is_relative() ? (folder / path).string() : path;
  };
  for (std::string& item : items) {
    const MapItem split = SplitMapItem(Trim(item));
    item = relative(split.map) +
           (split.stations_file.empty() ? "" : ":" + relative(split.stations_file));
  }
  return items;
}

// The maps of a --maps list: files as given, folders as their .map files in
// name order; each must exist and be a MovingAI map (read here, once, so a
// study with a bad map fails before it starts).
Result<std::vector<StudyOptions::Map>> ExpandMapList(const std::vector<std::string>& items,
                                                     const std::string& origin) {
  namespace fs = std::filesystem;
  std::vector<MapItem> paths;
  for (const std::string& given : items) {
    const MapItem split = SplitMapItem(given);
    const std::string& item = split.map;
    std::error_code error;
    if (fs::is_directory(item, error)) {
      if (!split.stations_file.empty()) {
        return Error{origin + ": " + given + ": a stations file is one map's, not a folder's"};
      }
      std::vector<std::string> found;
      for (const fs::directory_entry& entry : fs::directory_iterator(item, error)) {
        if (ToLower(entry.path().extension().string()) == ".map")
          found.push_back(entry.path().string());
      }
      if (error) {
        return Error::File(error.value(),
                           origin + ": cannot list folder " + item + ": " + error.message());
      }
      if (found.empty()) return Error{origin + ": folder " + item + " holds no .map file"};
      std::sort(found.begin(), found.end());
      for (const std::string& path : found) paths.push_back(MapItem{path, ""});
    } else {
      paths.push_back(split);
    }
  }
  std::vector<StudyOptions::Map> maps;
  for (const auto& [path, stations_file] : paths) {
    Result<std::string> bytes = ReadTextFile(path);
    if (!bytes) return bytes.error().Prefixed(origin + ": ");
    Result<Grid> grid = ParseMovingAiMap(*bytes);
    if (!grid) return grid.error().Prefixed(origin + ": " + path + ": ");
    if (!stations_file.empty()) {
      if (Result<std::vector<int>> stations = LoadStationsFile(stations_file, *grid); !stations) {
        return stations.error().Prefixed(origin + ": " + path + ": ");
      }
    }
    for (const StudyOptions::Map& earlier : maps) {
      if (Status distinct = CheckDistinctMaps(earlier.path, path); !distinct) {
        return distinct.error().Prefixed(origin + ": ");
      }
    }
    maps.push_back(StudyOptions::Map{path, grid->rows(), grid->cols(), stations_file});
  }
  return maps;
}

}  // namespace

std::string StudyModeName(StudyMode mode) {
  switch (mode) {
    case StudyMode::kLocal:
      return "local";
    case StudyMode::kAgents:
      return "agents";
    case StudyMode::kEmbedded:
      return "embedded";
  }
  return "local";
}

void DeclareRepeatsOption(runtime::OptionGroup& group, std::optional<long long>& repeats,
                          const std::string& default_text) {
  group.Option("--repeats", repeats, "N",
               "run N times (1 to " + std::to_string(kMaxRepeats) +
                   "), repeat k with learner seed B + (k-1) x " +
                   std::to_string(kRepeatSeedStride) +
                   ", B the --learner-seed or the maze's seed (repeat 1: the default stream), "
                   "--threads at once with --local; writes repeats.csv and summary.csv "
                   "(docs/howto/STUDIES.md, Repeats)",
               default_text);
}

void DeclareStudyConfigOption(runtime::OptionGroup& group, std::optional<std::string>& path) {
  group.Option("--config", path, "FILE",
               "read options from a TOML file (key = value, same names); the command line "
               "overrides it");
}

void DeclareStudyCommandLine(runtime::OptionGroup& group, StudyCommandLine& o) {
  using runtime::ValueKind;
  group.List("--sizes", o.sizes, ValueKind::kIntegerList, "LIST",
             "comma-separated maze sizes (rows = columns, at least 2)", kDefaultSizes);
  group.List("--difficulties", o.difficulties, ValueKind::kStringList, "LIST",
             "comma-separated difficulties: " + runtime::DifficultyWords().List(),
             kDefaultDifficulties);
  group.List("--approaches", o.approaches, ValueKind::kStringList, "LIST",
             "comma-separated approaches: " + ApproachNamesText() +
                 "; or all; py:MODULE:CLASS is one written in Python (--local, no manifest; "
                 "docs/howto/PYTHON.md)",
             kAllApproaches);
  group.Flag("--edge-case", o.edge_case,
             "also run the report's edge case, the hard 50x50 maze of seed 102 (default: on)");
  group.Flag("--no-edge-case", o.no_edge_case, "leave the edge case out");
  group.List("--maps", o.maps, ValueKind::kStringList, "LIST",
             "comma-separated MovingAI maps (.map files, or folders of them) to run after the "
             "mazes, each with --stations (default " +
                 std::string(kDefaultStations) + ") and --movers (default " + kDefaultMovers +
                 "); MAP:FILE gives that map its stations from FILE ('row col' lines) "
                 "instead; with --maps, --sizes and the edge case default to none",
             "none");
  runtime::DeclareMapPopulationOptions(group, o.stations, o.movers);
  runtime::DeclareSeedAndStepsOptions(group, o.seed, o.steps);
  DeclareRepeatsOption(group, o.repeats, "1, or the number of --maze-seeds");
  group.List("--maze-seeds", o.maze_seeds, ValueKind::kIntegerList, "LIST",
             "comma-separated maze seeds, one per repeat: repeat k runs on the maze, change "
             "sequence (and a map's stations and movers) of the k-th; instead of --seed; the edge "
             "case keeps its maze",
             "none: every repeat on the same maze");
  runtime::DeclareLearnerOptions(group, o.learner);
  runtime::DeclareModeOptions(group, o.mode);
  runtime::DeclarePlacementOption(group, o.learner);
  runtime::DeclareThreadOptions(group, o.threads);
  group.Option("--parallel", o.parallel, "P",
               "with --local: run P configurations (or repeats) at once, each with --threads / P "
               "threads (results are the same; time columns then measure contended runs)",
               "1; with --repeats, --threads");
  runtime::DeclareLcmUrlOption(group, o.lcm_url);
  runtime::DeclareLogOptions(group, o.log);
  group.Option("--out", o.out, "DIR", "study directory", kDefaultStudyDir);
}

namespace {

// Where each option of a StudyCommandLine lives, by key.
runtime::OptionFields FieldsOf(StudyCommandLine& options) {
  runtime::OptionFields fields;
  runtime::OptionGroup group(fields);
  DeclareStudyCommandLine(group, options);
  return fields;
}

// The option names given with --edge-case's meaning: --no-edge-case is
// "edge-case" given false.
constexpr const char* kEdgeCase = "edge-case";
constexpr const char* kNoEdgeCase = "no-edge-case";

}  // namespace

const runtime::OptionKinds& StudyOptionKinds() {
  static const runtime::OptionKinds kinds = [] {
    runtime::OptionKinds declared;
    StudyCommandLine options;
    for (const auto& [name, field] : FieldsOf(options)) declared[name] = field.kind;
    declared.erase(kNoEdgeCase);  // a file says edge-case = false
    return declared;
  }();
  return kinds;
}

Result<GivenStudyOptions> CommandLineStudyOptions(const CLI::App& app,
                                                  const StudyCommandLine& parsed) {
  if (parsed.edge_case && parsed.no_edge_case) {
    return Error{"choose one of --edge-case and --no-edge-case"};
  }
  GivenStudyOptions given;
  given.values = parsed;
  const runtime::OptionFields fields = FieldsOf(given.values);
  for (const CLI::Option* option : app.get_options()) {
    if (option->count() == 0 || option->get_lnames().empty()) continue;
    const std::string name = option->get_lnames().front();
    if (fields.count(name) == 0) continue;  // not the study's (--config, --force)
    given.origins[name == kNoEdgeCase ? kEdgeCase : name] = "option --" + name;
  }
  return given;
}

namespace {

// A TOML number (integer or float) as a double.
double NumberOf(const ConfigValue& value) {
  return value.kind == ConfigValue::Kind::kFloat ? value.number
                                                 : static_cast<double>(value.integer);
}

}  // namespace

Result<GivenStudyOptions> StudyFileOptions(const ConfigFile& file) {
  GivenStudyOptions given;
  const runtime::OptionFields fields = FieldsOf(given.values);
  const runtime::OptionKinds& kinds = StudyOptionKinds();
  for (const ConfigEntry& entry : file.entries) {
    const std::string& key = entry.key;
    const auto spec = kinds.find(key);
    const std::string where = file.name + ":" + std::to_string(entry.line);
    if (spec == kinds.end()) {
      std::string names;
      for (const auto& [name, kind] : kinds) names += (names.empty() ? "" : ", ") + name;
      return Error{where + ": unknown key '" + entry.written + "' (expected one of: " + names +
                   ")"};
    }
    const runtime::OptionField& field = fields.at(key);
    const ConfigValue& value = entry.value;
    const std::string origin = where + ": " + key;
    auto wrong = [&](const std::string& expected) {
      return Error{
          origin + ": expected " + expected + ", got " +
          (value.kind == ConfigValue::Kind::kArray ? "an array" : "a " + value.KindName())};
    };
    const Error empty{origin + ": must not be empty"};
    using Kind = ConfigValue::Kind;
    // A parameter may list values to sweep.
    const bool sweepable = IsParameter(key) && value.kind == Kind::kArray;
    switch (spec->second) {
      case runtime::ValueKind::kInteger:
        if (sweepable) {
          if (value.items.empty() || value.items.front().kind != Kind::kInteger) {
            return wrong("an integer or a non-empty array of integers");
          }
        } else if (value.kind != Kind::kInteger) {
          return wrong("an integer");
        }
        runtime::SetOptionInteger(field, sweepable ? value.items.front().integer : value.integer);
        break;
      case runtime::ValueKind::kFloat:
        if (sweepable) {
          for (const ConfigValue& item : value.items) {
            if (item.kind != Kind::kFloat && item.kind != Kind::kInteger) {
              return wrong("a number or an array of numbers");
            }
          }
          if (value.items.empty()) return wrong("a number or a non-empty array of numbers");
        } else if (value.kind != Kind::kFloat && value.kind != Kind::kInteger) {
          return wrong("a number");
        }
        runtime::SetOptionReal(field, NumberOf(sweepable ? value.items.front() : value));
        break;
      case runtime::ValueKind::kString:
        if (value.kind != Kind::kString) return wrong("a string");
        if (value.string.empty()) return empty;
        runtime::SetOptionText(field, value.string);
        break;
      case runtime::ValueKind::kBoolean:
        if (value.kind != Kind::kBoolean) return wrong("true or false");
        if (key == kEdgeCase && !value.boolean) {
          runtime::SetOptionBoolean(fields.at(kNoEdgeCase), true);
        } else if (value.boolean) {
          runtime::SetOptionBoolean(field, true);
        }
        break;
      case runtime::ValueKind::kIntegerList:
      case runtime::ValueKind::kStringList: {
        const bool integers = spec->second == runtime::ValueKind::kIntegerList;
        const Kind item_kind = integers ? Kind::kInteger : Kind::kString;
        if (value.kind == Kind::kArray) {
          if (!value.items.empty() && value.items.front().kind != item_kind) {
            return wrong(integers ? "an array of integers" : "an array of strings");
          }
        } else if (value.kind != item_kind) {
          return wrong(integers ? "an integer or an array of integers"
                                : "a string or an array of strings");
        }
        // The list's items, as the items of a command line's list (where
        // a comma separates items, so none may hold one).
        std::vector<std::string> items;
        for (const ConfigValue& item :
             value.kind == Kind::kArray ? value.items : std::vector{value}) {
          if (item.string.find(',') != std::string::npos) {
            return Error{origin + ": '" + item.string + "' holds a comma"};
          }
          items.push_back(integers ? std::to_string(item.integer) : item.string);
        }
        if (key == "maps") items = MapsRelativeToFile(items, file.name);
        if (runtime::JoinList(items).empty()) return empty;  // [] or [""]
        runtime::SetOptionList(field, std::move(items));
        break;
      }
    }
    if ((key == "local" || key == "embedded") && !value.boolean) continue;
    if (sweepable && value.items.size() > 1) {
      std::vector<double>& sweep = given.sweeps[key];
      for (const ConfigValue& item : value.items) sweep.push_back(NumberOf(item));
    }
    given.origins[key] = origin;
  }
  return given;
}

GivenStudyOptions MergeStudyOptions(const GivenStudyOptions& file,
                                    const GivenStudyOptions& command_line) {
  GivenStudyOptions merged = file;
  const runtime::OptionFields to = FieldsOf(merged.values);
  StudyCommandLine cli_values = command_line.values;
  const runtime::OptionFields from = FieldsOf(cli_values);
  const OptionOrigins& given = command_line.origins;
  const bool mode_given = given.count("local") || given.count("agents") || given.count("embedded");
  if (mode_given) {
    StudyCommandLine defaults;
    const runtime::OptionFields unset = FieldsOf(defaults);
    for (const char* mode : {"local", "agents", "embedded"}) {
      runtime::CopyOptionField(unset.at(mode), to.at(mode));
      merged.origins.erase(mode);
    }
  }
  for (const auto& [name, origin] : given) {
    runtime::CopyOptionField(from.at(name), to.at(name));
    if (name == kEdgeCase) runtime::CopyOptionField(from.at(kNoEdgeCase), to.at(kNoEdgeCase));
    merged.origins[name] = origin;
    merged.sweeps.erase(name);
  }
  return merged;
}

namespace {

// The given options, and where each came from.
class GivenOptions {
 public:
  explicit GivenOptions(const GivenStudyOptions& given) : given_(given) {}

  const StudyCommandLine& operator*() const { return given_.values; }
  const StudyCommandLine* operator->() const { return &given_.values; }
  // Where option `name` was given, or null when it was not.
  const std::string* Find(const std::string& name) const {
    const auto it = given_.origins.find(name);
    return it == given_.origins.end() ? nullptr : &it->second;
  }
  // A runtime check's error, "option --NAME must be ...", as "ORIGIN: must
  // be ..." for the value of the option it concerns (its subject; `name`
  // when it has none), so that a study file's value is reported with its line.
  Error Located(const Error& error, const std::string& name) const {
    const std::string option = error.subject.empty() ? name : error.subject;
    const std::string* origin = Find(option);
    Error located = error;
    located.message = (origin ? *origin : "option --" + option) + ": " + error.Detail();
    located.subject = option;
    return located;
  }

 private:
  const GivenStudyOptions& given_;
};

// A list option's items as given and where they came from.
struct ListValue {
  std::vector<std::string> items;
  std::string origin;
};

// The given list option `name` (its items `items`), or none.
std::optional<ListValue> GivenList(const GivenOptions& given, const std::string& name,
                                   const std::optional<std::vector<std::string>>& items) {
  const std::string* origin = given.Find(name);
  if (!origin || !items) return std::nullopt;
  return ListValue{*items, *origin};
}

// A default list, written as a command line would give it.
ListValue DefaultList(const char* text, const std::string& origin) {
  return ListValue{runtime::SplitList(text), origin};
}

// The items of a list, each trimmed, none empty.
Result<std::vector<std::string>> ListItems(const ListValue& value) {
  const std::string text = runtime::JoinList(value.items);  // as typed, for the errors
  if (text.empty()) return Error{value.origin + ": the list is empty"};
  std::vector<std::string> items;
  for (const std::string& item : value.items) {
    items.push_back(Trim(item));
    if (items.back().empty()) return Error{value.origin + ": empty item in '" + text + "'"};
  }
  return items;
}

// --stations or --movers (`text`, the option `name`, else `default_text`):
// N or P% of a map's free cells, so only with maps. Parsed here, once.
Status ResolveCellCount(const GivenOptions& given, const std::string& name,
                        const std::optional<std::string>& text, const char* default_text,
                        const StudyOptions& options, CellCount& resolved) {
  const std::string* origin = given.Find(name);
  if (!text || !origin) {
    resolved = *ParseCellCount(default_text);  // a constant that parses
    return Ok{};
  }
  if (options.maps.empty()) return Error{*origin + ": needs maps"};
  Result<CellCount> count = ParseCellCount(*text);
  if (!count) return count.error().Prefixed(*origin + ": ");
  resolved = *count;
  return Ok{};
}

// --maps, and the --stations and --movers every map gets.
Status ResolveMaps(const GivenOptions& given, StudyOptions& options) {
  if (const std::optional<ListValue> maps = GivenList(given, "maps", given->maps)) {
    Result<std::vector<std::string>> items = ListItems(*maps);
    if (!items) return items.error();
    Result<std::vector<StudyOptions::Map>> read = ExpandMapList(*items, maps->origin);
    if (!read) return read.error();
    options.maps = std::move(*read);
  }
  Status stations = ResolveCellCount(given, "stations", given->stations, kDefaultStations, options,
                                     options.stations);
  if (!stations) return stations;
  return ResolveCellCount(given, "movers", given->movers, kDefaultMovers, options, options.movers);
}

// --sizes (none by default with maps) and --difficulties.
Status ResolveMazes(const GivenOptions& given, StudyOptions& options) {
  std::optional<ListValue> sizes = GivenList(given, "sizes", given->sizes);
  if (!sizes && options.maps.empty()) sizes = DefaultList(kDefaultSizes, "default sizes");
  if (sizes) {
    Result<std::vector<std::string>> items = ListItems(*sizes);
    if (!items) return items.error();
    for (const std::string& item : *items) {
      const std::optional<int> size = SizeOf(item);
      if (!size) {
        return Error{sizes->origin + ": size '" + item + "' is not an integer from 2 to " +
                     std::to_string(kMaxSize)};
      }
      if (std::count(options.sizes.begin(), options.sizes.end(), *size) > 0) {
        return Error{sizes->origin + ": size " + item + " is given twice"};
      }
      options.sizes.push_back(*size);
    }
  }

  const ListValue difficulties =
      GivenList(given, "difficulties", given->difficulties)
          .value_or(DefaultList(kDefaultDifficulties, "default difficulties"));
  Result<std::vector<std::string>> items = ListItems(difficulties);
  if (!items) return items.error();
  for (const std::string& item : *items) {
    const std::optional<Difficulty> difficulty = runtime::DifficultyWords().Parse(item);
    if (!difficulty) {
      return Error{difficulties.origin + ": unknown difficulty '" + item + "' (expected " +
                   runtime::DifficultyWords().List() + ")"};
    }
    if (std::count(options.difficulties.begin(), options.difficulties.end(), *difficulty) > 0) {
      return Error{difficulties.origin + ": difficulty " + item + " is given twice"};
    }
    options.difficulties.push_back(*difficulty);
  }
  return Ok{};
}

// --approaches, the edge case (off by default with maps), --seed, --steps.
Status ResolveRuns(const GivenOptions& given, StudyOptions& options) {
  const ListValue approaches = GivenList(given, "approaches", given->approaches)
                                   .value_or(DefaultList(kAllApproaches, "default approaches"));
  if (Trim(runtime::JoinList(approaches.items)).empty()) {
    return Error{approaches.origin + ": the list is empty"};
  }
  Result<std::vector<Approach>> parsed = ParseApproachList(approaches.items);
  if (!parsed) return parsed.error().Prefixed(approaches.origin + ": ");
  options.approaches = std::move(*parsed);

  options.edge_case = given->edge_case || (options.maps.empty() && !given->no_edge_case);
  // The bounds `dynapath run` puts on them (runtime::ResolveScenario), which
  // has no resolver of these two alone: checked here for every maze at once.
  Result<long long> seed = runtime::InRange("seed", given->seed, 0, 0, runtime::kMaxSeed);
  if (!seed) return given.Located(seed.error(), "seed");
  Result<long long> steps = runtime::InRange("steps", given->steps, 0, 0, runtime::kMaxSteps);
  if (!steps) return given.Located(steps.error(), "steps");
  if (given->seed) options.seed = static_cast<unsigned>(*seed);
  if (given->steps) options.steps = static_cast<int>(*steps);

  Result<long long> repeats = runtime::InRange("repeats", given->repeats, 1, 1, kMaxRepeats);
  if (!repeats) return given.Located(repeats.error(), "repeats");
  options.repeats = static_cast<int>(*repeats);
  if (const std::optional<ListValue> maze_seeds =
          GivenList(given, "maze-seeds", given->maze_seeds)) {
    if (given->seed) return Error{maze_seeds->origin + ": choose one of --seed and --maze-seeds"};
    Result<std::vector<std::string>> items = ListItems(*maze_seeds);
    if (!items) return items.error();
    for (const std::string& item : *items) {
      long long value = -1;
      const char* end = item.data() + item.size();
      const auto [last, error] = std::from_chars(item.data(), end, value);
      if (error != std::errc() || last != end || value < 0 || value > runtime::kMaxSeed) {
        return Error{maze_seeds->origin + ": seed '" + item + "' is not an integer from 0 to " +
                     std::to_string(runtime::kMaxSeed)};
      }
      options.maze_seeds.push_back(static_cast<unsigned>(value));
    }
    const int count = static_cast<int>(options.maze_seeds.size());
    if (!given->repeats) {
      if (count > kMaxRepeats) {
        return Error{maze_seeds->origin + ": at most " + std::to_string(kMaxRepeats) + " seeds"};
      }
      options.repeats = count;
    } else if (count != options.repeats) {
      return Error{maze_seeds->origin + ": " + std::to_string(count) + " seeds for " +
                   std::to_string(options.repeats) + " repeats (one seed per repeat)"};
    }
  }
  return Ok{};
}

// --out, and the learner options and --placement, resolved by `dynapath
// run`'s own ResolveRunOptions into the study's run plan (with the study's
// approaches, resolved before).
Status ResolveLearner(const GivenOptions& given, StudyOptions& options) {
  options.out = given->out.value_or(kDefaultStudyDir);
  runtime::RunOptions run = given->learner;
  run.out = options.out;  // a directory too, with the same rule
  Result<runtime::RunPlan> plan = runtime::ResolveRunOptions(run);
  if (!plan) return given.Located(plan.error(), "");
  options.run = std::move(*plan);
  options.run.approaches = options.approaches;
  options.learner = given->learner;
  // Every repeat's learner seed must be one --learner-seed accepts.
  if (options.learner.learner_seed) {
    const long long last = *options.learner.learner_seed +
                           (options.repeats - 1) * static_cast<long long>(kRepeatSeedStride);
    if (last > runtime::kMaxLearnerSeed) {
      const std::string* origin = given.Find("learner-seed");
      return Error{(origin ? *origin : std::string("option --learner-seed")) + ": with " +
                   std::to_string(options.repeats) + " repeats the last repeat's learner seed " +
                   std::to_string(last) + " would exceed " +
                   std::to_string(runtime::kMaxLearnerSeed)};
    }
  }
  return Ok{};
}

// The mode (runtime::ResolveMode, as `dynapath run`), --threads (the
// machine's `hardware_threads` by default), --log-level, --lcm-url.
Status ResolveExecution(const GivenOptions& given, int hardware_threads, StudyOptions& options) {
  Result<runtime::RunMode> mode = runtime::ResolveMode(given->mode, runtime::kMaxAgents);
  if (!mode) {
    const char* mode_option = given->mode.local    ? "local"
                              : given->mode.agents ? "agents"
                                                   : "embedded";
    return given.Located(mode.error(), mode_option);
  }
  options.mode = *mode;
  options.threads = std::max(1, hardware_threads);
  if (given->threads.threads) {
    Result<int> threads = runtime::ResolveThreads(given->threads);
    if (!threads) return given.Located(threads.error(), "threads");
    options.threads = *threads;
  }
  Result<long long> parallel = runtime::InRange("parallel", given->parallel, 1, 1, 256);
  if (!parallel) return given.Located(parallel.error(), "parallel");
  if (*parallel > 1 && options.mode.kind != StudyMode::kLocal) {
    return Error{*given.Find("parallel") +
                 ": runs configurations at once only with --local (agents spread one run's "
                 "training over their cores)"};
  }
  options.parallel = static_cast<int>(*parallel);
  // Repeats run at once over the cores by default (--local).
  if (!given->parallel && options.repeats > 1 && options.mode.kind == StudyMode::kLocal) {
    options.parallel = options.threads;
  }
  if (Status status = runtime::CheckLogLevel(given->log.log_level); !status) {
    return given.Located(status.error(), "log-level");
  }
  options.log = given->log;
  if (const std::string* url = given.Find("lcm-url")) {
    if (options.mode.kind != StudyMode::kAgents) {
      return Error{*url + ": an LCM URL needs --agents N (processes)"};
    }
    if (given->lcm_url.empty()) return Error{*url + ": must not be empty"};
    options.lcm_url = given->lcm_url;
  }
  return Ok{};
}

}  // namespace

namespace {

// The parameters a study file gave several values (in name order: the
// first varies slowest): each sweep's values checked and distinct, the grid
// not too large.
Status TakeSweeps(const GivenOptions& given,
                  const std::map<std::string, std::vector<double>>& lists,
                  std::vector<StudyOptions::Sweep>& sweeps) {
  size_t points = 1;
  for (const auto& [name, values] : lists) {
    const std::optional<size_t> index = ParameterIndex(name);
    const std::string* origin = given.Find(name);
    if (!index || !origin) continue;
    const Parameter& parameter = Parameters()[*index];
    StudyOptions::Sweep sweep{*index, {}};
    for (const double number : values) {
      PlannerOptions check;
      if (Status status = SetParameter(check, *index, number); !status) {
        return Error{*origin + ": " + status.error().Detail()};
      }
      if (std::find(sweep.values.begin(), sweep.values.end(), number) != sweep.values.end()) {
        return Error{*origin + ": " + ParameterText(parameter, number) + " is given twice"};
      }
      sweep.values.push_back(number);
    }
    points *= sweep.values.size();
    if (points > kMaxSweepPoints) {
      return Error{*origin + ": the sweep's grid would have more than " +
                   std::to_string(kMaxSweepPoints) + " points"};
    }
    sweeps.push_back(std::move(sweep));
  }
  return Ok{};
}

}  // namespace

Result<StudyOptions> ResolveStudyOptions(const GivenStudyOptions& given_options,
                                         int hardware_threads) {
  const GivenOptions given(given_options);
  std::vector<StudyOptions::Sweep> sweeps;
  if (Status status = TakeSweeps(given, given_options.sweeps, sweeps); !status) {
    return status.error();
  }
  StudyOptions options;
  // The maps first: with maps, sizes and the edge case default to none.
  if (Status status = ResolveMaps(given, options); !status) return status.error();
  if (Status status = ResolveMazes(given, options); !status) return status.error();
  if (Status status = ResolveRuns(given, options); !status) return status.error();
  if (Status status = ResolveLearner(given, options); !status) return status.error();
  if (Status status = ResolveExecution(given, hardware_threads, options); !status) {
    return status.error();
  }
  // The swept parameters are the points' own, not the study's (a point's
  // values are set over the study's plan: RunPlanOf).
  for (const StudyOptions::Sweep& sweep : sweeps) {
    options.learner.parameters.integers[sweep.parameter].reset();
    options.learner.parameters.reals[sweep.parameter].reset();
  }
  options.sweeps = std::move(sweeps);
  return options;
}

std::string StudyConfiguration::BaseName() const {
  if (!map.empty()) return "map_" + map_label + "_" + std::to_string(seed);
  const std::string name =
      std::to_string(size) + "_" + LowerDifficulty(difficulty) + "_" + std::to_string(seed);
  return edge_case ? "edge_" + name : name;
}

std::string StudyConfiguration::PointToken() const {
  std::string token;
  for (const auto& [index, value] : point) {
    const Parameter& parameter = Parameters()[index];
    token += (token.empty() ? "" : "_") + parameter.name + "-" + ParameterText(parameter, value);
  }
  return token;
}

std::string StudyConfiguration::Name() const {
  std::string name = BaseName();
  if (!point.empty()) name += "_" + PointToken();
  return repeat > 1 ? name + "_r" + std::to_string(repeat) : name;
}

std::string StudyConfiguration::SizeText() const {
  return SizeLabel(size, map.empty() ? size : cols);
}

std::string StudyConfiguration::DifficultyText() const {
  return map.empty() ? DifficultyName(difficulty) : map_label;
}

std::string StudyConfiguration::Directory() const { return "runs/" + Name(); }

std::string StudyConfiguration::Label() const {
  std::string of_repeats =
      repeats > 1 ? ", repeat " + std::to_string(repeat) + "/" + std::to_string(repeats) : "";
  for (const auto& [index, value] : point) {
    const Parameter& parameter = Parameters()[index];
    of_repeats += ", " + parameter.name + " " + ParameterText(parameter, value);
  }
  if (!map.empty()) {
    return "map " + map_label + " " + SizeLabel(size, cols) + ", seed " + std::to_string(seed) +
           of_repeats;
  }
  return std::string(edge_case ? "edge case " : "") + std::to_string(size) + " " +
         DifficultyName(difficulty) + ", seed " + std::to_string(seed) + of_repeats;
}

std::string StudyConfiguration::ShortLabel() const {
  std::string of_repeats = repeats > 1 ? " r" + std::to_string(repeat) : "";
  if (!point.empty()) of_repeats += " " + PointToken();
  if (!map.empty()) return map_label + " s" + std::to_string(seed) + of_repeats;
  return std::string(edge_case ? "edge " : "") + std::to_string(size) + " " +
         DifficultyName(difficulty) + " s" + std::to_string(seed) + of_repeats;
}

double StudyConfiguration::Work() const {
  // Relative wall time, fitted to the full study's per-configuration times
  // (docs/howto/STUDIES.md): a fixed part (process start, the baselines'
  // set-up: about a second) plus (cells x steps)^0.8. Plain cells x steps
  // made the first small configurations predict hours for the 300x300 ones.
  const double cell_steps =
      static_cast<double>(size) * (map.empty() ? size : cols) * (static_cast<double>(steps) + 1.0);
  return 15800.0 + std::pow(cell_steps, 0.8);
}

namespace {

// The configurations of one repeat, in study order.
std::vector<StudyConfiguration> OneRepeat(const StudyOptions& options,
                                          std::optional<unsigned> seed) {
  std::vector<StudyConfiguration> plan;
  for (const int size : options.sizes) {
    for (const Difficulty difficulty : options.difficulties) {
      StudyConfiguration configuration;
      configuration.size = size;
      configuration.difficulty = difficulty;
      configuration.seed = seed ? *seed : ReportSeed(difficulty);
      configuration.steps = options.steps ? *options.steps : ReportTimeSteps(size);
      plan.push_back(configuration);
    }
  }
  if (options.edge_case) {
    StudyConfiguration edge;
    edge.size = 50;
    edge.difficulty = Difficulty::kHard;
    edge.seed = kEdgeCaseSeed;
    edge.steps = options.steps ? *options.steps : ReportTimeSteps(50);
    edge.edge_case = true;
    plan.push_back(edge);
  }
  for (const StudyOptions::Map& map : options.maps) {
    StudyConfiguration configuration;
    configuration.map = map.path;
    configuration.map_label = runtime::MapLabel(map.path);
    configuration.size = map.rows;
    configuration.cols = map.cols;
    configuration.seed = seed ? *seed : ReportSeed(Difficulty::kEasy);
    configuration.steps = options.steps ? *options.steps : ReportTimeSteps(configuration.size);
    configuration.stations = options.stations;
    configuration.stations_file = map.stations_file;
    configuration.movers = options.movers;
    plan.push_back(configuration);
  }
  return plan;
}

}  // namespace

std::vector<StudyConfiguration> MakeStudyPlan(const StudyOptions& options) {
  std::vector<std::vector<StudyConfiguration>> repeats;
  for (int k = 1; k <= options.repeats; ++k) {
    const std::optional<unsigned> seed =
        options.maze_seeds.empty() ? options.seed
                                   : std::optional<unsigned>(options.maze_seeds[size_t(k - 1)]);
    repeats.push_back(OneRepeat(options, seed));
  }
  // The sweep's grid points, the first swept parameter varying slowest.
  std::vector<std::vector<std::pair<size_t, double>>> points = {{}};
  for (const StudyOptions::Sweep& sweep : options.sweeps) {
    std::vector<std::vector<std::pair<size_t, double>>> next;
    for (const auto& point : points) {
      for (const double value : sweep.values) {
        next.push_back(point);
        next.back().emplace_back(sweep.parameter, value);
      }
    }
    points = std::move(next);
  }
  std::vector<StudyConfiguration> plan;
  for (const auto& point : points) {
    for (size_t i = 0; i < repeats.front().size(); ++i) {
      for (int k = 1; k <= options.repeats; ++k) {
        StudyConfiguration configuration = repeats[size_t(k - 1)][i];
        configuration.repeat = k;
        configuration.repeats = options.repeats;
        configuration.learner_seed =
            RepeatLearnerSeed(options.learner.learner_seed, configuration.seed, k);
        configuration.point = point;
        plan.push_back(configuration);
      }
    }
  }
  return plan;
}

runtime::ScenarioSpec ScenarioSpecOf(const StudyConfiguration& configuration) {
  runtime::ScenarioSpec spec;
  spec.seed = configuration.seed;
  spec.steps = configuration.steps;
  if (!configuration.map.empty()) {
    spec.maze = configuration.map;
    if (configuration.stations_file.empty()) {
      spec.stations = configuration.stations;
    } else {
      spec.stations_file = configuration.stations_file;
    }
    spec.movers = configuration.movers;
    return spec;
  }
  spec.size = configuration.size;
  spec.difficulty = configuration.difficulty;
  return spec;
}

runtime::RunPlan RunPlanOf(const StudyOptions& options, const StudyConfiguration& configuration,
                           const std::string& out_dir) {
  runtime::RunPlan plan = options.run;
  plan.out_dir = out_dir;
  plan.learner_seed = configuration.learner_seed;
  for (const auto& [index, value] : configuration.point) {
    // In range: each sweep's values were checked (TakeSweeps).
    (void)SetParameter(plan.options, index, value);
  }
  return plan;
}

runtime::RunOptions RunOptionsOf(const StudyOptions& options,
                                 const StudyConfiguration& configuration,
                                 const std::string& out_dir) {
  std::vector<std::string> names;
  for (const Approach approach : options.approaches) names.push_back(ApproachName(approach));
  runtime::RunOptions run = options.learner;
  run.approach = runtime::JoinList(names);  // the coordinator's command line
  run.out = out_dir;
  run.learner_seed.reset();
  if (configuration.learner_seed) {
    run.learner_seed = static_cast<long long>(*configuration.learner_seed);
  }
  for (const auto& [index, value] : configuration.point) {
    if (Parameters()[index].integer) {
      run.parameters.integers[index] = static_cast<long long>(value);
    } else {
      run.parameters.reals[index] = value;
    }
  }
  return run;
}

namespace {

// Every parameter by name with its value, numbers as in params.toml.
Json ParametersJson(const PlannerOptions& planner) {
  Json json = Json::object();
  const std::vector<Parameter>& parameters = Parameters();
  for (size_t i = 0; i < parameters.size(); ++i) {
    const double value = ParameterValue(planner, i);
    if (parameters[i].integer) {
      json[parameters[i].name] = static_cast<long long>(value);
    } else {
      json[parameters[i].name] = value;
    }
  }
  return json;
}

}  // namespace

Json StudyIdentityWithParameters(Json identity) {
  if (!identity.is_object()) return identity;
  if (!identity.contains("parameters")) identity["parameters"] = ParametersJson(PlannerOptions{});
  // A manifest records stations and movers as written before they were
  // kept typed ("0.50%"); a value that does not parse stays, and differs.
  for (const char* key : {"stations", "movers"}) {
    if (!identity.contains(key) || !identity[key].is_string()) continue;
    if (Result<CellCount> count = ParseCellCount(identity[key].get<std::string>())) {
      identity[key] = runtime::CellCountText(*count);
    }
  }
  return identity;
}

Json StudyIdentityJson(const StudyOptions& options) {
  Json json = Json::object();
  Json& sizes = json["sizes"] = Json::array();
  for (const int size : options.sizes) sizes.push_back(size);
  Json& difficulties = json["difficulties"] = Json::array();
  for (const Difficulty difficulty : options.difficulties) {
    difficulties.push_back(LowerDifficulty(difficulty));
  }
  Json& approaches = json["approaches"] = Json::array();
  for (const Approach approach : options.approaches) approaches.push_back(ApproachName(approach));
  json["edge_case"] = options.edge_case;
  json["seed"] = options.seed ? Json(*options.seed) : Json();
  json["steps"] = options.steps ? Json(*options.steps) : Json();
  json["leaf_limit"] = options.learner.leaf_limit;
  json["bootstrap"] = options.learner.bootstrap;
  // Only when not the default, so the identity of earlier studies (which had
  // no such option) stays the same and they can still be resumed.
  if (options.learner.semantics != runtime::RunOptions().semantics) {
    json["semantics"] = options.learner.semantics;
  }
  if (options.learner.learner_seed) json["learner_seed"] = *options.learner.learner_seed;
  // Only when used, so that studies without repeats keep their identity.
  if (options.repeats > 1) json["repeats"] = options.repeats;
  if (!options.maze_seeds.empty()) {
    Json& seeds = json["maze_seeds"] = Json::array();
    for (const unsigned seed : options.maze_seeds) seeds.push_back(seed);
  }
  json["parameters"] = ParametersJson(options.run.options);
  // A swept parameter's entry is its list of values.
  for (const StudyOptions::Sweep& sweep : options.sweeps) {
    const Parameter& parameter = Parameters()[sweep.parameter];
    Json& values = json["parameters"][parameter.name] = Json::array();
    for (const double value : sweep.values) {
      if (parameter.integer) {
        values.push_back(static_cast<long long>(value));
      } else {
        values.push_back(value);
      }
    }
  }
  if (!options.maps.empty()) {
    Json& maps = json["maps"] = Json::array();
    for (const StudyOptions::Map& map : options.maps) {
      maps.push_back(map.stations_file.empty() ? map.path : map.path + ":" + map.stations_file);
    }
    json["stations"] = runtime::CellCountText(options.stations);
    json["movers"] = runtime::CellCountText(options.movers);
  }
  return json;
}

Json ExecutionJson(const StudyOptions& options) {
  Json json = Json::object();
  const bool local = options.mode.kind == StudyMode::kLocal;
  json["mode"] = StudyModeName(options.mode.kind);
  json["agents"] = local ? Json() : Json(options.mode.agents);
  json["placement"] = local ? Json() : Json(options.learner.placement);
  json["threads"] = options.threads;
  if (options.parallel > 1) json["parallel"] = options.parallel;
  json["lcm_url"] = options.lcm_url.empty() ? Json() : Json(options.lcm_url);
  json["log_level"] = options.log.log_level;
  json["out"] = options.out;
  return json;
}

}  // namespace dynapath::study
