#include "protocol/varint.h"

#include <cstddef>
#include <limits>

namespace dynapath::protocol {
namespace {

constexpr uint64_t kMaxValue = std::numeric_limits<int32_t>::max();

void Put(uint64_t value, std::vector<uint8_t>& out) {
  while (value >= 0x80) {
    out.push_back(static_cast<uint8_t>(value | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<uint8_t>(value));
}

// Reads one varint at `pos` (at most 5 bytes: values up to 2^35 - 1).
bool Get(const std::vector<uint8_t>& in, size_t& pos, uint64_t& value) {
  value = 0;
  for (int shift = 0; shift < 35; shift += 7) {
    if (pos >= in.size()) return false;
    const uint8_t byte = in[pos++];
    value |= static_cast<uint64_t>(byte & 0x7f) << shift;
    if ((byte & 0x80) == 0) return true;
  }
  return false;
}

}  // namespace

std::vector<uint8_t> EncodeAscending(const std::vector<uint32_t>& indices) {
  std::vector<uint8_t> out;
  out.reserve(indices.size() + 8);
  uint64_t next = 0;  // the smallest index the next one may have
  for (uint32_t index : indices) {
    Put(index - next, out);
    next = static_cast<uint64_t>(index) + 1;
  }
  return out;
}

bool DecodeAscending(const std::vector<uint8_t>& bytes, int32_t count,
                     std::vector<uint32_t>& indices) {
  if (count < 0 || static_cast<size_t>(count) > bytes.size()) return false;
  indices.resize(static_cast<size_t>(count));
  size_t pos = 0;
  uint64_t next = 0;
  for (int32_t i = 0; i < count; ++i) {
    uint64_t gap = 0;
    if (!Get(bytes, pos, gap)) return false;
    const uint64_t index = next + gap;
    if (index > kMaxValue) return false;
    indices[static_cast<size_t>(i)] = static_cast<uint32_t>(index);
    next = index + 1;
  }
  return pos == bytes.size();
}

std::vector<uint8_t> EncodeCounts(const std::vector<uint32_t>& counts) {
  std::vector<uint8_t> out;
  out.reserve(counts.size() + 8);
  for (uint32_t count : counts) Put(count - 1u, out);
  return out;
}

bool DecodeCounts(const std::vector<uint8_t>& bytes, int32_t count, std::vector<uint32_t>& counts) {
  if (count < 0 || static_cast<size_t>(count) > bytes.size()) return false;
  counts.resize(static_cast<size_t>(count));
  size_t pos = 0;
  for (int32_t i = 0; i < count; ++i) {
    uint64_t value = 0;
    if (!Get(bytes, pos, value) || value + 1 > kMaxValue) return false;
    counts[static_cast<size_t>(i)] = static_cast<uint32_t>(value + 1);
  }
  return pos == bytes.size();
}

}  // namespace dynapath::protocol
