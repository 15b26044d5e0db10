#include "tools/common/study_results.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "dynapath/results_csv.h"
#include "dynapath/text_file.h"
#include "tests/temp_path.h"

namespace dynapath::cli {
namespace {

namespace fs = std::filesystem;

std::vector<ApproachRun> Runs(const std::vector<Approach>& approaches, const std::string& size,
                              const std::string& difficulty, int steps) {
  std::vector<ApproachRun> runs;
  for (Approach approach : approaches) {
    ApproachRun run;
    run.approach = approach;
    run.size_label = size;
    run.difficulty_label = difficulty;
    for (int t = 0; t <= steps; ++t) {
      StepRecord record;
      record.time_step = t;
      record.success_rate = 1.0;
      run.steps.push_back(record);
    }
    runs.push_back(run);
  }
  return runs;
}

class StudyResultsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(test_paths::UniqueTempPath("study_results_test"));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
  const std::vector<Approach> approaches_ = {Approach::kBfsOracle, Approach::kSingleAgent};
};

TEST_F(StudyResultsTest, CompleteOnlyWithEveryApproachAndStep) {
  const std::string a = (dir_ / "a").string();
  EXPECT_FALSE(ConfigurationComplete(a, approaches_, "20", "Easy", 5));  // no files
  ASSERT_TRUE(WriteResultFiles(Runs({Approach::kBfsOracle}, "20", "Easy", 5), a));
  EXPECT_FALSE(ConfigurationComplete(a, approaches_, "20", "Easy", 5));  // one approach of two
  ASSERT_TRUE(WriteResultFiles(Runs(approaches_, "20", "Easy", 5), a));
  EXPECT_TRUE(ConfigurationComplete(a, approaches_, "20", "Easy", 5));
  EXPECT_FALSE(ConfigurationComplete(a, approaches_, "20", "Easy", 6));  // other steps
  EXPECT_FALSE(ConfigurationComplete(a, approaches_, "20", "Hard", 5));  // other maze
  EXPECT_FALSE(ConfigurationComplete(a, {Approach::kSingleAgent, Approach::kBfsOracle}, "20",
                                     "Easy", 5));  // other order
  // A detailed file of an earlier, shorter run.
  ASSERT_TRUE(WriteTextFileAtomically(a + "/results_detailed.csv",
                                      DetailedResultsCsv(Runs(approaches_, "20", "Easy", 4))));
  EXPECT_FALSE(ConfigurationComplete(a, approaches_, "20", "Easy", 5));
}

TEST_F(StudyResultsTest, MergesInOrderWithOneHeader) {
  const std::string a = (dir_ / "a").string(), b = (dir_ / "b").string();
  const std::vector<ApproachRun> runs_a = Runs(approaches_, "20", "Easy", 2);
  const std::vector<ApproachRun> runs_b = Runs(approaches_, "50", "Hard", 3);
  ASSERT_TRUE(WriteResultFiles(runs_a, a));
  ASSERT_TRUE(WriteResultFiles(runs_b, b));
  ASSERT_TRUE(MergeResultFiles({b, a}, dir_.string(), "edge_"));
  std::vector<ApproachRun> both = runs_b;
  both.insert(both.end(), runs_a.begin(), runs_a.end());
  EXPECT_EQ(*ReadTextFile((dir_ / "edge_results.csv").string()), SummaryResultsCsv(both));
  EXPECT_EQ(*ReadTextFile((dir_ / "edge_results_detailed.csv").string()), DetailedResultsCsv(both));

  ASSERT_TRUE(MergeResultFiles({}, dir_.string(), ""));
  EXPECT_EQ(*ReadTextFile((dir_ / "results.csv").string()), SummaryResultsCsv({}));
  // Both files are tried, and the error names each one not written.
  const Status missing = MergeResultFiles({(dir_ / "missing").string()}, dir_.string(), "");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("results.csv not written: "), std::string::npos);
  EXPECT_NE(missing.error().message.find("results_detailed.csv not written: "), std::string::npos)
      << missing.error().message;
}

}  // namespace
}  // namespace dynapath::cli
