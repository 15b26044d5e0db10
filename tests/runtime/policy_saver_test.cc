// The --save-policy file of a run: sections it does not rewrite are kept,
// and a resumed run takes up only the file its checkpoint recorded.
#include "runtime/policy_saver.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "dynapath/quadtree.h"
#include "dynapath/text_file.h"
#include "tests/temp_path.h"

namespace dynapath::runtime {
namespace {

PolicyState MakeState(Approach approach, int step) {
  PolicyState s;
  s.approach = approach;
  s.rows = 8;
  s.cols = 8;
  s.leaf_limit = 4;
  s.node_count = QuadTree(8, 8, 4).node_count();
  s.step = step;
  s.training_counts.assign(static_cast<size_t>(s.node_count), step);
  s.table = QTable(64, QPrecision::kFloat);
  for (size_t i = 0; i < s.table.size(); ++i) s.table.values()[i] = static_cast<float>(i + step);
  return s;
}

class PolicySaverTest : public testing::Test {
 protected:
  void SetUp() override { std::filesystem::create_directories(dir_); }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  PolicyPlan Plan() const {
    PolicyPlan plan;
    plan.save_path = path_;
    return plan;  // --save-at 0
  }
  // The checkpoint of a run of `approaches_` after its first approach,
  // with what `saver` holds.
  RunCheckpoint AfterFirst(const std::vector<SavedSection>& record) const {
    RunCheckpoint checkpoint;
    checkpoint.pass = 1;
    checkpoint.approach_count = 2;
    checkpoint.runs.resize(1);
    checkpoint.runs[0].approach = approaches_[0];
    checkpoint.policy_file = record;
    return checkpoint;
  }
  std::string OpenError(const RunCheckpoint& checkpoint) const {
    Result<PolicySaver> saver = PolicySaver::Open(Plan(), approaches_, 5, &checkpoint);
    return saver ? "" : saver.error().message;
  }

  const std::string dir_ = test_paths::UniqueTempPath("policy_saver");
  const std::string path_ = dir_ + "/p.pol";
  const std::vector<Approach> approaches_ = {Approach::kSingleAgent, Approach::kFedAsynQEqAvg};
};

TEST_F(PolicySaverTest, KeepsTheSectionsItDoesNotRewrite) {
  ASSERT_TRUE(WritePolicyFile(
      path_, {MakeState(Approach::kSingleAgent, 0), MakeState(Approach::kFedAsynQEqAvg, 0)}));
  Result<PolicySaver> saver = PolicySaver::Open(Plan(), {Approach::kFedAsynQEqAvg}, 5, nullptr);
  ASSERT_TRUE(saver) << saver.error().message;
  ASSERT_TRUE(saver->Save(MakeState(Approach::kFedAsynQEqAvg, 3)));
  Result<std::vector<PolicyState>> read = ReadPolicyFile(path_);
  ASSERT_TRUE(read) << read.error().message;
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ((*read)[0].approach, Approach::kSingleAgent);
  EXPECT_EQ((*read)[0].step, 0);
  EXPECT_EQ((*read)[1].approach, Approach::kFedAsynQEqAvg);
  EXPECT_EQ((*read)[1].step, 3);
}

TEST_F(PolicySaverTest, RefusesToOverwriteWhatIsNotAPolicyFile) {
  ASSERT_TRUE(WriteTextFileAtomically(path_, "Approach,Size\n"));
  Result<PolicySaver> saver = PolicySaver::Open(Plan(), approaches_, 5, nullptr);
  ASSERT_FALSE(saver);
  EXPECT_NE(saver.error().message.find("is there and is not a policy file"), std::string::npos);
}

TEST_F(PolicySaverTest, AResumedRunTakesUpOnlyTheFileItsCheckpointRecorded) {
  Result<PolicySaver> first = PolicySaver::Open(Plan(), approaches_, 5, nullptr);
  ASSERT_TRUE(first);
  ASSERT_TRUE(first->Save(MakeState(Approach::kSingleAgent, 0)));
  const RunCheckpoint checkpoint = AfterFirst(first->Record());
  EXPECT_EQ(OpenError(checkpoint), "");

  // A newer section of the approach still to run (written just before a
  // kill) is replaced later: fine.
  ASSERT_TRUE(first->Save(MakeState(Approach::kFedAsynQEqAvg, 0)));
  EXPECT_EQ(OpenError(checkpoint), "");

  std::filesystem::remove(path_);
  EXPECT_NE(OpenError(checkpoint)
                .find("p.pol is gone: at the checkpoint it held the run's "
                      "singleAgent section; restore it"),
            std::string::npos);
  // Another run's file: another singleAgent section, or none.
  ASSERT_TRUE(WritePolicyFile(path_, {MakeState(Approach::kSingleAgent, 2)}));
  EXPECT_NE(OpenError(checkpoint).find("p.pol's singleAgent section is not the one it held"),
            std::string::npos);
  ASSERT_TRUE(WritePolicyFile(path_, {MakeState(Approach::kFedAsynQEqAvg, 0)}));
  EXPECT_NE(OpenError(checkpoint).find("no longer holds the singleAgent section"),
            std::string::npos);
  // A section of an approach the run does not save, not there at its start.
  ASSERT_TRUE(WritePolicyFile(
      path_, {MakeState(Approach::kSingleAgent, 0), MakeState(Approach::kOnlyTrainLeafNodes, 0)}));
  EXPECT_NE(OpenError(checkpoint).find("holds a onlyTrainLeafNodes section the run neither saved"),
            std::string::npos);
  // The checkpointed run saved nothing (--save-policy given on resuming).
  EXPECT_NE(OpenError(AfterFirst({})).find("the checkpointed run saved no singleAgent section"),
            std::string::npos);
}

}  // namespace
}  // namespace dynapath::runtime
