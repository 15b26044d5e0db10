#pragma once
// A test hook of the envsim and coordinator processes: stop this process
// (SIGSTOP) at a known time step, so that a test pauses it mid-run
// deterministically instead of racing a signal against the run's progress.
// Set by the environment variable DYNAPATH_TEST_HOLD=PROCESS:STEP (PROCESS
// is "envsim" or "coordinator"); the test continues the process with SIGCONT.
// Only a process's main() reads it: threads of an embedded run never hold.

#include <string_view>

namespace dynapath::runtime {

// The time step at which `process` ("envsim", "coordinator") is to hold, or
// -1 when DYNAPATH_TEST_HOLD is unset, names another process or is not of
// the form PROCESS:STEP.
int TestHoldStep(std::string_view process);

// Logs that `process` holds at `time_step` and stops the whole process until
// it is continued (SIGCONT).
void HoldForTest(std::string_view process, int time_step);

}  // namespace dynapath::runtime
