#include "runtime/scenario_options.h"

#include <gtest/gtest.h>

#include <string>

namespace dynapath::runtime {
namespace {

const std::string kMap = std::string(DYNAPATH_SOURCE_DIR) + "/tests/data/maps/wide-5-9.map";

// A command line's words and a spec filled directly give the same scenario.
void ExpectSameScenario(const Result<ScenarioSetup>& a, const Result<ScenarioSetup>& b) {
  ASSERT_TRUE(a) << a.error().message;
  ASSERT_TRUE(b) << b.error().message;
  EXPECT_EQ(a->scenario.grid, b->scenario.grid);
  EXPECT_EQ(a->scenario.changes, b->scenario.changes);
  EXPECT_EQ(a->labels.size_label, b->labels.size_label);
  EXPECT_EQ(a->labels.difficulty_label, b->labels.difficulty_label);
  EXPECT_EQ(a->seed, b->seed);
}

TEST(ScenarioSpecTest, WordsParsedOnceEqualAFilledSpec) {
  ScenarioOptions words;
  words.size = 12;
  words.difficulty = "MEDIUM";
  words.steps = 5;
  Result<ScenarioSpec> parsed = ParseScenarioOptions(words);
  ASSERT_TRUE(parsed) << parsed.error().message;
  EXPECT_EQ(parsed->difficulty, Difficulty::kMedium);
  ScenarioSpec spec;
  spec.size = 12;
  spec.difficulty = Difficulty::kMedium;
  spec.steps = 5;
  ExpectSameScenario(ResolveScenario(words), ResolveScenario(spec));

  // A map with stations and movers from the seed.
  words = ScenarioOptions{};
  words.maze = kMap;
  words.stations = "2";
  words.movers = "10%";
  words.seed = 5;
  words.steps = 6;
  parsed = ParseScenarioOptions(words);
  ASSERT_TRUE(parsed) << parsed.error().message;
  ASSERT_TRUE(parsed->stations && parsed->movers);
  EXPECT_EQ(parsed->stations->count, 2);
  EXPECT_EQ(parsed->movers->percent, 10.0);
  spec = ScenarioSpec{};
  spec.maze = kMap;
  spec.stations = CellCount{2, -1.0};
  spec.movers = CellCount{0, 10.0};
  spec.seed = 5;
  spec.steps = 6;
  const Result<ScenarioSetup> from_spec = ResolveScenario(spec);
  ExpectSameScenario(ResolveScenario(words), from_spec);
  ASSERT_TRUE(from_spec);
  EXPECT_EQ(from_spec->scenario.grid.Count(Cell::kStation), 2);
  EXPECT_EQ(from_spec->labels.difficulty_label, "wide-5-9");

  // Back to words (envsim's command line) and parsed again: the same spec.
  const ScenarioOptions again = ScenarioOptionsOf(*parsed);
  EXPECT_EQ(again.stations, "2");
  EXPECT_EQ(again.movers, "10%");
  EXPECT_FALSE(again.difficulty);
  ExpectSameScenario(ResolveScenario(again), from_spec);
}

TEST(ScenarioSpecTest, CellCountTextReadsBackTheSameValue) {
  for (const char* text : {"0", "12", "0%", "0.5%", "2%", "100%", "0.1%", "33.3%"}) {
    Result<CellCount> count = ParseCellCount(text);
    ASSERT_TRUE(count) << text;
    EXPECT_EQ(CellCountText(*count), text);
  }
  EXPECT_EQ(CellCountText(*ParseCellCount(" 0.50% ")), "0.5%");
  EXPECT_EQ(CellCountText(*ParseCellCount("007")), "7");
  for (const double percent : {100.0 / 3.0, 1e-7, 99.99999999999, 0.30000000000000004}) {
    Result<CellCount> back = ParseCellCount(CellCountText(CellCount{0, percent}));
    ASSERT_TRUE(back) << percent;
    EXPECT_EQ(back->percent, percent);
  }
}

TEST(ScenarioSpecTest, BadWordsNameTheirOption) {
  ScenarioOptions words;
  words.maze = kMap;
  words.stations = "x";
  Result<ScenarioSpec> parsed = ParseScenarioOptions(words);
  ASSERT_FALSE(parsed);
  EXPECT_EQ(parsed.error().message,
            "option --stations: expected a count N or a percentage P% (0 to 100), got 'x'");
  EXPECT_EQ(parsed.error().subject, "stations");
  words.stations.reset();
  words.movers = "101%";
  parsed = ParseScenarioOptions(words);
  ASSERT_FALSE(parsed);
  EXPECT_EQ(parsed.error().subject, "movers");
  words = ScenarioOptions{};
  words.difficulty = "extreme";
  parsed = ParseScenarioOptions(words);
  ASSERT_FALSE(parsed);
  EXPECT_EQ(parsed.error().subject, "difficulty");
  // With --replay another option is the error, whatever its value.
  words.replay = "run.lcm";
  parsed = ParseScenarioOptions(words);
  ASSERT_FALSE(parsed);
  EXPECT_EQ(parsed.error().message,
            "--replay sets the maze and changes: do not combine it with --difficulty");
}

}  // namespace
}  // namespace dynapath::runtime
