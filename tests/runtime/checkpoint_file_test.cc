#include "runtime/checkpoint_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dynapath/quadtree.h"
#include "tests/temp_path.h"

namespace dynapath::runtime {
namespace {

ApproachRun MakeRun(Approach approach, int rows) {
  ApproachRun run;
  run.approach = approach;
  run.size_label = "12x9";
  run.difficulty_label = "Custom";
  run.initial_seconds = 0.125;
  run.load_seconds = 0.0625;
  for (int t = 0; t < rows; ++t) {
    // Values that a decimal round trip would not keep exactly.
    run.steps.push_back(
        StepRecord{t, t * 3, t / 7.0, 1.0 / (t + 3), 6.0 + t / 11.0, t % 4, t % 3 - 1});
  }
  return run;
}

PolicyState MakePolicy(Approach approach, int step) {
  PolicyState s;
  s.approach = approach;
  s.rows = 12;
  s.cols = 9;
  s.leaf_limit = 4;
  s.node_count = QuadTree(12, 9, 4).node_count();
  s.step = step;
  s.run_seed = 52;
  s.training_counts.assign(static_cast<size_t>(s.node_count), 1);
  s.baselines.assign(static_cast<size_t>(s.node_count), 0.75);
  s.table = QTable(12 * 9, QPrecision::kFloat);
  for (size_t i = 0; i < s.table.size(); ++i) s.table.values()[i] = static_cast<float>(i) / 8;
  return s;
}

RunCheckpoint InProgress() {
  RunCheckpoint c;
  c.pass = 2;
  c.runs = {MakeRun(Approach::kBfsOracle, 9), MakeRun(Approach::kSingleAgent, 9),
            MakeRun(Approach::kFedAsynQEqAvg, 5)};
  c.policy = MakePolicy(Approach::kFedAsynQEqAvg, 4);
  c.approach_count = 4;
  c.policy_file = {{Approach::kSingleAgent, 0x0123456789abcdefULL},
                   {Approach::kOnlyTrainLeafNodes, 7}};
  return c;
}

void ExpectSameRuns(const std::vector<ApproachRun>& a, const std::vector<ApproachRun>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].approach, b[i].approach);
    EXPECT_EQ(a[i].size_label, b[i].size_label);
    EXPECT_EQ(a[i].difficulty_label, b[i].difficulty_label);
    EXPECT_EQ(a[i].initial_seconds, b[i].initial_seconds);
    EXPECT_EQ(a[i].load_seconds, b[i].load_seconds);
    ASSERT_EQ(a[i].steps.size(), b[i].steps.size());
    for (size_t t = 0; t < a[i].steps.size(); ++t) {
      const StepRecord &x = a[i].steps[t], &y = b[i].steps[t];
      EXPECT_EQ(x.time_step, y.time_step);
      EXPECT_EQ(x.num_changes, y.num_changes);
      EXPECT_EQ(x.adapt_seconds, y.adapt_seconds);  // exact: bits, not decimals
      EXPECT_EQ(x.success_rate, y.success_rate);
      EXPECT_EQ(x.average_path_length, y.average_path_length);
      EXPECT_EQ(x.nodes_trained, y.nodes_trained);
      EXPECT_EQ(x.highest_level, y.highest_level);
    }
  }
}

std::string_view View(const std::vector<uint8_t>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

TEST(CheckpointFile, RoundTripsAnApproachInProgressExactly) {
  const RunCheckpoint c = InProgress();
  Result<std::vector<uint8_t>> bytes = EncodeCheckpoint(c);
  ASSERT_TRUE(bytes) << bytes.error().message;
  Result<RunCheckpoint> back = DecodeCheckpoint(View(*bytes));
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back->pass, 2);
  EXPECT_EQ(back->approach_count, 4);
  EXPECT_EQ(back->policy_file, c.policy_file);
  ExpectSameRuns(c.runs, back->runs);
  ASSERT_TRUE(back->policy.has_value());
  EXPECT_EQ(back->policy->step, 4);
  EXPECT_EQ(back->policy->table.values(), c.policy->table.values());
  EXPECT_EQ(back->policy->baselines, c.policy->baselines);
}

TEST(CheckpointFile, RoundTripsFinishedApproachesWithoutAPolicy) {
  RunCheckpoint c;
  c.pass = 1;
  c.approach_count = 1;
  c.runs = {MakeRun(Approach::kAStarStatic, 3)};
  Result<std::vector<uint8_t>> bytes = EncodeCheckpoint(c);
  ASSERT_TRUE(bytes);
  Result<RunCheckpoint> back = DecodeCheckpoint(View(*bytes));
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back->pass, 1);
  EXPECT_FALSE(back->policy.has_value());
  ExpectSameRuns(c.runs, back->runs);
}

TEST(CheckpointFile, RefusesInconsistentCheckpointsToEncode) {
  RunCheckpoint c = InProgress();
  c.pass = 0;  // three runs, none finished
  EXPECT_FALSE(EncodeCheckpoint(c));
  c = InProgress();
  c.approach_count = 2;  // fewer than its runs
  EXPECT_FALSE(EncodeCheckpoint(c));
  RunCheckpoint policy_without_run;
  policy_without_run.pass = 0;
  policy_without_run.policy = MakePolicy(Approach::kSingleAgent, 0);
  EXPECT_FALSE(EncodeCheckpoint(policy_without_run));
}

TEST(CheckpointFile, EveryFlippedByteAndEveryTruncationIsOneCorruptError) {
  Result<std::vector<uint8_t>> bytes = EncodeCheckpoint(InProgress());
  ASSERT_TRUE(bytes);
  for (size_t at = 0; at < bytes->size(); at += 97) {
    std::vector<uint8_t> damaged = *bytes;
    damaged[at] ^= 0x20;
    Result<RunCheckpoint> back = DecodeCheckpoint(View(damaged));
    ASSERT_FALSE(back) << "byte " << at;
    EXPECT_EQ(back.error().code, Error::Code::kCorrupt);
  }
  for (size_t size = 0; size < bytes->size(); size += 101) {
    const std::vector<uint8_t> cut(bytes->begin(), bytes->begin() + static_cast<long>(size));
    ASSERT_FALSE(DecodeCheckpoint(View(cut))) << "cut at " << size;
  }
}

TEST(CheckpointFile, SaysWhatIsWrong) {
  Result<std::vector<uint8_t>> bytes = EncodeCheckpoint(InProgress());
  ASSERT_TRUE(bytes);
  std::vector<uint8_t> version = *bytes;
  version[8] = 9;
  EXPECT_NE(DecodeCheckpoint(View(version)).error().message.find("format version 9"),
            std::string::npos);
  std::vector<uint8_t> magic = *bytes;
  magic[0] = 'X';
  EXPECT_NE(DecodeCheckpoint(View(magic)).error().message.find("not a DynaPath checkpoint"),
            std::string::npos);
  std::vector<uint8_t> flipped = *bytes;
  flipped[40] ^= 1;
  EXPECT_NE(DecodeCheckpoint(View(flipped)).error().message.find("checksum mismatch"),
            std::string::npos);
}

TEST(CheckpointFile, RefusesAPolicyOfAnotherStepOrApproachThanTheRows) {
  RunCheckpoint c = InProgress();
  c.policy->step = 3;  // the rows end at step 4
  Result<std::vector<uint8_t>> bytes = EncodeCheckpoint(c);
  ASSERT_TRUE(bytes);
  Result<RunCheckpoint> back = DecodeCheckpoint(View(*bytes));
  ASSERT_FALSE(back);
  EXPECT_NE(back.error().message.find("of step 3, its last row of step 4"), std::string::npos);
  c = InProgress();
  c.policy = MakePolicy(Approach::kSingleAgent, 4);
  bytes = EncodeCheckpoint(c);
  ASSERT_TRUE(bytes);
  EXPECT_FALSE(DecodeCheckpoint(View(*bytes)));
}

TEST(CheckpointFile, WritesAndReadsADirectory) {
  const std::string dir = test_paths::UniqueTempPath("checkpoint_dir");
  std::filesystem::create_directories(dir);
  Result<RunCheckpoint> none = ReadCheckpoint(dir);
  ASSERT_FALSE(none);
  EXPECT_TRUE(none.error().IsNotFound());
  ASSERT_TRUE(WriteCheckpoint(dir, InProgress()));
  Result<RunCheckpoint> back = ReadCheckpoint(dir);
  ASSERT_TRUE(back) << back.error().message;
  ExpectSameRuns(InProgress().runs, back->runs);
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename(), kCheckpointFileName) << "left behind: " << entry.path();
  }
  { std::ofstream(dir + "/" + kCheckpointFileName, std::ios::binary | std::ios::trunc) << "DYNA"; }
  Result<RunCheckpoint> cut = ReadCheckpoint(dir);
  ASSERT_FALSE(cut);
  EXPECT_NE(cut.error().message.find("checkpoint " + dir + "/checkpoint.dpc: "), std::string::npos);
  std::filesystem::remove_all(dir);
}

// A new run may take a folder with no checkpoint or a finished run's; an
// unfinished one's is refused, saying what is there and how to resume it.
TEST(CheckpointFile, ANewRunLeavesAnUnfinishedRunsCheckpointAlone) {
  const std::string dir = test_paths::UniqueTempPath("checkpoint_free");
  std::filesystem::create_directories(dir);
  EXPECT_TRUE(CheckCheckpointFree(dir));
  ASSERT_TRUE(WriteCheckpoint(dir, InProgress()));
  Status taken = CheckCheckpointFree(dir);
  ASSERT_FALSE(taken);
  EXPECT_EQ(taken.error().message,
            "option --checkpoint " + dir +
                " holds the checkpoint of an unfinished run (2 of 4 approaches finished, "
                "fedAsynQ_EqAvg after step 4): finish it with `dynapath run --resume " +
                dir + "`, or give --force to start a new run there (that checkpoint is then lost)");
  RunCheckpoint finished;
  finished.pass = finished.approach_count = 1;
  finished.runs = {MakeRun(Approach::kAStarStatic, 3)};
  ASSERT_TRUE(WriteCheckpoint(dir, finished));
  EXPECT_TRUE(CheckCheckpointFree(dir));
  std::ofstream(dir + "/" + kCheckpointFileName, std::ios::binary | std::ios::trunc) << "DYNA";
  Status damaged = CheckCheckpointFree(dir);
  ASSERT_FALSE(damaged);
  EXPECT_NE(damaged.error().message.find("cannot be read"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dynapath::runtime
