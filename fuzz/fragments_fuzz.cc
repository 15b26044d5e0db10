// libFuzzer target: the fragment assembler under arbitrary pieces (message
// ids, totals, counts, offsets, sizes all from the input) with small caps:
// the bytes it holds never exceed its budget, a completed message has
// exactly its announced size, and the NACKs it asks for (selective repair)
// name only pieces of partial messages, with a bitmap of their count.
// Parity pieces (rebuilding a missing piece from them) are fuzzed alike.

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "protocol/fragments.h"
#include "protocol/validate.h"

namespace {

int32_t Take32(const uint8_t*& p, const uint8_t* end) {
  int32_t value = 0;
  for (int i = 0; i < 4; ++i) value = (value << 8) | (p < end ? *p++ : 0);
  return value;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dynapath::protocol::FragmentLimits limits;
  limits.max_message_bytes = 4096;
  limits.max_buffered_bytes = 8192 + 1024;
  limits.max_partials = 4;
  limits.lifetime = 50;
  limits.min_piece_bytes = 1;
  dynapath::protocol::FragmentAssembler assembler(limits);
  const uint8_t* p = data;
  const uint8_t* end = data + size;
  int64_t now = 0;
  while (end - p >= 8) {
    dynapath::fragment_t fragment{};
    fragment.run_id = "r";
    fragment.message_id = *p++ % 8;
    fragment.fingerprint = *p++ % 2;
    now += *p++ % 16;
    // Small fields mostly, any int32 sometimes; parity pieces (groups of 0,
    // 2, 3 or 4) a quarter of the time.
    const uint8_t flags = *p++;
    const bool wide = (flags & 7) == 0;
    fragment.parity = (flags & 0x18) == 0x18;
    fragment.group_size = (flags >> 5) & 3;
    if (fragment.group_size == 1) fragment.group_size = 4;
    auto field = [&](int32_t small) { return wide ? Take32(p, end) : small; };
    fragment.total_size = field(*p % 64 + 1);
    fragment.count = field(end - p > 1 ? p[1] % 8 + 1 : 1);
    fragment.index = field(end - p > 2 ? p[2] % 8 : 0);
    fragment.offset = field(end - p > 3 ? p[3] % 64 : 0);
    p += std::min<ptrdiff_t>(4, end - p);
    const int32_t piece = static_cast<int32_t>(std::min<ptrdiff_t>(end - p, p < end ? *p % 32 : 0));
    fragment.size = piece;
    fragment.data.assign(p, p + piece);
    p += piece;
    if (!dynapath::protocol::Validate(fragment).ok()) continue;
    const auto outcome = assembler.Add("C", fragment, now);
    if (assembler.buffered_bytes() > limits.max_buffered_bytes || assembler.buffered_bytes() < 0 ||
        assembler.pending() > limits.max_partials) {
      std::abort();
    }
    if (outcome.kind == dynapath::protocol::FragmentAssembler::Outcome::Kind::kComplete &&
        static_cast<int32_t>(outcome.bytes.size()) != fragment.total_size) {
      std::abort();
    }
    for (const dynapath::protocol::Nack& nack : assembler.DueNacks(now, 3, 5, 4)) {
      if (nack.count < 1 || nack.missing.size() != (static_cast<size_t>(nack.count) + 7) / 8 ||
          nack.missing_count < 1 || nack.missing_count > nack.count || assembler.pending() == 0) {
        std::abort();
      }
    }
  }
  return 0;
}
