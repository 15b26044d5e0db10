// libFuzzer target: the policy file reader (--load-policy FILE). The first
// byte chooses whether the checksum is checked: random bytes never carry a
// valid BLAKE2b checksum, so half the inputs skip it to reach the section
// parser (lengths, shape bounds, zstd blocks, consistency checks). A decoded
// file is encoded again and must decode to the same bytes.

#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "runtime/policy_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > (1 << 20)) return 0;
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  dynapath::Result<std::vector<dynapath::PolicyState>> states =
      dynapath::runtime::DecodePolicyFile(bytes, (data[0] & 1) == 0);
  if (!states) return 0;
  dynapath::Result<std::vector<uint8_t>> encoded = dynapath::runtime::EncodePolicyFile(*states);
  if (!encoded) std::abort();
  dynapath::Result<std::vector<dynapath::PolicyState>> again = dynapath::runtime::DecodePolicyFile(
      std::string_view(reinterpret_cast<const char*>(encoded->data()), encoded->size()));
  if (!again || again->size() != states->size()) std::abort();
  return 0;
}
