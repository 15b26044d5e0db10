#include "tools/view/policy_stream.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>

#include "dynapath/fragment_t.hpp"
#include "dynapath/heartbeat_t.hpp"
#include "tests/view/policy_test_support.h"

namespace dynapath::view {
namespace {

using testing::MakePolicy;

const std::string kChannel = "DYNAPATH/r1/POLICY";

template <class T>
std::vector<uint8_t> Encode(const T& message) {
  std::vector<uint8_t> bytes(static_cast<size_t>(message.getEncodedSize()));
  message.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// The pieces a Bus sends for `bytes` (see protocol/bus.cc).
std::vector<std::vector<uint8_t>> Fragments(const std::vector<uint8_t>& bytes, int piece,
                                            int64_t message_id, const std::string& run = "r1") {
  fragment_t fragment{};
  fragment.run_id = run;
  fragment.message_id = message_id;
  fragment.fingerprint = static_cast<int64_t>(policy_t::getHash());
  fragment.total_size = static_cast<int32_t>(bytes.size());
  fragment.count = static_cast<int32_t>((bytes.size() + piece - 1) / piece);
  std::vector<std::vector<uint8_t>> pieces;
  for (int32_t i = 0; i < fragment.count; ++i) {
    const size_t begin = static_cast<size_t>(i) * piece;
    const size_t end = std::min(bytes.size(), begin + piece);
    fragment.index = i;
    fragment.offset = static_cast<int32_t>(begin);
    fragment.size = static_cast<int32_t>(end - begin);
    fragment.data.assign(bytes.begin() + static_cast<std::ptrdiff_t>(begin),
                         bytes.begin() + static_cast<std::ptrdiff_t>(end));
    pieces.push_back(Encode(fragment));
  }
  return pieces;
}

std::optional<policy_t> Feed(PolicyAssembler& assembler, const std::vector<uint8_t>& bytes,
                             const std::string& channel = kChannel, int64_t now = 0) {
  return assembler.Feed(channel, bytes.data(), static_cast<int>(bytes.size()), now);
}

TEST(PolicyStream, ChannelRun) {
  EXPECT_EQ(PolicyChannelRun("DYNAPATH/r1/POLICY"), "r1");
  EXPECT_EQ(PolicyChannelRun("DYNAPATH/r2026-1_x/POLICY"), "r2026-1_x");
  EXPECT_EQ(PolicyChannelRun("DYNAPATH/r1/REPORT"), std::nullopt);
  EXPECT_EQ(PolicyChannelRun("DYNAPATH//POLICY"), std::nullopt);
  EXPECT_EQ(PolicyChannelRun("DYNAPATH/a/b/POLICY"), std::nullopt);
  EXPECT_EQ(PolicyChannelRun("OTHER/r1/POLICY"), std::nullopt);
  EXPECT_EQ(PolicyChannelRun("POLICY"), std::nullopt);
}

TEST(PolicyStream, WholeMessage) {
  PolicyAssembler assembler;
  policy_t sent = MakePolicy(6, 7);
  sent.actions[3] = 4;
  sent.reaches[3] = 1;
  const std::optional<policy_t> got = Feed(assembler, Encode(sent));
  ASSERT_TRUE(got.has_value()) << assembler.why();
  EXPECT_EQ(got->approach, sent.approach);
  EXPECT_EQ(got->actions, sent.actions);
  EXPECT_EQ(assembler.counters().policies, 1);
  EXPECT_EQ(assembler.counters().dropped, 0);
}

TEST(PolicyStream, ReassemblesFragmentsInAnyOrder) {
  PolicyAssembler assembler;
  policy_t sent = MakePolicy(300, 300, "BFS Oracle", 12);  // 270 KB: fragmented by the Bus
  for (int i = 0; i < sent.num_cells; i += 7) sent.actions[static_cast<size_t>(i)] = 3;
  std::vector<std::vector<uint8_t>> pieces = Fragments(Encode(sent), 60000, 77);
  ASSERT_EQ(pieces.size(), 5u);
  std::swap(pieces[0], pieces[3]);
  pieces.insert(pieces.begin() + 3, pieces[1]);  // a piece heard twice
  int completed = 0;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const std::optional<policy_t> got = Feed(assembler, pieces[i]);
    if (got) {
      ++completed;
      EXPECT_EQ(i, pieces.size() - 1);
      EXPECT_EQ(got->time_step, 12);
      EXPECT_EQ(got->actions, sent.actions);
    }
  }
  EXPECT_EQ(completed, 1);
  EXPECT_EQ(assembler.pending(), 0u);
  EXPECT_EQ(assembler.counters().fragments, 6);
  EXPECT_EQ(assembler.counters().dropped, 0);

  // Two messages interleaved.
  const auto a = Fragments(Encode(MakePolicy(300, 300, "a")), 60000, 1);
  const auto b = Fragments(Encode(MakePolicy(300, 300, "b")), 60000, 2);
  std::vector<std::string> approaches;
  for (size_t i = 0; i < a.size(); ++i) {
    for (const auto* pieces_of : {&a, &b}) {
      if (auto got = Feed(assembler, (*pieces_of)[i])) approaches.push_back(got->approach);
    }
  }
  EXPECT_EQ(approaches, (std::vector<std::string>{"a", "b"}));
}

TEST(PolicyStream, DropsBadMessages) {
  PolicyAssembler assembler;
  int expected_drops = 0;
  auto expect_drop = [&](const std::vector<uint8_t>& bytes, const std::string& why,
                         const std::string& channel = kChannel) {
    EXPECT_FALSE(Feed(assembler, bytes, channel).has_value());
    EXPECT_EQ(assembler.counters().dropped, ++expected_drops);
    EXPECT_NE(assembler.why().find(why), std::string::npos) << assembler.why();
  };
  expect_drop({}, "another type");
  expect_drop({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}, "another type");
  heartbeat_t beat{};
  beat.run_id = "r1";
  expect_drop(Encode(beat), "another type");
  expect_drop(Encode(MakePolicy(3, 3)), "not a POLICY channel", "DYNAPATH/r1/REPORT");

  // The right fingerprint, a garbage body.
  std::vector<uint8_t> bytes = Encode(MakePolicy(4, 4));
  std::vector<uint8_t> truncated(bytes.begin(), bytes.begin() + 20);
  expect_drop(truncated, "undecodable");
  std::vector<uint8_t> huge_count = bytes;
  for (size_t i = 8; i < huge_count.size(); ++i) huge_count[i] = 0x7f;
  expect_drop(huge_count, "policy_t");

  policy_t bad_action = MakePolicy(3, 3);
  bad_action.actions[4] = 9;
  expect_drop(Encode(bad_action), "bad action");
  policy_t bad_region = MakePolicy(3, 3);
  testing::AddRegion(bad_region, 2, 2, 2, 1);
  expect_drop(Encode(bad_region), "region");
  policy_t mismatch = MakePolicy(3, 3);
  mismatch.num_cells = 8;
  mismatch.cells.resize(8);
  expect_drop(Encode(mismatch), "cell count");
  expect_drop(Encode(MakePolicy(3, 3, "x", 0, "r2")), "run");

  // Fragments: of another run, of another type, pointing outside their
  // message, inconsistent with earlier pieces.
  const std::vector<uint8_t> big = Encode(MakePolicy(300, 300));
  expect_drop(Fragments(big, 60000, 5, "r9")[0], "another run");
  fragment_t fragment{};
  auto pieces = Fragments(big, 60000, 6);
  ASSERT_EQ(fragment.decode(pieces[1].data(), 0, static_cast<int>(pieces[1].size())),
            static_cast<int>(pieces[1].size()));
  fragment_t other_type = fragment;
  other_type.fingerprint = static_cast<int64_t>(heartbeat_t::getHash());
  expect_drop(Encode(other_type), "no policy_t");
  fragment_t outside = fragment;
  outside.offset = outside.total_size - 10;
  expect_drop(Encode(outside), "fragment_t");
  fragment_t bad_index = fragment;
  bad_index.index = bad_index.count;
  expect_drop(Encode(bad_index), "fragment_t");
  EXPECT_FALSE(Feed(assembler, pieces[0]).has_value());  // a good first piece
  fragment_t inconsistent = fragment;
  inconsistent.total_size -= 1;
  expect_drop(Encode(inconsistent), "inconsistent");
  std::vector<uint8_t> garbage_fragment = pieces[2];
  garbage_fragment.resize(30);
  expect_drop(garbage_fragment, "undecodable fragment");
  EXPECT_EQ(assembler.counters().policies, 0);
}

TEST(PolicyStream, ForgetsStalePartialMessages) {
  PolicyAssembler assembler(1000);
  const auto pieces = Fragments(Encode(MakePolicy(300, 300)), 60000, 9);
  EXPECT_FALSE(Feed(assembler, pieces[0], kChannel, 0).has_value());
  EXPECT_EQ(assembler.pending(), 1u);
  const auto other = Fragments(Encode(MakePolicy(300, 300)), 60000, 10);
  EXPECT_FALSE(Feed(assembler, other[0], kChannel, 5000).has_value());
  EXPECT_EQ(assembler.pending(), 1u);
  EXPECT_EQ(assembler.counters().expired, 1);
}

class PolicyLogTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() / ("policy_log_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  static void Write(lcm::LogFile& log, int64_t time, const std::string& channel,
                    const std::vector<uint8_t>& bytes) {
    lcm::LogEvent event{};
    event.timestamp = time;
    event.channel = channel;
    event.datalen = static_cast<int32_t>(bytes.size());
    event.data = const_cast<uint8_t*>(bytes.data());
    ASSERT_EQ(log.writeEvent(&event), 0);
  }

  std::filesystem::path dir_;
};

TEST_F(PolicyLogTest, ReadsWholeAndFragmentedPolicies) {
  const std::string path = Path("run.lcm");
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    heartbeat_t beat{};
    beat.run_id = "r1";
    Write(log, 1, "DYNAPATH/r1/HEARTBEAT", Encode(beat));
    Write(log, 2, kChannel, Encode(MakePolicy(5, 5, "A* Oracle", 0)));
    Write(log, 3, kChannel, {0xde, 0xad, 0xbe, 0xef});  // garbage
    for (const auto& piece : Fragments(Encode(MakePolicy(300, 300, "big", 1)), 60000, 4)) {
      Write(log, 4, kChannel, piece);
    }
    Write(log, 5, "DYNAPATH/r2/POLICY", Encode(MakePolicy(5, 5, "other", 0, "r2")));
    // A message cut short at the end of the log.
    Write(log, 6, kChannel, Fragments(Encode(MakePolicy(300, 300, "cut", 2)), 60000, 5)[0]);
  }
  std::vector<std::string> seen;
  Result<PolicyLogSummary> summary =
      ReadPolicyLog(path, "", [&](policy_t& policy) { seen.push_back(policy.approach); });
  ASSERT_TRUE(summary.ok()) << summary.error().message;
  EXPECT_EQ(seen, (std::vector<std::string>{"A* Oracle", "big", "other"}));
  EXPECT_EQ(summary->events, 10);
  EXPECT_EQ(summary->policy_events, 9);
  EXPECT_EQ(summary->counters.policies, 3);
  EXPECT_EQ(summary->counters.dropped, 1);
  EXPECT_EQ(summary->incomplete, 1);

  seen.clear();
  summary = ReadPolicyLog(path, "r2", [&](policy_t& policy) { seen.push_back(policy.approach); });
  ASSERT_TRUE(summary.ok());
  EXPECT_EQ(seen, (std::vector<std::string>{"other"}));
}

TEST_F(PolicyLogTest, Errors) {
  auto nothing = [](policy_t&) {};
  Result<PolicyLogSummary> missing = ReadPolicyLog(Path("missing.lcm"), "", nothing);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("cannot open log"), std::string::npos);

  Result<PolicyLogSummary> directory = ReadPolicyLog(dir_.string(), "", nothing);
  ASSERT_FALSE(directory.ok());
  EXPECT_NE(directory.error().message.find("directory"), std::string::npos);

  const std::string text = Path("notes.txt");
  FILE* file = std::fopen(text.c_str(), "w");
  ASSERT_NE(file, nullptr);
  for (int i = 0; i < 1000; ++i) std::fputs("not an LCM log at all\n", file);
  std::fclose(file);
  Result<PolicyLogSummary> not_a_log = ReadPolicyLog(text, "", nothing);
  ASSERT_FALSE(not_a_log.ok());
  EXPECT_NE(not_a_log.error().message.find("not an LCM log"), std::string::npos);

  const std::string empty = Path("empty.lcm");
  std::fclose(std::fopen(empty.c_str(), "w"));
  EXPECT_FALSE(ReadPolicyLog(empty, "", nothing).ok());
}

}  // namespace
}  // namespace dynapath::view
