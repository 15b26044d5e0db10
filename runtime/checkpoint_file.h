#pragma once
// A run's checkpoint (docs/howto/CHECKPOINTS.md; the bytes:
// docs/reference/CHECKPOINT_FORMAT.md): what `dynapath run --resume` needs
// to finish a run whose process died, written by the process that runs the
// approaches (`run --local`, or the coordinator) after every K time steps
// and after every approach.
//
// It holds the rows of every approach finished so far, and of the approach
// in progress its rows so far and, for a learning approach, its policy after
// its last row (a policy file, runtime/policy_file.h, embedded whole). A
// baseline in progress has no state to keep: it runs again from step 0.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "dynapath/experiment.h"
#include "dynapath/policy_state.h"
#include "dynapath/result.h"

namespace dynapath::runtime {

inline constexpr uint32_t kCheckpointFormatVersion = 2;
// The file in a checkpoint directory, and the run's options beside it.
inline constexpr const char* kCheckpointFileName = "checkpoint.dpc";
inline constexpr const char* kCheckpointOptionsName = "run.toml";

// A section of the run's --save-policy file, by its fingerprint
// (PolicySection::Fingerprint).
struct SavedSection {
  Approach approach = Approach::kSingleAgent;
  uint64_t fingerprint = 0;
  bool operator==(const SavedSection& other) const {
    return approach == other.approach && fingerprint == other.fingerprint;
  }
};

struct RunCheckpoint {
  // Which run: its seed and number of time steps, checked on resuming.
  uint64_t run_seed = 0;
  int total_steps = 0;
  // How many approaches the run has: it is finished when pass is this.
  int approach_count = 0;
  // The sections its --save-policy file holds as the run last wrote it (or
  // found it, before its first write); empty without --save-policy. A
  // resumed run checks the file against them (runtime/policy_saver.h).
  std::vector<SavedSection> policy_file;
  // runs[0..pass) are finished; runs[pass], when present, is the approach
  // in progress, its rows so far (then `policy` is its state after the
  // last of them, or absent for a baseline, which runs again).
  int pass = 0;
  std::vector<ApproachRun> runs;
  std::optional<PolicyState> policy;
};

Result<std::vector<uint8_t>> EncodeCheckpoint(const RunCheckpoint& checkpoint);
// The checkpoint in `bytes`, or a kCorrupt error saying what is wrong.
// `verify_checksum` false is for the fuzz target only.
Result<RunCheckpoint> DecodeCheckpoint(std::string_view bytes, bool verify_checksum = true);

// DIR/checkpoint.dpc, written durably (write, fsync, rename, fsync the
// folder): after a crash the previous checkpoint or this one, whole.
Status WriteCheckpoint(const std::string& dir, const RunCheckpoint& checkpoint);
// DIR/checkpoint.dpc; kNotFound when DIR holds none yet.
Result<RunCheckpoint> ReadCheckpoint(const std::string& dir);

// Ok when a new run may write its checkpoints into `dir`: it holds no
// checkpoint, or that of a finished run. Otherwise an error (option
// --checkpoint) saying what is there and how to resume it.
Status CheckCheckpointFree(const std::string& dir);

}  // namespace dynapath::runtime
