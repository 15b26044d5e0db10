// Validation computes regions and counts from received int32 fields in 64
// bits: values near INT_MAX must not wrap into range (hostile-network table, docs/RELIABILITY.md,
// row 6).

#include "protocol/validate.h"

#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <limits>

#include "dynapath/learners.h"
#include "protocol/convert.h"
#include "tests/protocol/validation_problem.h"

namespace dynapath::protocol {
namespace {

job_batch_t BatchWithJob(int32_t row0, int32_t rows, int32_t col0, int32_t cols) {
  job_batch_t batch{};
  batch.kind = job_batch_t::KIND_SINGLE_AGENT;
  batch.max_episodes = batch.replay_capacity = batch.convergence_interval = 1;
  batch.convergence_checks = batch.learners = batch.sync_period = batch.iterations_per_cell = 1;
  job_t job{};
  job.row0 = row0;
  job.rows = rows;
  job.col0 = col0;
  job.cols = cols;
  job.grid_rows = job.grid_cols = 10;
  job.num_cells = 2;
  job.codes = {1, 1};
  batch.jobs = {job};
  batch.num_jobs = 1;
  return batch;
}

TEST(Validate, JobRegionsDoNotWrap) {
  EXPECT_EQ(ValidationProblem(BatchWithJob(0, 2, 0, 1)), "");
  EXPECT_EQ(ValidationProblem(BatchWithJob(8, 2, 9, 1)), "");
  EXPECT_NE(ValidationProblem(BatchWithJob(INT_MAX, 2, 0, 1)), "");
  EXPECT_NE(ValidationProblem(BatchWithJob(0, 2, INT_MAX, 1)), "");
  EXPECT_NE(ValidationProblem(BatchWithJob(INT_MAX - 1, 2, 0, 1)), "");
  EXPECT_NE(ValidationProblem(BatchWithJob(9, 2, 0, 1)), "");
  // rows * cols wrapping to the cell count.
  job_batch_t batch = BatchWithJob(0, 65536, 0, 65536);
  batch.jobs[0].num_cells = 0;
  batch.jobs[0].codes.clear();
  EXPECT_NE(ValidationProblem(batch), "");
}

TEST(Validate, PolicyRegionsDoNotWrap) {
  policy_t policy{};
  policy.rows = policy.cols = 2;
  policy.num_cells = 4;
  policy.cells = {1, 1, 1, 2};
  policy.actions = {0, 0, 0, -1};
  policy.reaches = {1, 1, 1, -1};
  policy.num_regions = 1;
  policy.region_row0 = {0};
  policy.region_col0 = {0};
  policy.region_rows = {2};
  policy.region_cols = {1};
  EXPECT_EQ(ValidationProblem(policy), "");
  policy.region_row0 = {INT_MAX};
  EXPECT_NE(ValidationProblem(policy), "");
  policy.region_row0 = {0};
  policy.region_col0 = {INT_MAX};
  EXPECT_NE(ValidationProblem(policy), "");
}

TEST(Validate, GridCellCountInSixtyFourBits) {
  grid_t grid{};
  grid.rows = grid.cols = 65536;  // above the limit anyway
  grid.num_cells = 0;
  EXPECT_NE(ValidationProblem(grid), "");
  grid.rows = grid.cols = 2;
  grid.num_cells = 4;
  grid.cells = {1, 1, 1, 2};
  EXPECT_EQ(ValidationProblem(grid), "");
}

TEST(Validate, EveryLearnerKindTravelsAndNoOtherIsAccepted) {
  job_batch_t batch = BatchWithJob(0, 1, 0, 2);
  for (LearnerKind kind : kAllLearnerKinds) {
    batch.kind = LearnerKindToWire(kind);
    EXPECT_EQ(LearnerKindFromWire(batch.kind), kind);
    EXPECT_EQ(ValidationProblem(batch), "");
  }
  batch.kind = 2;
  EXPECT_EQ(ValidationProblem(batch), "unknown learner kind");
  batch.kind = -1;
  EXPECT_EQ(ValidationProblem(batch), "unknown learner kind");
}

TEST(Validate, EveryBootstrapAndAveragingTravelsAndNoOtherIsAccepted) {
  job_batch_t batch = BatchWithJob(0, 1, 0, 2);
  for (Bootstrap bootstrap : {Bootstrap::kInGrid, Bootstrap::kInRegion, Bootstrap::kAllStored}) {
    for (Averaging averaging : {Averaging::kEqual, Averaging::kImportance}) {
      LearnerConfig config;
      config.bootstrap = bootstrap;
      config.federated.averaging = averaging;
      SetBatchOptions(config, batch);
      ASSERT_EQ(ValidationProblem(batch), "");
      Result<ReceivedJob> received = JobFromBatch(batch, 0);
      ASSERT_TRUE(received.ok()) << received.error().message;
      EXPECT_EQ(received->job.bootstrap, bootstrap);
      EXPECT_EQ(received->job.federated.averaging, averaging);
    }
  }
  job_batch_t bad = batch;
  bad.bootstrap = 3;
  EXPECT_EQ(ValidationProblem(bad), "bad bootstrap or averaging");
  bad = batch;
  bad.averaging = 2;
  EXPECT_EQ(ValidationProblem(bad), "bad bootstrap or averaging");
}

TEST(Validate, UnvalidatedHeaderEnumsAreAnErrorNotADefault) {
  // JobFromBatch never guesses: a value Validate would refuse is an error
  // there too (it used to fall back to single-agent / float).
  for (auto spoil :
       {+[](job_batch_t& b) { b.kind = 9; }, +[](job_batch_t& b) { b.bootstrap = -1; },
        +[](job_batch_t& b) { b.averaging = 7; }, +[](job_batch_t& b) { b.precision = 5; }}) {
    job_batch_t batch = BatchWithJob(0, 1, 0, 2);
    spoil(batch);
    EXPECT_NE(ValidationProblem(batch), "");
    EXPECT_FALSE(JobFromBatch(batch, 0).ok());
  }
}

TEST(Validate, OnlyALearnerThatTrainsInRoundsIsSplit) {
  job_batch_t batch = BatchWithJob(0, 1, 0, 2);
  batch.num_items = 1;
  batch.item_job = {0};
  batch.item_learner = {0};  // learner 0 of job 0: a split item
  batch.item_agent = {1};
  batch.kind = LearnerKindToWire(LearnerKind::kFedAsynQ);
  EXPECT_EQ(ValidationProblem(batch), "");
  batch.kind = LearnerKindToWire(LearnerKind::kSingleAgent);
  EXPECT_EQ(ValidationProblem(batch), "split item of a whole-job learner");
  batch.item_learner = {-1};  // the whole job
  EXPECT_EQ(ValidationProblem(batch), "");
}

TEST(Validate, EveryLearnerOptionOutsideItsRangeIsNamed) {
  job_batch_t good = BatchWithJob(0, 1, 0, 2);
  SetBatchOptions(LearnerConfig{}, good);  // the defaults are in range
  ASSERT_EQ(ValidationProblem(good), "");
  job_batch_t batch = good;
  batch.learners = learner_option::kMaxLearners + 1;
  EXPECT_EQ(ValidationProblem(batch), "bad federated option learners");
  batch = good;
  batch.sync_period = 0;
  EXPECT_EQ(ValidationProblem(batch), "bad federated option sync_period");
  batch = good;
  batch.replay_batch = -1;
  EXPECT_EQ(ValidationProblem(batch), "bad single-agent option replay_batch");
  batch = good;
  batch.epsilon_decay = std::nan("");
  EXPECT_EQ(ValidationProblem(batch), "bad single-agent option epsilon_decay");
  batch = good;
  batch.convergence_threshold = std::numeric_limits<double>::infinity();
  EXPECT_EQ(ValidationProblem(batch), "bad single-agent option convergence_threshold");
  // The parameters' ranges (dynapath/parameters.h), the same as on the
  // command line.
  batch = good;
  batch.replay_start_episode = -5;
  EXPECT_EQ(ValidationProblem(batch), "bad single-agent option replay_start_episode");
  batch = good;
  batch.epsilon_start = 1.5;
  EXPECT_EQ(ValidationProblem(batch), "bad single-agent option epsilon_start");
  batch = good;
  batch.replay_capacity = 10000001;  // bounds the buffer an agent allocates
  EXPECT_EQ(ValidationProblem(batch), "bad single-agent option replay_capacity");
  batch = good;
  batch.epsilon_start = 0.0;  // the ends of a range are in it
  batch.replay_batch = 10000;
  EXPECT_EQ(ValidationProblem(batch), "");
}

TEST(Validate, LearnerOptionsRoundTripThroughTheWire) {
  LearnerConfig config;
  config.kind = LearnerKind::kFedAsynQ;
  config.single_agent.max_episodes = 7;
  config.single_agent.epsilon_decay = 0.25;
  config.single_agent.convergence_checks = 3;
  config.federated.learners = 5;
  config.federated.iterations_per_cell = 9;
  job_batch_t batch = BatchWithJob(0, 1, 0, 2);
  SetBatchOptions(config, batch);
  ASSERT_EQ(ValidationProblem(batch), "");
  Result<ReceivedJob> received = JobFromBatch(batch, 0);
  ASSERT_TRUE(received.ok()) << received.error().message;
  const TrainingJob& job = received->job;
  EXPECT_EQ(job.kind, LearnerKind::kFedAsynQ);
#define DYNAPATH_EXPECT_SAME(member, ...) \
  EXPECT_EQ(job.single_agent.member, config.single_agent.member) << #member;
  DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_EXPECT_SAME)
#undef DYNAPATH_EXPECT_SAME
#define DYNAPATH_EXPECT_SAME(member, ...) \
  EXPECT_EQ(job.federated.member, config.federated.member) << #member;
  DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_EXPECT_SAME)
#undef DYNAPATH_EXPECT_SAME
}

// --semantics report's double tables travel as doubles, bit for bit; a
// table of the other precision, or an unknown precision, is refused.
TEST(Validate, TablesTravelInTheBatchPrecision) {
  for (const QPrecision precision : {QPrecision::kFloat, QPrecision::kDouble}) {
    TrainingJob job;
    job.node = 3;
    job.region = Region{0, 0, 0, 1};
    job.codes = {1, 1};
    job.grid_rows = job.grid_cols = 10;
    job.precision = precision;
    job.warm_start = QTable(2, precision);
    WithValueType(precision, [&]<typename V>(V*) {
      for (size_t i = 0; i < job.warm_start.size(); ++i) {
        job.warm_start.Values<V>()[i] = static_cast<V>(0.1) * static_cast<V>(i + 1);
      }
    });
    job_batch_t batch{};
    SetBatchOptions(LearnerConfig{}, batch);
    AddJob(job, JobProgress{}, batch);
    ASSERT_EQ(ValidationProblem(batch), "");
    Result<ReceivedJob> received = JobFromBatch(batch, 0);
    ASSERT_TRUE(received.ok()) << received.error().message;
    EXPECT_EQ(received->job.precision, precision);
    EXPECT_TRUE(received->job.warm_start == job.warm_start);

    // The table in the other precision's field.
    job_batch_t wrong = batch;
    wrong.precision = precision == QPrecision::kFloat ? job_batch_t::PRECISION_DOUBLE
                                                      : job_batch_t::PRECISION_FLOAT;
    EXPECT_EQ(ValidationProblem(wrong), "job table size mismatch");
    wrong.precision = 2;
    EXPECT_EQ(ValidationProblem(wrong), "unknown table precision");
  }
}

}  // namespace
}  // namespace dynapath::protocol
