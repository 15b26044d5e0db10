#include "dynapath/bfs_oracle.h"

#include <gtest/gtest.h>

#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "dynapath/astar_paths.h"
#include "dynapath/difficulty.h"
#include "dynapath/grid.h"
#include "dynapath/scenario.h"
#include "dynapath/text_file.h"
#include "dynapath/text_util.h"
#include "tests/grid_test_support.h"

namespace dynapath {
namespace {

using test_grids::Distances;
using test_grids::FromText;

// The reference CSV was written by a C++ ostream at its default precision:
// 6 significant digits, printf "%g" style.
std::string SixDigits(double value) {
  std::ostringstream out;
  out << std::setprecision(6) << value;
  return out.str();
}

constexpr int32_t U = kUnreachable;

TEST(BfsOracleTest, ReproducesEveryPublishedStepZeroFigure) {
  const Result<std::string> text = ReadTextFile(DYNAPATH_REFERENCE_DIR "/paper_step0_oracle.csv");
  ASSERT_TRUE(text.ok());
  std::istringstream lines(text.value());
  std::string line;
  ASSERT_TRUE(std::getline(lines, line));
  EXPECT_EQ(Trim(line), "Size,Difficulty,Seed,OracleSuccessRateStep0,OracleAvgPathLengthStep0");
  int rows_checked = 0;
  std::vector<int32_t> distance, queue;
  while (std::getline(lines, line)) {
    if (Trim(line).empty()) continue;
    const std::vector<std::string> fields = Split(line, ',');
    ASSERT_EQ(fields.size(), 5u) << line;
    const int size = std::stoi(fields[0]);
    const bool edge = fields[1] == "Hard-edge";
    const std::optional<Difficulty> difficulty =
        edge ? Difficulty::kHard : ParseDifficulty(fields[1]);
    ASSERT_TRUE(difficulty.has_value()) << line;
    const unsigned seed = static_cast<unsigned>(std::stoul(fields[2]));
    EXPECT_EQ(seed, edge ? kEdgeCaseSeed : ReportSeed(*difficulty)) << line;

    const Scenario scenario = GenerateScenario(size, size, *difficulty, seed, /*steps=*/0);
    NearestStationDistances(scenario.grid, distance, queue);
    const PolicyScore score = ScoreDistances(scenario.grid, distance);
    EXPECT_EQ(SixDigits(score.success_rate()), SixDigits(std::stod(fields[3]))) << line;
    EXPECT_EQ(SixDigits(score.average_path_length()), SixDigits(std::stod(fields[4]))) << line;
    ++rows_checked;
  }
  // 5 sizes x 3 difficulties, plus the edge case.
  EXPECT_EQ(rows_checked, 16);
}

TEST(BfsOracleTest, DiagonalMovesPassBetweenObstacleCorners) {
  const Grid grid = FromText(
      "C#.\n"
      "#..\n"
      "..#\n");
  EXPECT_EQ(Distances(grid), (std::vector<int32_t>{0, U, 2,  //
                                                   U, 1, 2,  //
                                                   2, 2, U}));
}

TEST(BfsOracleTest, WallForcesDetour) {
  const Grid grid = FromText(
      ".....\n"
      "####.\n"
      "C....\n");
  EXPECT_EQ(Distances(grid), (std::vector<int32_t>{8, 7, 6, 5, 5,  //
                                                   U, U, U, U, 4,  //
                                                   0, 1, 2, 3, 4}));
}

TEST(BfsOracleTest, EnclosedPocketIsUnreachable) {
  const Grid grid = FromText(
      "C...\n"
      "####\n"
      ".#..\n");
  EXPECT_EQ(Distances(grid), (std::vector<int32_t>{0, 1, 2, 3,  //
                                                   U, U, U, U,  //
                                                   U, U, U, U}));
  const PolicyScore score = ScoreDistances(grid, Distances(grid));
  EXPECT_EQ(score.starts, 7);  // obstacles are not starts; the pocket is
  EXPECT_EQ(score.successes, 4);
  EXPECT_EQ(score.total_length, 6);
}

TEST(BfsOracleTest, NoStationMeansNothingIsReachable) {
  const Grid grid = FromText(
      "...\n"
      ".#.\n");
  EXPECT_EQ(Distances(grid), std::vector<int32_t>(6, U));
  const PolicyScore score = ScoreDistances(grid, Distances(grid));
  EXPECT_EQ(score.starts, 5);
  EXPECT_EQ(score.successes, 0);
  EXPECT_DOUBLE_EQ(score.success_rate(), 0.0);
  EXPECT_DOUBLE_EQ(score.average_path_length(), 0.0);
}

TEST(BfsOracleTest, SeveralStationsGiveTheNearest) {
  const Grid grid = FromText("C.....C\n");
  EXPECT_EQ(Distances(grid), (std::vector<int32_t>{0, 1, 2, 3, 2, 1, 0}));
}

TEST(BfsOracleTest, ScratchBuffersAreReusedAcrossSizes) {
  std::vector<int32_t> distance, queue;
  NearestStationDistances(FromText("C....\n.....\n"), distance, queue);
  EXPECT_EQ(distance.size(), 10u);
  NearestStationDistances(FromText("C.\n"), distance, queue);
  EXPECT_EQ(distance, (std::vector<int32_t>{0, 1}));
}

}  // namespace
}  // namespace dynapath
