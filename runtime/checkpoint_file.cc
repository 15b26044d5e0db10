// The checkpoint codec (docs/reference/CHECKPOINT_FORMAT.md describes the
// bytes).
#include "runtime/checkpoint_file.h"

#include <bit>

#include "dynapath/text_file.h"
#include "runtime/byte_codec.h"
#include "runtime/policy_file.h"
#include "runtime/scenario_options.h"

namespace dynapath::runtime {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the checkpoint's numbers are little-endian");

constexpr char kCheckpointMagic[8] = {'D', 'Y', 'N', 'A', 'C', 'K', 'P', '\n'};
// A run has at most one row per approach and time step.
constexpr uint64_t kMaxRows = kMaxSteps + 1;
constexpr size_t kMaxLabelBytes = 256;
constexpr size_t kRowBytes = 4 + 4 + 8 + 8 + 8 + 4 + 4;
constexpr size_t kMaxSavedSections = 4;  // a policy file's most
constexpr uint64_t kMaxCheckpointBytes = kMaxPolicyFileBytes + (uint64_t{1} << 30);

Error TruncatedIn(const std::string& what) { return Error::Corrupt("truncated in " + what); }

void PutRun(ByteWriter& out, const ApproachRun& run) {
  out.PutText(ApproachName(run.approach));
  out.PutText(run.size_label);
  out.PutText(run.difficulty_label);
  out.Put<double>(run.initial_seconds);
  out.Put<double>(run.load_seconds);
  out.Put<uint64_t>(run.steps.size());
  for (const StepRecord& row : run.steps) {
    out.Put<int32_t>(row.time_step);
    out.Put<int32_t>(row.num_changes);
    out.Put<double>(row.adapt_seconds);
    out.Put<double>(row.success_rate);
    out.Put<double>(row.average_path_length);
    out.Put<int32_t>(row.nodes_trained);
    out.Put<int32_t>(row.highest_level);
  }
}

Result<ApproachRun> GetRun(ByteReader& in) {
  ApproachRun run;
  std::string approach;
  if (!in.GetText(kMaxLabelBytes, approach) || !in.GetText(kMaxLabelBytes, run.size_label) ||
      !in.GetText(kMaxLabelBytes, run.difficulty_label)) {
    return Error::Corrupt("an approach's name or labels are truncated or too long");
  }
  const std::optional<Approach> parsed = ParseApproach(approach);
  if (!parsed) return Error::Corrupt("unknown approach '" + approach.substr(0, 40) + "'");
  run.approach = *parsed;
  uint64_t rows = 0;
  if (!in.Get(run.initial_seconds) || !in.Get(run.load_seconds) || !in.Get(rows)) {
    return TruncatedIn("an approach's header");
  }
  // Checked against the bytes left before anything is allocated.
  if (rows > kMaxRows || rows * kRowBytes > in.left()) {
    return Error::Corrupt(ApproachName(run.approach) + " claims " + std::to_string(rows) +
                          " rows, more than the file holds");
  }
  run.steps.resize(static_cast<size_t>(rows));
  int previous = -1;
  for (StepRecord& row : run.steps) {
    in.Get(row.time_step);
    in.Get(row.num_changes);
    in.Get(row.adapt_seconds);
    in.Get(row.success_rate);
    in.Get(row.average_path_length);
    in.Get(row.nodes_trained);
    in.Get(row.highest_level);
    if (row.time_step <= previous) {
      return Error::Corrupt(ApproachName(run.approach) + "'s time steps are not increasing");
    }
    previous = row.time_step;
  }
  return run;
}

}  // namespace

Result<std::vector<uint8_t>> EncodeCheckpoint(const RunCheckpoint& checkpoint) {
  const size_t in_progress = static_cast<size_t>(checkpoint.pass) < checkpoint.runs.size() ? 1 : 0;
  if (checkpoint.pass < 0 ||
      checkpoint.runs.size() != static_cast<size_t>(checkpoint.pass) + in_progress ||
      (checkpoint.policy && in_progress == 0) ||
      checkpoint.approach_count < static_cast<int>(checkpoint.runs.size()) ||
      checkpoint.policy_file.size() > kMaxSavedSections) {
    return Error::Internal("a checkpoint's runs do not match its pass");
  }
  std::vector<uint8_t> policy;
  if (checkpoint.policy) {
    Result<std::vector<uint8_t>> encoded = EncodePolicyFile({*checkpoint.policy});
    if (!encoded) return encoded.error();
    policy = std::move(*encoded);
  }
  ByteWriter out;
  out.PutBytes(kCheckpointMagic, sizeof(kCheckpointMagic));
  out.Put<uint32_t>(kCheckpointFormatVersion);
  out.Put<uint64_t>(checkpoint.run_seed);
  out.Put<uint32_t>(static_cast<uint32_t>(checkpoint.total_steps));
  out.Put<uint32_t>(static_cast<uint32_t>(checkpoint.pass));
  out.Put<uint32_t>(static_cast<uint32_t>(checkpoint.runs.size()));
  out.Put<uint32_t>(static_cast<uint32_t>(checkpoint.approach_count));
  for (const ApproachRun& run : checkpoint.runs) PutRun(out, run);
  out.Put<uint32_t>(static_cast<uint32_t>(checkpoint.policy_file.size()));
  for (const SavedSection& section : checkpoint.policy_file) {
    out.PutText(ApproachName(section.approach));
    out.Put<uint64_t>(section.fingerprint);
  }
  out.Put<uint64_t>(policy.size());
  out.PutBytes(policy.data(), policy.size());
  AppendChecksum(out);
  return std::move(out.bytes());
}

Result<RunCheckpoint> DecodeCheckpoint(std::string_view bytes, bool verify_checksum) {
  ByteReader in(bytes);
  std::string_view magic;
  if (!in.GetView(sizeof(kCheckpointMagic), magic) ||
      magic != std::string_view(kCheckpointMagic, sizeof(kCheckpointMagic))) {
    return Error::Corrupt("not a DynaPath checkpoint (no DYNACKP magic)");
  }
  uint32_t version = 0, pass = 0, count = 0;
  if (!in.Get(version)) return TruncatedIn("the header");
  if (version != kCheckpointFormatVersion) {
    return Error::Corrupt("format version " + std::to_string(version) + ", this build reads " +
                          std::to_string(kCheckpointFormatVersion));
  }
  if (in.left() < kChecksumBytes) return TruncatedIn("the header");
  if (verify_checksum && !ChecksumMatches(bytes)) {
    return Error::Corrupt("checksum mismatch (the file is damaged or cut short)");
  }
  ByteReader body(
      bytes.substr(0, bytes.size() - kChecksumBytes).substr(sizeof(kCheckpointMagic) + 4));
  constexpr uint32_t kMaxRuns = 64;  // a run has at most one pass per approach
  uint32_t total_steps = 0, approach_count = 0;
  RunCheckpoint checkpoint;
  if (!body.Get(checkpoint.run_seed) || !body.Get(total_steps) || !body.Get(pass) ||
      !body.Get(count) || !body.Get(approach_count)) {
    return TruncatedIn("the header");
  }
  if (total_steps > kMaxSteps) return Error::Corrupt("more time steps than any run has");
  checkpoint.total_steps = static_cast<int>(total_steps);
  if (count > kMaxRuns || pass > count || count > pass + 1 || approach_count < count ||
      approach_count > kMaxRuns) {
    return Error::Corrupt(std::to_string(count) + " approaches with " + std::to_string(pass) +
                          " finished of " + std::to_string(approach_count) +
                          " is not a checkpoint");
  }
  checkpoint.pass = static_cast<int>(pass);
  checkpoint.approach_count = static_cast<int>(approach_count);
  for (uint32_t i = 0; i < count; ++i) {
    Result<ApproachRun> run = GetRun(body);
    if (!run) return run.error();
    checkpoint.runs.push_back(std::move(*run));
  }
  uint32_t saved = 0;
  if (!body.Get(saved)) return TruncatedIn("the policy file's sections");
  if (saved > kMaxSavedSections) {
    return Error::Corrupt(std::to_string(saved) + " policy file sections, a file has at most " +
                          std::to_string(kMaxSavedSections));
  }
  for (uint32_t i = 0; i < saved; ++i) {
    std::string name;
    SavedSection section;
    if (!body.GetText(kMaxLabelBytes, name) || !body.Get(section.fingerprint)) {
      return TruncatedIn("the policy file's sections");
    }
    const std::optional<Approach> approach = ParseApproach(name);
    if (!approach || !IsLearningApproach(*approach)) {
      return Error::Corrupt("the policy file's sections name '" + name.substr(0, 40) +
                            "', not a learning approach");
    }
    section.approach = *approach;
    checkpoint.policy_file.push_back(section);
  }
  uint64_t policy_bytes = 0;
  std::string_view policy;
  if (!body.Get(policy_bytes)) return TruncatedIn("the policy's length");
  if (policy_bytes != body.left()) {
    return Error::Corrupt("the policy's length is " + std::to_string(policy_bytes) + ", " +
                          std::to_string(body.left()) + " bytes are left");
  }
  body.GetView(static_cast<size_t>(policy_bytes), policy);
  if (!policy.empty()) {
    if (count == pass) return Error::Corrupt("a policy but no approach in progress");
    Result<std::vector<PolicyState>> states = DecodePolicyFile(policy, verify_checksum);
    if (!states) return Error::Corrupt("its policy: " + states.error().message);
    if (states->size() != 1 || (*states)[0].approach != checkpoint.runs.back().approach) {
      return Error::Corrupt("its policy is not the approach in progress's");
    }
    const int last_row =
        checkpoint.runs.back().steps.empty() ? -1 : checkpoint.runs.back().steps.back().time_step;
    if ((*states)[0].step != last_row) {
      return Error::Corrupt("its policy is of step " + std::to_string((*states)[0].step) +
                            ", its last row of step " + std::to_string(last_row));
    }
    checkpoint.policy = std::move((*states)[0]);
  }
  return checkpoint;
}

Status WriteCheckpoint(const std::string& dir, const RunCheckpoint& checkpoint) {
  Result<std::vector<uint8_t>> bytes = EncodeCheckpoint(checkpoint);
  if (!bytes) return bytes.error();
  const std::vector<uint8_t>& b = *bytes;
  return WriteFileDurably(dir + "/" + kCheckpointFileName,
                          std::string_view(reinterpret_cast<const char*>(b.data()), b.size()));
}

Result<RunCheckpoint> ReadCheckpoint(const std::string& dir) {
  const std::string path = dir + "/" + kCheckpointFileName;
  Result<std::string> bytes = ReadBoundedFile(path, kMaxCheckpointBytes, "checkpoint");
  if (!bytes) return bytes.error();
  Result<RunCheckpoint> checkpoint = DecodeCheckpoint(*bytes);
  if (!checkpoint) return Error::Corrupt("checkpoint " + path + ": " + checkpoint.error().message);
  return checkpoint;
}

Status CheckCheckpointFree(const std::string& dir) {
  Result<RunCheckpoint> found = ReadCheckpoint(dir);
  if (!found && found.error().IsNotFound()) return Ok{};
  const std::string path = dir + "/" + kCheckpointFileName;
  if (!found) {
    return Error::Option("checkpoint", path + " cannot be read (" + found.error().message +
                                           "): give --force to start a new run there (it is "
                                           "replaced)");
  }
  if (found->pass >= found->approach_count) return Ok{};  // a finished run's
  std::string where = std::to_string(found->pass) + " of " + std::to_string(found->approach_count) +
                      " approaches finished";
  if (found->policy) {
    where += ", " + ApproachName(found->runs.back().approach) + " after step " +
             std::to_string(found->policy->step);
  }
  return Error::Option("checkpoint", dir + " holds the checkpoint of an unfinished run (" + where +
                                         "): finish it with `dynapath run --resume " + dir +
                                         "`, or give --force to start a new run there (that "
                                         "checkpoint is then lost)");
}

}  // namespace dynapath::runtime
