#include "study/study_results.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "dynapath/results_csv.h"
#include "dynapath/text_file.h"
#include "dynapath/text_util.h"
#include "study/repeat_statistics.h"
#include "tests/temp_path.h"

namespace dynapath::study {
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

// repeats.csv rows: Repeat,Seed,LearnerSeed,Approach,Size,Difficulty,
// InitialTime,AdaptTimePerStep,AvgSuccessRate,AvgPathLength.
std::string RepeatsCsv(const std::vector<std::string>& rows) {
  std::string csv = RepeatsCsvHeader() + "\n";
  for (const std::string& row : rows) csv += row + "\n";
  return csv;
}

// The fields of row `index` (0 = header) of a CSV text.
std::vector<std::string> Row(const std::string& csv, size_t index) {
  size_t start = 0;
  for (size_t i = 0; i < index; ++i) start = csv.find('\n', start) + 1;
  return Split(csv.substr(start, csv.find('\n', start) - start), ',');
}

size_t RowCount(const std::string& csv) {
  return static_cast<size_t>(std::count(csv.begin(), csv.end(), '\n')) - 1;
}

// Two approaches on 20 Hard over four repeats (values exact in binary).
const std::vector<std::string> kRows = {
    "1,52,52,X,20,Hard,1,0.5,1,4",         "1,52,52,Y,20,Hard,2,0.5,0.5,5",
    "2,52,1000055,X,20,Hard,3,0.5,0.5,4",  "2,52,1000055,Y,20,Hard,2,0.5,0.5,6",
    "3,52,2000058,X,20,Hard,1,0.5,0.75,8", "3,52,2000058,Y,20,Hard,2,0.5,0.25,5",
    "4,52,3000061,X,20,Hard,3,0.5,0.25,4", "4,52,3000061,Y,20,Hard,2,0.5,0.5,4",
};

TEST(RepeatFilesTest, SummaryHoldsTheStatisticsOfEachConfigurationAndApproach) {
  Result<std::string> summary = SummaryCsv(RepeatsCsv(kRows));
  ASSERT_TRUE(summary.ok()) << summary.error().message;
  EXPECT_EQ(Row(*summary, 0)[0], "Approach");
  ASSERT_EQ(RowCount(*summary), 8u);  // one configuration: no rows over all
  // X's success rates 1, 0.5, 0.75, 0.25: mean 0.625, deviations +-0.375
  // and +-0.125, squares 0.3125 / 3; median and IQM (0.5 + 0.75) / 2.
  const std::vector<std::string> success = Row(*summary, 1);
  ASSERT_EQ(success.size(), 15u);
  EXPECT_EQ(success[0], "X");
  EXPECT_EQ(success[3], "AvgSuccessRate");
  EXPECT_EQ(success[4], "4");
  EXPECT_EQ(success[5], "0.625");
  EXPECT_EQ(success[6], "0.3227486122");  // sqrt(0.3125 / 3)
  EXPECT_EQ(success[7], "0.625");
  EXPECT_EQ(success[8], "0.625");
  const Interval ci = StratifiedBootstrap({{1, 0.5, 0.75, 0.25}}, Mean);
  char low[32];
  std::snprintf(low, sizeof low, "%.10g", ci.low);
  EXPECT_EQ(success[9], low);
  EXPECT_EQ(success[13], std::to_string(kBootstrapResamples));
  EXPECT_EQ(success[14], std::to_string(kBootstrapSeed));
  // X's path lengths 4, 4, 8, 4: median 4, IQM of {4, 4} 4, mean 5.
  const std::vector<std::string> length = Row(*summary, 2);
  EXPECT_EQ(length[3], "AvgPathLength");
  EXPECT_EQ(length[5], "5");
  EXPECT_EQ(length[7], "4");
  EXPECT_EQ(length[8], "4");
  EXPECT_EQ(Row(*summary, 3)[3], "InitialTime");
  EXPECT_EQ(Row(*summary, 3)[5], "2");
  EXPECT_EQ(Row(*summary, 5)[0], "Y");

  // A second configuration adds its rows and, per approach, rows over all.
  std::vector<std::string> rows = kRows;
  rows.push_back("1,50,50,X,30,Easy,1,0.5,1,3");
  rows.push_back("1,50,50,Y,30,Easy,1,0.5,1,3");
  summary = SummaryCsv(RepeatsCsv(rows));
  ASSERT_TRUE(summary.ok());
  ASSERT_EQ(RowCount(*summary), 8u + 8u + 8u);
  const std::vector<std::string> all = Row(*summary, 17);
  EXPECT_EQ(all[0] + "," + all[1] + "," + all[2] + "," + all[3] + "," + all[4],
            "X,all,all,AvgSuccessRate,5");
  EXPECT_EQ(all[5], "0.7");  // (2.5 + 1) / 5
}

// A repeats.csv saved with CRLF line ends (a Windows editor) is the same
// table, not one with the wrong header.
TEST(RepeatFilesTest, CrlfLineEndsReadAsLf) {
  const std::string lf = RepeatsCsv(kRows);
  std::string crlf;
  for (const char ch : lf) crlf += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
  Result<std::string> from_crlf = SummaryCsv(crlf);
  ASSERT_TRUE(from_crlf.ok()) << from_crlf.error().message;
  EXPECT_EQ(*from_crlf, *SummaryCsv(lf));
}

TEST(RepeatFilesTest, MalformedRepeatsAreOneErrorNamingTheLine) {
  EXPECT_FALSE(SummaryCsv("Repeat,Seed\n1,2\n").ok());
  Result<std::string> bad = SummaryCsv(RepeatsCsv({"1,52,52,X,20,Hard,1,0.5,one,4"}));
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "line 2: AvgSuccessRate: not a number: 'one'");
  bad = SummaryCsv(RepeatsCsv({"1,52,52,X,20,Hard,1,0.5,1"}));
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "line 2: expected 10 fields, got 9");
  bad = SummaryCsv(RepeatsCsv({kRows[0], kRows[0]}));
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "line 3: repeat 1 of X on 20 Hard is there twice");
}

TEST(RepeatFilesTest, CompareTakesPairedDifferences) {
  Result<std::string> compare = CompareCsv(RepeatsCsv(kRows), "X", "Y");
  ASSERT_TRUE(compare.ok()) << compare.error().message;
  ASSERT_EQ(RowCount(*compare), 4u);
  // Success X - Y: 0.5, 0, 0.5, -0.25: mean 0.1875, deviations 0.3125,
  // -0.1875, 0.3125, -0.4375, squares 0.421875 / 3 = 0.140625, std 0.375;
  // sorted -0.25 0 0.5 0.5: median and IQM 0.25; X greater in 2 pairs, tied
  // in 1: (2 + 0.5) / 4.
  const std::vector<std::string> success = Row(*compare, 1);
  ASSERT_EQ(success.size(), 15u);
  EXPECT_EQ(success[0] + "," + success[1] + "," + success[4] + "," + success[5],
            "X,Y,AvgSuccessRate,4");
  EXPECT_EQ(success[6], "0.1875");
  EXPECT_EQ(success[7], "0.375");
  EXPECT_EQ(success[8], "0.25");
  EXPECT_EQ(success[9], "0.25");
  EXPECT_EQ(success[12], "0.625");
  const Interval ci = StratifiedBootstrap({{0.5, 0, 0.5, -0.25}}, Mean);
  char high[32];
  std::snprintf(high, sizeof high, "%.10g", ci.high);
  EXPECT_EQ(success[11], high);

  // Pairs only where both have the repeat: Y's repeat 4 missing.
  std::vector<std::string> rows(kRows.begin(), kRows.end() - 1);
  compare = CompareCsv(RepeatsCsv(rows), "X", "Y");
  ASSERT_TRUE(compare.ok());
  EXPECT_EQ(Row(*compare, 1)[5], "3");

  EXPECT_FALSE(CompareCsv(RepeatsCsv(kRows), "X", "X").ok());
  Result<std::string> missing = CompareCsv(RepeatsCsv(kRows), "X", "Z");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, "approach 'Z' has no repeats here (there are: X, Y)");
  EXPECT_FALSE(CompareCsv(RepeatsCsv({kRows[0], "2,52,1,Y,30,Hard,1,1,1,1"}), "X", "Y").ok());
}

}  // namespace
}  // namespace dynapath::study
