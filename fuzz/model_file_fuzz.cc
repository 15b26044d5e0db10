// libFuzzer target: the model file reader (--model FILE), versions 1 and 2. The first byte
// chooses whether the checksum is checked: random bytes never carry a valid
// BLAKE2b checksum, so half the inputs skip it to reach the field checks. A
// decoded file is encoded again and must decode to the same model.

#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "runtime/model_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > 8192) return 0;
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  dynapath::Result<dynapath::runtime::ModelFile> file =
      dynapath::runtime::DecodeModelFile(bytes, (data[0] & 1) == 0);
  if (!file) return 0;
  dynapath::Result<std::vector<uint8_t>> encoded = dynapath::runtime::EncodeModelFile(*file);
  if (!encoded) std::abort();
  dynapath::Result<dynapath::runtime::ModelFile> again = dynapath::runtime::DecodeModelFile(
      std::string_view(reinterpret_cast<const char*>(encoded->data()), encoded->size()));
  if (!again || !(again->model == file->model)) std::abort();
  return 0;
}
