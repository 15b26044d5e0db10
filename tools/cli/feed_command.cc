// dynapath feed: publishes a change sequence to a running `dynapath serve`
// as live obstacle updates, one obstacle_update_t (or with --xy one
// obstacle_points_t, in metres) per time step, either in
// lock step with the service's commits (the default: the service then
// makes exactly the run's time steps) or at a fixed rate.

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "dynapath/latency_histogram.h"
#include "dynapath/obstacle_update_t.hpp"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"
#include "tools/cli/commands.h"
#include "tools/cli/service_client.h"

namespace dynapath::cli {
namespace {

constexpr const char* kFeedProgram = "dynapath feed";

int64_t NowMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

int FeedCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Publishes a maze's change sequence to a running `dynapath serve` as live updates\n"
      "(obstacle_update_t on DYNAPATH/<run>/MAP_UPDATES, one per time step; with --xy\n"
      "obstacle_points_t on MAP_POINTS, the changed cells' centres in metres): the\n"
      "sequence of --changes FILE (as `dynapath maze --save-changes` writes it), or the\n"
      "one generated for the maze options as `run` would. The maze options must be the\n"
      "service's (its maze fingerprint is checked first); the steps sent are those after\n"
      "the service's current step. Without --rate it waits for the service to commit\n"
      "each step before sending the next, so the service's time steps are the run's;\n"
      "with --rate R it sends R steps a second whatever the service does. Prints one\n"
      "JSON line: steps sent and, in lock step, the service's last step and the times\n"
      "from publishing an update to the first reply from a policy of its step\n"
      "(commit_p50_ms, ...; for a step that retrains, the interim policy committed\n"
      "before the training) and to the step's own retrained policy (trained_p50_ms, ...).",
      kFeedProgram);
  runtime::OptionGroup group(app);
  runtime::ScenarioOptions scenario;
  runtime::DeclareScenarioOptions(group, scenario);
  runtime::ProcessOptions process_options;
  runtime::DeclareProcessOptions(group, process_options, true);
  std::optional<double> rate;
  group.Option("--rate", rate, "R", "time steps per second (0.01-100000) instead of lock step",
               "lock step with the service's commits");
  std::optional<std::string> source_given;
  DeclareUpdateSourceOption(group, source_given, "feed-PID");
  std::optional<long long> max_steps;
  group.Option("--max-steps", max_steps, "N",
               "send at most N steps (1-10000000) after the service's current one", "all");
  MetresOptions metres;
  DeclareMetresOptions(group, metres);
  double timeout = 60;
  DeclareServiceWaitOption(group, timeout);
  runtime::LogOptions log;
  runtime::DeclareLogOptions(group, log);
  if (int code = runtime::ParseCommandLine(app, args, kFeedProgram); code >= 0) return code;
  if (Status status = runtime::ApplyLogLevel(log); !status) {
    return runtime::ProcessError(kFeedProgram, status.error().message);
  }
  Result<runtime::ProcessSetup> process = runtime::ResolveProcessOptions(process_options, true);
  if (!process) return runtime::ProcessError(kFeedProgram, process.error().message);
  const std::string source = source_given.value_or("feed-" + std::to_string(getpid()));
  if (source.empty() || source.size() > 64) {
    return runtime::ProcessError(kFeedProgram, "--source must have 1-64 characters");
  }
  if (rate && !(*rate >= 0.01 && *rate <= 100000)) {
    return runtime::ProcessError(kFeedProgram, "--rate must be between 0.01 and 100000");
  }
  if (!(timeout > 0 && timeout <= 3600)) {
    return runtime::ProcessError(kFeedProgram, "--timeout must be between 0 and 3600 seconds");
  }
  if (max_steps) {
    Result<long long> checked = runtime::InRange("max-steps", *max_steps, 1, 1, 10000000);
    if (!checked) return runtime::ProcessError(kFeedProgram, checked.error().message);
  }
  Result<runtime::ScenarioSetup> setup = runtime::ResolveScenario(scenario);
  if (!setup) return runtime::ProcessError(kFeedProgram, setup.error().message);
  const Grid& grid = setup->scenario.grid;
  Result<std::optional<MapFrame>> frame = ResolveMetresOptions(metres, scenario.maze, grid);
  if (!frame) return runtime::ProcessError(kFeedProgram, frame.error().message);
  Result<std::unique_ptr<ServiceClient>> opened =
      ServiceClient::Open(*process, "feed-" + std::to_string(getpid()), ServiceClient::kReports);
  if (!opened) return runtime::ProcessError(kFeedProgram, opened.error().message, kExitFailure);
  ServiceClient& client = **opened;
  // The service's maze and step: its first commit answers this probe (a
  // request without starts, counted as a probe, not as a start).
  const std::vector<std::pair<int32_t, int32_t>> probe;
  Result<path_reply_t> first = client.Meet(grid, timeout);
  if (!first) {
    return runtime::ProcessError(kFeedProgram, first.error().message,
                                 first.error().IsInvalidArgument() ? kExitUsage : kExitFailure);
  }
  // The service is at step T of this sequence (a loaded policy caught up
  // with it, or an earlier feed): it goes on from step T + 1.
  int expected_step = first->time_step;
  const std::vector<ChangeStep>& steps = setup->scenario.changes.steps;
  if (expected_step > static_cast<int>(steps.size())) {
    return runtime::ProcessError(
        kFeedProgram,
        "the service is at time step " + std::to_string(expected_step) +
            " and the change sequence has " + std::to_string(steps.size()) +
            " steps: nothing of it is left to send (give --steps or a change file that goes on)");
  }
  if (expected_step > 0) {
    spdlog::info("feed: the service is at time step {}: sending from step {}", expected_step,
                 expected_step + 1);
  }
  const auto start = std::chrono::steady_clock::now();
  int sent = 0;
  LatencyHistogram commit;   // lock step: update published -> a policy of its step answering
  LatencyHistogram trained;  // ... -> the step's own (retrained) policy committed
  const size_t last = max_steps ? std::min(steps.size(), static_cast<size_t>(expected_step) +
                                                             static_cast<size_t>(*max_steps))
                                : steps.size();
  for (size_t t = static_cast<size_t>(expected_step); t < last; ++t) {
    const ChangeStep& step = steps[t];
    const int64_t sequence = ++sent;
    const uint64_t maze = static_cast<uint64_t>(first->maze_fingerprint);
    if (rate) {
      std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                std::chrono::duration<double>((sent - 1) / *rate)));
      PublishStep(client, step, grid, *frame, source, sequence, maze, NowMicros());
      continue;
    }
    const auto published = std::chrono::steady_clock::now();
    PublishStep(client, step, grid, *frame, source, sequence, maze, NowMicros());
    if (step.changes.empty()) continue;  // the service makes no step of nothing
    ++expected_step;
    // Lock step: probe until a reply comes from the step this update made.
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(timeout));
    bool committed = false;
    while (!committed && std::chrono::steady_clock::now() < deadline) {
      std::optional<path_reply_t> reply = client.Ask(probe, 1.0);
      committed = reply && reply->time_step >= expected_step;
      if (!committed) std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    // Publication to the first reply from the new policy (probes 0.5 ms
    // apart: the figure is at most that much late).
    commit.Add(std::chrono::duration_cast<std::chrono::microseconds>(
                   std::chrono::steady_clock::now() - published)
                   .count());
    if (!committed) {
      return runtime::ProcessError(kFeedProgram,
                                   "the service did not commit time step " +
                                       std::to_string(expected_step) + " within --timeout",
                                   kExitFailure);
    }
    // A step that retrains answers first from an interim policy (its grid,
    // the previous policy); its own comes when the training ends, announced
    // by its REPORT. The next update waits for that, so every figure starts
    // from a service with nothing in hand.
    const std::optional<std::chrono::steady_clock::time_point> reported =
        client.ReportArrival(expected_step, timeout);
    if (!reported) {
      return runtime::ProcessError(kFeedProgram,
                                   "no report of time step " + std::to_string(expected_step) +
                                       " from the service within --timeout",
                                   kExitFailure);
    }
    trained.Add(
        std::chrono::duration_cast<std::chrono::microseconds>(*reported - published).count());
  }
  if (std::optional<std::string> two = client.SecondService()) {
    return runtime::ProcessError(kFeedProgram, *two, kExitFailure);
  }
  if (rate) {
    std::printf("{\"sent\":%d}\n", sent);
  } else {
    const auto ms = [](int64_t micros) { return static_cast<double>(micros) / 1000.0; };
    std::printf(
        "{\"sent\":%d,\"service_step\":%d,\"commit_p50_ms\":%.3f,\"commit_p99_ms\":%.3f,"
        "\"commit_max_ms\":%.3f,\"trained_p50_ms\":%.3f,\"trained_p99_ms\":%.3f,"
        "\"trained_max_ms\":%.3f}\n",
        sent, expected_step, ms(commit.Quantile(0.5)), ms(commit.Quantile(0.99)), ms(commit.max()),
        ms(trained.Quantile(0.5)), ms(trained.Quantile(0.99)), ms(trained.max()));
  }
  return 0;
}

}  // namespace dynapath::cli
