#include "runtime/policy_file.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "dynapath/quadtree.h"
#include "tests/temp_path.h"

namespace dynapath::runtime {
namespace {

PolicyState MakeState(Approach approach, QPrecision precision, bool baselines) {
  PolicyState s;
  s.approach = approach;
  s.rows = 12;
  s.cols = 9;
  s.leaf_limit = 4;
  s.node_count = QuadTree(12, 9, 4).node_count();
  s.precision = precision;
  s.semantics = precision == QPrecision::kDouble ? Semantics::kReport : Semantics::kOurs;
  s.learner.single_agent.max_episodes = 777;
  s.learner.federated.learners = 5;
  s.thresholds.max_drop = 0.02;
  s.run_seed = 0x1234567890abcdefull;
  s.step = 7;
  s.initial_fingerprint = 11;
  s.fingerprint = 22;
  for (int node = 0; node < s.node_count; ++node) s.training_counts.push_back(node % 3);
  if (baselines) {
    for (int node = 0; node < s.node_count; ++node) s.baselines.push_back(node % 2 ? -1.0 : 0.5);
  }
  s.table = QTable(12 * 9, precision);
  for (size_t i = 0; i < s.table.size(); ++i) {
    if (precision == QPrecision::kFloat) {
      s.table.values()[i] = static_cast<float>(i % 17) * 0.25f;
    } else {
      s.table.wide_values()[i] = static_cast<double>(i % 13) / 3.0;
    }
  }
  return s;
}

void ExpectEqual(const PolicyState& a, const PolicyState& b) {
  EXPECT_EQ(a.approach, b.approach);
  EXPECT_EQ(a.rows, b.rows);
  EXPECT_EQ(a.cols, b.cols);
  EXPECT_EQ(a.leaf_limit, b.leaf_limit);
  EXPECT_EQ(a.node_count, b.node_count);
  EXPECT_EQ(a.semantics, b.semantics);
  EXPECT_EQ(a.precision, b.precision);
  EXPECT_EQ(a.learner.bootstrap, b.learner.bootstrap);
  EXPECT_EQ(a.learner.single_agent.max_episodes, b.learner.single_agent.max_episodes);
  EXPECT_EQ(a.learner.single_agent.epsilon_decay, b.learner.single_agent.epsilon_decay);
  EXPECT_EQ(a.learner.federated.learners, b.learner.federated.learners);
  EXPECT_EQ(a.thresholds.max_drop, b.thresholds.max_drop);
  EXPECT_EQ(a.run_seed, b.run_seed);
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.initial_fingerprint, b.initial_fingerprint);
  EXPECT_EQ(a.fingerprint, b.fingerprint);
  EXPECT_EQ(a.training_counts, b.training_counts);
  EXPECT_EQ(a.baselines, b.baselines);
  EXPECT_TRUE(a.table == b.table);
}

std::vector<PolicyState> TwoStates() {
  return {MakeState(Approach::kSingleAgent, QPrecision::kFloat, true),
          MakeState(Approach::kOnlyTrainLeafNodes, QPrecision::kDouble, false)};
}

std::string Encoded() {
  Result<std::vector<uint8_t>> bytes = EncodePolicyFile(TwoStates());
  EXPECT_TRUE(bytes.ok());
  return std::string(bytes->begin(), bytes->end());
}

std::string DecodeError(const std::string& bytes, bool verify = true) {
  Result<std::vector<PolicyState>> states = DecodePolicyFile(bytes, verify);
  EXPECT_FALSE(states.ok());
  if (states.ok()) return "";
  EXPECT_TRUE(states.error().IsCorrupt()) << states.error().message;
  return states.error().message;
}

TEST(PolicyFileTest, RoundTripsEveryField) {
  const std::vector<PolicyState> states = TwoStates();
  Result<std::vector<PolicyState>> decoded = DecodePolicyFile(Encoded());
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  ASSERT_EQ(decoded->size(), 2u);
  ExpectEqual(states[0], (*decoded)[0]);
  ExpectEqual(states[1], (*decoded)[1]);
}

TEST(PolicyFileTest, WritesAndReadsAFile) {
  const std::string path = test_paths::UniqueTempPath("policy_file_test.pol");
  ASSERT_TRUE(WritePolicyFile(path, TwoStates()).ok());
  Result<std::vector<PolicyState>> read = ReadPolicyFile(path);
  ASSERT_TRUE(read.ok()) << read.error().message;
  EXPECT_EQ(read->size(), 2u);
  std::remove(path.c_str());
  Result<std::vector<PolicyState>> missing = ReadPolicyFile(path);
  ASSERT_FALSE(missing.ok());
  EXPECT_TRUE(missing.error().IsNotFound());
  EXPECT_NE(missing.error().message.find(path), std::string::npos);
}

TEST(PolicyFileTest, RefusesBadMagicVersionAndChecksum) {
  const std::string good = Encoded();
  std::string bad = good;
  bad[0] = 'X';
  EXPECT_NE(DecodeError(bad).find("not a DynaPath policy file"), std::string::npos);
  bad = good;
  bad[8] = 2;
  EXPECT_EQ(DecodeError(bad), "format version 2, this build reads 1");
  bad = good;
  bad[good.size() / 2] ^= 1;
  EXPECT_EQ(DecodeError(bad), "checksum mismatch (the file is damaged)");
  bad = good;
  bad.back() ^= 1;
  EXPECT_EQ(DecodeError(bad), "checksum mismatch (the file is damaged)");
}

TEST(PolicyFileTest, RefusesEveryTruncationAndExtension) {
  const std::string good = Encoded();
  for (size_t size = 0; size < good.size(); size += 7) {
    DecodeError(good.substr(0, size));
    DecodeError(good.substr(0, size), false);
  }
  EXPECT_NE(DecodeError(good + "x").find("truncated or extended"), std::string::npos);
}

// With the checksum skipped (as the fuzz target does), a damaged section
// is still refused by the section parser, never accepted wrongly sized.
TEST(PolicyFileTest, SectionParserChecksShapeAgainstBlocks) {
  const std::string good = Encoded();
  // The first section's rows field: header 24 bytes, 2 lengths, 32-byte name.
  const size_t rows_at = 24 + 2 * 8 + 32;
  std::string bad = good;
  uint32_t rows = 13;
  std::memcpy(bad.data() + rows_at, &rows, sizeof(rows));
  EXPECT_NE(DecodeError(bad, false).find("section 1"), std::string::npos);
  rows = 100000;
  std::memcpy(bad.data() + rows_at, &rows, sizeof(rows));
  EXPECT_NE(DecodeError(bad, false).find("outside 1..4096"), std::string::npos);
  bad = good;
  bad[24 + 2 * 8] = 'Z';  // the approach name
  EXPECT_NE(DecodeError(bad, false).find("unknown learning approach"), std::string::npos);
}

TEST(PolicyFileTest, RefusesTwoSectionsOfOneApproach) {
  std::vector<PolicyState> states = TwoStates();
  states[1] = states[0];
  Result<std::vector<uint8_t>> bytes = EncodePolicyFile(states);
  ASSERT_TRUE(bytes.ok());
  EXPECT_EQ(DecodeError(std::string(bytes->begin(), bytes->end())), "two sections for singleAgent");
}

TEST(PolicyFileTest, RefusesAnOversizedFileUnread) {
  const std::string path = test_paths::UniqueTempPath("policy_file_big.pol");
  {
    std::ofstream out(path, std::ios::binary);
    out.seekp(static_cast<std::streamoff>(kMaxPolicyFileBytes));
    out.put('x');
  }
  Result<std::vector<PolicyState>> read = ReadPolicyFile(path);
  std::remove(path.c_str());
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.error().message.find("more than any policy file"), std::string::npos);
}

}  // namespace
}  // namespace dynapath::runtime
