#include "runtime/test_hold.h"

#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <string>

namespace dynapath::runtime {

int TestHoldStep(std::string_view process) {
  const char* value = std::getenv("DYNAPATH_TEST_HOLD");
  if (value == nullptr) return -1;
  const std::string_view hold(value);
  const size_t colon = hold.find(':');
  if (colon == std::string_view::npos || hold.substr(0, colon) != process) return -1;
  const std::string step(hold.substr(colon + 1));
  if (step.empty() || step.size() > 9 ||
      step.find_first_not_of("0123456789") != std::string::npos) {
    return -1;
  }
  return std::stoi(step);
}

void HoldForTest(std::string_view process, int time_step) {
  // Once: envsim answers a repeated request for the step again, and a
  // second hold would wait for a SIGCONT the test does not send.
  static std::atomic<bool> held{false};
  if (held.exchange(true)) return;
  spdlog::info("{}: holding at time step {} (DYNAPATH_TEST_HOLD); continue with SIGCONT", process,
               time_step);
  spdlog::default_logger()->flush();
  std::raise(SIGSTOP);
}

}  // namespace dynapath::runtime
