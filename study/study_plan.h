#pragma once
// What a study (`dynapath experiment`) runs: its options, taken from the
// command line and from a config file (study_config.h) under the same names,
// and the list of maze configurations they give, in study order.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/repeats.h"
#include "dynapath/approach.h"
#include "dynapath/difficulty.h"
#include "dynapath/map_scenario.h"
#include "dynapath/result.h"
#include "runtime/option_group.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"
#include "study/json.h"
#include "study/study_config.h"

namespace dynapath::study {

// How each configuration of a study runs: runtime::RunMode's kinds, as
// runtime::ResolveMode decides them for `dynapath run`.
using StudyMode = runtime::RunMode::Kind;
// "local", "agents", "embedded".
std::string StudyModeName(StudyMode mode);

// Defaults of the study's own options, written once: StudyOptions and the
// --help text (DeclareStudyCommandLine) take them from here.
inline constexpr const char* kDefaultStations = "0.5%";
inline constexpr const char* kDefaultMovers = "2%";
inline constexpr const char* kDefaultStudyDir = "study";

struct StudyOptions {
  // What the study computes: a study is resumed only with the same values.
  std::vector<int> sizes;
  std::vector<Difficulty> difficulties;
  std::vector<Approach> approaches;
  bool edge_case = true;
  // MovingAI maps, after the generated mazes: their paths, in
  // order (a folder gives its .map files, sorted), with the stations and
  // movers every map gets (N or P% of its free cells, from the seed).
  struct Map {
    std::string path;
    int rows = 0, cols = 0;  // read once, when the options are resolved
    // "a.map:a.stations" in --maps (MAP:FILE): this map's stations from the file
    // ('row col' per line) instead of --stations; "" none.
    std::string stations_file;
  };
  std::vector<Map> maps;
  CellCount stations, movers;    // ResolveStudyOptions: as given, else the defaults above
  std::optional<unsigned> seed;  // none: the report's 50 + difficulty index
  std::optional<int> steps;      // none: the report's 2 x rows
  // --repeats: each configuration runs this many times, repeat k with the
  // learner seed RepeatLearnerSeed gives; --maze-seeds: repeat k on the maze
  // (and change sequence, and a map's stations and movers) of seed
  // maze_seeds[k - 1] instead of --seed or the report's (the edge case keeps
  // its maze). Empty: every repeat on the same maze.
  int repeats = 1;
  std::vector<unsigned> maze_seeds;
  // A study file's parameter given a list (`epsilon-start = [0.01, 0.1]`):
  // the study runs the grid of every swept parameter's values (the first
  // swept parameter varying slowest), each point with the whole plan.
  struct Sweep {
    size_t parameter = 0;  // index in Parameters()
    std::vector<double> values;
  };
  std::vector<Sweep> sweeps;
  // leaf_limit, bootstrap, semantics, placement, the parameters and the
  // learner seed as given (words, for the manifest and the coordinator
  // processes), with `dynapath run`'s defaults and checks; approach and out
  // are each configuration's (RunOptionsOf).
  runtime::RunOptions learner;
  // The same resolved once by `dynapath run`'s resolver, with the study's
  // approaches: the plan every configuration runs (RunPlanOf), its out
  // directory, learner seed and sweep point its own.
  runtime::RunPlan run;
  // How it runs; may change from one session of a study to the next.
  runtime::RunMode mode;  // kind and agents
  int threads = 1;        // ResolveStudyOptions: --threads or the hardware's
  // --parallel: configurations run at once (--local only), each with
  // threads / parallel threads.
  int parallel = 1;
  runtime::LogOptions log;
  std::string lcm_url;
  std::string out = kDefaultStudyDir;
};

// The study's options as given, declared once (DeclareStudyCommandLine):
// the study's own (lists kept as their items: a command line's split at its
// commas where it is read, a study file's array item by item) and the
// groups it shares with `dynapath run`
// (learner options, placement, mode, threads, LCM URL, log level, seed and
// steps). CLI11 parses a command line into it; a study file's values are
// set into its fields by their keys (the same names, with '-' or '_'; the
// declaration on runtime::OptionFields says where each lives and its kind).
struct StudyCommandLine {
  std::optional<std::vector<std::string>> sizes, difficulties, approaches, maps, maze_seeds;
  std::optional<std::string> out, stations, movers;
  bool edge_case = false, no_edge_case = false;
  std::optional<long long> seed, steps, repeats, parallel;
  runtime::RunOptions learner;  // leaf-limit, bootstrap, semantics, placement
  runtime::ModeOptions mode;
  runtime::ThreadOptions threads;
  std::string lcm_url;
  runtime::LogOptions log;
};
void DeclareStudyCommandLine(runtime::OptionGroup& group, StudyCommandLine& options);
// --config FILE of a study (`dynapath experiment`, dynapath.experiment): a
// TOML study file read by toml++ (study_config.h), so that its errors name
// the line (CLI11's own --config would not); the command line overrides it.
void DeclareStudyConfigOption(runtime::OptionGroup& group, std::optional<std::string>& path);
// --repeats N, of `dynapath experiment` and `dynapath run` (which runs its
// repeats in DIR/r<k>).
void DeclareRepeatsOption(runtime::OptionGroup& group, std::optional<long long>& repeats,
                          const std::string& default_text);
// The keys a study file may hold, with their kinds (from the declaration).
const runtime::OptionKinds& StudyOptionKinds();

// Where each given option came from, by option name: "option --sizes" or
// "study.toml:3: sizes".
using OptionOrigins = std::map<std::string, std::string>;

// The study's options as given, typed: the declared struct's values (CLI11's
// parse of a command line, or a study file's values set into its fields by
// their keys), which options were given and from where, and a study file's
// sweeps. --no-edge-case (a file's `edge-case = false`) is given as
// "edge-case".
struct GivenStudyOptions {
  StudyCommandLine values;
  OptionOrigins origins;
  // A parameter given a list of several values in a study file, by name
  // (its value in `values` is the list's first).
  std::map<std::string, std::vector<double>> sweeps;
};

// The options given on a command line that CLI11 parsed into `parsed`
// (declared on `app` with DeclareStudyCommandLine; the app's other options
// are left out); an error when both --edge-case and --no-edge-case are.
Result<GivenStudyOptions> CommandLineStudyOptions(const CLI::App& app,
                                                  const StudyCommandLine& parsed);
// The entries of a study file set into the declared struct by their keys,
// each converted from its TOML value (no command line is built); unknown
// keys, values of the wrong type and empty values are errors naming the
// line. `local = false`, `embedded = false` set nothing. Relative `maps`
// paths are made relative to the file's folder.
Result<GivenStudyOptions> StudyFileOptions(const ConfigFile& file);
// The file's options overridden, option by option, by the command line's.
// A mode given on the command line (--local, --agents, --embedded) replaces
// the file's mode; a parameter given there replaces the file's sweep of it.
GivenStudyOptions MergeStudyOptions(const GivenStudyOptions& file,
                                    const GivenStudyOptions& command_line);
// Checks every given value (unset options keep the declared struct's
// defaults), with `dynapath run`'s own checks where the option is one of
// run's; the first error names the value's origin. `hardware_threads` is
// the default of --threads.
Result<StudyOptions> ResolveStudyOptions(const GivenStudyOptions& given, int hardware_threads);

// One maze of the study.
struct StudyConfiguration {
  int size = 20;
  Difficulty difficulty = Difficulty::kEasy;
  unsigned seed = 50;
  int steps = 40;
  bool edge_case = false;  // the report's edge case, kept in edge_results*.csv
  // A MovingAI map instead of a generated maze: its path, its label in
  // result files (MapLabel) and its columns (`size` holds its rows).
  std::string map, map_label;
  int cols = 0;
  CellCount stations, movers;    // as StudyOptions
  std::string stations_file;     // the map's own (StudyOptions::Map), "" none
  // Its repeat (1..repeats) and the study's repeats; the learner seed of a
  // repeat after the first, or of every repeat with --learner-seed (unset:
  // the maze's seed, the stream of a run without --learner-seed).
  int repeat = 1, repeats = 1;
  std::optional<uint64_t> learner_seed;
  // Its point of the sweep grid: (parameter index, value) per swept
  // parameter; empty without sweeps.
  std::vector<std::pair<size_t, double>> point;
  // "epsilon-start-0.05" ("_"-joined for several); "" without sweeps.
  std::string PointToken() const;

  // "20_easy_50"; the edge case is "edge_50_hard_102"; a map
  // "map_warehouse-10-20-10-2-1_50"; then "_<point token>" at a sweep's
  // point, and "_r<k>" for repeat k > 1: "20_easy_50_epsilon-start-0.05_r2".
  std::string Name() const;
  // The name of the maze (without point and repeat).
  std::string BaseName() const;
  // Its Size and Difficulty columns in result files: "50" and "Hard", or
  // "63x161" and the map's label.
  std::string SizeText() const;
  std::string DifficultyText() const;
  // "runs/<name>", relative to the study directory.
  std::string Directory() const;
  // "50 Hard, seed 52" (the edge case: "edge case 50 Hard, seed 102").
  std::string Label() const;
  // "50 Hard s52" ("edge 50 Hard s102").
  std::string ShortLabel() const;
  // A rough relative cost for the time estimate: about a second of fixed
  // work plus (cells x (steps + 1))^0.8, fitted to a measured full study.
  double Work() const;
};

// Sizes in order, each with the difficulties in order; then the edge case
// (hard 50x50 of seed 102, with --steps when given) when enabled; then the
// maps in order (seed --seed or 50, steps --steps or 2 x rows). Each
// configuration's repeats follow each other (repeat 1 first).
std::vector<StudyConfiguration> MakeStudyPlan(const StudyOptions& options);

// The learner seed of each repeat, and the most repeats: app/repeats.h.
using app::kMaxRepeats;
using app::kRepeatSeedStride;
using app::RepeatLearnerSeed;
inline constexpr size_t kMaxSweepPoints = 1000;

// The scenario of a configuration, typed (size, difficulty, seed, steps; a
// map's path, stations and movers), as `dynapath run` resolves its options'
// (envsim's process takes it as text: runtime::ScenarioOptionsOf).
runtime::ScenarioSpec ScenarioSpecOf(const StudyConfiguration& configuration);
// The run plan of a configuration, built from the study's resolved plan:
// its out directory, its learner seed and its sweep point's parameter values
// (checked when the study was resolved) over the study's. No checkpoint.
runtime::RunPlan RunPlanOf(const StudyOptions& options, const StudyConfiguration& configuration,
                           const std::string& out_dir);
// The same as the options a coordinator process is given (the launcher
// writes them into its config pipe): approaches, out, leaf limit,
// bootstrap, semantics, placement, parameters, the learner seed.
runtime::RunOptions RunOptionsOf(const StudyOptions& options,
                                 const StudyConfiguration& configuration,
                                 const std::string& out_dir);

// The options that determine the results (compared to resume a study), and
// the others, as manifest objects.
// Its "parameters" are every learner and strategy parameter's value.
Json StudyIdentityJson(const StudyOptions& options);
// A study identity read from a manifest, with the default parameters when it
// has none (a study of a version before parameters were options ran with
// the defaults) and its stations and movers in their shortest spelling
// (runtime::CellCountText: "0.50%" is "0.5%"), so that it compares with
// StudyIdentityJson.
Json StudyIdentityWithParameters(Json identity);
Json ExecutionJson(const StudyOptions& options);

}  // namespace dynapath::study
