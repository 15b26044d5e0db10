#pragma once
// The policy file (docs/reference/POLICY_FORMAT.md): one or more learning
// approaches' PolicyState (dynapath/policy_state.h) in a versioned binary
// format with a BLAKE2b checksum and zstd-compressed blocks. Here, not in
// core/, because the checksum is libsodium's, which the protocol library
// links and core does not.
//
// Reading is bounded: a file larger than kMaxPolicyFileBytes is refused
// before it is read, every length is checked against the bytes left and the
// shape in the section's header before anything is allocated from it, and
// a block's decompressed size must be exactly what the shape says.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "dynapath/policy_state.h"
#include "dynapath/result.h"

namespace dynapath::runtime {

inline constexpr uint32_t kPolicyFormatVersion = 1;
// Larger files are refused unread: four sections of a 4096x4096 table of
// doubles compress to less (a table is 8 values per cell).
inline constexpr uint64_t kMaxPolicyFileBytes = uint64_t{1} << 31;

// The file's bytes for `states` (one section each, at most one per
// approach, at most four).
Result<std::vector<uint8_t>> EncodePolicyFile(const std::vector<PolicyState>& states);

// The states in `bytes`, or a kCorrupt error saying what is wrong ("not a
// policy file", "version 7, this build reads 1", "checksum mismatch",
// "truncated", ...). `verify_checksum` false is for the fuzz target only
// (it lets random bytes reach the section parser).
Result<std::vector<PolicyState>> DecodePolicyFile(std::string_view bytes,
                                                  bool verify_checksum = true);

// One section as the file holds it: what a run keeps of a file it saves
// into (the sections it does not rewrite) without decoding their tables.
struct PolicySection {
  Approach approach = Approach::kSingleAgent;
  std::vector<uint8_t> bytes;
  // Fingerprint64 of the bytes: which section this is, for a checkpoint.
  uint64_t Fingerprint() const;
};
Result<PolicySection> EncodePolicySection(const PolicyState& state);
// The file's bytes for `sections` (1 to 4, at most one per approach: the
// caller's to keep, as with EncodePolicyFile).
Result<std::vector<uint8_t>> AssemblePolicyFile(const std::vector<PolicySection>& sections);
// The sections of the policy file at `path`, its checksum and layout
// checked and each section's approach read, its tables not decoded; every
// error names `path` (kNotFound when there is no file).
Result<std::vector<PolicySection>> ReadPolicySections(const std::string& path);

// EncodePolicyFile written atomically to `path`.
Status WritePolicyFile(const std::string& path, const std::vector<PolicyState>& states);
// AssemblePolicyFile written atomically to `path`.
Status WritePolicySections(const std::string& path, const std::vector<PolicySection>& sections);
// DecodePolicyFile of `path`'s contents; every error names `path`.
Result<std::vector<PolicyState>> ReadPolicyFile(const std::string& path);

}  // namespace dynapath::runtime
