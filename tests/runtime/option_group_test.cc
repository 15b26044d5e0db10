// The option declarations of runtime/: a struct written as a
// config file by its declaration reads back the same through CLI11, values
// a config cannot carry are refused, and bad command lines give one error.

#include "runtime/option_group.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "dynapath/text_file.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"

namespace dynapath::runtime {
namespace {

struct Everything {
  ScenarioOptions scenario;
  RunOptions run;
  ProcessOptions process;
  LogOptions log;
};

void Declare(OptionGroup& group, Everything& o) {
  DeclareScenarioOptions(group, o.scenario);
  DeclareRunOptions(group, o.run);
  DeclareProcessOptions(group, o.process, true);
  DeclareLogOptions(group, o.log);
}

class OptionGroupTest : public testing::Test {
 protected:
  void SetUp() override {
    char name[] = "/tmp/option_group_test_XXXXXX";
    const int fd = mkstemp(name);
    ASSERT_GE(fd, 0);
    close(fd);
    path_ = name;
  }
  void TearDown() override { std::remove(path_.c_str()); }

  // Writes `given` with its declaration, then parses the file into a fresh
  // struct with the same declaration, as a child process does.
  int RoundTrip(Everything given, Everything& read, std::vector<std::string> args = {}) {
    ConfigWriter writer;
    OptionGroup out(writer);
    Declare(out, given);
    EXPECT_TRUE(writer.status());
    std::ofstream(path_) << writer.Text();
    CLI::App app;
    OptionGroup in(app);
    Declare(in, read);
    AddConfigOption(app);
    args.insert(args.begin(), {"--config", path_});
    return ParseCommandLine(app, args, "test");
  }

  // What parsing a config file of `text` prints; it must be refused.
  std::string ConfigError(const std::string& text) {
    std::ofstream(path_) << text;
    CLI::App app;
    OptionGroup group(app);
    Everything options;
    Declare(group, options);
    AddConfigOption(app);
    testing::internal::CaptureStderr();
    EXPECT_EQ(ParseCommandLine(app, {"--config", path_}, "test"), 2);
    return testing::internal::GetCapturedStderr();
  }

  std::string path_;
};

TEST_F(OptionGroupTest, AStructReadsBackTheSame) {
  Everything given;
  given.scenario.size = 33;
  given.scenario.cols = 41;
  given.scenario.difficulty = "hard";
  given.scenario.seed = 4294967295LL;
  given.scenario.maze = "/tmp/a dir/it's a map.map";  // a space and a quote
  given.scenario.allow_unreachable = true;
  given.run.approach = "A* Static,fedAsynQ_EqAvg,BFS Oracle";  // commas stay one value
  given.run.out = "out/x";
  given.run.leaf_limit = 7;
  given.run.semantics = "report";
  given.run.placement = "split";
  given.process.run_id = "r1";
  given.process.secret_file = "/dev/fd/9";
  given.process.grid_cells = 2500;
  given.process.fault_drop = 0.1;  // no exact binary value: must read back bit for bit
  given.log.log_level = "warn";
  Everything read;
  ASSERT_EQ(RoundTrip(given, read), -1);
  EXPECT_EQ(read.scenario.size, 33);
  EXPECT_EQ(read.scenario.cols, 41);
  EXPECT_EQ(read.scenario.difficulty, "hard");
  EXPECT_EQ(read.scenario.seed, 4294967295LL);
  EXPECT_EQ(read.scenario.maze, given.scenario.maze);
  EXPECT_FALSE(read.scenario.steps);  // unset stays unset
  EXPECT_FALSE(read.scenario.replay);
  EXPECT_TRUE(read.scenario.allow_unreachable);
  EXPECT_EQ(read.run.approach, given.run.approach);
  EXPECT_EQ(read.run.out, "out/x");
  EXPECT_EQ(read.run.leaf_limit, 7);
  EXPECT_EQ(read.run.bootstrap, "in-grid");
  EXPECT_EQ(read.run.semantics, "report");
  EXPECT_EQ(read.run.placement, "split");
  EXPECT_EQ(read.process.run_id, "r1");
  EXPECT_EQ(read.process.secret_file, "/dev/fd/9");
  EXPECT_FALSE(read.process.insecure);
  EXPECT_EQ(read.process.grid_cells, 2500);
  EXPECT_EQ(read.process.fault_drop, 0.1);
  EXPECT_EQ(read.log.log_level, "warn");
}

TEST_F(OptionGroupTest, TheCommandLineOverridesTheFile) {
  Everything given;
  given.scenario.size = 33;
  given.run.leaf_limit = 7;
  Everything read;
  ASSERT_EQ(RoundTrip(given, read, {"--size", "12"}), -1);
  EXPECT_EQ(read.scenario.size, 12);
  EXPECT_EQ(read.run.leaf_limit, 7);
}

TEST_F(OptionGroupTest, DoubleQuotedTextUsesLiteralQuotes) {
  Everything given;
  given.scenario.maze = "/tmp/a \"quoted\" map.txt";
  Everything read;
  ASSERT_EQ(RoundTrip(given, read), -1);
  EXPECT_EQ(read.scenario.maze, given.scenario.maze);
}

TEST(ConfigWriterTest, RefusesWhatCli11CannotReadBack) {
  for (const char* text : {"both ' and \"", "a\nline break"}) {
    ConfigWriter writer;
    OptionGroup group(writer);
    ScenarioOptions options;
    options.maze = text;
    DeclareScenarioOptions(group, options);
    Status status = writer.status();
    ASSERT_FALSE(status) << text;
    EXPECT_NE(status.error().message.find("--maze"), std::string::npos);
  }
}

TEST(ParseCommandLineTest, BadInputIsOneErrorAndExitTwo) {
  const std::pair<std::vector<std::string>, std::string> cases[] = {
      {{"--sise", "20"}, "unknown option --sise"},
      {{"--out"}, "option --out needs a value"},
      {{"--size", "abc"}, "option --size needs a decimal number, got 'abc'"},
      // CLI11 alone would read these as hexadecimal and octal (16 and 8).
      {{"--size", "0x10"}, "option --size needs a decimal number, got '0x10'"},
      {{"--seed", "1e3"}, "option --seed needs a decimal number, got '1e3'"},
      {{"stray"}, "unexpected argument 'stray'"},
      // Too large to read: out of range as typed, not CLI11's clamped value.
      {{"--seed", "99999999999999999999"},
       "option --seed is out of range, got '99999999999999999999'"},
      {{"--size", "-099999999999999999999"},
       "option --size is out of range, got '-099999999999999999999'"},
      // An empty value would read as "not given": refused for every kind.
      {{"--save-policy", ""}, "option --save-policy must not be empty"},
      {{"--checkpoint", ""}, "option --checkpoint must not be empty"},
      {{"--epsilon-start", ""}, "option --epsilon-start must not be empty"},
      {{"--seed", ""}, "option --seed must not be empty"},
      {{"--approach", ""}, "option --approach must not be empty"},
      {{"--run-id", ""}, "option --run-id must not be empty"},
  };
  for (const auto& [args, expected] : cases) {
    CLI::App app;
    OptionGroup group(app);
    Everything options;
    Declare(group, options);
    testing::internal::CaptureStderr();
    EXPECT_EQ(ParseCommandLine(app, args, "test"), 2) << expected;
    const std::string error = testing::internal::GetCapturedStderr();
    EXPECT_EQ(error.rfind("test: " + expected, 0), 0u) << error;
    EXPECT_EQ(std::count(error.begin(), error.end(), '\n'), 1) << error;
  }
}

TEST(ParseCommandLineTest, IntegersAreDecimalWithLeadingZeros) {
  CLI::App app;
  OptionGroup group(app);
  Everything options;
  Declare(group, options);
  ASSERT_EQ(ParseCommandLine(app, {"--size", "020", "--seed", "010", "--steps", "+7"}, "test"), -1);
  EXPECT_EQ(options.scenario.size, 20ll);  // not octal 16
  EXPECT_EQ(options.scenario.seed, 10ll);
  EXPECT_EQ(options.scenario.steps, 7ll);
}

TEST_F(OptionGroupTest, AnUnknownConfigKeyIsAnError) {
  EXPECT_EQ(ConfigError("size=12\ncolour=\"red\"\n"),
            "test: unknown key 'colour' in the --config file\n");
}

TEST_F(OptionGroupTest, AnEmptyConfigValueIsAnError) {
  EXPECT_EQ(ConfigError("size=12\nload-policy=\"\"\n"),
            "test: option --load-policy must not be empty\n");
}

// "" means "not given": the writer leaves it out, so what it writes reads
// back under the rule above.
TEST_F(OptionGroupTest, EmptyTextIsNotWritten) {
  Everything given;  // --checkpoint, --save-policy, --load-policy: ""
  Everything read;
  ASSERT_EQ(RoundTrip(given, read), -1);
  EXPECT_EQ(read.run.checkpoint, "");
  EXPECT_EQ(read.run.policy.save_policy, "");
}

// An option that means something only with another is refused without it.
TEST(ResolveRunOptionsTest, CheckpointTimingNeedsCheckpoint) {
  RunOptions run;
  run.checkpoint_every = 5;
  Result<RunPlan> plan = ResolveRunOptions(run);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.error().message, "option --checkpoint-every needs --checkpoint DIR");
  run.checkpoint_every.reset();
  run.checkpoint_interval = 2;
  plan = ResolveRunOptions(run);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.error().message, "option --checkpoint-interval needs --checkpoint DIR");
  run.checkpoint = "ck";
  EXPECT_TRUE(ResolveRunOptions(run).ok());
}

TEST(InRangeTest, FallbackUncheckedValueChecked) {
  EXPECT_EQ(*InRange("n", std::nullopt, 0, 1, 5), 0);
  EXPECT_EQ(*InRange("n", 5, 0, 1, 5), 5);
  Result<long long> bad = InRange("n", 6, 0, 1, 5);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "option --n must be between 1 and 5, got 6");
}

TEST(OptionKindsTest, TheDeclarationRecordsEachKind) {
  CLI::App app;
  OptionKinds kinds;
  OptionGroup group(app, &kinds);
  Everything options;
  Declare(group, options);
  EXPECT_EQ(kinds.at("size"), ValueKind::kInteger);
  EXPECT_EQ(kinds.at("maze"), ValueKind::kString);
  EXPECT_EQ(kinds.at("allow-unreachable"), ValueKind::kBoolean);
  EXPECT_EQ(kinds.at("fault-drop"), ValueKind::kFloat);
  EXPECT_EQ(kinds.at("leaf-limit"), ValueKind::kInteger);
}

// The same declaration on OptionFields says where each option lives, with
// the kind CLI11's declaration records; a field's value copies to the same
// option's field of another struct (a study file's values under a command
// line's), optional or not.
TEST(OptionFieldsTest, TheDeclarationRecordsEachFieldAndItsKind) {
  CLI::App app;
  OptionKinds kinds;
  OptionGroup declared(app, &kinds);
  Everything parsed;
  Declare(declared, parsed);
  OptionFields fields;
  OptionGroup group(fields);
  Everything options;
  Declare(group, options);
  ASSERT_EQ(fields.size(), kinds.size());
  for (const auto& [name, kind] : kinds) EXPECT_EQ(fields.at(name).kind, kind) << name;
  EXPECT_EQ(std::get<std::optional<long long>*>(fields.at("size").value), &options.scenario.size);
  EXPECT_EQ(std::get<long long*>(fields.at("leaf-limit").value), &options.run.leaf_limit);

  Everything other;
  OptionFields other_fields;
  OptionGroup other_group(other_fields);
  Declare(other_group, other);
  other.scenario.size = 30;
  other.run.leaf_limit = 7;
  other.run.bootstrap = "in-region";
  other.scenario.allow_unreachable = true;
  for (const char* name : {"size", "leaf-limit", "bootstrap", "allow-unreachable"}) {
    CopyOptionField(other_fields.at(name), fields.at(name));
  }
  EXPECT_EQ(options.scenario.size, 30);
  EXPECT_EQ(options.run.leaf_limit, 7);
  EXPECT_EQ(options.run.bootstrap, "in-region");
  EXPECT_TRUE(options.scenario.allow_unreachable);
  EXPECT_FALSE(options.scenario.seed);  // not copied
}

// An enum option's words are one table; its list, check, parse
// and default word come from it, with the case rules the options had.
TEST(WordTableTest, ListCheckAndParseComeFromOneTable) {
  EXPECT_EQ(PlacementWords().List(), "auto, whole or split");
  EXPECT_EQ(CheckPlacement("whole").ok(), true);
  EXPECT_EQ(CheckPlacement("x").error().message, "must be auto, whole or split, got 'x'");
  EXPECT_EQ(CheckBootstrap("In-grid").error().message,
            "must be in-grid or in-region, got 'In-grid'");  // exact case
  EXPECT_EQ(SemanticsWords().Parse("report"), Semantics::kReport);
  Result<Placement> bad = PlacementWords().ParseOption("placement", "none");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "option --placement must be auto, whole or split, got 'none'");
}

TEST(WordTableTest, DifficultyIgnoresCaseAndLogLevelKeepsSpdlogAliases) {
  EXPECT_EQ(DifficultyWords().Parse("HaRd"), Difficulty::kHard);
  EXPECT_EQ(DifficultyWords().List(), "easy, medium or hard");
  EXPECT_EQ(CheckLogLevel("x").error().message,
            "must be trace, debug, info, warn, error or off, got 'x'");
  for (const char* alias : {"warning", "err", "critical"}) EXPECT_TRUE(CheckLogLevel(alias).ok());
  EXPECT_FALSE(CheckLogLevel("Info").ok());
}

TEST(WordTableTest, DefaultsAreTheLibrariesValuesAsWords) {
  const RunOptions run;
  EXPECT_EQ(run.bootstrap, "in-grid");
  EXPECT_EQ(run.semantics, "ours");
  EXPECT_EQ(run.placement, "auto");
  EXPECT_EQ(run.out, "results");
  EXPECT_EQ(LogOptions{}.log_level, "info");
}

// The option checkers say which option a bad value is of (Error::subject)
// with the code kInvalidArgument; the message is unchanged.
TEST(OptionErrorTest, CheckersNameTheirOption) {
  Result<long long> range = InRange("fragment-size", 5, 0, 1024, 60000);
  ASSERT_FALSE(range.ok());
  EXPECT_EQ(range.error().message, "option --fragment-size must be between 1024 and 60000, got 5");
  EXPECT_EQ(range.error().code, Error::Code::kInvalidArgument);
  EXPECT_EQ(range.error().subject, "fragment-size");

  Result<Placement> word = PlacementWords().ParseOption("placement", "none");
  ASSERT_FALSE(word.ok());
  EXPECT_EQ(word.error().subject, "placement");
  EXPECT_EQ(word.error().Detail(), "must be auto, whole or split, got 'none'");

  RunOptions run;
  run.out = "";
  Result<RunPlan> plan = ResolveRunOptions(run);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.error().message, "option --out must not be empty");
  EXPECT_EQ(plan.error().code, Error::Code::kInvalidArgument);
  EXPECT_EQ(plan.error().subject, "out");

  ProcessOptions process;
  Result<ProcessSetup> setup = ResolveProcessOptions(process, true);
  ASSERT_FALSE(setup.ok());
  EXPECT_EQ(setup.error().message, "option --run-id is required");
  EXPECT_EQ(setup.error().subject, "run-id");

  ScenarioOptions scenario;
  scenario.size = 0;
  Result<ScenarioSetup> sized = ResolveScenario(scenario);
  ASSERT_FALSE(sized.ok());
  EXPECT_EQ(sized.error().subject, "size");
  scenario.size.reset();
  scenario.maze = "/nonexistent/dynapath/maze.txt";
  Result<ScenarioSetup> missing = ResolveScenario(scenario);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, Error::Code::kNotFound);
  EXPECT_EQ(missing.error().message,
            "/nonexistent/dynapath/maze.txt: cannot open for reading: No such file or directory");
}

// A 10x10 maze of `steps` time steps.
Result<ScenarioSetup> SmallMaze(long long steps) {
  ScenarioOptions scenario;
  scenario.size = 10;
  scenario.steps = steps;
  return ResolveScenario(scenario);
}

// A run of `approaches` writing into `dir`.
RunOptions RunInto(const std::string& dir, const std::string& approaches) {
  RunOptions run;
  run.approach = approaches;
  run.out = dir;
  return run;
}

// A stopped local run ends with kCancelled ("interrupted") and writes no
// result files for the approach it cut short.
TEST(RunLocalTest, StopEndsTheRunCancelled) {
  char name[] = "/tmp/run_local_test_XXXXXX";
  ASSERT_NE(mkdtemp(name), nullptr);
  const std::string dir = name;
  Result<ScenarioSetup> setup = SmallMaze(6);
  ASSERT_TRUE(setup.ok()) << setup.error().message;
  Result<RunPlan> plan = ResolveRunOptions(RunInto(dir, "BFS Oracle"));
  ASSERT_TRUE(plan.ok()) << plan.error().message;

  std::atomic<bool> stop{false};
  int last_step = -1;
  Result<std::vector<ApproachRun>> runs = RunLocal(
      *plan, *setup, 1,
      [&](const StepView& view) {
        last_step = view.run.steps.back().time_step;
        if (last_step == 2) stop = true;  // as Ctrl-C would
      },
      &stop);
  ASSERT_FALSE(runs.ok());
  EXPECT_EQ(runs.error().code, Error::Code::kCancelled);
  EXPECT_EQ(runs.error().message, "interrupted");
  EXPECT_EQ(last_step, 2);
  EXPECT_NE(access((dir + "/results.csv").c_str(), F_OK), 0);

  stop = false;
  Result<std::vector<ApproachRun>> whole = RunLocal(*plan, *setup, 1, {}, &stop);
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  ASSERT_EQ(whole->size(), 1u);
  EXPECT_EQ(whole->front().steps.size(), 7u);
  EXPECT_EQ(access((dir + "/results.csv").c_str(), F_OK), 0);
  std::remove((dir + "/results.csv").c_str());
  std::remove((dir + "/results_detailed.csv").c_str());
  rmdir(dir.c_str());
}

// A policy file that cannot be written ends the run, but the rows of the
// approach that saved it are written first.
TEST(RunLocalTest, AFailedPolicyWriteKeepsTheRows) {
  char name[] = "/tmp/run_local_policy_XXXXXX";
  ASSERT_NE(mkdtemp(name), nullptr);
  const std::string dir = name;
  Result<ScenarioSetup> setup = SmallMaze(2);
  ASSERT_TRUE(setup.ok()) << setup.error().message;
  RunOptions run = RunInto(dir, "BFS Oracle,fedAsynQ_EqAvg");
  run.policy.save_policy = dir + "/missing/p.pol";  // not checked here, as `run` does
  Result<RunPlan> plan = ResolveRunOptions(run);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  Result<std::vector<ApproachRun>> runs = RunLocal(*plan, *setup, 1);
  ASSERT_FALSE(runs.ok());
  EXPECT_NE(runs.error().message.find("policy file " + dir + "/missing/p.pol"), std::string::npos)
      << runs.error().message;
  Result<std::string> results = ReadTextFile(dir + "/results.csv");
  ASSERT_TRUE(results.ok());
  EXPECT_NE(results->find("\nfedAsynQ_EqAvg,"), std::string::npos) << *results;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dynapath::runtime
