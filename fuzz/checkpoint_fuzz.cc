// libFuzzer target: the checkpoint reader (`dynapath run --resume DIR`). As
// for the policy file, the first byte chooses whether the checksum is
// checked, so that random bytes reach the row and policy parsers. A decoded
// checkpoint is encoded again and must decode to as many rows.

#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "runtime/checkpoint_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > (1 << 20)) return 0;
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  dynapath::Result<dynapath::runtime::RunCheckpoint> checkpoint =
      dynapath::runtime::DecodeCheckpoint(bytes, (data[0] & 1) == 0);
  if (!checkpoint) return 0;
  dynapath::Result<std::vector<uint8_t>> encoded = dynapath::runtime::EncodeCheckpoint(*checkpoint);
  if (!encoded) std::abort();
  dynapath::Result<dynapath::runtime::RunCheckpoint> again = dynapath::runtime::DecodeCheckpoint(
      std::string_view(reinterpret_cast<const char*>(encoded->data()), encoded->size()));
  if (!again || again->runs.size() != checkpoint->runs.size()) std::abort();
  for (size_t i = 0; i < again->runs.size(); ++i) {
    if (again->runs[i].steps.size() != checkpoint->runs[i].steps.size()) std::abort();
  }
  return 0;
}
