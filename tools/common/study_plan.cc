#include "tools/common/study_plan.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/experiment.h"
#include "core/limits.h"
#include "core/map_scenario.h"
#include "core/movingai_map.h"
#include "core/scenario.h"
#include "core/text_file.h"
#include "core/text_util.h"

namespace dynapath::cli {
namespace {

constexpr int kMaxSize = kMaxGridSide;

std::string ScalarText(const ConfigValue& value) {
  switch (value.kind) {
    case ConfigValue::Kind::kString:
      return value.string;
    case ConfigValue::Kind::kInteger:
      return std::to_string(value.integer);
    case ConfigValue::Kind::kFloat: {
      char text[32];  // shortest round-trip form, whatever the locale
      const auto end = std::to_chars(text, text + sizeof text, value.number).ptr;
      return std::string(text, end);
    }
    case ConfigValue::Kind::kBoolean:
      return value.boolean ? "true" : "false";
    case ConfigValue::Kind::kArray:
      break;
  }
  return "";
}

Result<long long> ParseInteger(const OptionValue& value, long long min, long long max) {
  const std::string& text = value.text;
  char* end = nullptr;
  errno = 0;
  const long long number = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE) {
    return Error{value.origin + ": needs an integer, got '" + text + "'"};
  }
  if (number < min || number > max) {
    return Error{value.origin + ": must be between " + std::to_string(min) + " and " +
                 std::to_string(max) + ", got " + text};
  }
  return number;
}

std::string Join(const std::vector<std::string>& pieces, const std::string& separator) {
  std::string text;
  for (const std::string& piece : pieces) text += (text.empty() ? "" : separator) + piece;
  return text;
}

std::string LowerDifficulty(Difficulty difficulty) { return ToLower(DifficultyName(difficulty)); }

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

// A study file's relative map paths are relative to the file's folder, as
// users expect of a config file (the map folder can travel with it); the
// command line's stay relative to the working directory. `out` is not a
// path to read, so it stays as given.
std::string MapsRelativeToFile(const std::string& list, const std::string& file_name) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::path(file_name).parent_path();
  if (folder.empty()) return list;  // the file is in the working directory
  std::vector<std::string> paths = Split(list, ',');
  for (std::string& path : paths) {
    if (!path.empty() && fs::path(path).is_relative()) path = (folder / path).string();
  }
  return Join(paths, ",");
}

// The maps of a --maps list: files as given, folders as their .map files in
// name order; each must exist and be a MovingAI map (read here, once, so a
// study with a bad map fails before it starts).
Result<std::vector<StudyOptions::Map>> ExpandMapList(const std::vector<std::string>& items,
                                                     const std::string& origin) {
  namespace fs = std::filesystem;
  std::vector<std::string> paths;
  for (const std::string& item : items) {
    std::error_code error;
    if (fs::is_directory(item, error)) {
      std::vector<std::string> found;
      for (const fs::directory_entry& entry : fs::directory_iterator(item, error)) {
        if (entry.path().extension() == ".map") found.push_back(entry.path().string());
      }
      if (error) return Error{origin + ": cannot list folder " + item + ": " + error.message()};
      if (found.empty()) return Error{origin + ": folder " + item + " holds no .map file"};
      std::sort(found.begin(), found.end());
      paths.insert(paths.end(), found.begin(), found.end());
    } else {
      paths.push_back(item);
    }
  }
  std::vector<StudyOptions::Map> maps;
  for (const std::string& path : paths) {
    Result<std::string> bytes = ReadTextFile(path);
    if (!bytes) return Error{origin + ": " + bytes.error().message};
    Result<Grid> grid = ParseMovingAiMap(*bytes);
    if (!grid) return Error{origin + ": " + path + ": " + grid.error().message};
    for (const StudyOptions::Map& earlier : maps) {
      if (Status distinct = CheckDistinctMaps(earlier.path, path); !distinct) {
        return Error{origin + ": " + distinct.error().message};
      }
    }
    maps.push_back(StudyOptions::Map{path, grid->rows(), grid->cols()});
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

void DeclareStudyCommandLine(runtime::OptionGroup& group, StudyCommandLine& o) {
  using runtime::ValueKind;
  group.List("--sizes", o.sizes, ValueKind::kIntegerList, "LIST",
             "comma-separated maze sizes (rows = columns, at least 2)", "20,50,100,200,300");
  group.List("--difficulties", o.difficulties, ValueKind::kStringList, "LIST",
             "comma-separated difficulties: easy, medium, hard", "easy,medium,hard");
  group.List("--approaches", o.approaches, ValueKind::kStringList, "LIST",
             "comma-separated approaches: " + ApproachNamesText() + "; or all", "all");
  group.Flag("--edge-case", o.edge_case,
             "also run the report's edge case, the hard 50x50 maze of seed 102 (default: on)");
  group.Flag("--no-edge-case", o.no_edge_case, "leave the edge case out");
  group.List("--maps", o.maps, ValueKind::kStringList, "LIST",
             "comma-separated MovingAI maps (.map files, or folders of them) to run after the "
             "mazes, each with --stations (default 0.5%) and --movers (default 2%); with "
             "--maps, --sizes and the edge case default to none",
             "none");
  runtime::DeclareMapPopulationOptions(group, o.stations, o.movers);
  runtime::DeclareSeedAndStepsOptions(group, o.seed, o.steps);
  runtime::DeclareLearnerOptions(group, o.learner);
  runtime::DeclareModeOptions(group, o.mode);
  runtime::DeclarePlacementOption(group, o.learner);
  runtime::DeclareThreadOptions(group, o.threads);
  runtime::DeclareLcmUrlOption(group, o.lcm_url);
  runtime::DeclareLogOptions(group, o.log);
  group.Option("--out", o.out, "DIR", "study directory", "study");
}

const runtime::OptionKinds& StudyOptionKinds() {
  static const runtime::OptionKinds kinds = [] {
    runtime::OptionKinds declared;
    CLI::App app;
    StudyCommandLine options;
    runtime::OptionGroup group(app, &declared);
    DeclareStudyCommandLine(group, options);
    declared.erase("no-edge-case");  // a file says edge-case = false
    return declared;
  }();
  return kinds;
}

OptionValues GivenOptionValues(const CLI::App& app) {
  OptionValues values;
  for (const CLI::Option* option : app.get_options()) {
    if (option->count() == 0 || option->get_lnames().empty()) continue;
    const std::string name = option->get_lnames().front();
    std::string text = "true";  // a flag
    if (option->get_expected_min() > 0) text = Join(option->results(), ",");
    values[name] = OptionValue{text, "option --" + name};
  }
  return values;
}

Result<OptionValues> ConfigOptionValues(const ConfigFile& file) {
  OptionValues values;
  for (const ConfigEntry& entry : file.entries) {
    std::string key = entry.key;
    std::replace(key.begin(), key.end(), '_', '-');
    const runtime::OptionKinds& kinds = StudyOptionKinds();
    const auto spec = kinds.find(key);
    const std::string where = file.name + ":" + std::to_string(entry.line);
    if (spec == kinds.end()) {
      std::string names;
      for (const auto& [name, kind] : kinds) names += (names.empty() ? "" : ", ") + name;
      return Error{where + ": unknown key '" + entry.key + "' (expected one of: " + names + ")"};
    }
    const ConfigValue& value = entry.value;
    const std::string origin = where + ": " + key;
    auto wrong = [&](const std::string& expected) {
      return Error{
          origin + ": expected " + expected + ", got " +
          (value.kind == ConfigValue::Kind::kArray ? "an array" : "a " + value.KindName())};
    };
    using Kind = ConfigValue::Kind;
    switch (spec->second) {
      case runtime::ValueKind::kInteger:
        if (value.kind != Kind::kInteger) return wrong("an integer");
        break;
      case runtime::ValueKind::kFloat:
        if (value.kind != Kind::kFloat && value.kind != Kind::kInteger) return wrong("a number");
        break;
      case runtime::ValueKind::kString:
        if (value.kind != Kind::kString) return wrong("a string");
        break;
      case runtime::ValueKind::kBoolean:
        if (value.kind != Kind::kBoolean) return wrong("true or false");
        break;
      case runtime::ValueKind::kIntegerList:
        if (value.kind == Kind::kArray) {
          if (!value.items.empty() && value.items.front().kind != Kind::kInteger) {
            return wrong("an array of integers");
          }
        } else if (value.kind != Kind::kInteger) {
          return wrong("an integer or an array of integers");
        }
        break;
      case runtime::ValueKind::kStringList:
        if (value.kind == Kind::kArray) {
          if (!value.items.empty() && value.items.front().kind != Kind::kString) {
            return wrong("an array of strings");
          }
        } else if (value.kind != Kind::kString) {
          return wrong("a string or an array of strings");
        }
        break;
    }
    if ((key == "local" || key == "embedded") && !value.boolean) continue;
    std::string text;
    if (value.kind == Kind::kArray) {
      std::vector<std::string> items;
      for (const ConfigValue& item : value.items) {
        if (item.string.find(',') != std::string::npos) {
          return Error{origin + ": '" + item.string + "' holds a comma"};
        }
        items.push_back(ScalarText(item));
      }
      text = Join(items, ",");
    } else {
      text = ScalarText(value);
    }
    if (key == "maps") text = MapsRelativeToFile(text, file.name);
    values[key] = OptionValue{text, origin};
  }
  return values;
}

OptionValues MergeOptionValues(const OptionValues& file, const OptionValues& command_line) {
  OptionValues merged = file;
  const bool mode_given =
      command_line.count("local") || command_line.count("agents") || command_line.count("embedded");
  if (mode_given) {
    for (const char* mode : {"local", "agents", "embedded"}) merged.erase(mode);
  }
  for (const auto& [name, value] : command_line) merged[name] = value;
  return merged;
}

Result<StudyOptions> ResolveStudyOptions(const OptionValues& values, int hardware_threads) {
  StudyOptions options;
  auto find = [&](const std::string& name) -> const OptionValue* {
    const auto it = values.find(name);
    return it == values.end() ? nullptr : &it->second;
  };
  auto list = [&](const OptionValue& value) -> Result<std::vector<std::string>> {
    std::vector<std::string> pieces = Split(value.text, ',');
    if (value.text.empty() || pieces.empty()) return Error{value.origin + ": the list is empty"};
    for (const std::string& piece : pieces) {
      if (piece.empty()) return Error{value.origin + ": empty item in '" + value.text + "'"};
    }
    return pieces;
  };

  if (const OptionValue* maps = find("maps")) {
    Result<std::vector<std::string>> items = list(*maps);
    if (!items) return items.error();
    Result<std::vector<StudyOptions::Map>> read = ExpandMapList(*items, maps->origin);
    if (!read) return read.error();
    options.maps = *read;
  }
  for (const char* name : {"stations", "movers"}) {
    const OptionValue* value = find(name);
    if (!value) continue;
    if (options.maps.empty()) return Error{value->origin + ": needs maps"};
    Result<CellCount> count = ParseCellCount(value->text);
    if (!count) return Error{value->origin + ": " + count.error().message};
    (std::string(name) == "stations" ? options.stations : options.movers) = value->text;
  }

  // With maps, the generated mazes and the edge case are opt-in.
  const OptionValue default_sizes{options.maps.empty() ? "20,50,100,200,300" : "", "default sizes"};
  const OptionValue* sizes = find("sizes");
  if (!options.maps.empty()) options.edge_case = false;
  Result<std::vector<std::string>> size_items =
      sizes || options.maps.empty() ? list(sizes ? *sizes : default_sizes)
                                    : Result<std::vector<std::string>>(std::vector<std::string>{});
  if (!size_items) return size_items.error();
  for (const std::string& item : *size_items) {
    Result<long long> size = ParseInteger(OptionValue{item, ""}, 2, kMaxSize);
    if (!size) {
      return Error{(sizes ? *sizes : default_sizes).origin + ": size '" + item +
                   "' is not an integer from 2 to " + std::to_string(kMaxSize)};
    }
    if (std::find(options.sizes.begin(), options.sizes.end(), *size) != options.sizes.end()) {
      return Error{(sizes ? *sizes : default_sizes).origin + ": size " + item + " is given twice"};
    }
    options.sizes.push_back(static_cast<int>(*size));
  }

  const OptionValue default_difficulties{"easy,medium,hard", "default difficulties"};
  const OptionValue& difficulties =
      find("difficulties") ? *find("difficulties") : default_difficulties;
  Result<std::vector<std::string>> difficulty_items = list(difficulties);
  if (!difficulty_items) return difficulty_items.error();
  for (const std::string& item : *difficulty_items) {
    const std::optional<Difficulty> difficulty = ParseDifficulty(item);
    if (!difficulty) {
      return Error{difficulties.origin + ": unknown difficulty '" + item +
                   "' (expected easy, medium or hard)"};
    }
    if (std::find(options.difficulties.begin(), options.difficulties.end(), *difficulty) !=
        options.difficulties.end()) {
      return Error{difficulties.origin + ": difficulty " + item + " is given twice"};
    }
    options.difficulties.push_back(*difficulty);
  }

  if (const OptionValue* approaches = find("approaches")) {
    if (Trim(approaches->text).empty()) return Error{approaches->origin + ": the list is empty"};
    Result<std::vector<Approach>> parsed = ParseApproachList(approaches->text);
    if (!parsed) return Error{approaches->origin + ": " + parsed.error().message};
    options.approaches = *parsed;
  } else {
    options.approaches = AllApproaches();
  }

  if (const OptionValue* edge = find("edge-case")) {
    if (edge->text != "true" && edge->text != "false") {
      return Error{edge->origin + ": must be true or false, got '" + edge->text + "'"};
    }
    options.edge_case = edge->text == "true";
  }
  if (const OptionValue* seed = find("seed")) {
    Result<long long> value = ParseInteger(*seed, 0, runtime::kMaxSeed);
    if (!value) return value.error();
    options.seed = static_cast<unsigned>(*value);
  }
  if (const OptionValue* steps = find("steps")) {
    Result<long long> value = ParseInteger(*steps, 0, runtime::kMaxSteps);
    if (!value) return value.error();
    options.steps = static_cast<int>(*value);
  }
  if (const OptionValue* leaf = find("leaf-limit")) {
    Result<long long> value = ParseInteger(*leaf, 1, runtime::kMaxLeafLimit);
    if (!value) return value.error();
    options.leaf_limit = static_cast<int>(*value);
  }
  if (const OptionValue* bootstrap = find("bootstrap")) {
    if (Status status = runtime::CheckBootstrap(bootstrap->text); !status) {
      return Error{bootstrap->origin + ": " + status.error().message};
    }
    options.bootstrap = bootstrap->text;
  }
  if (const OptionValue* semantics = find("semantics")) {
    if (Status status = runtime::CheckSemantics(semantics->text); !status) {
      return Error{semantics->origin + ": " + status.error().message};
    }
    if (semantics->text == "report" && options.bootstrap != "in-grid") {
      return Error{semantics->origin + ": report sets the bootstrap itself; leave bootstrap out"};
    }
    options.semantics = semantics->text;
  }
  if (const OptionValue* placement = find("placement")) {
    if (Status status = runtime::CheckPlacement(placement->text); !status) {
      return Error{placement->origin + ": " + status.error().message};
    }
    options.placement = placement->text;
  }

  // The mode, as `dynapath run` takes it: --embedded may come with --agents N.
  const OptionValue* local = find("local");
  const OptionValue* agents = find("agents");
  const OptionValue* embedded = find("embedded");
  // runtime::ResolveMode decides, as for `dynapath run`; the study only
  // names where the offending value came from.
  runtime::ModeOptions given_mode;
  given_mode.local = local != nullptr;
  given_mode.embedded = embedded != nullptr;
  if (agents) {
    Result<long long> value = ParseInteger(*agents, 1, runtime::kMaxAgents);
    if (!value) return value.error();
    given_mode.agents = *value;
  }
  Result<runtime::RunMode> mode = runtime::ResolveMode(given_mode, runtime::kMaxAgents);
  if (!mode)
    return Error{(local    ? local
                  : agents ? agents
                           : embedded)
                     ->origin +
                 ": " + mode.error().message};
  options.agents = mode->agents;
  switch (mode->kind) {
    case runtime::RunMode::kLocal:
      options.mode = StudyMode::kLocal;
      break;
    case runtime::RunMode::kAgents:
      options.mode = StudyMode::kAgents;
      break;
    case runtime::RunMode::kEmbedded:
      options.mode = StudyMode::kEmbedded;
      break;
  }

  if (const OptionValue* threads = find("threads")) {
    Result<long long> value = ParseInteger(*threads, 1, runtime::kMaxThreads);
    if (!value) return value.error();
    options.threads = static_cast<int>(*value);
  } else {
    options.threads = std::max(1, hardware_threads);
  }
  if (const OptionValue* level = find("log-level")) {
    if (Status status = runtime::CheckLogLevel(level->text); !status) {
      return Error{level->origin + ": " + status.error().message};
    }
    options.log_level = level->text;
  }
  if (const OptionValue* url = find("lcm-url")) {
    if (options.mode != StudyMode::kAgents) {
      return Error{url->origin + ": an LCM URL needs --agents N (processes)"};
    }
    if (url->text.empty()) return Error{url->origin + ": must not be empty"};
    options.lcm_url = url->text;
  }
  if (const OptionValue* out = find("out")) {
    if (out->text.empty()) return Error{out->origin + ": must not be empty"};
    options.out = out->text;
  }
  return options;
}

std::string StudyConfiguration::Name() const {
  if (!map.empty()) return "map_" + map_label + "_" + std::to_string(seed);
  const std::string name =
      std::to_string(size) + "_" + LowerDifficulty(difficulty) + "_" + std::to_string(seed);
  return edge_case ? "edge_" + name : name;
}

std::string StudyConfiguration::SizeText() const {
  return SizeLabel(size, map.empty() ? size : cols);
}

std::string StudyConfiguration::DifficultyText() const {
  return map.empty() ? DifficultyName(difficulty) : map_label;
}

std::string StudyConfiguration::Directory() const { return "runs/" + Name(); }

std::string StudyConfiguration::Label() const {
  if (!map.empty()) {
    return "map " + map_label + " " + SizeLabel(size, cols) + ", seed " + std::to_string(seed);
  }
  return std::string(edge_case ? "edge case " : "") + std::to_string(size) + " " +
         DifficultyName(difficulty) + ", seed " + std::to_string(seed);
}

std::string StudyConfiguration::ShortLabel() const {
  if (!map.empty()) return map_label + " s" + std::to_string(seed);
  return std::string(edge_case ? "edge " : "") + std::to_string(size) + " " +
         DifficultyName(difficulty) + " s" + std::to_string(seed);
}

double StudyConfiguration::Work() const {
  // Relative wall time, fitted to the full study's per-configuration times
  // (docs/EXPERIMENTS.md): a fixed part (process start, the baselines'
  // set-up: about a second) plus (cells x steps)^0.8. Plain cells x steps
  // made the first small configurations predict hours for the 300x300 ones.
  const double cell_steps =
      static_cast<double>(size) * (map.empty() ? size : cols) * (static_cast<double>(steps) + 1.0);
  return 15800.0 + std::pow(cell_steps, 0.8);
}

std::vector<StudyConfiguration> MakeStudyPlan(const StudyOptions& options) {
  std::vector<StudyConfiguration> plan;
  for (const int size : options.sizes) {
    for (const Difficulty difficulty : options.difficulties) {
      StudyConfiguration configuration;
      configuration.size = size;
      configuration.difficulty = difficulty;
      configuration.seed = options.seed ? *options.seed : ReportSeed(difficulty);
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
    configuration.seed = options.seed ? *options.seed : ReportSeed(Difficulty::kEasy);
    configuration.steps = options.steps ? *options.steps : ReportTimeSteps(configuration.size);
    configuration.stations = options.stations;
    configuration.movers = options.movers;
    plan.push_back(configuration);
  }
  return plan;
}

runtime::ScenarioOptions ScenarioOptionsOf(const StudyConfiguration& configuration) {
  runtime::ScenarioOptions options;
  options.seed = configuration.seed;
  options.steps = configuration.steps;
  if (!configuration.map.empty()) {
    options.maze = configuration.map;
    options.stations = configuration.stations;
    if (!configuration.movers.empty()) options.movers = configuration.movers;
    return options;
  }
  options.size = configuration.size;
  options.difficulty = LowerDifficulty(configuration.difficulty);
  return options;
}

runtime::RunOptions RunOptionsOf(const StudyOptions& options, const std::string& out_dir) {
  std::vector<std::string> names;
  for (const Approach approach : options.approaches) names.push_back(ApproachName(approach));
  runtime::RunOptions run;
  run.approach = Join(names, ",");
  run.out = out_dir;
  run.leaf_limit = options.leaf_limit;
  run.bootstrap = options.bootstrap;
  run.semantics = options.semantics;
  run.placement = options.placement;
  return run;
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
  json["leaf_limit"] = options.leaf_limit;
  json["bootstrap"] = options.bootstrap;
  // Only when not the default, so the identity of earlier studies (which had
  // no such option) stays the same and they can still be resumed.
  if (options.semantics != "ours") json["semantics"] = options.semantics;
  if (!options.maps.empty()) {
    Json& maps = json["maps"] = Json::array();
    for (const StudyOptions::Map& map : options.maps) maps.push_back(map.path);
    json["stations"] = options.stations;
    json["movers"] = options.movers;
  }
  return json;
}

Json ExecutionJson(const StudyOptions& options) {
  Json json = Json::object();
  json["mode"] = StudyModeName(options.mode);
  json["agents"] = options.mode == StudyMode::kLocal ? Json() : Json(options.agents);
  json["placement"] = options.mode == StudyMode::kLocal ? Json() : Json(options.placement);
  json["threads"] = options.threads;
  json["lcm_url"] = options.lcm_url.empty() ? Json() : Json(options.lcm_url);
  json["log_level"] = options.log_level;
  json["out"] = options.out;
  return json;
}

}  // namespace dynapath::cli
