// The model file codec (docs/reference/MODEL_FORMAT.md describes the bytes).
#include "runtime/model_file.h"

#include <bit>
#include <cstring>

#include "dynapath/text_file.h"
#include "runtime/byte_codec.h"

namespace dynapath::runtime {
namespace {

static_assert(std::endian::native == std::endian::little, "the model file is little-endian");

constexpr char kModelMagic[8] = {'D', 'Y', 'N', 'A', 'M', 'O', 'D', '\n'};
constexpr uint32_t kConvQKind = 1;  // the weight-shared recurrent convolution
// Training sizes a file may record (the command's own bounds).
constexpr uint32_t kMaxRecordedCount = 1u << 24;

}  // namespace

Result<std::vector<uint8_t>> EncodeModelFile(const ModelFile& file) {
  if (Status checked = CheckConvQModel(file.model); !checked) return checked.error();
  const ConvQTrainingOptions& t = file.training;
  ByteWriter out;
  out.PutBytes(kModelMagic, sizeof(kModelMagic));
  const bool federated = t.learners > 0;
  out.Put<uint32_t>(federated ? 2u : 1u);
  out.Put<uint32_t>(kConvQKind);
  out.Put<uint64_t>(t.seed);
  out.Put<uint32_t>(static_cast<uint32_t>(t.rounds));
  out.Put<uint32_t>(static_cast<uint32_t>(t.mazes_per_round));
  out.Put<uint32_t>(static_cast<uint32_t>(t.samples_per_maze));
  out.Put<uint32_t>(static_cast<uint32_t>(t.min_side));
  out.Put<uint32_t>(static_cast<uint32_t>(t.max_side));
  if (federated) {
    out.Put<uint32_t>(static_cast<uint32_t>(t.learners));
    out.Put<uint32_t>(t.averaging == ConvQAveraging::kEqual ? 0u : 1u);
  }
  out.Put<uint32_t>(static_cast<uint32_t>(kConvQWeightCount));
  for (double weight : ConvQWeights(file.model)) out.Put<double>(weight);
  AppendChecksum(out);
  return std::move(out.bytes());
}

Result<ModelFile> DecodeModelFile(std::string_view bytes, bool verify_checksum) {
  ByteReader in(bytes);
  std::string_view magic;
  if (!in.GetView(sizeof(kModelMagic), magic) ||
      std::memcmp(magic.data(), kModelMagic, sizeof(kModelMagic)) != 0) {
    return Error::Corrupt("not a model file");
  }
  uint32_t version = 0, kind = 0;
  if (!in.Get(version)) return Error::Corrupt("truncated in the header");
  if (version != 1 && version != 2) {
    return Error::Corrupt("format version " + std::to_string(version) +
                          ", this build reads 1 and " + std::to_string(kModelFormatVersion));
  }
  const size_t expected = version == 1 ? kModelFileBytes : kFederatedModelFileBytes;
  if (bytes.size() != expected) {
    return Error::Corrupt(std::to_string(bytes.size()) + " bytes, a version " +
                          std::to_string(version) + " model file has " + std::to_string(expected) +
                          " (truncated or extended)");
  }
  if (verify_checksum && !ChecksumMatches(bytes)) return Error::Corrupt("checksum mismatch");
  if (!in.Get(kind) || kind != kConvQKind) {
    return Error::Corrupt("unknown model kind " + std::to_string(kind));
  }
  ModelFile file;
  uint32_t rounds = 0, mazes = 0, samples = 0, min_side = 0, max_side = 0, count = 0;
  if (!in.Get(file.training.seed) || !in.Get(rounds) || !in.Get(mazes) || !in.Get(samples) ||
      !in.Get(min_side) || !in.Get(max_side)) {
    return Error::Corrupt("truncated in the training record");
  }
  uint32_t learners = 0, averaging = 0;
  if (version == 2) {
    if (!in.Get(learners) || !in.Get(averaging)) {
      return Error::Corrupt("truncated in the training record");
    }
    if (learners < 1 || learners > static_cast<uint32_t>(kMaxConvQLearners) || averaging > 1) {
      return Error::Corrupt("the federated training record is out of bounds");
    }
  }
  if (!in.Get(count)) return Error::Corrupt("truncated in the training record");
  if (rounds > kMaxRecordedCount || mazes > kMaxRecordedCount || samples > kMaxRecordedCount ||
      min_side > kMaxRecordedCount || max_side > kMaxRecordedCount || min_side > max_side) {
    return Error::Corrupt("the training record is out of bounds");
  }
  if (count != kConvQWeightCount) {
    return Error::Corrupt(std::to_string(count) + " weights, convQ has " +
                          std::to_string(kConvQWeightCount));
  }
  file.training.threads = 0;
  file.training.rounds = static_cast<int>(rounds);
  file.training.mazes_per_round = static_cast<int>(mazes);
  file.training.samples_per_maze = static_cast<int>(samples);
  file.training.min_side = static_cast<int>(min_side);
  file.training.max_side = static_cast<int>(max_side);
  file.training.learners = static_cast<int>(learners);
  file.training.averaging = averaging == 0 ? ConvQAveraging::kEqual : ConvQAveraging::kImportance;
  std::array<double, kConvQWeightCount> weights{};
  for (double& weight : weights) {
    if (!in.Get(weight)) return Error::Corrupt("truncated in the weights");
  }
  file.model = ConvQModelFromWeights(weights);
  if (Status checked = CheckConvQModel(file.model); !checked) return checked.error();
  if (in.left() != kChecksumBytes) return Error::Corrupt("the layout does not add up");
  return file;
}

Status WriteModelFile(const std::string& path, const ModelFile& file) {
  Result<std::vector<uint8_t>> bytes = EncodeModelFile(file);
  if (!bytes) return bytes.error();
  return WriteFileAtomically(path, *bytes);
}

Result<ModelFile> ReadModelFile(const std::string& path) {
  Result<std::string> bytes = ReadBoundedFile(path, kMaxModelFileBytes, "model file");
  if (!bytes) return bytes.error();
  Result<ModelFile> file = DecodeModelFile(*bytes);
  if (!file) return Error::Corrupt("model file " + path + ": " + file.error().message);
  return file;
}

}  // namespace dynapath::runtime
