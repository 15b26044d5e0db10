// dynapath serve: the planner on the bus (docs/howto/SERVICE.md). Parses
// the options into a service plan and runs it (app/service_session.h: the
// path service, its bus glue and the training on agents); here only the
// command line, the probe for another service and what is printed.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "app/service_session.h"
#include "protocol/dispatcher.h"
#include "runtime/reply_witness.h"
#include "tools/cli/commands.h"
#include "tools/cli/service_client.h"
#include "tools/common/toml_config.h"

namespace dynapath::cli {
namespace {

constexpr const char* kServeProgram = "dynapath serve";
// How long a starting service listens for another one of its run id: a
// service answers a probe within milliseconds, even while training.
constexpr double kOtherServiceSeconds = 0.5;

}  // namespace

int ServeCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Serves paths to stations over LCM while the map changes: loads the maze, trains\n"
      "one approach on it (or takes over --load-policy's policy; convQ trains nothing:\n"
      "its model, --model, settles on the map and re-settles around each change), then\n"
      "until Ctrl-C or SIGTERM answers path_request_t on DYNAPATH/<run>/PATH_REQUEST\n"
      "from the last committed policy and takes obstacle_update_t on MAP_UPDATES,\n"
      "obstacle_points_t on MAP_POINTS (metres in the map's frame: a ROS map's YAML,\n"
      "else --resolution and --origin) and occupancy_grid_t on MAP_GRID (the map or a\n"
      "window of it, of the map's resolution): the updates that arrive while a step trains make\n"
      "the next time step, and the retraining strategy decides as in `run`. Publishes\n"
      "the policy on POLICY (dynapath view) and each step on REPORT. Without --lcm-url\n"
      "it runs in a private network of its own (join it with nsenter, see dynapath-spy\n"
      "--pid). On stop it prints what it served. Guide: docs/howto/SERVICE.md.\n"
      "  --local       train in this process on a thread pool (default)\n"
      "  --agents N    train on N agent processes this command starts, on the service's\n"
      "                network (it plays the coordinator's part)\n"
      "  --embedded    the agents as threads of this process over memq:// (N from\n"
      "                --agents, else 1); clients still use the service's network\n"
      "The policies, and so every answer, are the same in every mode.",
      kServeProgram);
  runtime::OptionGroup group(app);
  app::ServiceOptions o;
  runtime::DeclareModeOptions(group, o.mode);
  runtime::DeclareScenarioOptions(group, o.scenario);
  runtime::DeclareRunOptions(group, o.run);
  runtime::DeclareProcessOptions(group, o.process, true);
  runtime::DeclareThreadOptions(group, o.threads);
  group.Option("--answer", o.answer, "HOW",
               std::string("answer from the ") + app::AnswerModeWords() +
                   " (exact: Incremental Oracle's shortest paths; learned-else-exact: the "
                   "policy's path, the exact one where the policy fails)");
  group.Option("--max-starts", o.max_starts, "N",
               "starts one request may carry (1-65536); larger requests are refused");
  group.Option("--occupied-thresh", o.occupied_thresh, "P",
               "occupancy grids: a value above P (0-1) is an obstacle");
  group.Option("--free-thresh", o.free_thresh, "P",
               "occupancy grids: a value below P (0-1) is free; between: unchanged");
  group.Option("--policy-every", o.policy_every, "SECONDS",
               "publish the current policy again after SECONDS without a new one, for late "
               "viewers (0: never)");
  group.Option("--policy-gap", o.policy_gap, "SECONDS",
               "at most one policy message every SECONDS: commits in between are published as "
               "the latest of them (0: one per commit, as run publishes steps)");
  runtime::DeclareGoalOptions(group, o.goals);
  runtime::DeclareLogOptions(group, o.log);
  runtime::AddConfigOption(app);
  ReadConfigAsToml(app);
  auto fail = [](const Status& status) {
    if (status.error().IsInvalidArgument()) {
      std::fprintf(stderr, "%s: %s\n", kServeProgram, status.error().message.c_str());
      return kExitUsage;
    }
    if (status.error().IsCancelled()) return kExitInterrupted;
    if (!status.error().message.empty()) spdlog::error("{}", status.error().message);
    return kExitFailure;
  };
  if (int code = runtime::ParseCommandLine(app, args, kServeProgram); code >= 0) return code;
  if (Status status = runtime::ApplyLogLevel(o.log); !status) return fail(status);
  o.save_at_given = app.count("--save-at") > 0;
  o.placement_given = app.count("--placement") > 0;
  o.out_given = app.count("--out") > 0;
  Result<app::ServicePlan> plan = app::PlanService(o);
  if (!plan) return fail(Error(plan.error().message));  // every error of the options
  // Before Open, whose log line tells a script the service has started: a
  // SIGINT from then on is honoured even where it was inherited as ignored
  // (a background job of a non-interactive shell).
  const std::atomic<bool>& stop =
      protocol::StopOnSignals("\ndynapath serve: stopping (Ctrl-C again: at once)\n",
                              "\ndynapath serve: stopped at once\n");
  app::ServiceSession session(std::move(*plan));
  if (Status opened = session.Open(); !opened) return fail(opened);
  // Before any work: is another service answering this run here? Two
  // would both answer every request (a private network or memq:// has no
  // other process; this one does not answer its own probe).
  if (session.may_have_company()) {
    const runtime::ProcessSetup& process = session.plan().process;
    Result<std::unique_ptr<ServiceClient>> prober =
        ServiceClient::Open(process, session.probe_client(), ServiceClient::kRepliesOnly);
    if (!prober) return fail(Error(prober.error().message, Error::Code::kUnavailable));
    if (std::optional<path_reply_t> other = (*prober)->Ask({}, kOtherServiceSeconds)) {
      return fail(Error("run " + process.run_id + " is already served on this network by " +
                        runtime::DescribeReplier(*other) + "; this service's maze has " +
                        FingerprintText(session.maze_fingerprint()) +
                        ": give it a run id of its own, or stop the other"));
    }
  }
  const Status served = session.Serve(stop);
  std::printf("%s", session.Summary().c_str());
  std::fflush(stdout);
  if (!served) return fail(served);
  if (Status finished = session.Finish(); !finished) return fail(finished);
  return 0;
}

}  // namespace dynapath::cli
