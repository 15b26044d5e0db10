#pragma once
// The model file (docs/reference/MODEL_FORMAT.md): convQ's weights
// (dynapath/convq_model.h) and how they were trained, versioned, with a
// BLAKE2b checksum. Fixed size; a file of any other size, version, kind or
// weight count, or with a weight out of its bounds, is refused.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "dynapath/convq_model.h"
#include "dynapath/convq_training.h"
#include "dynapath/result.h"

namespace dynapath::runtime {

inline constexpr uint32_t kModelFormatVersion = 1;
// Larger files are refused unread (a model file is kModelFileBytes).
inline constexpr uint64_t kMaxModelFileBytes = 4096;

struct ModelFile {
  ConvQModel model;
  ConvQTrainingOptions training;  // threads is not recorded (0 when read)
};

// The file's size: header 16, training 28, weight count 4, weights 40,
// checksum 32.
inline constexpr size_t kModelFileBytes = 120;

Result<std::vector<uint8_t>> EncodeModelFile(const ModelFile& file);
// kCorrupt saying what is wrong. `verify_checksum` false: fuzz target only.
Result<ModelFile> DecodeModelFile(std::string_view bytes, bool verify_checksum = true);

// Atomic write; read with every error naming `path`.
Status WriteModelFile(const std::string& path, const ModelFile& file);
Result<ModelFile> ReadModelFile(const std::string& path);

}  // namespace dynapath::runtime
