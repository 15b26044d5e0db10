// The test hook (runtime/test_hold.h): the environment names the process and
// step; the process stops once, however often it reaches the hold.

#include "runtime/test_hold.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>

namespace dynapath::runtime {
namespace {

TEST(TestHold, ReadsProcessAndStepFromTheEnvironment) {
  unsetenv("DYNAPATH_TEST_HOLD");
  EXPECT_EQ(TestHoldStep("envsim"), -1);
  setenv("DYNAPATH_TEST_HOLD", "envsim:100", 1);
  EXPECT_EQ(TestHoldStep("envsim"), 100);
  EXPECT_EQ(TestHoldStep("coordinator"), -1);
  for (const char* bad : {"envsim", "envsim:", "envsim:x1", "envsim:-1", "envsim:1234567890"}) {
    setenv("DYNAPATH_TEST_HOLD", bad, 1);
    EXPECT_EQ(TestHoldStep("envsim"), -1) << bad;
  }
  unsetenv("DYNAPATH_TEST_HOLD");
}

// envsim answers a request the coordinator repeated (on a loaded machine)
// twice: only the first answer may hold, or the process stops again and
// waits for a SIGCONT the test never sends.
TEST(TestHold, StopsTheProcessOnce) {
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    HoldForTest("envsim", 100);
    HoldForTest("envsim", 100);  // the repeated request's answer
    _exit(0);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, WUNTRACED), child);
  ASSERT_TRUE(WIFSTOPPED(status)) << "the first hold did not stop the process";
  kill(child, SIGCONT);
  ASSERT_EQ(waitpid(child, &status, WUNTRACED), child);
  if (WIFSTOPPED(status)) {
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
    FAIL() << "the second hold stopped the process again";
  }
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace dynapath::runtime
