#pragma once
// Compact encodings of the integer arrays in learner shards: LEB128 varints
// (7 bits per byte, high bit = more bytes follow). Ascending table indices
// travel as gaps (first index, then each index minus the previous minus 1),
// so the dense runs a learner updates cost one byte per entry.

#include <cstdint>
#include <vector>

namespace dynapath::protocol {

// `indices` must be strictly ascending.
std::vector<uint8_t> EncodeAscending(const std::vector<uint32_t>& indices);
// Decodes exactly `count` indices from all of `bytes`; false when the bytes
// are malformed (truncated, overlong, trailing bytes) or an index exceeds
// INT32_MAX. Strictly ascending by construction.
bool DecodeAscending(const std::vector<uint8_t>& bytes, int32_t count,
                     std::vector<uint32_t>& indices);

// Counts >= 1, stored minus one.
std::vector<uint8_t> EncodeCounts(const std::vector<uint32_t>& counts);
// Decodes exactly `count` counts (each >= 1, <= INT32_MAX) from all of `bytes`.
bool DecodeCounts(const std::vector<uint8_t>& bytes, int32_t count, std::vector<uint32_t>& counts);

}  // namespace dynapath::protocol
