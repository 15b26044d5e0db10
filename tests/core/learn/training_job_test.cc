#include "dynapath/training_job.h"

#include <gtest/gtest.h>

namespace dynapath {
namespace {

TrainingJob TwoByTwoJob() {
  TrainingJob job;
  job.region = Region{0, 1, 0, 1};
  job.codes = {0, 0, 0, 1};
  return job;
}

TEST(TrainingJobTest, CheckJobAcceptsMatchingCodesAndWarmStarts) {
  TrainingJob job = TwoByTwoJob();
  EXPECT_TRUE(CheckJob(job).ok());  // no warm start: zeros
  EXPECT_EQ(StartingTable(job).cells(), 4);
  job.warm_start = QTable(4);
  job.warm_start.values()[3] = 2.5f;
  ASSERT_TRUE(CheckJob(job).ok());
  EXPECT_EQ(StartingTable(job).values()[3], 2.5f);
}

TEST(TrainingJobTest, CheckJobReportsWhatDoesNotMatchTheRegion) {
  TrainingJob codes = TwoByTwoJob();
  codes.codes.pop_back();
  const Status bad_codes = CheckJob(codes);
  ASSERT_FALSE(bad_codes.ok());
  EXPECT_NE(bad_codes.error().message.find("cell codes"), std::string::npos);
  TrainingJob warm = TwoByTwoJob();
  warm.warm_start = QTable(3);
  const Status bad_warm = CheckJob(warm);
  ASSERT_FALSE(bad_warm.ok());
  EXPECT_NE(bad_warm.error().message.find("warm start"), std::string::npos);
}

}  // namespace
}  // namespace dynapath
