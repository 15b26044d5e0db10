#include "dynapath/change_sequence.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "dynapath/scenario.h"
#include "tests/temp_path.h"

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
  const std::string text = ChangesToText(scenario.changes, scenario.grid);
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "dynapath-changes 2 50 50 100 " + FingerprintText(MazeFingerprint(scenario.grid)));
  ChangeFileHeader header;
  Result<ChangeSequence> parsed = ChangesFromText(text, 50, 50, &header);
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_EQ(*parsed, scenario.changes);
  EXPECT_EQ(header.version, 2);
  EXPECT_EQ(header.fingerprint, MazeFingerprint(scenario.grid));
}

TEST(ChangeSequenceTest, FileRoundTrip) {
  const Scenario scenario = GenerateScenario(20, 30, Difficulty::kEasy, 9);
  const std::string path = test_paths::UniqueTempPath("changes_test.txt");
  ASSERT_TRUE(SaveChanges(scenario.changes, scenario.grid, path).ok());
  Result<ChangeSequence> loaded = LoadChanges(path, 20, 30);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(*loaded, scenario.changes);
  std::filesystem::remove(path);
}

TEST(ChangeSequenceTest, RejectsBadFiles) {
  EXPECT_FALSE(ChangesFromText("", 5, 5).ok());
  EXPECT_FALSE(ChangesFromText("hello 1 5 5 1\n1 0\n", 5, 5).ok());
  EXPECT_FALSE(ChangesFromText("dynapath-changes 3 5 5 1\n1 0\n", 5, 5).ok());
  // Version 2 needs its fingerprint: 16 hex digits.
  EXPECT_FALSE(ChangesFromText("dynapath-changes 2 5 5 1\n1 0\n", 5, 5).ok());
  EXPECT_FALSE(ChangesFromText("dynapath-changes 2 5 5 1 12345678abcdefgh\n1 0\n", 5, 5).ok());
  EXPECT_TRUE(ChangesFromText("dynapath-changes 2 5 5 1 12345678abcdef00\n1 0\n", 5, 5).ok());
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

TEST(ChangeSequenceTest, FingerprintIsFnv1aOfSidesAndCells) {
  // FNV-1a 64 of 01 00 00 00 | 01 00 00 00 | 01 (python3, by hand).
  EXPECT_EQ(FingerprintText(MazeFingerprint(Grid(1, 1))), "5f490f070d449c5c");
  Grid two(1, 2);
  two.set(0, Cell::kStation);  // 01 00 00 00 | 02 00 00 00 | 02 01
  EXPECT_EQ(FingerprintText(MazeFingerprint(two)), "0a53e42e79849517");
  // One station moved, one more obstacle, the sides swapped: all differ.
  const Scenario scenario = GenerateScenario(20, 20, Difficulty::kHard, 52);
  const uint64_t base = MazeFingerprint(scenario.grid);
  Grid moved = scenario.grid;
  for (int cell = 0; cell < moved.size(); ++cell) {
    if (moved.at(cell) == Cell::kFree) {
      moved.set(cell, Cell::kStation);
      break;
    }
  }
  EXPECT_NE(MazeFingerprint(moved), base);
  EXPECT_NE(MazeFingerprint(Grid(2, 3)), MazeFingerprint(Grid(3, 2)));
}

TEST(ChangeSequenceTest, VersionOneFilesAreReadWithoutAFingerprint) {
  ChangeFileHeader header;
  Result<ChangeSequence> parsed =
      ChangesFromText("dynapath-changes 1 5 5 1\n1 2 3 1 4 0\n", 5, 5, &header);
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_EQ(header.version, 1);
  EXPECT_FALSE(header.fingerprint.has_value());
}

TEST(ChangeSequenceTest, GeneratedSequencesFitTheirMaze) {
  for (Difficulty difficulty : {Difficulty::kEasy, Difficulty::kMedium, Difficulty::kHard}) {
    for (unsigned seed : {50u, 52u, 102u}) {
      const Scenario scenario = GenerateScenario(30, 40, difficulty, seed);
      const Status fits = CheckChangesFit(scenario.changes, scenario.grid);
      EXPECT_TRUE(fits.ok()) << fits.error().message;
    }
  }
}

TEST(ChangeSequenceTest, ChangesThatDoNotFitTheGridAreRefusedWithStepAndCell) {
  // .#
  // C.
  Grid grid(2, 2);
  grid.set(1, Cell::kObstacle);
  grid.set(2, Cell::kStation);
  auto refused = [&](std::vector<ChangeStep> steps, const std::string& expected) {
    const Status status = CheckChangesFit(ChangeSequence{std::move(steps)}, grid);
    ASSERT_FALSE(status.ok()) << expected;
    EXPECT_TRUE(status.error().IsCorrupt());
    EXPECT_EQ(status.error().message.substr(0, expected.size()), expected)
        << status.error().message;
  };
  // A valid move, then one onto the station at step 2.
  const ChangeStep move{1, {{1, Cell::kFree}, {0, Cell::kObstacle}}};
  EXPECT_TRUE(CheckChangesFit(ChangeSequence{{move}}, grid).ok());
  refused({move, ChangeStep{1, {{2, Cell::kObstacle}}}},
          "time step 2, change 1 at cell 2 (row 1, column 0): would remove the station");
  refused({ChangeStep{1, {{3, Cell::kStation}}}},
          "time step 1, change 1 at cell 3 (row 1, column 1): would create a station");
  refused({ChangeStep{1, {{3, Cell::kFree}}}},
          "time step 1, change 1 at cell 3 (row 1, column 1): moves an obstacle away from a cell "
          "that holds none");
  refused({ChangeStep{1, {{0, Cell::kObstacle}, {1, Cell::kObstacle}}}},
          "time step 1, change 2 at cell 1 (row 0, column 1): puts an obstacle on a cell");
}

TEST(ChangeSequenceTest, AnotherSeedsChangeFileDoesNotFit) {
  // The tester's case: same size, another seed. The fingerprints differ and
  // the changes do not fit the grid.
  const Scenario ours = GenerateScenario(50, 50, Difficulty::kHard, 52);
  const Scenario other = GenerateScenario(50, 50, Difficulty::kHard, 53);
  EXPECT_NE(MazeFingerprint(ours.grid), MazeFingerprint(other.grid));
  EXPECT_FALSE(CheckChangesFit(other.changes, ours.grid).ok());
}

TEST(ChangeSequenceTest, ParserMemoryStaysProportionalToTheText) {
  // A million steps announced, each a huge count: refused without
  // reserving for the announcement.
  Result<ChangeSequence> parsed =
      ChangesFromText("dynapath-changes 1 4096 4096 1000000\n1 33554432\n", 4096, 4096);
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.error().message.find("time step 1: truncated"), std::string::npos)
      << parsed.error().message;
}

}  // namespace
}  // namespace dynapath
