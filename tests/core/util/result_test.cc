// Error codes: what each kind of failure of core/ reports (a missing file,
// a corrupt maze or change file, a bad value, a stopped run), and the
// helpers that build and re-word errors without losing their code.

#include "dynapath/result.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "dynapath/change_sequence.h"
#include "dynapath/experiment.h"
#include "dynapath/grid.h"
#include "dynapath/map_scenario.h"
#include "dynapath/movingai_map.h"
#include "dynapath/scenario.h"
#include "dynapath/text_file.h"
#include "tests/temp_path.h"

namespace dynapath {
namespace {

using Code = Error::Code;

std::string WriteTemp(const std::string& name, const std::string& contents) {
  const std::string path = test_paths::UniqueTempPath(name);
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

TEST(ResultTest, PlainErrorIsAnInvalidArgumentAboutNothing) {
  const Error error{"bad"};
  EXPECT_EQ(error.message, "bad");
  EXPECT_EQ(error.code, Code::kInvalidArgument);
  EXPECT_TRUE(error.IsInvalidArgument());
  EXPECT_EQ(error.subject, "");
}

TEST(ResultTest, FactoriesSetTheirCode) {
  EXPECT_TRUE(Error::NotFound("x").IsNotFound());
  EXPECT_TRUE(Error::Corrupt("x").IsCorrupt());
  EXPECT_TRUE(Error::Io("x").IsIo());
  EXPECT_TRUE(Error::Unavailable("x").IsUnavailable());
  EXPECT_TRUE(Error::Internal("x").IsInternal());
  EXPECT_EQ(Error::File(ENOENT, "x").code, Code::kNotFound);
  EXPECT_EQ(Error::File(EACCES, "x").code, Code::kIo);
  const Error cancelled = Error::Cancelled();
  EXPECT_TRUE(cancelled.IsCancelled());
  EXPECT_FALSE(cancelled.IsInvalidArgument());
  EXPECT_EQ(cancelled.message, "interrupted");
}

TEST(ResultTest, CodeNames) {
  EXPECT_STREQ(CodeName(Code::kInvalidArgument), "invalid argument");
  EXPECT_STREQ(CodeName(Code::kNotFound), "not found");
  EXPECT_STREQ(CodeName(Code::kCorrupt), "corrupt");
  EXPECT_STREQ(CodeName(Code::kIo), "I/O error");
  EXPECT_STREQ(CodeName(Code::kUnavailable), "unavailable");
  EXPECT_STREQ(CodeName(Code::kCancelled), "cancelled");
  EXPECT_STREQ(CodeName(Code::kInternal), "internal");
}

TEST(ResultTest, OptionErrorNamesItsOption) {
  const Error error = Error::Option("leaf-limit", "must be between 1 and 10000, got 0");
  EXPECT_EQ(error.message, "option --leaf-limit must be between 1 and 10000, got 0");
  EXPECT_EQ(error.code, Code::kInvalidArgument);
  EXPECT_EQ(error.subject, "leaf-limit");
  EXPECT_EQ(error.Detail(), "must be between 1 and 10000, got 0");
}

TEST(ResultTest, DetailLeavesOtherMessagesWhole) {
  EXPECT_EQ(
      Error("option --stations: expected a count", Code::kInvalidArgument, "stations").Detail(),
      "expected a count");
  EXPECT_EQ(
      Error("--steps 9 is more than the 3 time steps", Code::kInvalidArgument, "steps").Detail(),
      "--steps 9 is more than the 3 time steps");
  EXPECT_EQ(Error("option --x must be 1").Detail(), "option --x must be 1");  // no subject
}

TEST(ResultTest, PrefixedKeepsCodeAndSubject) {
  const Error error = Error("must be 1", Code::kCorrupt, "field").Prefixed("f.txt: ");
  EXPECT_EQ(error.message, "f.txt: must be 1");
  EXPECT_EQ(error.code, Code::kCorrupt);
  EXPECT_EQ(error.subject, "field");
}

TEST(ResultTest, MissingFileIsNotFound) {
  const std::string path = test_paths::UniqueTempPath("does_not_exist.txt");
  Result<std::string> text = ReadTextFile(path);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error().code, Code::kNotFound);
  EXPECT_EQ(text.error().message, path + ": cannot open for reading: No such file or directory");

  Result<Grid> grid = LoadGrid(path);
  ASSERT_FALSE(grid.ok());
  EXPECT_EQ(grid.error().code, Code::kNotFound);
  Result<Grid> map = LoadMazeFile(path, nullptr);
  ASSERT_FALSE(map.ok());
  EXPECT_EQ(map.error().code, Code::kNotFound);
  Result<ChangeSequence> changes = LoadChanges(path, 5, 5);
  ASSERT_FALSE(changes.ok());
  EXPECT_EQ(changes.error().code, Code::kNotFound);
}

TEST(ResultTest, DirectoryIsAnIoError) {
  const std::string dir = test_paths::UniqueTempPath("a_directory");
  std::filesystem::create_directories(dir);
  Result<std::string> text = ReadTextFile(dir);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error().code, Code::kIo);
  EXPECT_EQ(text.error().message, dir + ": is a directory, not a file");
  std::filesystem::remove(dir);
}

TEST(ResultTest, UnwritableFileIsAnIoError) {
  const std::string path = test_paths::UniqueTempPath("no_such_dir") + "/grid.txt";
  Status saved = SaveGrid(Grid(2, 2), path);
  ASSERT_FALSE(saved.ok());
  EXPECT_EQ(saved.error().code, Code::kIo);
}

TEST(ResultTest, CorruptMazeFileIsCorrupt) {
  const std::string path = WriteTemp("bad_maze.txt", "..C\n.x.\n");
  Result<Grid> grid = LoadGrid(path);
  ASSERT_FALSE(grid.ok());
  EXPECT_EQ(grid.error().code, Code::kCorrupt);
  EXPECT_EQ(grid.error().message,
            path + ": line 2, column 2: unexpected character 'x' (expected '#', '.' or 'C')");
  EXPECT_EQ(grid.error().subject, "");
  std::filesystem::remove(path);
}

TEST(ResultTest, CorruptMovingAiMapIsCorrupt) {
  const std::string path = WriteTemp("bad.map", "type octile\nheight 2\nwidth 2\nmap\n..\n.\n");
  Result<Grid> grid = LoadMazeFile(path, nullptr);
  ASSERT_FALSE(grid.ok());
  EXPECT_EQ(grid.error().code, Code::kCorrupt);
  EXPECT_EQ(grid.error().message, path + ": line 6: a row of 1 cells, the header says width 2");
  std::filesystem::remove(path);
}

TEST(ResultTest, CorruptChangeFileIsCorrupt) {
  const std::string path = WriteTemp("bad_changes.txt", "dynapath-changes 1 5 5 1\n1 1 25 1\n");
  Result<ChangeSequence> changes = LoadChanges(path, 5, 5);
  ASSERT_FALSE(changes.ok());
  EXPECT_EQ(changes.error().code, Code::kCorrupt);
  EXPECT_EQ(changes.error().message, path + ": time step 1: cell 25 outside the maze");
  Result<ChangeSequence> header = ChangesFromText("hello 1 5 5 1\n", 5, 5);
  ASSERT_FALSE(header.ok());
  EXPECT_EQ(header.error().code, Code::kCorrupt);
  std::filesystem::remove(path);
}

TEST(ResultTest, CorruptStationFileIsCorrupt) {
  const Grid grid(3, 3);
  Result<std::vector<int>> stations = ParseStationsFile("1 1\n7 7\n", grid);
  ASSERT_FALSE(stations.ok());
  EXPECT_EQ(stations.error().code, Code::kCorrupt);
  EXPECT_EQ(stations.error().message, "line 2: (7, 7) is outside the 3x3 map");
}

TEST(ResultTest, BadCellCountIsAnInvalidArgument) {
  Result<CellCount> count = ParseCellCount("lots");
  ASSERT_FALSE(count.ok());
  EXPECT_EQ(count.error().code, Code::kInvalidArgument);
}

// A source that is stopped (as the coordinator's is by Ctrl-C) before time
// step `stop_at`: the run ends there and the source says why.
class StoppedSource : public StepSource {
 public:
  StoppedSource(const Scenario& scenario, int stop_at) : inner_(scenario), stop_at_(stop_at) {}
  int total_steps() const override { return inner_.total_steps(); }
  Grid Initial(int pass) override { return inner_.Initial(pass); }
  ChangeStep Changes(int pass, int t) override {
    if (t >= stop_at_) {
      status_ = Error::Cancelled();
      return {};
    }
    return inner_.Changes(pass, t);
  }
  Status status() const override { return status_; }

 private:
  ScenarioStepSource inner_;
  int stop_at_;
  Status status_ = Ok{};
};

TEST(ResultTest, CancelledSourceEndsTheRunWithItsStatus) {
  const Scenario scenario = GenerateScenario(10, 10, Difficulty::kEasy, 3, 6);
  StoppedSource source(scenario, 4);
  const ApproachRun run =
      RunApproach(source, 0, Approach::kBfsOracle, PlannerOptions{}, nullptr, RunLabels{});
  // Time steps 0..3 ran; step 4 was never applied.
  ASSERT_EQ(run.steps.size(), 4u);
  EXPECT_EQ(run.steps.back().time_step, 3);
  ASSERT_FALSE(source.status().ok());
  EXPECT_EQ(source.status().error().code, Code::kCancelled);
  EXPECT_EQ(source.status().error().message, "interrupted");
}

TEST(ResultTest, SourceThatNeverFailsRunsEveryStep) {
  const Scenario scenario = GenerateScenario(10, 10, Difficulty::kEasy, 3, 6);
  ScenarioStepSource source(scenario);
  const ApproachRun run =
      RunApproach(source, 0, Approach::kBfsOracle, PlannerOptions{}, nullptr, RunLabels{});
  EXPECT_EQ(run.steps.size(), 7u);
  EXPECT_TRUE(source.status().ok());
}

}  // namespace
}  // namespace dynapath
