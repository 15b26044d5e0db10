#include "study/study_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "tests/study_command_line.h"
#include "tests/temp_path.h"

namespace dynapath::study {
namespace {

// A command line's options, parsed by CLI11 as `dynapath experiment` does.
Result<GivenStudyOptions> Cli(std::initializer_list<std::pair<std::string, std::string>> values) {
  return test_support::ParseStudyCommandLine(values);
}

// A command line resolved; its parse error when CLI11 refused it.
Result<StudyOptions> Resolve(const Result<GivenStudyOptions>& given, int threads) {
  if (!given) return given.error();
  return study::ResolveStudyOptions(*given, threads);
}

Result<StudyOptions> FromFile(const std::string& text) {
  Result<ConfigFile> file = ParseConfigText(text, "s.toml");
  if (!file) return file.error();
  Result<GivenStudyOptions> values = StudyFileOptions(*file);
  if (!values) return values.error();
  return study::ResolveStudyOptions(*values, 4);
}

TEST(StudyPlanTest, DefaultsAreTheReportsStudy) {
  Result<StudyOptions> options = ResolveStudyOptions(GivenStudyOptions{}, 4);
  ASSERT_TRUE(options) << options.error().message;
  EXPECT_EQ(options->sizes, (std::vector<int>{20, 50, 100, 200, 300}));
  EXPECT_EQ(options->approaches, AllApproaches());
  EXPECT_TRUE(options->edge_case);
  EXPECT_EQ(options->mode.kind, StudyMode::kLocal);
  EXPECT_EQ(options->threads, 4);
  EXPECT_EQ(options->out, "study");

  const std::vector<StudyConfiguration> plan = MakeStudyPlan(*options);
  ASSERT_EQ(plan.size(), 16u);
  // Sizes in order, each with easy, medium, hard; seeds 50 + difficulty index;
  // 2 x rows time steps.
  const char* names[] = {"20_easy_50",   "20_medium_51",  "20_hard_52",    "50_easy_50",
                         "50_medium_51", "50_hard_52",    "100_easy_50",   "100_medium_51",
                         "100_hard_52",  "200_easy_50",   "200_medium_51", "200_hard_52",
                         "300_easy_50",  "300_medium_51", "300_hard_52",   "edge_50_hard_102"};
  for (size_t i = 0; i < plan.size(); ++i) {
    EXPECT_EQ(plan[i].Name(), names[i]) << i;
    EXPECT_EQ(plan[i].steps, 2 * plan[i].size) << i;
    EXPECT_EQ(plan[i].edge_case, i == 15) << i;
  }
  EXPECT_EQ(plan[15].size, 50);
  EXPECT_EQ(plan[15].difficulty, Difficulty::kHard);
  EXPECT_EQ(plan[15].seed, 102u);
  EXPECT_EQ(plan[15].Directory(), "runs/edge_50_hard_102");
  EXPECT_EQ(plan[15].Label(), "edge case 50 Hard, seed 102");
  EXPECT_EQ(plan[4].Label(), "50 Medium, seed 51");
  EXPECT_EQ(plan[4].ShortLabel(), "50 Medium s51");
  EXPECT_EQ(plan[15].ShortLabel(), "edge 50 Hard s102");
  EXPECT_DOUBLE_EQ(plan[0].Work(), 15800.0 + std::pow(20.0 * 20 * 41, 0.8));
}

TEST(StudyPlanTest, SeedStepsAndEdgeCaseOptions) {
  Result<StudyOptions> options = Resolve(Cli({{"sizes", "50, 20"},
                                              {"difficulties", "hard,easy"},
                                              {"seed", "7"},
                                              {"steps", "10"},
                                              {"approaches", "BFS Oracle,fedAsynQ_ImAvg"}}),
                                         2);
  ASSERT_TRUE(options) << options.error().message;
  std::vector<StudyConfiguration> plan = MakeStudyPlan(*options);
  ASSERT_EQ(plan.size(), 5u);
  EXPECT_EQ(plan[0].Name(), "50_hard_7");
  EXPECT_EQ(plan[1].Name(), "50_easy_7");
  EXPECT_EQ(plan[2].Name(), "20_hard_7");
  EXPECT_EQ(plan[3].Name(), "20_easy_7");
  // The edge case keeps its seed, takes --steps.
  EXPECT_EQ(plan[4].Name(), "edge_50_hard_102");
  EXPECT_EQ(plan[4].steps, 10);
  const runtime::ScenarioSpec scenario = ScenarioSpecOf(plan[0]);
  EXPECT_EQ(scenario.size, 50);
  EXPECT_EQ(scenario.difficulty, Difficulty::kHard);
  EXPECT_EQ(scenario.seed, 7);
  EXPECT_EQ(scenario.steps, 10);
  EXPECT_FALSE(scenario.maze || scenario.cols || scenario.replay || scenario.stations);
  // As envsim's process gets it: the words `dynapath run` takes.
  const runtime::ScenarioOptions maze_words = runtime::ScenarioOptionsOf(scenario);
  EXPECT_EQ(maze_words.size, 50);
  EXPECT_EQ(maze_words.difficulty, "hard");
  EXPECT_FALSE(maze_words.maze || maze_words.stations || maze_words.movers);
  // The configuration's run plan, built from the study's typed plan.
  const runtime::RunPlan run = RunPlanOf(*options, plan[0], "out/runs/x");
  EXPECT_EQ(run.approaches,
            (std::vector<Approach>{Approach::kBfsOracle, Approach::kFedAsynQImAvg}));
  EXPECT_EQ(run.out_dir, "out/runs/x");
  EXPECT_EQ(run.options.leaf_limit, 20);
  EXPECT_EQ(run.options.bootstrap, PlannerOptions{}.bootstrap);
  EXPECT_EQ(run.options.semantics, Semantics::kOurs);
  EXPECT_EQ(run.placement, runtime::Placement::kAuto);
  EXPECT_FALSE(run.learner_seed);
  EXPECT_TRUE(run.checkpoint.dir.empty());
  // A coordinator process's options, as it resolves them: the same plan.
  const runtime::RunOptions words = RunOptionsOf(*options, plan[0], "out/runs/x");
  EXPECT_EQ(words.approach, "BFS Oracle,fedAsynQ_ImAvg");
  EXPECT_EQ(words.out, "out/runs/x");
  EXPECT_EQ(words.bootstrap, "in-grid");
  EXPECT_EQ(words.semantics, "ours");
  EXPECT_EQ(words.placement, "auto");
  Result<runtime::RunPlan> resolved = runtime::ResolveRunOptions(words);
  ASSERT_TRUE(resolved) << resolved.error().message;
  EXPECT_EQ(resolved->approaches, run.approaches);
  EXPECT_EQ(resolved->options.leaf_limit, run.options.leaf_limit);
  EXPECT_EQ(RunPlanToml(*resolved), RunPlanToml(run));

  options = Resolve(Cli({{"sizes", "20"}, {"edge-case", "false"}}), 2);
  ASSERT_TRUE(options);
  plan = MakeStudyPlan(*options);
  ASSERT_EQ(plan.size(), 3u);
  EXPECT_EQ(plan[2].Name(), "20_hard_52");
}

TEST(StudyPlanTest, ConfigFileValuesAndCommandLineOverrides) {
  Result<ConfigFile> file = ParseConfigText(
      "sizes = [20, 50]\n"
      "difficulties = 'easy'\n"
      "approaches = [\"A* Static\", \"singleAgent\"]\n"
      "edge_case = false\n"
      "agents = 3\n"
      "leaf-limit = 10\n"
      "local = false\n"
      "out = \"from-file\"\n",
      "s.toml");
  ASSERT_TRUE(file) << file.error().message;
  Result<GivenStudyOptions> values = StudyFileOptions(*file);
  ASSERT_TRUE(values) << values.error().message;
  EXPECT_EQ(values->values.sizes, (std::vector<std::string>{"20", "50"}));
  EXPECT_EQ(values->values.approaches, (std::vector<std::string>{"A* Static", "singleAgent"}));
  EXPECT_EQ(values->origins.at("sizes"), "s.toml:1: sizes");
  EXPECT_EQ(values->values.mode.agents, 3);
  EXPECT_EQ(values->values.learner.leaf_limit, 10);
  EXPECT_TRUE(values->values.no_edge_case);
  EXPECT_EQ(values->origins.at("edge-case"), "s.toml:4: edge-case");
  EXPECT_EQ(values->origins.count("local"), 0u);  // false sets nothing
  EXPECT_FALSE(values->values.mode.local);

  Result<StudyOptions> options = study::ResolveStudyOptions(*values, 2);
  ASSERT_TRUE(options) << options.error().message;
  EXPECT_EQ(options->sizes, (std::vector<int>{20, 50}));
  EXPECT_EQ(options->difficulties, (std::vector<Difficulty>{Difficulty::kEasy}));
  EXPECT_EQ(options->approaches,
            (std::vector<Approach>{Approach::kAStarStatic, Approach::kSingleAgent}));
  EXPECT_FALSE(options->edge_case);
  EXPECT_EQ(options->mode.kind, StudyMode::kAgents);
  EXPECT_EQ(options->mode.agents, 3);
  EXPECT_EQ(options->learner.leaf_limit, 10);

  // The command line wins; its mode replaces the file's.
  options = study::ResolveStudyOptions(
      MergeStudyOptions(*values, *Cli({{"local", "true"}, {"sizes", "30"}, {"out", "cli"}})), 2);
  ASSERT_TRUE(options) << options.error().message;
  EXPECT_EQ(options->mode.kind, StudyMode::kLocal);
  EXPECT_EQ(options->sizes, (std::vector<int>{30}));
  EXPECT_EQ(options->out, "cli");
  EXPECT_EQ(options->learner.leaf_limit, 10);

  options = study::ResolveStudyOptions(MergeStudyOptions(*values, *Cli({{"embedded", "true"}})), 2);
  ASSERT_TRUE(options) << options.error().message;
  EXPECT_EQ(options->mode.kind, StudyMode::kEmbedded);
  EXPECT_EQ(options->mode.agents, 1);
}

// A study file's values are set into the declared options by their keys,
// typed (no command line is built): either spelling of a key, integers,
// numbers and words as the file gives them; an empty value, a key given
// twice or a value of the wrong type is refused naming the key and line.
TEST(StudyPlanTest, FileValuesAreSetIntoTheirOptionsTyped) {
  Result<ConfigFile> file = ParseConfigText(
      "epsilon_start = 0.25\nlearners = 3\nleaf_limit = 7\nlearner-seed = 9\n"
      "bootstrap = 'in-region'\nthreads = 3\nmaze_seeds = [4, 5]\nembedded = true\n",
      "s.toml");
  ASSERT_TRUE(file) << file.error().message;
  Result<GivenStudyOptions> given = StudyFileOptions(*file);
  ASSERT_TRUE(given) << given.error().message;
  const StudyCommandLine& values = given->values;
  EXPECT_EQ(values.learner.parameters.reals[1], 0.25);
  EXPECT_EQ(values.learner.parameters.integers[11], 3);
  EXPECT_EQ(values.learner.leaf_limit, 7);
  EXPECT_EQ(values.learner.learner_seed, 9);
  EXPECT_EQ(values.learner.bootstrap, "in-region");
  EXPECT_EQ(values.threads.threads, 3);
  EXPECT_EQ(values.maze_seeds, (std::vector<std::string>{"4", "5"}));
  EXPECT_TRUE(values.mode.embedded);
  EXPECT_EQ(given->origins.at("epsilon-start"), "s.toml:1: epsilon-start");
  EXPECT_TRUE(given->sweeps.empty());
  Result<StudyOptions> options = study::ResolveStudyOptions(*given, 2);
  ASSERT_TRUE(options) << options.error().message;
  EXPECT_EQ(options->run.options.single_agent.epsilon_start, 0.25);
  EXPECT_EQ(options->run.options.federated.learners, 3);
  EXPECT_EQ(options->run.options.leaf_limit, 7);
  EXPECT_EQ(options->run.learner_seed, 9u);
  EXPECT_EQ(options->repeats, 2);
  EXPECT_EQ(options->mode.kind, StudyMode::kEmbedded);

  const std::pair<const char*, const char*> bad[] = {
      {"\nout = ''\n", "s.toml:2: out: must not be empty"},
      {"difficulties = []\n", "s.toml:1: difficulties: must not be empty"},
      {"leaf_limit = 'x'\n", "s.toml:1: leaf-limit: expected an integer, got a string"},
      {"threads = 2\nthreads = 3\n",
       "s.toml:2: Error while parsing key-value pair: cannot redefine"},
      {"leaf-limit = 2\nleaf_limit = 3\n", "s.toml:2: 'leaf_limit' gives 'leaf-limit' of line 1"},
  };
  for (const auto& [text, expected] : bad) {
    Result<StudyOptions> refused = FromFile(text);
    ASSERT_FALSE(refused) << text;
    EXPECT_EQ(refused.error().message.rfind(expected, 0), 0u) << refused.error().message;
  }
}

// Maps: a folder gives its maps in name order, after any mazes;
// with maps, sizes and the edge case default to none; each map run is the
// `dynapath run --maze` of its path with the study's stations and movers.
TEST(StudyPlanTest, MapsFromFilesAndFolders) {
  const std::string maps = std::string(DYNAPATH_TEST_DATA_DIR) + "/maps";
  Result<StudyOptions> options = Resolve(Cli({{"maps", maps}, {"movers", "3"}}), 2);
  ASSERT_TRUE(options) << options.error().message;
  ASSERT_EQ(options->maps.size(), 2u);
  EXPECT_EQ(options->maps[0].path, maps + "/maze-25-61-1.map");
  EXPECT_EQ(options->maps[1].path, maps + "/wide-5-9.map");
  EXPECT_EQ(options->maps[0].rows, 25);
  EXPECT_EQ(options->maps[0].cols, 61);
  EXPECT_TRUE(options->sizes.empty());
  EXPECT_FALSE(options->edge_case);
  EXPECT_EQ(options->stations.percent, 0.5);
  EXPECT_EQ(options->movers.count, 3);
  EXPECT_LT(options->movers.percent, 0);
  const std::vector<StudyConfiguration> plan = MakeStudyPlan(*options);
  ASSERT_EQ(plan.size(), 2u);
  EXPECT_EQ(plan[0].Name(), "map_maze-25-61-1_50");
  EXPECT_EQ(plan[0].Directory(), "runs/map_maze-25-61-1_50");
  EXPECT_EQ(plan[0].Label(), "map maze-25-61-1 25x61, seed 50");
  EXPECT_EQ(plan[0].ShortLabel(), "maze-25-61-1 s50");
  EXPECT_EQ(plan[0].SizeText(), "25x61");
  EXPECT_EQ(plan[0].DifficultyText(), "maze-25-61-1");
  EXPECT_EQ(plan[0].steps, 50);  // 2 x rows
  EXPECT_EQ(plan[1].Name(), "map_wide-5-9_50");
  EXPECT_EQ(plan[1].steps, 10);
  EXPECT_DOUBLE_EQ(plan[1].Work(), 15800.0 + std::pow(5.0 * 9 * 11, 0.8));
  const runtime::ScenarioSpec scenario = ScenarioSpecOf(plan[1]);
  EXPECT_EQ(scenario.maze, maps + "/wide-5-9.map");
  ASSERT_TRUE(scenario.stations && scenario.movers);
  EXPECT_EQ(scenario.stations->percent, 0.5);
  EXPECT_EQ(scenario.movers->count, 3);
  EXPECT_EQ(scenario.seed, 50);
  EXPECT_EQ(scenario.steps, 10);
  EXPECT_FALSE(scenario.difficulty || scenario.size);
  const runtime::ScenarioOptions words = runtime::ScenarioOptionsOf(scenario);
  EXPECT_EQ(words.stations, "0.5%");
  EXPECT_EQ(words.movers, "3");
  EXPECT_FALSE(words.difficulty);
  const Json identity = StudyIdentityJson(*options);
  EXPECT_EQ(identity["maps"].size(), 2u);
  EXPECT_EQ(identity["stations"], "0.5%");
  EXPECT_EQ(identity["movers"], "3");
  // A manifest's other spelling of the same values is the same study.
  Json written = identity;
  written["stations"] = "0.50%";
  written["movers"] = "03";
  EXPECT_EQ(StudyIdentityWithParameters(written), identity);
  written["movers"] = "4";
  EXPECT_NE(StudyIdentityWithParameters(written), identity);

  // Mazes and the edge case when asked for, before the maps; one map file.
  options = Resolve(Cli({{"maps", maps + "/wide-5-9.map"},
                         {"sizes", "20"},
                         {"difficulties", "hard"},
                         {"edge-case", "true"},
                         {"seed", "7"},
                         {"steps", "4"}}),
                    2);
  ASSERT_TRUE(options) << options.error().message;
  const std::vector<StudyConfiguration> mixed = MakeStudyPlan(*options);
  ASSERT_EQ(mixed.size(), 3u);
  EXPECT_EQ(mixed[0].Name(), "20_hard_7");
  EXPECT_TRUE(mixed[1].edge_case);
  EXPECT_EQ(mixed[2].Name(), "map_wide-5-9_7");
  EXPECT_EQ(mixed[2].steps, 4);
  // Without maps, nothing about them enters the identity (old studies resume).
  EXPECT_FALSE(
      StudyIdentityJson(*study::ResolveStudyOptions(GivenStudyOptions{}, 2)).contains("maps"));
}

TEST(StudyPlanTest, BadMapOptions) {
  const std::string maps = std::string(DYNAPATH_TEST_DATA_DIR) + "/maps";
  const std::pair<Result<GivenStudyOptions>, std::string> cases[] = {
      {Cli({{"maps", maps + "/missing.map"}}), "option --maps: " + maps + "/missing.map: cannot"},
      {Cli({{"maps", std::string(DYNAPATH_TEST_DATA_DIR)}}), "option --maps: folder "},
      {Cli({{"maps", maps + "/wide-5-9.stations"}}),
       "option --maps: " + maps + "/wide-5-9.stations"},
      {Cli({{"maps", maps + "/wide-5-9.map," + maps}}), "option --maps: map "},
      {Cli({{"stations", "3"}}), "option --stations: needs maps"},
      {Cli({{"maps", maps}, {"movers", "lots"}}), "option --movers: expected a count"},
  };
  for (const auto& [values, expected] : cases) {
    Result<StudyOptions> options = Resolve(values, 2);
    ASSERT_FALSE(options) << expected;
    EXPECT_EQ(options.error().message.rfind(expected, 0), 0u) << options.error().message;
  }
}

// A MovingAI map of `rows` x `cols` free cells at `path` (its folder made).
void WriteMap(const std::filesystem::path& path, int rows, int cols) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path);
  out << "type octile\nheight " << rows << "\nwidth " << cols << "\nmap\n";
  for (int r = 0; r < rows; ++r) out << std::string(static_cast<size_t>(cols), '.') << "\n";
}

// Two maps named alike would share runs/map_<name>_<seed> and the
// Difficulty column (one map's results lost, two identical rows); one file
// reached by two spellings would run twice. Both are refused, naming both.
TEST(StudyPlanTest, MapsOfOneNameOrOneFileAreRefused) {
  namespace fs = std::filesystem;
  const fs::path root = test_paths::UniqueTempPath("maps");
  WriteMap(root / "a" / "x.map", 3, 7);
  WriteMap(root / "b" / "x.map", 7, 3);
  const std::string a = (root / "a").string(), b = (root / "b").string();
  Result<StudyOptions> options = Resolve(Cli({{"maps", a + "," + b}}), 2);
  ASSERT_FALSE(options);
  EXPECT_EQ(options.error().message, "option --maps: maps " + a + "/x.map and " + b +
                                         "/x.map have the same name 'x' (their runs and result "
                                         "rows would be mixed up); rename one");

  const std::string wide = std::string(DYNAPATH_TEST_DATA_DIR) + "/maps/wide-5-9.map";
  const std::string other_spelling =
      std::string(DYNAPATH_TEST_DATA_DIR) + "/maps/../maps/./wide-5-9.map";
  options = Resolve(Cli({{"maps", wide + "," + other_spelling}}), 2);
  ASSERT_FALSE(options);
  EXPECT_EQ(options.error().message,
            "option --maps: maps " + wide + " and " + other_spelling + " are the same file");

  // In a study file too, with its origin.
  options = FromFile("maps = ['" + a + "/x.map', '" + b + "/x.map']\n");
  ASSERT_FALSE(options);
  EXPECT_EQ(options.error().message.rfind("s.toml:1: maps: maps " + a + "/x.map and ", 0), 0u)
      << options.error().message;
  fs::remove_all(root);
}

// A study file's relative map paths are relative to its folder;
// the command line's to the working directory (the tests run in the build
// tree, which has no maps/ folder).
// MAP.map:FILE: that map's stations from a file, checked before the study,
// handed to its run as --stations-file and kept in the identity.
TEST(StudyPlanTest, AMapMayHaveItsOwnStationsFile) {
  const std::string maps = std::string(DYNAPATH_TEST_DATA_DIR) + "/maps";
  const std::string wide = maps + "/wide-5-9.map", stations = maps + "/wide-5-9.stations";
  Result<StudyOptions> options =
      Resolve(Cli({{"maps", wide + ":" + stations + "," + maps + "/maze-25-61-1.map"}}), 2);
  ASSERT_TRUE(options) << options.error().message;
  ASSERT_EQ(options->maps.size(), 2u);
  EXPECT_EQ(options->maps[0].path, wide);
  EXPECT_EQ(options->maps[0].stations_file, stations);
  EXPECT_EQ(options->maps[1].stations_file, "");
  const std::vector<StudyConfiguration> plan = MakeStudyPlan(*options);
  ASSERT_EQ(plan.size(), 2u);
  EXPECT_EQ(plan[0].Name(), "map_wide-5-9_50");
  runtime::ScenarioSpec scenario = ScenarioSpecOf(plan[0]);
  EXPECT_EQ(scenario.stations_file, stations);
  EXPECT_FALSE(scenario.stations);
  scenario = ScenarioSpecOf(plan[1]);
  ASSERT_TRUE(scenario.stations);
  EXPECT_EQ(scenario.stations->percent, 0.5);
  EXPECT_FALSE(scenario.stations_file);
  EXPECT_EQ(StudyIdentityJson(*options)["maps"][0], wide + ":" + stations);

  // In a study file both paths are relative to its folder.
  const std::string data = DYNAPATH_TEST_DATA_DIR;
  Result<ConfigFile> file =
      ParseConfigText("maps = ['maps/wide-5-9.map:maps/wide-5-9.stations']\n", data + "/s.toml");
  ASSERT_TRUE(file);
  Result<GivenStudyOptions> values = StudyFileOptions(*file);
  ASSERT_TRUE(values) << values.error().message;
  EXPECT_EQ(values->values.maps, std::vector<std::string>{data + "/maps/wide-5-9.map:" + data +
                                                          "/maps/wide-5-9.stations"});

  // A missing stations file or one for a folder: one error before the study.
  options = Resolve(Cli({{"maps", wide + ":" + maps + "/none.stations"}}), 2);
  ASSERT_FALSE(options);
  EXPECT_NE(options.error().message.find("none.stations"), std::string::npos)
      << options.error().message;
  options = Resolve(Cli({{"maps", maps + ":" + stations}}), 2);
  ASSERT_FALSE(options);
  EXPECT_NE(options.error().message.find("a stations file is one map's, not a folder's"),
            std::string::npos)
      << options.error().message;
}

TEST(StudyPlanTest, StudyFileMapsAreRelativeToTheFile) {
  const std::string data = DYNAPATH_TEST_DATA_DIR;
  Result<ConfigFile> file = ParseConfigText(
      "maps = ['maps/wide-5-9.map', '" + data + "/maps/maze-25-61-1.map']\n", data + "/s.toml");
  ASSERT_TRUE(file) << file.error().message;
  Result<GivenStudyOptions> values = StudyFileOptions(*file);
  ASSERT_TRUE(values) << values.error().message;
  EXPECT_EQ(
      values->values.maps,  // the second, absolute, kept
      (std::vector<std::string>{data + "/maps/wide-5-9.map", data + "/maps/maze-25-61-1.map"}));
  Result<StudyOptions> options = study::ResolveStudyOptions(*values, 2);
  ASSERT_TRUE(options) << options.error().message;
  ASSERT_EQ(options->maps.size(), 2u);
  EXPECT_EQ(options->maps[0].path, data + "/maps/wide-5-9.map");
  EXPECT_EQ(options->maps[0].rows, 5);

  // A file in the working directory: its paths stay as written.
  file = ParseConfigText("maps = 'maps/wide-5-9.map'\n", "s.toml");
  ASSERT_TRUE(file);
  values = StudyFileOptions(*file);
  ASSERT_TRUE(values);
  EXPECT_EQ(values->values.maps, std::vector<std::string>{"maps/wide-5-9.map"});
  // The command line's relative paths are the working directory's.
  options = Resolve(Cli({{"maps", "maps/wide-5-9.map"}}), 2);
  ASSERT_FALSE(options);
  EXPECT_EQ(options.error().message.rfind("option --maps: maps/wide-5-9.map: cannot", 0), 0u)
      << options.error().message;
}

TEST(StudyPlanTest, BadValuesGiveOneErrorNamingTheirOrigin) {
  const std::pair<Result<GivenStudyOptions>, const char*> cases[] = {
      {Cli({{"sizes", "1"}}), "option --sizes: size '1' is not an integer from 2 to 4096"},
      {Cli({{"sizes", "20,abc"}}), "option --sizes: size 'abc' is not an integer"},
      {Cli({{"sizes", "20,50,20"}}), "option --sizes: size 20 is given twice"},
      {Cli({{"sizes", "20,,50"}}), "option --sizes: empty item"},
      // Refused by the parse, as `dynapath experiment` refuses them.
      {Cli({{"sizes", ""}}), "option --sizes must not be empty"},
      {Cli({{"difficulties", "easy,extreme"}}),
       "option --difficulties: unknown difficulty 'extreme'"},
      {Cli({{"difficulties", "hard,HARD"}}),
       "option --difficulties: difficulty HARD is given twice"},
      {Cli({{"approaches", "magic"}}), "option --approaches: unknown approach 'magic'"},
      {Cli({{"seed", "-1"}}), "option --seed: must be between 0 and 4294967295"},
      {Cli({{"steps", "x"}}), "option --steps needs a decimal number, got 'x'"},
      {Cli({{"agents", "0"}}), "option --agents: must be between 1 and 256"},
      {Cli({{"local", "true"}, {"agents", "2"}}), "option --local: choose one of"},
      {Cli({{"lcm-url", "udpm://"}}), "option --lcm-url: an LCM URL needs --agents N"},
      {Cli({{"bootstrap", "both"}}), "option --bootstrap: must be in-grid or in-region"},
      {Cli({{"semantics", "theirs"}}), "option --semantics: must be ours or report"},
      {Cli({{"semantics", "report"}, {"bootstrap", "in-region"}}),
       "option --semantics: report sets the bootstrap itself"},
      {Cli({{"log-level", "loud"}}), "option --log-level: must be trace"},
      {Cli({{"out", ""}}), "option --out must not be empty"},
  };
  for (const auto& [values, expected] : cases) {
    Result<StudyOptions> options = Resolve(values, 2);
    ASSERT_FALSE(options) << expected;
    EXPECT_EQ(options.error().message.rfind(expected, 0), 0u) << options.error().message;
  }
}

// A command line's list is split at its commas where it is read, a study
// file's array kept item by item; each item is trimmed when resolved, and
// an error quotes the list as written.
TEST(StudyPlanTest, ListsAreCarriedAsTheirItems) {
  Result<GivenStudyOptions> given =
      Cli({{"sizes", "50, 20"}, {"approaches", " BFS Oracle,A* Static"}, {"maze-seeds", "3,4"}});
  ASSERT_TRUE(given) << given.error().message;
  EXPECT_EQ(given->values.sizes, (std::vector<std::string>{"50", " 20"}));
  EXPECT_EQ(given->values.approaches, (std::vector<std::string>{" BFS Oracle", "A* Static"}));
  Result<StudyOptions> options = study::ResolveStudyOptions(*given, 2);
  ASSERT_TRUE(options) << options.error().message;
  EXPECT_EQ(options->sizes, (std::vector<int>{50, 20}));
  EXPECT_EQ(options->approaches,
            (std::vector<Approach>{Approach::kBfsOracle, Approach::kAStarStatic}));
  EXPECT_EQ(options->maze_seeds, (std::vector<unsigned>{3, 4}));
  EXPECT_EQ(options->repeats, 2);

  const std::pair<Result<StudyOptions>, const char*> refused[] = {
      {Resolve(Cli({{"sizes", "20, ,50"}}), 2), "option --sizes: empty item in '20, ,50'"},
      {Resolve(Cli({{"maze-seeds", "1,"}}), 2), "option --maze-seeds: empty item in '1,'"},
      {FromFile("difficulties = ['easy', ' ']\n"),
       "s.toml:1: difficulties: empty item in 'easy, '"},
      {FromFile("approaches = [' ']\n"), "s.toml:1: approaches: the list is empty"},
      {FromFile("maps = ['']\n"), "s.toml:1: maps: must not be empty"},
      {FromFile("difficulties = ['easy,hard']\n"),
       "s.toml:1: difficulties: 'easy,hard' holds a comma"},
  };
  for (const auto& [result, expected] : refused) {
    ASSERT_FALSE(result) << expected;
    EXPECT_EQ(result.error().message, expected);
  }
}

TEST(StudyPlanTest, BadFileValuesNameTheLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"sizes = [20]\ncolour = 'red'\n", "s.toml:2: unknown key 'colour'"},
      {"\nsteps = '10'\n", "s.toml:2: steps: expected an integer, got a string"},
      {"\nsteps = 1.5\n", "s.toml:2: steps: expected an integer, got a float"},
      {"sizes = '20'\n", "s.toml:1: sizes: expected an integer or an array of integers"},
      {"sizes = [20,\n 1]\n", "s.toml:1: sizes: size '1' is not an integer from 2"},
      {"difficulties = [1]\n", "s.toml:1: difficulties: expected an array of strings"},
      {"\n\nedge-case = 'no'\n", "s.toml:3: edge-case: expected true or false"},
      {"approaches = ['magic']\n", "s.toml:1: approaches: unknown approach 'magic'"},
      {"approaches = ['A* Static,BFS Oracle']\n",
       "s.toml:1: approaches: 'A* Static,BFS Oracle' holds a comma"},
      {"local = true\nagents = 2\n", "s.toml:1: local: choose one of"},
  };
  for (const auto& [text, expected] : cases) {
    Result<StudyOptions> options = FromFile(text);
    ASSERT_FALSE(options) << text;
    EXPECT_EQ(options.error().message.rfind(expected, 0), 0u) << options.error().message;
  }
}

// The runtime checks' errors are placed by their subject (the option they
// concern), not by their text: the message names the value's origin, the
// code and subject stay.
TEST(StudyPlanTest, CheckedValuesAreLocatedByTheirSubject) {
  const struct {
    Result<StudyOptions> options;
    const char* message;
    const char* subject;
  } cases[] = {
      {FromFile("\nseed = -1\n"), "s.toml:2: seed: must be between 0 and 4294967295, got -1",
       "seed"},
      {FromFile("leaf-limit = 0\n"), "s.toml:1: leaf-limit: must be between 1 and 10000, got 0",
       "leaf-limit"},
      {FromFile("semantics = 'report'\nbootstrap = 'in-region'\n"),
       "s.toml:1: semantics: report sets the bootstrap itself; leave --bootstrap out", "semantics"},
      {Resolve(Cli({{"placement", "none"}}), 2),
       "option --placement: must be auto, whole or split, got 'none'", "placement"},
      {Resolve(Cli({{"threads", "0"}}), 2), "option --threads: must be between 1 and 1024, got 0",
       "threads"},
      {Resolve(Cli({{"local", "true"}, {"agents", "2"}}), 2),
       "option --local: choose one of --local, --agents N and --embedded", "local"},
  };
  for (const auto& c : cases) {
    ASSERT_FALSE(c.options) << c.message;
    EXPECT_EQ(c.options.error().message, c.message);
    EXPECT_EQ(c.options.error().code, Error::Code::kInvalidArgument) << c.message;
    EXPECT_EQ(c.options.error().subject, c.subject) << c.message;
  }
}

TEST(StudyPlanTest, IdentityHoldsWhatDeterminesTheResults) {
  Result<StudyOptions> a = Resolve(Cli({{"sizes", "20"}, {"steps", "10"}}), 2);
  Result<StudyOptions> b = Resolve(
      Cli({{"sizes", "20"}, {"steps", "10"}, {"agents", "2"}, {"threads", "7"}, {"out", "x"}}), 2);
  Result<StudyOptions> c = Resolve(Cli({{"sizes", "20"}, {"steps", "11"}}), 2);
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(StudyIdentityJson(*a), StudyIdentityJson(*b));  // mode, threads, out do not count
  EXPECT_NE(StudyIdentityJson(*a), StudyIdentityJson(*c));
  EXPECT_EQ(DumpJson(StudyIdentityJson(*a), -1),
            "{\"sizes\":[20],\"difficulties\":[\"easy\",\"medium\",\"hard\"],\"approaches\":[\"A* "
            "Static\",\"A* Oracle\",\"BFS Oracle\",\"onlyTrainLeafNodes\",\"singleAgent\","
            "\"fedAsynQ_EqAvg\",\"fedAsynQ_ImAvg\",\"Incremental "
            "Oracle\"],\"edge_case\":true,\"seed\":null,\"steps\":10,"
            "\"leaf_limit\":20,\"bootstrap\":\"in-grid\",\"parameters\":{\"max-episodes\":10000,"
            "\"epsilon-start\":1.0,\"epsilon-decay\":0.999,\"epsilon-min\":0.01,\"replay-"
            "capacity\":1000,\"replay-start-episode\":500,\"replay-batch\":64,\"convergence-"
            "start-episode\":500,\"convergence-interval\":50,\"convergence-threshold\":0.0005,"
            "\"convergence-checks\":21,\"learners\":12,\"sync-period\":1000,\"iterations-per-"
            "cell\":200,\"max-drop\":0.01,\"min-success-rate\":0.9,\"escalate-below\":0.9}}");
  // A parameter changes the results: part of the identity, by name.
  Result<StudyOptions> e = Resolve(
      Cli({{"sizes", "20"}, {"steps", "10"}, {"epsilon-start", "0.3"}, {"learners", "4"}}), 2);
  ASSERT_TRUE(e);
  EXPECT_NE(StudyIdentityJson(*a), StudyIdentityJson(*e));
  EXPECT_EQ(StudyIdentityJson(*e)["parameters"]["epsilon-start"].get<double>(), 0.3);
  EXPECT_EQ(StudyIdentityJson(*e)["parameters"]["learners"].get<int>(), 4);
  EXPECT_EQ(RunPlanOf(*e, MakeStudyPlan(*e)[0], "x").options.single_agent.epsilon_start, 0.3);
  EXPECT_EQ(RunPlanOf(*e, MakeStudyPlan(*e)[0], "x").options.federated.learners, 4);
  // A manifest of a study before parameters were options: the defaults.
  Json earlier = StudyIdentityJson(*a);
  earlier.erase("parameters");
  EXPECT_EQ(StudyIdentityWithParameters(earlier), StudyIdentityJson(*a));
  EXPECT_EQ(StudyIdentityWithParameters(StudyIdentityJson(*e)), StudyIdentityJson(*e));
  // --semantics report changes the results, so it is part of the identity.
  Result<StudyOptions> d =
      Resolve(Cli({{"sizes", "20"}, {"steps", "10"}, {"semantics", "report"}}), 2);
  ASSERT_TRUE(d);
  EXPECT_NE(StudyIdentityJson(*a), StudyIdentityJson(*d));
  EXPECT_EQ(StudyIdentityJson(*d)["semantics"].get<std::string>(), "report");
  EXPECT_EQ(ExecutionJson(*b)["mode"].get<std::string>(), "agents");
  EXPECT_EQ(ExecutionJson(*b)["agents"].get<int>(), 2);
}

TEST(StudyPlanTest, RepeatsGiveEachConfigurationItsRepeatsAndLearnerSeeds) {
  Result<StudyOptions> options =
      Resolve(Cli({{"sizes", "20"}, {"difficulties", "easy,hard"}, {"repeats", "3"}}), 2);
  ASSERT_TRUE(options) << options.error().message;
  EXPECT_EQ(options->parallel, 2);  // --local repeats over the cores by default
  const std::vector<StudyConfiguration> plan = MakeStudyPlan(*options);
  ASSERT_EQ(plan.size(), 9u);  // (20 easy, 20 hard, edge) x 3, repeats together
  EXPECT_EQ(plan[0].Name(), "20_easy_50");
  EXPECT_FALSE(plan[0].learner_seed);  // repeat 1: the default stream
  EXPECT_EQ(plan[1].Name(), "20_easy_50_r2");
  EXPECT_EQ(*plan[1].learner_seed, 50u + 1000003u);
  EXPECT_EQ(*plan[2].learner_seed, 50u + 2 * 1000003u);
  EXPECT_EQ(plan[3].Name(), "20_hard_52");
  EXPECT_EQ(plan[8].Name(), "edge_50_hard_102_r3");
  EXPECT_EQ(*plan[8].learner_seed, 102u + 2 * 1000003u);
  EXPECT_EQ(plan[2].Label(), "20 Easy, seed 50, repeat 3/3");
  EXPECT_EQ(*RunOptionsOf(*options, plan[2], "d").learner_seed, 2000056);
  EXPECT_FALSE(RunOptionsOf(*options, plan[0], "d").learner_seed);
  EXPECT_EQ(*RunPlanOf(*options, plan[2], "d").learner_seed, 2000056u);
  EXPECT_FALSE(RunPlanOf(*options, plan[0], "d").learner_seed);
  EXPECT_EQ(StudyIdentityJson(*options)["repeats"], 3);

  // --learner-seed is the base of every repeat; --maze-seeds the mazes.
  options = Resolve(Cli({{"sizes", "20"},
                         {"difficulties", "easy"},
                         {"maze-seeds", "7,9"},
                         {"learner-seed", "5"},
                         {"edge-case", "false"}}),
                    2);
  ASSERT_TRUE(options) << options.error().message;
  EXPECT_EQ(options->repeats, 2);
  const std::vector<StudyConfiguration> seeded = MakeStudyPlan(*options);
  ASSERT_EQ(seeded.size(), 2u);
  EXPECT_EQ(seeded[0].Name(), "20_easy_7");
  EXPECT_EQ(*seeded[0].learner_seed, 5u);
  EXPECT_EQ(seeded[1].Name(), "20_easy_9_r2");
  EXPECT_EQ(*seeded[1].learner_seed, 5u + 1000003u);

  // Without repeats nothing changes: no suffix, no seed, no identity entry.
  options = Resolve(Cli({{"sizes", "20"}}), 2);
  ASSERT_TRUE(options);
  EXPECT_EQ(options->parallel, 1);
  EXPECT_EQ(MakeStudyPlan(*options)[0].Name(), "20_easy_50");
  EXPECT_FALSE(StudyIdentityJson(*options).contains("repeats"));
  EXPECT_FALSE(StudyIdentityJson(*options).contains("learner_seed"));
}

TEST(StudyPlanTest, ASweepRunsTheGridOfItsParametersValues) {
  Result<StudyOptions> options = FromFile(
      "sizes = [20]\ndifficulties = ['hard']\nedge-case = false\n"
      "epsilon-start = [0.05, 0.1, 1.0]\nlearners = [2, 4]\nreplay-batch = 32\n");
  ASSERT_TRUE(options) << options.error().message;
  ASSERT_EQ(options->sweeps.size(), 2u);
  const std::vector<StudyConfiguration> plan = MakeStudyPlan(*options);
  ASSERT_EQ(plan.size(), 6u);
  EXPECT_EQ(plan[0].Name(), "20_hard_52_epsilon-start-0.05_learners-2");
  EXPECT_EQ(plan[1].Name(), "20_hard_52_epsilon-start-0.05_learners-4");
  EXPECT_EQ(plan[5].Name(), "20_hard_52_epsilon-start-1.0_learners-4");
  EXPECT_EQ(plan[1].Label(), "20 Hard, seed 52, epsilon-start 0.05, learners 4");
  // Each point's run options carry its values over the study's others.
  const runtime::RunPlan run = RunPlanOf(*options, plan[3], "d");
  EXPECT_EQ(run.options.single_agent.epsilon_start, 0.1);
  EXPECT_EQ(run.options.federated.learners, 4);
  EXPECT_EQ(run.options.single_agent.replay_batch, 32);
  // A coordinator process resolves the same values from its options.
  Result<runtime::RunPlan> words = runtime::ResolveRunOptions(RunOptionsOf(*options, plan[3], "d"));
  ASSERT_TRUE(words) << words.error().message;
  EXPECT_EQ(RunPlanToml(*words), RunPlanToml(run));
  const Json identity = StudyIdentityJson(*options);
  EXPECT_EQ(identity["parameters"]["epsilon-start"], Json::array({0.05, 0.1, 1.0}));
  EXPECT_EQ(identity["parameters"]["learners"], Json::array({2, 4}));
  EXPECT_EQ(identity["parameters"]["replay-batch"], 32);

  // One value in an array is no sweep; the command line's value replaces a list.
  options = FromFile("sizes = [20]\nepsilon-start = [0.5]\n");
  ASSERT_TRUE(options);
  EXPECT_TRUE(options->sweeps.empty());
  const std::pair<const char*, const char*> bad[] = {
      {"epsilon-start = [0.5, 1.5]\n", "s.toml:1: epsilon-start: must be a number from 0.0 to 1.0"},
      {"learners = [2, 2]\n", "s.toml:1: learners: 2 is given twice"},
      {"learners = [2.5, 3.5]\n", "s.toml:1: learners: expected an integer"},
      {"learners = []\n", "s.toml:1: learners: expected an integer or a non-empty array"},
      {"epsilon-start = ['a']\n", "s.toml:1: epsilon-start: expected a number or an array"},
  };
  for (const auto& [text, expected] : bad) {
    Result<StudyOptions> refused = FromFile(text);
    ASSERT_FALSE(refused) << text;
    EXPECT_EQ(refused.error().message.rfind(expected, 0), 0u) << refused.error().message;
  }
}

}  // namespace
}  // namespace dynapath::study
