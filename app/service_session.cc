#include "app/service_session.h"

#include <malloc.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <limits>
#include <thread>

#include "app/resources.h"
#include "coordinator/training_session.h"
#include "dynapath/results_csv.h"
#include "launch/launcher.h"
#include "protocol/channels.h"
#include "runtime/output_check.h"
#include "runtime/word_table.h"

namespace dynapath::app {
namespace {

const runtime::WordTable<AnswerMode>& AnswerWords() {
  static const runtime::WordTable<AnswerMode> words(
      {{"learned", AnswerMode::kLearned},
       {"exact", AnswerMode::kExact},
       {"learned-else-exact", AnswerMode::kLearnedElseExact}});
  return words;
}

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

const char* AnswerModeWords() {
  static const std::string list = AnswerWords().List();
  return list.c_str();
}

std::string AnswerModeName(AnswerMode mode) { return AnswerWords().Name(mode); }

Result<ServicePlan> PlanService(const ServiceOptions& options) {
  ServicePlan plan;
  Result<runtime::RunMode> run_mode = runtime::ResolveMode(options.mode, runtime::kMaxAgents);
  if (!run_mode) return run_mode.error();
  plan.mode = *run_mode;
  const bool on_agents = plan.mode.kind != runtime::RunMode::kLocal;
  Result<int> threads = runtime::ResolveThreads(options.threads);
  if (!threads) return threads.error();
  plan.threads = *threads;
  Result<runtime::RunPlan> run = runtime::ResolveRunOptions(options.run);
  if (!run) return run.error();
  plan.run = std::move(*run);
  if (plan.run.approaches.size() != 1 ||
      (!IsLearningApproach(plan.run.approaches[0]) && plan.run.approaches[0] != Approach::kConvQ &&
       plan.run.approaches[0] != Approach::kIncrementalOracle)) {
    return OptionError("--approach must name one learning approach, convQ or Incremental Oracle",
                       "approach");
  }
  // convQ trains nothing (its model settles on the map in this process):
  // agents would only idle.
  if (plan.run.approaches[0] == Approach::kConvQ && on_agents) {
    return OptionError(
        "convQ trains nothing, so it has no work for agents: serve it without --agents and "
        "--embedded (it settles on the map in this process)",
        "agents");
  }
  if (!plan.run.model_path.empty() && plan.run.approaches[0] != Approach::kConvQ) {
    return OptionError("--model is convQ's model file: give --approach convQ, or leave it out",
                       "model");
  }
  if (!plan.run.policy.save_path.empty() || options.save_at_given) {
    return OptionError(
        "--save-policy and --save-at are run's: a service's steps come from live updates that a "
        "later service could not replay to catch up with a saved step; save a policy with "
        "dynapath run",
        "save-policy");
  }
  if (!plan.run.checkpoint.dir.empty() || plan.run.checkpoint.resume) {
    return OptionError("--checkpoint is run's: a service starts from a policy file (--load-policy)",
                       "checkpoint");
  }
  if (options.placement_given && !on_agents) {
    return OptionError("--placement is for training on agents: give --agents N or --embedded",
                       "placement");
  }
  Result<AnswerMode> answer_mode = AnswerWords().ParseOption("answer", options.answer);
  if (!answer_mode) return answer_mode.error();
  Result<long long> starts_limit = runtime::InRange("max-starts", options.max_starts, 64, 1, 65536);
  if (!starts_limit) return starts_limit.error();
  if (!(options.occupied_thresh >= 0 && options.occupied_thresh <= 1 && options.free_thresh >= 0 &&
        options.free_thresh < options.occupied_thresh)) {
    return OptionError("--free-thresh and --occupied-thresh must satisfy 0 <= free < occupied <= 1",
                       "free-thresh");
  }
  if (!(options.policy_every >= 0 && options.policy_every <= 3600)) {
    return OptionError("--policy-every must be between 0 and 3600 seconds", "policy-every");
  }
  if (!(options.policy_gap >= 0 && options.policy_gap <= 3600)) {
    return OptionError("--policy-gap must be between 0 and 3600 seconds", "policy-gap");
  }
  Result<runtime::ProcessSetup> process = runtime::ResolveProcessOptions(options.process, true);
  if (!process) return process.error();
  plan.process = std::move(*process);
  Result<runtime::ScenarioSetup> setup = runtime::ResolveScenario(options.scenario);
  if (!setup) return setup.error();
  plan.setup = std::move(*setup);
  const Grid& maze = plan.setup.scenario.grid;
  if (Status policy = runtime::CheckPolicyPlan(
          plan.run.policy, plan.run.approaches, plan.run.options, maze,
          static_cast<int>(plan.setup.scenario.changes.steps.size()), plan.setup.seed);
      !policy) {
    return policy.error();
  }
  Result<runtime::GoalServiceConfig> goals =
      runtime::ResolveGoalOptions(options.goals, options.scenario.maze, maze);
  if (!goals) return goals.error();
  plan.goals = std::move(*goals);
  plan.goals.max_starts = static_cast<int>(*starts_limit);
  runtime::ServiceConfig& config = plan.config;
  config.approach = plan.run.approaches[0];
  config.answer = *answer_mode;
  config.options = plan.run.options;
  config.options.run_seed = plan.setup.seed;
  config.labels = plan.setup.labels;
  config.threads = plan.threads;
  config.max_starts = static_cast<int>(*starts_limit);
  config.catch_up = plan.setup.scenario.changes;
  config.load = plan.run.policy.Find(config.approach);
  if (Status loadable = runtime::PathService::CheckLoad(maze, config); !loadable) {
    return OptionError(
        "--load-policy " + plan.run.policy.load_path + ": " + loadable.error().message,
        "load-policy");
  }
  config.load = nullptr;  // a pointer into plan.run: ServiceSession sets it again
  plan.bus.thresholds = {options.occupied_thresh, options.free_thresh};
  plan.bus.policy_gap_seconds = options.policy_gap;
  plan.bus.republish_seconds = options.policy_every;
  plan.bus.own_probe_client = "serve-probe-" + std::to_string(getpid());
  plan.log_level = options.log.log_level;
  plan.write_results = options.out_given;
  return plan;
}

// The goal service follows every commit of the path service.
static runtime::ServiceConfig FollowedByGoals(runtime::ServiceConfig config,
                                              runtime::GoalService& goals) {
  config.on_snapshot = [&goals](const std::shared_ptr<const RouteSnapshot>& snapshot) {
    goals.OnCommit(snapshot);
  };
  return config;
}

ServiceOnBus::ServiceOnBus(protocol::Bus& bus, const Grid& maze, runtime::ServiceConfig config,
                           runtime::ServiceBusOptions options, runtime::GoalServiceConfig goals)
    : goals_(std::move(goals)),
      service_(maze, FollowedByGoals(std::move(config), goals_),
               [this](const runtime::Commit& commit) {
                 // Commits before the glue exists (none: the service starts
                 // later) have nowhere to go.
                 if (runtime::ServiceBus* glue = published_to_.load()) glue->PublishCommit(commit);
               }) {
  options.goals = &goals_;
  glue_.emplace(bus, service_, std::move(options));
  published_to_ = &*glue_;
}

ServiceOnBus::~ServiceOnBus() {
  (void)service_.Stop();  // no commit reaches the glue from here on
  published_to_ = nullptr;
  glue_.reset();
}

// Training on agents: the coordinator's part (its own LCM and Bus, apart
// from the service's, so a flood of queries neither fills the training
// traffic's receive buffer nor mixes into its counts) and the agents, as
// processes or as threads over memq://.
struct ServiceSession::Training {
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
  ~Training() {
    Stop();
    dispatcher.reset();
  }
};

ServiceSession::ServiceSession(ServicePlan plan) : plan_(std::move(plan)) {}

ServiceSession::~ServiceSession() {
  dispatcher_.reset();
  served_.reset();
  training_.reset();
}

Status ServiceSession::Open() {
  if (plan_.write_results) {
    Result<runtime::OutputLock> lock = runtime::LockResultDirectory(plan_.run.out_dir);
    if (!lock) return OptionError(lock.error().message, "out");
    out_lock_.emplace(std::move(*lock));
  }
  KeepFreedMemory();
  // Still single-threaded: a private network needs that.
  const launch::ProcessNetwork network = launch::EnterProcessNetwork(plan_.process.lcm_url);
  const std::string& url = plan_.process.lcm_url;
  if (network == launch::ProcessNetwork::kNone) {
    return OptionError("no private network can be made here: give --lcm-url", "lcm-url");
  }
  private_network_ = network == launch::ProcessNetwork::kPrivate;
  if (private_network_) {
    spdlog::info(
        "serving run {} in a private network; join it with: nsenter --target {} "
        "--user --net --preserve-credentials (or dynapath-spy --pid {})",
        plan_.process.run_id, getpid(), getpid());
  }
  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(url);
  if (!lcm) return Error(lcm.error().message, Error::Code::kUnavailable);
  lcm_ = std::move(*lcm);
  const Grid& maze = plan_.setup.scenario.grid;
  protocol::BusOptions bus_options = plan_.process.bus;
  bus_options.max_grid_cells = GridCap(maze);
  bus_.emplace(*lcm_, plan_.process.run_id, bus_options);

  training_ = std::make_unique<Training>();
  Training& training = *training_;
  if (plan_.mode.kind != runtime::RunMode::kLocal) {
    const bool embedded = plan_.mode.kind == runtime::RunMode::kEmbedded;
    protocol::BusOptions training_options = bus_options;
    if (protocol::IsMemq(protocol::ResolveLcmUrl(url))) {
      if (!embedded) {
        return OptionError(
            "agent processes cannot join memq://: use --embedded, or give a network URL",
            "lcm-url");
      }
      training.lcm = lcm_.get();  // one memq:// per process: share it
    } else if (embedded) {
      training.own_lcm = std::make_unique<lcm::LCM>("memq://");
      if (!training.own_lcm->good()) {
        return Error("cannot open LCM memq://", Error::Code::kUnavailable);
      }
      training.lcm = training.own_lcm.get();
      training_options.fragment_above = 0;
    } else {
      Result<std::unique_ptr<lcm::LCM>> own = protocol::OpenLcm(url);
      if (!own) return Error(own.error().message, Error::Code::kUnavailable);
      training.own_lcm = std::move(*own);
      training.lcm = training.own_lcm.get();
    }
    training.bus.emplace(*training.lcm, plan_.process.run_id, training_options);
    coordinator::TrainingSessionOptions session_options;
    session_options.min_agents = plan_.mode.agents;
    session_options.placement = plan_.run.placement;
    training.session.emplace(*training.bus, session_options);
    if (embedded) {
      training.embedded.emplace(*training.lcm, plan_.process.run_id, training_options,
                                plan_.mode.agents,
                                ThreadsPerAgent(plan_.threads, plan_.mode.agents));
    }
  }

  runtime::ServiceConfig config = plan_.config;
  config.load = plan_.run.policy.Find(config.approach);
  if (training.session) config.trainer = &*training.session;
  served_ = std::make_unique<ServiceOnBus>(*bus_, maze, std::move(config), plan_.bus, plan_.goals);
  spdlog::info("serve: run {}, maze {} {} ({}), {}, answers {}, {} threads", plan_.process.run_id,
               plan_.setup.labels.size_label, plan_.setup.labels.difficulty_label,
               plan_.setup.source, ApproachName(plan_.config.approach),
               AnswerModeName(plan_.config.answer), plan_.threads);
  dispatcher_.emplace(*lcm_);
  return Ok{};
}

bool ServiceSession::may_have_company() const {
  return !private_network_ && !protocol::IsMemq(protocol::ResolveLcmUrl(plan_.process.lcm_url));
}

uint64_t ServiceSession::maze_fingerprint() const {
  return MazeFingerprint(plan_.setup.scenario.grid);
}

Status ServiceSession::Serve(const std::atomic<bool>& stop) {
  runtime::PathService& service = served_->service();
  Training& training = *training_;
  if (training.session) {
    training.session->set_stop(&service.stopping());
    if (training.lcm != lcm_.get()) training.dispatcher.emplace(*training.lcm);
    training.session->Start();
    if (training.embedded) {
      training.embedded->Start();
      spdlog::info("serve: training on {} agent threads over memq://", plan_.mode.agents);
    } else {
      launch::AgentLaunch agents;
      agents.process = plan_.process;
      agents.process.bus.max_grid_cells = GridCap(plan_.setup.scenario.grid);
      agents.agents = plan_.mode.agents;
      agents.threads_per_agent = ThreadsPerAgent(plan_.threads, plan_.mode.agents);
      agents.log_level = plan_.log_level;
      training.processes.emplace(std::move(agents));
      if (!training.processes->Start()) return Error("", Error::Code::kUnavailable);  // logged
      spdlog::info("serve: training on {} agent processes", plan_.mode.agents);
    }
  }
  service.Start();
  started_ = true;
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
                   bus_->Channel(protocol::channel::kPathRequest));
      announced = true;
    }
  }
  run_ = service.Stop();
  training.Stop();
  if (failed && run_) run_ = Error("training ended before the service was stopped");
  if (!run_) return Error(run_.error().message, Error::Code::kInternal);
  return Ok{};
}

std::string ServiceSession::Summary() const {
  if (!started_) return {};
  std::string text = runtime::PathService::Summary(served_->service().stats());
  text += runtime::GoalService::Summary(served_->goals().stats());
  text += "messages: " + bus_->TrafficSummary() + "; " +
          std::to_string(served_->glue().policies_published()) + " policy messages\n";
  if (training_->session) {
    const coordinator::TrafficStats& t = training_->session->traffic();
    text += "training on agents: " + std::to_string(t.batches) + " batches, " +
            std::to_string(t.rounds) + " federated rounds, " + std::to_string(t.epochs) +
            " reassignments; messages: " + training_->bus->TrafficSummary() + "\n";
  }
  return text;
}

Status ServiceSession::Finish() {
  if (!run_) return Ok{};
  // Stopped before a step was scored (during the initial training): no
  // result to write, and the outcome of an interrupted run.
  if (run_->steps.empty()) {
    const bool interrupted = served_->service().Current() == nullptr;
    spdlog::info("serve: {}: no results written",
                 interrupted ? "stopped before its first policy" : "no time step was scored");
    return interrupted ? Status(Error::Cancelled()) : Status(Ok{});
  }
  if (!plan_.write_results) return Ok{};
  if (Status written = WriteResultFiles({*run_}, plan_.run.out_dir); !written) {
    return Error(written.error().message, Error::Code::kIo);
  }
  spdlog::info("wrote {}/results.csv and {}/results_detailed.csv", plan_.run.out_dir,
               plan_.run.out_dir);
  return Ok{};
}

}  // namespace dynapath::app
