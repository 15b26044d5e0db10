#pragma once
// A test hook: stop this process (SIGSTOP) at a known time step, so that a
// test pauses or kills it mid-run deterministically instead of racing a
// signal against the run's progress. Set by the environment variable
// DYNAPATH_TEST_HOLD=PROCESS:STEP; the test continues the process with
// SIGCONT (or kills it). PROCESS is
//   "envsim" or "coordinator": that process's main() reads it (threads of
//     an embedded run never hold);
//   "run": a checkpointed run (ResolveCheckpointOptions) holds once its
//     first approach's first checkpoint at or after STEP is on disk;
//   "train-model": `dynapath train-model` holds once round STEP is done
//     (its progress line logged), its agents still running.

#include <string_view>

namespace dynapath::runtime {

// The time step (or round) at which `process` is to hold, or
// -1 when DYNAPATH_TEST_HOLD is unset, names another process or is not of
// the form PROCESS:STEP.
int TestHoldStep(std::string_view process);

// Logs that `process` holds at `time_step` and stops the whole process until
// it is continued (SIGCONT). Only the first call holds: envsim answers a
// request repeated on a loaded machine twice, and a second stop would wait
// for a SIGCONT that never comes (the coordinator then gave up after 60 s).
void HoldForTest(std::string_view process, int time_step);

}  // namespace dynapath::runtime
