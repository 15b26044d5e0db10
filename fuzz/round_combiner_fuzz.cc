// libFuzzer target: the round combiner fed shards_t messages from arbitrary
// bytes (each one length-prefixed, bounds-checked, decoded and validated as
// the Bus does), for a federated job of a 10x10 map split over two agents.
// Whatever arrives, the combiner keeps at most two rounds and never crashes.

#include <cstdint>
#include <cstdlib>

#include "fuzz/combiner_job.h"
#include "protocol/decode.h"
#include "protocol/round_combiner.h"
#include "protocol/validate.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const auto averaging =
      (data[0] & 1) ? dynapath::Averaging::kImportance : dynapath::Averaging::kEqual;
  dynapath::protocol::RoundCombiner combiner(
      {dynapath::fuzz::CombinerJob(dynapath::fuzz::CombinerTrainingJob(averaging))},
      dynapath::fuzz::CombinerItems(), 0);
  size_t pos = 1;
  while (pos + 2 <= size) {
    const size_t length = (static_cast<size_t>(data[pos]) << 8) | data[pos + 1];
    pos += 2;
    if (length > size - pos) break;
    dynapath::shards_t message;
    if (dynapath::protocol::DecodeExactly(data + pos, static_cast<int>(length), message) &&
        dynapath::protocol::Validate(message).ok()) {
      std::string why;
      combiner.Add(message, &why);
      if (combiner.RoundComplete()) combiner.Combine();
    }
    pos += length;
  }
  return 0;
}
