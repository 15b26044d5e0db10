// The fragment assembler's caps (protocol/fragments.h): memory held
// follows the pieces that arrived, not what they announce; the budget and
// the number of partial messages are hard limits (oldest evicted, counted);
// pieces must tile their message; a forged piece cannot cancel a real one.

#include "protocol/fragments.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "protocol/limits.h"

namespace dynapath::protocol {
namespace {

FragmentLimits SmallLimits() {
  FragmentLimits limits;
  limits.max_message_bytes = 1000;
  limits.max_buffered_bytes = 2000;
  limits.max_partials = 4;
  limits.lifetime = 100;
  return limits;
}

fragment_t Piece(int64_t id, int32_t total, int32_t count, int32_t index, int32_t offset,
                 std::vector<uint8_t> data, int64_t fingerprint = 0) {
  fragment_t f{};
  f.run_id = "r";
  f.message_id = id;
  f.fingerprint = fingerprint;
  f.total_size = total;
  f.count = count;
  f.index = index;
  f.offset = offset;
  f.size = static_cast<int32_t>(data.size());
  f.data = std::move(data);
  return f;
}

using Kind = FragmentAssembler::Outcome::Kind;

TEST(FragmentAssembler, ReassemblesPiecesInAnyOrder) {
  FragmentAssembler assembler(SmallLimits());
  std::vector<uint8_t> whole(20);
  for (size_t i = 0; i < whole.size(); ++i) whole[i] = static_cast<uint8_t>(i);
  // Fingerprint 0: the first 8 bytes of `whole` are 0..7, so use them.
  const int64_t fingerprint = PeekFingerprint(whole.data(), 20);
  auto part = [&](int index, int offset, int size) {
    return Piece(1, 20, 3, index, offset,
                 std::vector<uint8_t>(whole.begin() + offset, whole.begin() + offset + size),
                 fingerprint);
  };
  EXPECT_EQ(assembler.Add("C", part(2, 15, 5), 0).kind, Kind::kIncomplete);
  EXPECT_EQ(assembler.Add("C", part(0, 0, 8), 0).kind, Kind::kIncomplete);
  EXPECT_EQ(assembler.Add("C", part(0, 0, 8), 0).kind, Kind::kIncomplete);  // re-sent
  const auto outcome = assembler.Add("C", part(1, 8, 7), 0);
  ASSERT_EQ(outcome.kind, Kind::kComplete);
  EXPECT_EQ(outcome.bytes, whole);
  EXPECT_EQ(assembler.pending(), 0u);
  EXPECT_EQ(assembler.buffered_bytes(), 0);
}

// 22 bytes in pieces of 8 (8, 8, 6), one parity group of 3: the XOR of the
// three padded to 8. Any one piece is rebuilt from the other two and the
// parity piece, whichever arrives last; a parity piece that contradicts the
// message's group size is dropped.
TEST(FragmentAssembler, ParityPieceRebuildsTheOneMissingPieceOfItsGroup) {
  std::vector<uint8_t> whole(22);
  for (size_t i = 0; i < whole.size(); ++i) whole[i] = static_cast<uint8_t>(3 * i + 1);
  const int64_t fingerprint = PeekFingerprint(whole.data(), 22);
  auto part = [&](int index) {
    const int offset = 8 * index, size = std::min(8, 22 - offset);
    fragment_t f = Piece(1, 22, 3, index, offset,
                         std::vector<uint8_t>(whole.begin() + offset, whole.begin() + offset + size),
                         fingerprint);
    f.group_size = 3;
    return f;
  };
  fragment_t parity = Piece(1, 22, 3, 0, 0, std::vector<uint8_t>(8, 0), fingerprint);
  parity.parity = true;
  parity.group_size = 3;
  for (int i = 0; i < 3; ++i) {
    const fragment_t data = part(i);
    for (size_t j = 0; j < data.data.size(); ++j) parity.data[j] ^= data.data[j];
  }
  for (int lost = 0; lost < 3; ++lost) {
    for (const bool parity_first : {true, false}) {
      SCOPED_TRACE(testing::Message() << "lost " << lost << (parity_first ? ", parity first" : ""));
      FragmentAssembler assembler(SmallLimits());
      std::vector<fragment_t> order;
      if (parity_first) order.push_back(parity);
      for (int i = 0; i < 3; ++i) {
        if (i != lost) order.push_back(part(i));
      }
      if (!parity_first) order.push_back(parity);
      for (size_t k = 0; k + 1 < order.size(); ++k) {
        EXPECT_EQ(assembler.Add("C", order[k], 0).kind, Kind::kIncomplete);
      }
      const auto outcome = assembler.Add("C", order.back(), 0);
      ASSERT_EQ(outcome.kind, Kind::kComplete);
      EXPECT_EQ(outcome.bytes, whole);
      EXPECT_EQ(assembler.rebuilt(), 1);
      EXPECT_EQ(assembler.buffered_bytes(), 0);
    }
  }
  FragmentAssembler assembler(SmallLimits());
  EXPECT_EQ(assembler.Add("C", parity, 0).kind, Kind::kIncomplete);
  fragment_t other = parity;
  other.group_size = 2;
  EXPECT_EQ(assembler.Add("C", other, 0).kind, Kind::kDropped);
  // Two missing: nothing to rebuild from (a NACK's job, BusTest).
  EXPECT_EQ(assembler.Add("C", part(1), 0).kind, Kind::kIncomplete);
  EXPECT_EQ(assembler.rebuilt(), 0);
}

TEST(FragmentAssembler, HoldsWhatArrivedNotWhatWasAnnounced) {
  FragmentAssembler assembler(SmallLimits());
  // Announces 1000 bytes in 1000 pieces; one byte arrived.
  EXPECT_EQ(assembler.Add("C", Piece(1, 1000, 1000, 5, 5, {1}), 0).kind, Kind::kIncomplete);
  EXPECT_EQ(assembler.buffered_bytes(), 1 + FragmentAssembler::kPieceOverhead);
}

TEST(FragmentAssembler, BudgetAndPartialCountAreHardLimitsOldestEvicted) {
  FragmentAssembler assembler(SmallLimits());
  // A flood of one-byte pieces of fresh messages: never more than 4 partial
  // messages or 2000 bytes (bookkeeping included).
  for (int64_t id = 0; id < 10000; ++id) {
    const auto outcome = assembler.Add("C", Piece(id, 1000, 1000, 0, 0, {1}), id);
    EXPECT_NE(outcome.kind, Kind::kComplete);
    ASSERT_LE(assembler.pending(), 4u);
    ASSERT_LE(assembler.buffered_bytes(), 2000);
  }
  EXPECT_GE(assembler.evicted(), 9990);
  // Many pieces of one message: the budget stops it, nothing else breaks.
  FragmentAssembler one(SmallLimits());
  for (int i = 0; i < 1000; ++i) {
    one.Add("C", Piece(7, 1000, 1000, i, i, {1}), 0);
    ASSERT_LE(one.buffered_bytes(), 2000);
  }
}

TEST(FragmentAssembler, RecentMessageSurvivesEvictionOfOlderOnes) {
  FragmentAssembler assembler(SmallLimits());
  assembler.Add("C", Piece(1, 10, 2, 0, 0, std::vector<uint8_t>(5, 0)), 0);
  for (int64_t id = 100; id < 103; ++id) assembler.Add("C", Piece(id, 10, 2, 0, 0, {1}), 1);
  // Message 1 is touched again (newest); the next newcomer evicts id 100.
  assembler.Add("C", Piece(1, 10, 2, 0, 0, std::vector<uint8_t>(5, 0)), 2);
  assembler.Add("C", Piece(200, 10, 2, 0, 0, {1}), 3);
  EXPECT_EQ(assembler.Add("C", Piece(1, 10, 2, 1, 5, std::vector<uint8_t>(5, 0)), 4).kind,
            Kind::kComplete);
}

TEST(FragmentAssembler, RejectsOversizedInconsistentAndGappyMessages) {
  FragmentAssembler assembler(SmallLimits());
  EXPECT_EQ(assembler.Add("C", Piece(1, 1001, 2, 0, 0, {1}), 0).kind, Kind::kDropped);
  EXPECT_EQ(assembler.Add("C", Piece(1, 10, 11, 0, 0, {1}), 0).kind,
            Kind::kDropped);  // count > size
  EXPECT_EQ(assembler.Add("C", Piece(1, 10, 2, 0, 8, {1, 2, 3}), 0).kind, Kind::kDropped);
  // A forged piece with another total is dropped; the real message completes.
  EXPECT_EQ(assembler.Add("C", Piece(2, 10, 2, 0, 0, std::vector<uint8_t>(5, 0)), 0).kind,
            Kind::kIncomplete);
  EXPECT_EQ(assembler.Add("C", Piece(2, 999, 2, 1, 5, {1}), 0).kind, Kind::kDropped);
  EXPECT_EQ(assembler.Add("C", Piece(2, 10, 2, 1, 5, std::vector<uint8_t>(5, 0)), 0).kind,
            Kind::kComplete);
  // Two pieces that overlap and leave a gap.
  EXPECT_EQ(assembler.Add("C", Piece(3, 10, 2, 0, 0, std::vector<uint8_t>(5, 0)), 0).kind,
            Kind::kIncomplete);
  EXPECT_EQ(assembler.Add("C", Piece(3, 10, 2, 1, 4, std::vector<uint8_t>(5, 0)), 0).kind,
            Kind::kDropped);
  EXPECT_EQ(assembler.pending(), 0u);
  EXPECT_EQ(assembler.buffered_bytes(), 0);
}

TEST(FragmentAssembler, ExpiresStalePartialMessages) {
  FragmentAssembler assembler(SmallLimits());
  assembler.Add("C", Piece(1, 10, 2, 0, 0, {1}), 0);
  assembler.Add("C", Piece(2, 10, 2, 0, 0, {1}), 500);
  EXPECT_EQ(assembler.expired(), 1);
  EXPECT_EQ(assembler.pending(), 1u);
}

// Selective repair: a partial message is NACKed with exactly its missing
// pieces once it has been quiet (reordered pieces arriving within the quiet
// period are no loss), again after the retry interval, never once complete;
// stray pieces of a completed message are not NACKed.
TEST(FragmentAssembler, NacksExactlyTheMissingPiecesAfterAQuietPeriod) {
  const int32_t total = 5 * 1024;  // five pieces of 1024 bytes (the Bus's smallest)
  auto piece = [&](int64_t id, int32_t index) {
    return Piece(id, total, 5, index, index * 1024, std::vector<uint8_t>(1024, 7),
                 0x0707070707070707);
  };
  FragmentLimits big = SmallLimits();
  big.lifetime = 100000;
  big.max_message_bytes = 10000;
  big.max_buffered_bytes = 100000;
  FragmentAssembler a(big);
  a.Add("C", piece(1, 0), 0);
  a.Add("C", piece(1, 3), 1);                      // 1 and 2 late or lost, 4 not yet sent
  EXPECT_TRUE(a.DueNacks(10, 15, 30, 5).empty());  // quiet for 9 ms only
  a.Add("C", piece(1, 1), 12);                     // reordered, not lost
  EXPECT_TRUE(a.DueNacks(20, 15, 30, 5).empty());
  std::vector<Nack> due = a.DueNacks(27, 15, 30, 5);
  ASSERT_EQ(due.size(), 1u);
  EXPECT_EQ(due[0].channel, "C");
  EXPECT_EQ(due[0].message_id, 1);
  EXPECT_EQ(due[0].count, 5);
  EXPECT_EQ(due[0].missing_count, 2);
  ASSERT_EQ(due[0].missing.size(), 1u);
  EXPECT_EQ(due[0].missing[0], (1u << 2) | (1u << 4));
  EXPECT_TRUE(a.DueNacks(40, 15, 30, 5).empty());   // retry not due yet
  EXPECT_EQ(a.DueNacks(58, 15, 30, 5).size(), 1u);  // the repair was lost too
  // The repair arrives: one round-trip sample, from the first NACK (Karn).
  EXPECT_EQ(a.Add("C", piece(1, 2), 60).repair_round_trip, 33);
  EXPECT_EQ(a.Add("C", piece(1, 4), 61).kind, Kind::kComplete);
  EXPECT_TRUE(a.DueNacks(500, 15, 30, 5).empty());
  // A stray repair piece of the completed message: held briefly, never NACKed.
  EXPECT_EQ(a.Add("C", piece(1, 2), 600).kind, Kind::kIncomplete);
  EXPECT_TRUE(a.DueNacks(700, 15, 30, 5).empty());
  // The whole message again (a sender's repeat) is delivered again.
  for (int32_t i = 0; i < 4; ++i) a.Add("C", piece(1, i == 2 ? 0 : i), 700);
  EXPECT_EQ(a.Add("C", piece(1, 4), 700).kind, Kind::kComplete);
  // At most max_nacks NACKs without progress.
  a.Add("C", piece(2, 0), 1000);
  int nacks = 0;
  for (int64_t t = 1000; t < 3000; t += 10)
    nacks += static_cast<int>(a.DueNacks(t, 15, 30, 5).size());
  EXPECT_EQ(nacks, 5);
}

TEST(ProtocolLimits, CapsFollowTheGrid) {
  EXPECT_LT(LargestMessageBytes(100 * 100), 3 * 1024 * 1024);
  EXPECT_GT(LargestMessageBytes(100 * 100), 73 * 100 * 100);  // a batch of double tables
  const FragmentLimits limits = BusFragmentLimits(1000 * 1000);
  EXPECT_GE(limits.max_buffered_bytes, 2 * limits.max_message_bytes);
  EXPECT_EQ(LargestMessageBytes(int64_t{1} << 40), LargestMessageBytes(kMaxGridCells));
}

}  // namespace
}  // namespace dynapath::protocol
