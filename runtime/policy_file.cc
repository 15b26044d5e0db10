// The policy file codec (docs/reference/POLICY_FORMAT.md describes the bytes).
#include "runtime/policy_file.h"

#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <set>

#include "dynapath/limits.h"
#include "dynapath/mdp.h"
#include "dynapath/text_file.h"
#include "protocol/convert.h"
#include "runtime/byte_codec.h"

namespace dynapath::runtime {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the policy file's numbers and tables are little-endian");

constexpr char kMagic[8] = {'D', 'Y', 'N', 'A', 'P', 'O', 'L', '\n'};
constexpr size_t kHeaderBytes = 24;  // magic, version, section count, body length
constexpr size_t kNameBytes = 32;
constexpr size_t kMaxSections = 4;  // one per learning approach
constexpr int kCompressionLevel = 3;

constexpr size_t kSingleAgentOptionCount = 0
#define DYNAPATH_COUNT_OPTION(member, ...) +1
    DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_COUNT_OPTION);
constexpr size_t kFederatedOptionCount = 0 DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_COUNT_OPTION);
#undef DYNAPATH_COUNT_OPTION

using Writer = ByteWriter;
using Reader = ByteReader;

Status Truncated(const std::string& what) { return Error::Corrupt("truncated in " + what); }

// zstd of `data`, its length first.
Status PutCompressed(Writer& out, const void* data, size_t size) {
  // Not a vector: its zero fill of the bound would cost as much as a copy.
  const size_t bound = ZSTD_compressBound(size);
  const std::unique_ptr<uint8_t[]> frame(new uint8_t[bound]);
  const size_t written = ZSTD_compress(frame.get(), bound, data, size, kCompressionLevel);
  if (ZSTD_isError(written)) {
    return Error::Internal(std::string("zstd: ") + ZSTD_getErrorName(written));
  }
  out.Put<uint64_t>(written);
  out.PutBytes(frame.get(), written);
  return Ok{};
}

struct DStreamFree {
  void operator()(ZSTD_DStream* stream) const { ZSTD_freeDStream(stream); }
};

// One zstd frame of exactly `expected` bytes from `reader`. The output
// grows with what really decompresses (a frame's claimed size is not
// trusted for allocation), and stops at `expected`.
Result<std::vector<uint8_t>> GetCompressed(Reader& reader, size_t expected,
                                           const std::string& what) {
  uint64_t length = 0;
  std::string_view frame;
  if (!reader.Get(length)) return Truncated(what).error();
  if (length > reader.left()) {
    return Error::Corrupt(what + " claims " + std::to_string(length) + " bytes, " +
                          std::to_string(reader.left()) + " are left");
  }
  reader.GetView(static_cast<size_t>(length), frame);
  const unsigned long long claimed = ZSTD_getFrameContentSize(frame.data(), frame.size());
  if (claimed != expected) {
    return Error::Corrupt(what + ": the compressed block is not the " + std::to_string(expected) +
                          " bytes the shape says");
  }
  std::unique_ptr<ZSTD_DStream, DStreamFree> stream(ZSTD_createDStream());
  if (!stream) return Error::Internal("zstd: out of memory");
  ZSTD_initDStream(stream.get());
  std::vector<uint8_t> out;
  ZSTD_inBuffer input{frame.data(), frame.size(), 0};
  constexpr size_t kChunk = size_t{1} << 20;
  size_t status = 1;
  while (status != 0) {
    const size_t have = out.size();
    const size_t grow = std::min(kChunk, expected - have);
    out.resize(have + grow);
    ZSTD_outBuffer output{out.data() + have, grow, 0};
    const size_t consumed = input.pos;
    status = ZSTD_decompressStream(stream.get(), &output, &input);
    if (ZSTD_isError(status)) return Error::Corrupt(what + ": " + ZSTD_getErrorName(status));
    out.resize(have + output.pos);
    if (status != 0 && output.pos == 0 && input.pos == consumed) {
      return Error::Corrupt(what + ": the compressed block ends early or holds more than the " +
                            std::to_string(expected) + " bytes the shape says");
    }
  }
  if (out.size() != expected || input.pos != input.size) {
    return Error::Corrupt(what + ": the compressed block is not the " + std::to_string(expected) +
                          " bytes the shape says");
  }
  return out;
}

uint8_t PrecisionCode(QPrecision precision) { return precision == QPrecision::kFloat ? 0 : 1; }

// The bootstrap's code is the wire's (0 in-grid, 1 in-region, 2 all stored).
uint8_t BootstrapCode(Bootstrap bootstrap) {
  return static_cast<uint8_t>(protocol::BootstrapToWire(bootstrap));
}

Status EncodeSection(const PolicyState& s, Writer& out) {
  if (Status consistent = CheckPolicyConsistent(s); !consistent) return consistent;
  char name[kNameBytes] = {};
  const std::string approach = ApproachName(s.approach);
  std::memcpy(name, approach.data(), std::min(approach.size(), kNameBytes - 1));
  out.PutBytes(name, kNameBytes);
  out.Put<uint32_t>(static_cast<uint32_t>(s.rows));
  out.Put<uint32_t>(static_cast<uint32_t>(s.cols));
  out.Put<uint32_t>(static_cast<uint32_t>(s.leaf_limit));
  out.Put<uint32_t>(static_cast<uint32_t>(s.node_count));
  out.Put<uint8_t>(s.semantics == Semantics::kReport ? 1 : 0);
  out.Put<uint8_t>(PrecisionCode(s.precision));
  out.Put<uint8_t>(BootstrapCode(s.learner.bootstrap));
  out.Put<uint8_t>(s.baselines.empty() ? 0 : 1);
  out.Put<uint32_t>(static_cast<uint32_t>(s.step));
  out.Put<uint64_t>(s.run_seed);
  out.Put<uint64_t>(s.initial_fingerprint);
  out.Put<uint64_t>(s.fingerprint);
#define DYNAPATH_PUT_THRESHOLD(member, ...) out.Put<double>(s.thresholds.member);
  DYNAPATH_RETRAINING_THRESHOLDS(DYNAPATH_PUT_THRESHOLD)
#undef DYNAPATH_PUT_THRESHOLD
  out.Put<uint32_t>(kSingleAgentOptionCount);
#define DYNAPATH_PUT_SINGLE(member, ...) \
  out.Put<double>(static_cast<double>(s.learner.single_agent.member));
  DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_PUT_SINGLE)
#undef DYNAPATH_PUT_SINGLE
  out.Put<uint32_t>(kFederatedOptionCount);
#define DYNAPATH_PUT_FEDERATED(member, ...) \
  out.Put<double>(static_cast<double>(s.learner.federated.member));
  DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_PUT_FEDERATED)
#undef DYNAPATH_PUT_FEDERATED
  Writer nodes;
  nodes.PutBytes(s.training_counts.data(), s.training_counts.size() * sizeof(int64_t));
  nodes.PutBytes(s.baselines.data(), s.baselines.size() * sizeof(double));
  if (Status put = PutCompressed(out, nodes.bytes().data(), nodes.bytes().size()); !put) {
    return put;
  }
  if (s.precision == QPrecision::kFloat) {
    const std::vector<float>& values = s.table.values();
    return PutCompressed(out, values.data(), values.size() * sizeof(float));
  }
  const std::vector<double>& values = s.table.wide_values();
  return PutCompressed(out, values.data(), values.size() * sizeof(double));
}

// An integer option read as a double: whole and in the int range.
bool ToInt(double value, int& out) {
  if (!(value >= -2147483648.0 && value <= 2147483647.0) || value != static_cast<int>(value)) {
    return false;
  }
  out = static_cast<int>(value);
  return true;
}
bool ToInt(double value, double& out) {
  out = value;
  return std::isfinite(value);
}

// The learning approach a section is for: its first kNameBytes.
Result<Approach> SectionApproach(Reader& in) {
  std::string_view name;
  if (!in.GetView(kNameBytes, name)) return Truncated("the section header").error();
  const std::string approach(name.substr(0, name.find('\0')));
  const std::optional<Approach> parsed = ParseApproach(approach);
  if (!parsed || !IsLearningApproach(*parsed)) {
    return Error::Corrupt("unknown learning approach '" + approach.substr(0, 40) + "'");
  }
  return *parsed;
}

Result<PolicyState> DecodeSection(std::string_view bytes) {
  Reader in(bytes);
  PolicyState s;
  Result<Approach> approach = SectionApproach(in);
  if (!approach) return approach.error();
  s.approach = *approach;
  uint32_t rows = 0, cols = 0, leaf_limit = 0, node_count = 0, step = 0;
  uint8_t semantics = 0, precision = 0, bootstrap = 0, has_baselines = 0;
  uint32_t single_count = 0, federated_count = 0;
  if (!in.Get(rows) || !in.Get(cols) || !in.Get(leaf_limit) || !in.Get(node_count) ||
      !in.Get(semantics) || !in.Get(precision) || !in.Get(bootstrap) || !in.Get(has_baselines) ||
      !in.Get(step) || !in.Get(s.run_seed) || !in.Get(s.initial_fingerprint) ||
      !in.Get(s.fingerprint)) {
    return Truncated("the section header").error();
  }
#define DYNAPATH_GET_THRESHOLD(member, ...) \
  if (!in.Get(s.thresholds.member)) return Truncated("the retraining thresholds").error();
  DYNAPATH_RETRAINING_THRESHOLDS(DYNAPATH_GET_THRESHOLD)
#undef DYNAPATH_GET_THRESHOLD
  if (rows < 1 || cols < 1 || rows > kMaxGridSide || cols > kMaxGridSide) {
    return Error::Corrupt("shape " + std::to_string(rows) + "x" + std::to_string(cols) +
                          " is outside 1.." + std::to_string(kMaxGridSide));
  }
  const uint64_t cells = uint64_t{rows} * cols;
  // A quadtree has fewer nodes than twice its cells (every split at least
  // halves a side); the planner checks the exact count against its tree.
  if (leaf_limit < 1 || leaf_limit > static_cast<uint32_t>(kMaxGridSide) || node_count < 1 ||
      node_count > 2 * cells || step > static_cast<uint32_t>(INT32_MAX)) {
    return Error::Corrupt("leaf limit, node count or step out of range");
  }
  const std::optional<Bootstrap> scope =
      protocol::BootstrapFromWire(static_cast<int8_t>(bootstrap));
  if (semantics > 1 || precision > 1 || !scope || has_baselines > 1) {
    return Error::Corrupt("unknown semantics, precision, bootstrap or baseline flag");
  }
  s.rows = static_cast<int>(rows);
  s.cols = static_cast<int>(cols);
  s.leaf_limit = static_cast<int>(leaf_limit);
  s.node_count = static_cast<int>(node_count);
  s.step = static_cast<int>(step);
  s.semantics = semantics == 1 ? Semantics::kReport : Semantics::kOurs;
  s.precision = precision == 1 ? QPrecision::kDouble : QPrecision::kFloat;
  s.learner.bootstrap = *scope;
  if (!in.Get(single_count) || single_count != kSingleAgentOptionCount) {
    return Error::Corrupt("expected " + std::to_string(kSingleAgentOptionCount) +
                          " single-agent options");
  }
  double value = 0;
#define DYNAPATH_GET_OPTION(group, member)                               \
  if (!in.Get(value)) return Truncated("the learner options").error();   \
  if (!ToInt(value, s.learner.group.member)) {                           \
    return Error::Corrupt("learner option " #member " is out of range"); \
  }
#define DYNAPATH_GET_SINGLE(member, ...) DYNAPATH_GET_OPTION(single_agent, member)
#define DYNAPATH_GET_FEDERATED(member, ...) DYNAPATH_GET_OPTION(federated, member)
  DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_GET_SINGLE)
  if (!in.Get(federated_count) || federated_count != kFederatedOptionCount) {
    return Error::Corrupt("expected " + std::to_string(kFederatedOptionCount) +
                          " federated options");
  }
  DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_GET_FEDERATED)
#undef DYNAPATH_GET_FEDERATED
#undef DYNAPATH_GET_SINGLE
#undef DYNAPATH_GET_OPTION
  const size_t nodes = node_count;
  Result<std::vector<uint8_t>> node_block =
      GetCompressed(in, nodes * sizeof(int64_t) * (1 + has_baselines), "the node block");
  if (!node_block) return node_block.error();
  s.training_counts.resize(nodes);
  std::memcpy(s.training_counts.data(), node_block->data(), nodes * sizeof(int64_t));
  if (has_baselines == 1) {
    s.baselines.resize(nodes);
    std::memcpy(s.baselines.data(), node_block->data() + nodes * sizeof(int64_t),
                nodes * sizeof(double));
  }
  const size_t entries = static_cast<size_t>(cells) * kNumActions;
  const size_t width = s.precision == QPrecision::kFloat ? sizeof(float) : sizeof(double);
  Result<std::vector<uint8_t>> table = GetCompressed(in, entries * width, "the table");
  if (!table) return table.error();
  s.table = QTable(static_cast<int>(cells), s.precision);
  if (s.precision == QPrecision::kFloat) {
    std::memcpy(s.table.values().data(), table->data(), table->size());
  } else {
    std::memcpy(s.table.wide_values().data(), table->data(), table->size());
  }
  if (in.left() != 0) return Error::Corrupt("the section has bytes after its table");
  if (Status consistent = CheckPolicyConsistent(s); !consistent) return consistent.error();
  return s;
}

// The sections of a policy file's `bytes` (header, checksum and lengths
// checked), each with the approach it is for (one section per approach).
Result<std::vector<std::pair<Approach, std::string_view>>> SplitPolicyFile(std::string_view bytes,
                                                                           bool verify_checksum) {
  Reader in(bytes);
  std::string_view magic;
  uint32_t version = 0, count = 0;
  uint64_t body = 0;
  if (!in.GetView(sizeof(kMagic), magic) || magic != std::string_view(kMagic, sizeof(kMagic))) {
    return Error::Corrupt("not a DynaPath policy file (no DYNAPOL magic)");
  }
  if (!in.Get(version) || !in.Get(count) || !in.Get(body)) {
    return Truncated("the file header").error();
  }
  if (version != kPolicyFormatVersion) {
    return Error::Corrupt("format version " + std::to_string(version) + ", this build reads " +
                          std::to_string(kPolicyFormatVersion));
  }
  if (count < 1 || count > kMaxSections) {
    return Error::Corrupt(std::to_string(count) + " sections, a file has 1 to 4");
  }
  if (body != in.left() - std::min(in.left(), kChecksumBytes) || in.left() < kChecksumBytes) {
    return Error::Corrupt("the header says " + std::to_string(body) +
                          " bytes follow, the file has " +
                          std::to_string(in.left() - std::min(in.left(), kChecksumBytes)) +
                          " (truncated or extended)");
  }
  if (verify_checksum && !ChecksumMatches(bytes)) {
    return Error::Corrupt("checksum mismatch (the file is damaged)");
  }
  std::vector<uint64_t> lengths(count);
  uint64_t total = 0;
  for (uint64_t& length : lengths) {
    if (!in.Get(length)) return Truncated("the section lengths").error();
    if (length > in.left()) return Error::Corrupt("a section is longer than the file");
    total += length;
  }
  if (total + count * sizeof(uint64_t) != body) {
    return Error::Corrupt("the section lengths do not add up to the body");
  }
  std::vector<std::pair<Approach, std::string_view>> sections;
  std::set<Approach> seen;
  for (size_t i = 0; i < lengths.size(); ++i) {
    std::string_view section;
    in.GetView(static_cast<size_t>(lengths[i]), section);
    Reader header(section);
    Result<Approach> approach = SectionApproach(header);
    if (!approach) {
      return Error::Corrupt("section " + std::to_string(i + 1) + ": " + approach.error().message);
    }
    if (!seen.insert(*approach).second) {
      return Error::Corrupt("two sections for " + ApproachName(*approach));
    }
    sections.emplace_back(*approach, section);
  }
  return sections;
}

}  // namespace

uint64_t PolicySection::Fingerprint() const {
  return Fingerprint64(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

Result<PolicySection> EncodePolicySection(const PolicyState& state) {
  Writer section;
  if (Status encoded = EncodeSection(state, section); !encoded) return encoded.error();
  return PolicySection{state.approach, std::move(section.bytes())};
}

Result<std::vector<uint8_t>> AssemblePolicyFile(const std::vector<PolicySection>& sections) {
  if (sections.empty() || sections.size() > kMaxSections) {
    return Error::Internal("a policy file holds 1 to 4 sections");
  }
  Writer out;
  out.PutBytes(kMagic, sizeof(kMagic));
  out.Put<uint32_t>(kPolicyFormatVersion);
  out.Put<uint32_t>(static_cast<uint32_t>(sections.size()));
  uint64_t body = 0;
  for (const PolicySection& section : sections) body += sizeof(uint64_t) + section.bytes.size();
  out.Put<uint64_t>(body);
  for (const PolicySection& section : sections) out.Put<uint64_t>(section.bytes.size());
  for (const PolicySection& section : sections) {
    out.PutBytes(section.bytes.data(), section.bytes.size());
  }
  AppendChecksum(out);
  return std::move(out.bytes());
}

Result<std::vector<uint8_t>> EncodePolicyFile(const std::vector<PolicyState>& states) {
  std::vector<PolicySection> sections;
  for (const PolicyState& state : states) {
    Result<PolicySection> section = EncodePolicySection(state);
    if (!section) return section.error();
    sections.push_back(std::move(*section));
  }
  return AssemblePolicyFile(sections);
}

Result<std::vector<PolicyState>> DecodePolicyFile(std::string_view bytes, bool verify_checksum) {
  Result<std::vector<std::pair<Approach, std::string_view>>> sections =
      SplitPolicyFile(bytes, verify_checksum);
  if (!sections) return sections.error();
  std::vector<PolicyState> states;
  for (size_t i = 0; i < sections->size(); ++i) {
    Result<PolicyState> state = DecodeSection((*sections)[i].second);
    if (!state) {
      return Error::Corrupt("section " + std::to_string(i + 1) + ": " + state.error().message);
    }
    states.push_back(std::move(*state));
  }
  return states;
}

Status WritePolicyFile(const std::string& path, const std::vector<PolicyState>& states) {
  Result<std::vector<uint8_t>> bytes = EncodePolicyFile(states);
  if (!bytes) return bytes.error();
  return WriteFileAtomically(path, *bytes);
}

Status WritePolicySections(const std::string& path, const std::vector<PolicySection>& sections) {
  Result<std::vector<uint8_t>> bytes = AssemblePolicyFile(sections);
  if (!bytes) return bytes.error();
  return WriteFileAtomically(path, *bytes);
}

Result<std::vector<PolicySection>> ReadPolicySections(const std::string& path) {
  Result<std::string> bytes = ReadBoundedFile(path, kMaxPolicyFileBytes, "policy file");
  if (!bytes) return bytes.error();
  Result<std::vector<std::pair<Approach, std::string_view>>> split = SplitPolicyFile(*bytes, true);
  if (!split) return Error::Corrupt("policy file " + path + ": " + split.error().message);
  std::vector<PolicySection> sections;
  for (const auto& [approach, section] : *split) {
    sections.push_back(
        PolicySection{approach, std::vector<uint8_t>(section.begin(), section.end())});
  }
  return sections;
}

Result<std::vector<PolicyState>> ReadPolicyFile(const std::string& path) {
  Result<std::string> bytes = ReadBoundedFile(path, kMaxPolicyFileBytes, "policy file");
  if (!bytes) return bytes.error();
  Result<std::vector<PolicyState>> states = DecodePolicyFile(*bytes);
  if (!states) return Error::Corrupt("policy file " + path + ": " + states.error().message);
  return states;
}

}  // namespace dynapath::runtime
