// dynapath serve: the planner on the bus (docs/howto/SERVICE.md). Loads a
// maze, trains one approach on it (or takes over a saved policy), then
// answers path requests and takes obstacle updates until SIGINT/SIGTERM;
// the service itself is runtime/path_service.h, its messages
// runtime/service_bus.h. With --agents N it plays the coordinator's part for
// training (coordinator/training_session.h) and trains on N agent processes
// (or, --embedded, agent threads over memq://).

#include <malloc.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <limits>
#include <optional>
#include <thread>

#include "coordinator/training_session.h"
#include "dynapath/results_csv.h"
#include "launch/launcher.h"
#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "runtime/goal_service.h"
#include "runtime/output_check.h"
#include "runtime/output_lock.h"
#include "runtime/path_service.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"
#include "runtime/service_bus.h"
#include "runtime/word_table.h"
#include "tools/cli/commands.h"
#include "tools/cli/service_client.h"
#include "tools/common/toml_config.h"

namespace dynapath::cli {
namespace {

constexpr const char* kServeProgram = "dynapath serve";
// How long a starting service listens for another one of its run id: a
// service answers a probe within milliseconds, even while training.
constexpr double kOtherServiceSeconds = 0.5;

const runtime::WordTable<AnswerMode>& AnswerWords() {
  static const runtime::WordTable<AnswerMode> words(
      {{"learned", AnswerMode::kLearned},
       {"exact", AnswerMode::kExact},
       {"learned-else-exact", AnswerMode::kLearnedElseExact}});
  return words;
}

// Training on agents: the coordinator's part (its own LCM and Bus, apart
// from the service's, so a flood of queries neither fills the training
// traffic's receive buffer nor mixes into its counts) and the agents, as
// processes or as threads over memq://.
struct AgentTraining {
  std::unique_ptr<lcm::LCM> own_lcm;  // processes: a second instance on the service's URL
  lcm::LCM* lcm = nullptr;
  std::optional<protocol::Bus> bus;
  std::optional<coordinator::TrainingSession> session;
  std::optional<launch::EmbeddedAgents> embedded;
  std::optional<protocol::Dispatcher> dispatcher;  // after the subscribers, destroyed first
  std::optional<launch::AgentProcesses> processes;

  // Ends it: the session's final heartbeat, then the agents; no process is
  // left behind.
  void Stop() {
    if (session) session->Finish();
    if (processes) processes->Stop(std::chrono::milliseconds(500));
    if (embedded) embedded->Stop();
  }
  ~AgentTraining() {
    Stop();
    dispatcher.reset();
  }
};

// Every commit builds a snapshot (megabytes on a large map) and frees an
// older one. glibc hands such blocks back to the kernel (munmap, or
// trimming the heap's top) and the next commit faults fresh pages in:
// measured on the 2-core virtual machine, 30-90 ms stalls of a commit
// that otherwise takes 1 ms (docs/PERFORMANCE.md, planning service). A
// service's memory is its working set anyway: keep it.
void KeepFreedMemory() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest: below it, blocks come from the heap
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
}

}  // namespace

int ServeCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Serves paths to stations over LCM while the map changes: loads the maze, trains\n"
      "one approach on it (or takes over --load-policy's policy), then\n"
      "until Ctrl-C or SIGTERM answers path_request_t on DYNAPATH/<run>/PATH_REQUEST\n"
      "from the last committed policy and takes obstacle_update_t on MAP_UPDATES and\n"
      "occupancy_grid_t on MAP_GRID: the updates that arrive while a step trains make\n"
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
  runtime::ModeOptions mode;
  runtime::DeclareModeOptions(group, mode);
  runtime::ScenarioOptions scenario;
  runtime::DeclareScenarioOptions(group, scenario);
  runtime::RunOptions run_options;
  run_options.approach = ApproachName(Approach::kFedAsynQEqAvg);
  runtime::DeclareRunOptions(group, run_options);
  runtime::ProcessOptions process_options;
  runtime::DeclareProcessOptions(group, process_options, true);
  runtime::ThreadOptions thread_options;
  runtime::DeclareThreadOptions(group, thread_options);
  std::string answer = AnswerWords().Name(AnswerMode::kLearnedElseExact);
  group.Option("--answer", answer, "HOW",
               "answer from the " + AnswerWords().List() +
                   " (exact: Incremental Oracle's shortest paths; learned-else-exact: the "
                   "policy's path, the exact one where the policy fails)");
  long long max_starts = 64;
  group.Option("--max-starts", max_starts, "N",
               "starts one request may carry (1-65536); larger requests are refused");
  double occupied_thresh = 0.65, free_thresh = 0.196;
  group.Option("--occupied-thresh", occupied_thresh, "P",
               "occupancy grids: a value above P (0-1) is an obstacle");
  group.Option("--free-thresh", free_thresh, "P",
               "occupancy grids: a value below P (0-1) is free; between: unchanged");
  double policy_every = 5;
  group.Option("--policy-every", policy_every, "SECONDS",
               "publish the current policy again after SECONDS without a new one, for late "
               "viewers (0: never)");
  double policy_gap = 1;
  group.Option("--policy-gap", policy_gap, "SECONDS",
               "at most one policy message every SECONDS: commits in between are published as "
               "the latest of them (0: one per commit, as run publishes steps)");
  runtime::GoalOptions goal_options;
  runtime::DeclareGoalOptions(group, goal_options);
  runtime::LogOptions log;
  runtime::DeclareLogOptions(group, log);
  runtime::AddConfigOption(app);
  ReadConfigAsToml(app);
  auto usage_error = [](const std::string& message) {
    std::fprintf(stderr, "%s: %s\n", kServeProgram, message.c_str());
    return kExitUsage;
  };
  if (int code = runtime::ParseCommandLine(app, args, kServeProgram); code >= 0) return code;
  if (Status status = runtime::ApplyLogLevel(log); !status) {
    return usage_error(status.error().message);
  }
  Result<runtime::RunMode> run_mode = runtime::ResolveMode(mode, runtime::kMaxAgents);
  if (!run_mode) return usage_error(run_mode.error().message);
  const bool on_agents = run_mode->kind != runtime::RunMode::kLocal;
  Result<int> threads = runtime::ResolveThreads(thread_options);
  if (!threads) return usage_error(threads.error().message);
  Result<runtime::RunPlan> plan = runtime::ResolveRunOptions(run_options);
  if (!plan) return usage_error(plan.error().message);
  if (plan->approaches.size() != 1 || (!IsLearningApproach(plan->approaches[0]) &&
                                       plan->approaches[0] != Approach::kIncrementalOracle)) {
    return usage_error("--approach must name one learning approach or Incremental Oracle");
  }
  if (!plan->policy.save_path.empty() || app.count("--save-at") > 0) {
    return usage_error(
        "--save-policy and --save-at are run's: a service's steps come from live updates that a "
        "later service could not replay to catch up with a saved step; save a policy with "
        "dynapath run");
  }
  if (!plan->checkpoint.dir.empty() || plan->checkpoint.resume) {
    return usage_error(
        "--checkpoint is run's: a service starts from a policy file (--load-policy)");
  }
  if (app.count("--placement") > 0 && !on_agents) {
    return usage_error("--placement is for training on agents: give --agents N or --embedded");
  }
  Result<AnswerMode> answer_mode = AnswerWords().ParseOption("answer", answer);
  if (!answer_mode) return usage_error(answer_mode.error().message);
  Result<long long> starts_limit = runtime::InRange("max-starts", max_starts, 64, 1, 65536);
  if (!starts_limit) return usage_error(starts_limit.error().message);
  if (!(occupied_thresh >= 0 && occupied_thresh <= 1 && free_thresh >= 0 &&
        free_thresh < occupied_thresh)) {
    return usage_error(
        "--free-thresh and --occupied-thresh must satisfy 0 <= free < occupied <= 1");
  }
  if (!(policy_every >= 0 && policy_every <= 3600)) {
    return usage_error("--policy-every must be between 0 and 3600 seconds");
  }
  if (!(policy_gap >= 0 && policy_gap <= 3600)) {
    return usage_error("--policy-gap must be between 0 and 3600 seconds");
  }
  Result<runtime::ProcessSetup> process = runtime::ResolveProcessOptions(process_options, true);
  if (!process) return usage_error(process.error().message);
  Result<runtime::ScenarioSetup> setup = runtime::ResolveScenario(scenario);
  if (!setup) return usage_error(setup.error().message);
  const Grid& maze = setup->scenario.grid;
  Result<runtime::GoalServiceConfig> goal_config =
      runtime::ResolveGoalOptions(goal_options, scenario.maze, maze);
  if (!goal_config) return usage_error(goal_config.error().message);
  goal_config->max_starts = static_cast<int>(*starts_limit);
  if (Status policy = runtime::CheckPolicyPlan(
          plan->policy, plan->approaches, plan->options, maze,
          static_cast<int>(setup->scenario.changes.steps.size()), setup->seed);
      !policy) {
    return usage_error(policy.error().message);
  }
  runtime::ServiceConfig config;
  config.approach = plan->approaches[0];
  config.answer = *answer_mode;
  config.options = plan->options;
  config.options.run_seed = setup->seed;
  config.labels = setup->labels;
  config.threads = *threads;
  config.max_starts = static_cast<int>(*starts_limit);
  config.load = plan->policy.Find(config.approach);
  config.catch_up = setup->scenario.changes;
  if (Status loadable = runtime::PathService::CheckLoad(maze, config); !loadable) {
    return usage_error("--load-policy " + plan->policy.load_path + ": " + loadable.error().message);
  }
  const bool write_results = app.count("--out") > 0;
  std::optional<runtime::OutputLock> out_lock;
  if (write_results) {
    Result<runtime::OutputLock> lock = runtime::LockResultDirectory(plan->out_dir);
    if (!lock) return usage_error(lock.error().message);
    out_lock.emplace(std::move(*lock));
  }

  KeepFreedMemory();
  // Still single-threaded: a private network needs that.
  const launch::ProcessNetwork network = launch::EnterProcessNetwork(process->lcm_url);
  std::string url = process->lcm_url;
  if (network == launch::ProcessNetwork::kNone) {
    return usage_error("no private network can be made here: give --lcm-url");
  }
  if (network == launch::ProcessNetwork::kPrivate) {
    spdlog::info(
        "serving run {} in a private network; join it with: nsenter --target {} "
        "--user --net --preserve-credentials (or dynapath-spy --pid {})",
        process->run_id, getpid(), getpid());
  }
  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(url);
  if (!lcm) {
    spdlog::error("{}", lcm.error().message);
    return kExitFailure;
  }
  protocol::BusOptions bus_options = process->bus;
  bus_options.max_grid_cells = static_cast<int64_t>(maze.rows()) * maze.cols();
  protocol::Bus bus(**lcm, process->run_id, bus_options);

  AgentTraining training;
  if (on_agents) {
    const bool embedded = run_mode->kind == runtime::RunMode::kEmbedded;
    protocol::BusOptions training_options = bus_options;
    if (protocol::IsMemq(protocol::ResolveLcmUrl(url))) {
      if (!embedded) {
        return usage_error(
            "agent processes cannot join memq://: use --embedded, or give a network URL");
      }
      training.lcm = lcm->get();  // one memq:// per process: share it
    } else if (embedded) {
      training.own_lcm = std::make_unique<lcm::LCM>("memq://");
      if (!training.own_lcm->good()) {
        spdlog::error("cannot open LCM memq://");
        return kExitFailure;
      }
      training.lcm = training.own_lcm.get();
      training_options.fragment_above = 0;
    } else {
      Result<std::unique_ptr<lcm::LCM>> own = protocol::OpenLcm(url);
      if (!own) {
        spdlog::error("{}", own.error().message);
        return kExitFailure;
      }
      training.own_lcm = std::move(*own);
      training.lcm = training.own_lcm.get();
    }
    training.bus.emplace(*training.lcm, process->run_id, training_options);
    coordinator::TrainingSessionOptions session_options;
    session_options.min_agents = run_mode->agents;
    session_options.placement = plan->placement;
    training.session.emplace(*training.bus, session_options);
    const int threads_per_agent = std::max(1, *threads / run_mode->agents);
    if (embedded) {
      training.embedded.emplace(*training.lcm, process->run_id, training_options, run_mode->agents,
                                threads_per_agent);
    }
  }

  if (training.session) config.trainer = &*training.session;
  runtime::GoalService goals(std::move(*goal_config));
  config.on_snapshot = [&goals](const std::shared_ptr<const RouteSnapshot>& snapshot) {
    goals.OnCommit(snapshot);
  };
  runtime::ServiceBus* glue = nullptr;
  runtime::PathService service(maze, config, [&glue](const runtime::Commit& commit) {
    if (glue != nullptr) glue->PublishCommit(commit);
  });
  runtime::ServiceBusOptions glue_options;
  glue_options.thresholds = {occupied_thresh, free_thresh};
  glue_options.policy_gap_seconds = policy_gap;
  glue_options.republish_seconds = policy_every;
  glue_options.own_probe_client = "serve-probe-" + std::to_string(getpid());
  glue_options.goals = &goals;
  runtime::ServiceBus service_bus(bus, service, glue_options);
  glue = &service_bus;

  const std::atomic<bool>& stop =
      protocol::StopOnSignals("\ndynapath serve: stopping (Ctrl-C again: at once)\n",
                              "\ndynapath serve: stopped at once\n");
  spdlog::info("serve: run {}, maze {} {} ({}), {}, answers {}, {} threads", process->run_id,
               setup->labels.size_label, setup->labels.difficulty_label, setup->source,
               ApproachName(config.approach), answer, *threads);
  protocol::Dispatcher dispatcher(**lcm);
  // Before any work: is another service answering this run here? Two
  // would both answer every request (a private network or memq:// has no
  // other process; this one does not answer its own probe).
  if (network != launch::ProcessNetwork::kPrivate &&
      !protocol::IsMemq(protocol::ResolveLcmUrl(url))) {
    Result<std::unique_ptr<ServiceClient>> prober =
        ServiceClient::Open(*process, glue_options.own_probe_client, ServiceClient::kRepliesOnly);
    if (!prober) {
      spdlog::error("{}", prober.error().message);
      return kExitFailure;
    }
    if (std::optional<path_reply_t> other = (*prober)->Ask({}, kOtherServiceSeconds)) {
      return usage_error("run " + process->run_id + " is already served on this network by " +
                         runtime::DescribeReplier(*other) + "; this service's maze has " +
                         FingerprintText(service.maze_fingerprint()) +
                         ": give it a run id of its own, or stop the other");
    }
  }
  if (training.session) {
    training.session->set_stop(&service.stopping());
    if (training.lcm != lcm->get()) training.dispatcher.emplace(*training.lcm);
    training.session->Start();
    if (training.embedded) {
      training.embedded->Start();
      spdlog::info("serve: training on {} agent threads over memq://", run_mode->agents);
    } else {
      launch::AgentLaunch agents;
      agents.process = *process;
      agents.process.bus.max_grid_cells = bus_options.max_grid_cells;
      agents.agents = run_mode->agents;
      agents.threads_per_agent = std::max(1, *threads / run_mode->agents);
      agents.log_level = log.log_level;
      training.processes.emplace(std::move(agents));
      if (!training.processes->Start()) return kExitFailure;
      spdlog::info("serve: training on {} agent processes", run_mode->agents);
    }
  }
  service.Start();
  bool announced = false;
  bool failed = false;
  while (!stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (service.training_ended()) {  // it failed (logged): no new policy will come
      failed = true;
      break;
    }
    if (training.processes) training.processes->Check();
    if (!announced && service.Current() != nullptr) {
      spdlog::info("serve: policy committed, answering on {}",
                   bus.Channel(protocol::channel::kPathRequest));
      announced = true;
    }
  }
  Result<ApproachRun> run = service.Stop();
  training.Stop();
  const runtime::ServiceStats stats = service.stats();
  std::printf("%s", runtime::PathService::Summary(stats).c_str());
  std::printf("%s", runtime::GoalService::Summary(goals.stats()).c_str());
  std::printf("messages: %s; %lld policy messages\n", bus.TrafficSummary().c_str(),
              static_cast<long long>(service_bus.policies_published()));
  if (training.session) {
    const coordinator::TrafficStats& t = training.session->traffic();
    std::printf(
        "training on agents: %lld batches, %lld federated rounds, %lld reassignments; messages: "
        "%s\n",
        static_cast<long long>(t.batches), static_cast<long long>(t.rounds),
        static_cast<long long>(t.epochs), training.bus->TrafficSummary().c_str());
  }
  std::fflush(stdout);
  if (failed && run) run = Error("training ended before the service was stopped");
  if (!run) {
    spdlog::error("{}", run.error().message);
    return kExitFailure;
  }
  // Stopped before a step was scored (during the initial training): no
  // result to write, and the exit status of an interrupted run.
  if (run->steps.empty()) {
    const bool interrupted = service.Current() == nullptr;
    spdlog::info("serve: {}: no results written",
                 interrupted ? "stopped before its first policy" : "no time step was scored");
    return interrupted ? kExitInterrupted : 0;
  }
  if (write_results) {
    if (Status written = WriteResultFiles({*run}, plan->out_dir); !written) {
      spdlog::error("{}", written.error().message);
      return kExitFailure;
    }
    spdlog::info("wrote {}/results.csv and {}/results_detailed.csv", plan->out_dir, plan->out_dir);
  }
  return 0;
}

}  // namespace dynapath::cli
