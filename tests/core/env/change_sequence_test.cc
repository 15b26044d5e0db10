#include "dynapath/change_sequence.h"

#include <gtest/gtest.h>

#include "tests/temp_path.h"

#include <filesystem>

#include "dynapath/scenario.h"

namespace dynapath {
namespace {

TEST(ChangeSequenceTest, ApplyInOrder) {
  Grid grid(2, 2);
  ChangeStep step{1, {{0, Cell::kObstacle}, {0, Cell::kFree}, {3, Cell::kObstacle}}};
  ApplyChanges(step, grid);
  EXPECT_EQ(grid.at(0), Cell::kFree);
  EXPECT_EQ(grid.at(3), Cell::kObstacle);
}

TEST(ChangeSequenceTest, TextRoundTripOfAReportSequence) {
  const Scenario scenario = GenerateScenario(50, 50, Difficulty::kHard, 102);
  const std::string text = ChangesToText(scenario.changes, 50, 50);
  Result<ChangeSequence> parsed = ChangesFromText(text, 50, 50);
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_EQ(*parsed, scenario.changes);
}

TEST(ChangeSequenceTest, FileRoundTrip) {
  const Scenario scenario = GenerateScenario(20, 30, Difficulty::kEasy, 9);
  const std::string path = test_paths::UniqueTempPath("changes_test.txt");
  ASSERT_TRUE(SaveChanges(scenario.changes, 20, 30, path).ok());
  Result<ChangeSequence> loaded = LoadChanges(path, 20, 30);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(*loaded, scenario.changes);
  std::filesystem::remove(path);
}

TEST(ChangeSequenceTest, RejectsBadFiles) {
  EXPECT_FALSE(ChangesFromText("", 5, 5).ok());
  EXPECT_FALSE(ChangesFromText("hello 1 5 5 1\n1 0\n", 5, 5).ok());
  EXPECT_FALSE(ChangesFromText("dynapath-changes 2 5 5 1\n1 0\n", 5, 5).ok());
  // Wrong maze size.
  Result<ChangeSequence> wrong_size = ChangesFromText("dynapath-changes 1 5 6 1\n1 0\n", 5, 5);
  ASSERT_FALSE(wrong_size.ok());
  EXPECT_NE(wrong_size.error().message.find("5x6"), std::string::npos);
  // Cell out of range, bad code, truncation, trailing garbage.
  EXPECT_FALSE(ChangesFromText("dynapath-changes 1 5 5 1\n1 1 25 1\n", 5, 5).ok());
  EXPECT_FALSE(ChangesFromText("dynapath-changes 1 5 5 1\n1 1 3 7\n", 5, 5).ok());
  EXPECT_FALSE(ChangesFromText("dynapath-changes 1 5 5 2\n1 1 3 1\n", 5, 5).ok());
  EXPECT_FALSE(ChangesFromText("dynapath-changes 1 5 5 1\n1 1 3 1\nextra\n", 5, 5).ok());
  EXPECT_FALSE(ChangesFromText("dynapath-changes 1 5 5 -1\n", 5, 5).ok());
  EXPECT_TRUE(ChangesFromText("dynapath-changes 1 5 5 1\n1 2 3 1 4 0\n", 5, 5).ok());
}

}  // namespace
}  // namespace dynapath
