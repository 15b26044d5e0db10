// dynapath-recorder: writes the LCM messages of a run (of any channels
// matching a pattern) into an LCM log file until SIGINT or SIGTERM, then
// writes what it had received and not yet written, and exits. What
// `dynapath run --log` starts; unlike lcm-logger it keeps every message
// its socket held while it was kept off the CPU (protocol/log_recorder.h).

#include <spdlog/spdlog.h>

#include <cerrno>
#include <chrono>
#include <optional>
#include <string>

#include "protocol/dispatcher.h"
#include "protocol/log_recorder.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"

namespace {

struct RecorderCommandLine {
  std::string lcm_url;
  std::string channel = ".*";
  std::optional<std::string> file;
  bool force = false;
  dynapath::runtime::LogOptions log;
};

// After the stop signal: what LCM had received and not yet handed over is
// written, until it has nothing for this long (or at most kDrainCap).
constexpr int kDrainQuietMs = 200;
constexpr auto kDrainCap = std::chrono::seconds(10);

}  // namespace

int main(int argc, char** argv) {
  using namespace dynapath;
  runtime::InitProcessLogging("recorder");
  RecorderCommandLine given;
  const int code = runtime::ParseProcessCommandLine(
      "dynapath-recorder",
      "Records the LCM messages of the channels matching --channel into the LCM log\n"
      "--file (the format of lcm-logger, read by dynapath render, web and\n"
      "log-to-mcap), until SIGINT or SIGTERM. Messages it received while kept off the\n"
      "CPU are all written, where lcm-logger keeps 30 of them.",
      [&given](runtime::OptionGroup& group) {
        runtime::DeclareLcmUrlOption(group, given.lcm_url);
        group.Option("--channel", given.channel, "REGEX",
                     "the channels to record (one run's: DYNAPATH/<run id>/.*)");
        group.Option("--file", given.file, "PATH", "the LCM log to write", "required");
        group.Flag("--force", given.force, "overwrite --file when it exists");
        runtime::DeclareLogOptions(group, given.log);
      },
      given.log, argc, argv);
  if (code >= 0) return code;
  if (!given.file) return runtime::ProcessError("dynapath-recorder", "option --file is required");

  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(given.lcm_url);
  if (!lcm) return runtime::ProcessError("dynapath-recorder", lcm.error().message, 1);
  Result<std::unique_ptr<protocol::LogRecorder>> recorder =
      protocol::LogRecorder::Open(**lcm, given.channel, *given.file, given.force);
  if (!recorder) return runtime::ProcessError("dynapath-recorder", recorder.error().message, 1);
  const std::atomic<bool>& stop = protocol::StopOnSignals();
  spdlog::info("recorder: recording {} into {}", given.channel, *given.file);

  // Each message is written through at once: the launcher takes a file
  // that has stopped growing, with empty sockets, for a recorder that is
  // done (launch/logger_drain.h).
  while (!stop) {
    errno = 0;
    if ((*lcm)->handleTimeout(100) < 0 && !stop && errno != EINTR) {
      return runtime::ProcessError("dynapath-recorder", "LCM stopped receiving", 1);
    }
    if (Status flushed = (*recorder)->Flush(); !flushed) {
      return runtime::ProcessError("dynapath-recorder", flushed.error().message, 1);
    }
  }
  const auto deadline = std::chrono::steady_clock::now() + kDrainCap;
  while (std::chrono::steady_clock::now() < deadline && (*lcm)->handleTimeout(kDrainQuietMs) > 0) {
  }
  if (Status flushed = (*recorder)->Flush(); !flushed) {
    return runtime::ProcessError("dynapath-recorder", flushed.error().message, 1);
  }
  spdlog::info("recorder: recorded {} messages ({} bytes) in {}", (*recorder)->events(),
               (*recorder)->bytes(), *given.file);
  return 0;
}
