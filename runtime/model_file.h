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

// Version 1: a model trained in one process; version 2 adds the federated
// training's learners and averaging. Written: version 1 when
// training.learners is 0, else 2. Read: both.
inline constexpr uint32_t kModelFormatVersion = 2;
// Larger files are refused unread (a model file is kModelFileBytes).
inline constexpr uint64_t kMaxModelFileBytes = 4096;

struct ModelFile {
  ConvQModel model;
  ConvQTrainingOptions training;  // threads is not recorded (0 when read)
};

// The file's size: header 16, training 28 (version 2: 36), weight count 4,
// weights 40, checksum 32.
inline constexpr size_t kModelFileBytes = 120;
inline constexpr size_t kFederatedModelFileBytes = 128;

Result<std::vector<uint8_t>> EncodeModelFile(const ModelFile& file);
// kCorrupt saying what is wrong. `verify_checksum` false: fuzz target only.
Result<ModelFile> DecodeModelFile(std::string_view bytes, bool verify_checksum = true);

// Atomic write; read with every error naming `path`.
Status WriteModelFile(const std::string& path, const ModelFile& file);
Result<ModelFile> ReadModelFile(const std::string& path);

}  // namespace dynapath::runtime
