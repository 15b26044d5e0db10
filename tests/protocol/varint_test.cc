#include "protocol/varint.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

namespace dynapath::protocol {
namespace {

TEST(VarintTest, AscendingRoundTripsRandomSets) {
  std::mt19937 random(7);  // 32-bit results
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<uint32_t> indices;
    uint32_t next = static_cast<uint32_t>(random() % 50);
    const int count = static_cast<int>(random() % 300);
    for (int i = 0; i < count; ++i) {
      indices.push_back(next);
      // Mostly dense runs, sometimes long jumps (up to 2^24).
      next += static_cast<uint32_t>(1 + (random() % 8 == 0 ? random() % (1u << 24) : random() % 3));
    }
    const std::vector<uint8_t> bytes = EncodeAscending(indices);
    std::vector<uint32_t> decoded;
    ASSERT_TRUE(DecodeAscending(bytes, static_cast<int32_t>(indices.size()), decoded));
    EXPECT_EQ(decoded, indices);
  }
}

TEST(VarintTest, DenseRunsCostOneBytePerIndex) {
  std::vector<uint32_t> indices;
  for (uint32_t i = 1000; i < 2000; ++i) indices.push_back(i);
  const std::vector<uint8_t> bytes = EncodeAscending(indices);
  EXPECT_EQ(bytes.size(), 2u + 999u);  // 1000 takes two bytes, then gaps of 0
}

TEST(VarintTest, KnownEncoding) {
  // 0 -> gap 0; 5 -> gap 4; 300 -> gap 294 = 0b10_0100110 -> 0xA6 0x02.
  EXPECT_EQ(EncodeAscending({0, 5, 300}), (std::vector<uint8_t>{0x00, 0x04, 0xA6, 0x02}));
  EXPECT_EQ(EncodeCounts({1, 2, 129}), (std::vector<uint8_t>{0x00, 0x01, 0x80, 0x01}));
}

TEST(VarintTest, RejectsMalformedBytes) {
  std::vector<uint32_t> out;
  const std::vector<uint8_t> good = EncodeAscending({3, 4, 9});
  EXPECT_TRUE(DecodeAscending(good, 3, out));
  EXPECT_FALSE(DecodeAscending(good, 2, out));    // trailing bytes
  EXPECT_FALSE(DecodeAscending(good, 4, out));    // truncated
  EXPECT_FALSE(DecodeAscending(good, -1, out));   // negative count
  EXPECT_FALSE(DecodeAscending({0x80}, 1, out));  // continuation without end
  // Overlong: six continuation bytes.
  EXPECT_FALSE(DecodeAscending({0xff, 0xff, 0xff, 0xff, 0xff, 0x01}, 1, out));
  // Beyond INT32_MAX: 2^31 = 0x80 0x80 0x80 0x80 0x08.
  EXPECT_FALSE(DecodeAscending({0x80, 0x80, 0x80, 0x80, 0x08}, 1, out));
  // The second index overflows only through the running sum.
  EXPECT_FALSE(DecodeAscending({0xfe, 0xff, 0xff, 0xff, 0x07, 0x05}, 2, out));
}

TEST(VarintTest, CountsRoundTripAndStayPositive) {
  const std::vector<uint32_t> counts = {1, 1, 2, 127, 128, 129, 100000, 1};
  std::vector<uint32_t> decoded;
  ASSERT_TRUE(DecodeCounts(EncodeCounts(counts), static_cast<int32_t>(counts.size()), decoded));
  EXPECT_EQ(decoded, counts);
  EXPECT_FALSE(DecodeCounts({0x00, 0x00}, 3, decoded));
  EXPECT_FALSE(DecodeCounts({0xff, 0xff, 0xff, 0xff, 0x07}, 1, decoded));  // 2^31 - 1 + 1
}

}  // namespace
}  // namespace dynapath::protocol
