#include "app/model_training.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "app/resources.h"
#include "coordinator/convq_trainer.h"
#include "launch/launcher.h"
#include "protocol/dispatcher.h"

namespace dynapath::app {

Result<ModelTrainingAgents> PlanModelTrainingAgents(const ModelTrainingAgentOptions& options) {
  Result<runtime::ProcessSetup> setup = runtime::ResolveProcessOptions(options.process, false);
  if (!setup) return setup.error();
  ModelTrainingAgents plan;
  plan.agents = options.agents;
  plan.embedded = options.embedded;
  plan.process = std::move(*setup);
  plan.secret_given = options.process.secret_file.has_value() || options.process.insecure;
  if (plan.embedded && !options.process.lcm_url.empty()) {
    // Threads over memq://: silently ignoring the URL would leave agents
    // started elsewhere waiting for a training they never see.
    return OptionError("--lcm-url needs processes on a network: use --agents N, not --embedded",
                       "lcm-url");
  }
  if (!plan.embedded && protocol::IsMemq(protocol::ResolveLcmUrl(options.process.lcm_url))) {
    return OptionError("agent processes cannot join memq://: use --embedded, or give a network URL",
                       "lcm-url");
  }
  return plan;
}

void EnterModelTrainingNetwork(ModelTrainingAgents& plan) {
  if (plan.embedded) return;
  plan.embedded = launch::EnterRunNetwork(plan.process.lcm_url, plan.process.run_id) ==
                  launch::ProcessNetwork::kNone;  // warned
}

Result<ConvQModel> TrainModelOnAgents(
    const ConvQTrainingOptions& options, const ModelTrainingAgents& plan,
    const std::atomic<bool>& stop, const std::function<void(const ConvQTrainingRound&)>& progress) {
  const runtime::ProcessSetup& process = plan.process;
  protocol::BusOptions bus_options = process.bus;
  std::unique_ptr<lcm::LCM> lcm;
  if (plan.embedded) {
    // One memq:// instance for the trainer and its agents: a second one in
    // this process would hear nothing.
    lcm = std::make_unique<lcm::LCM>("memq://");
    if (!lcm->good()) return Error::Unavailable("cannot open LCM memq://");
    bus_options.fragment_above = 0;
  } else {
    Result<std::unique_ptr<lcm::LCM>> opened = protocol::OpenLcm(process.lcm_url);
    if (!opened) return Error::Unavailable(opened.error().message);
    lcm = std::move(*opened);
  }
  protocol::Bus bus(*lcm, process.run_id, bus_options);
  coordinator::ConvQTrainerOptions trainer_options;
  trainer_options.min_agents = plan.agents;
  coordinator::ConvQTrainer trainer(bus, trainer_options);
  trainer.set_stop(&stop);
  const int threads_per_agent = ThreadsPerAgent(options.threads, plan.agents);
  std::optional<launch::EmbeddedAgents> threads;
  if (plan.embedded) {
    threads.emplace(*lcm, process.run_id, bus_options, plan.agents, threads_per_agent);
  }
  protocol::Dispatcher dispatcher(*lcm);
  trainer.Start();
  std::optional<launch::AgentProcesses> processes;
  if (plan.embedded) {
    threads->Start();
    spdlog::info("run {}: {} agents as threads over memq://", process.run_id, plan.agents);
  } else {
    launch::AgentLaunch launch;
    launch.process = process;
    launch.agents = plan.agents;
    launch.threads_per_agent = threads_per_agent;
    launch.log_level = "warn";
    processes.emplace(launch);
    if (!processes->Start()) {
      trainer.Finish();
      return Error::Unavailable("the agent processes could not be started");
    }
    spdlog::info("run {}: {} agent processes", process.run_id, plan.agents);
    if (!process.lcm_url.empty() && !plan.secret_given) {
      // The secret made here is known to this process's children only.
      spdlog::info(
          "processes started elsewhere cannot join this training: its secret is this process's "
          "own (to share one, make it with `dynapath secret PATH` and pass --secret-file PATH "
          "here and to them)");
    }
  }
  // The agent processes' watcher: one that exits is reported to the trainer
  // at once (its learners are reassigned then, not after its silence).
  std::atomic<bool> watching{processes.has_value()};
  std::thread watcher;
  if (processes) {
    watcher = std::thread([&] {
      while (watching.load() && !stop.load()) {
        const int running = processes->Check(
            [&](int agent, const std::string& how) { trainer.AgentExited(agent, how); });
        if (running == 0) {
          trainer.NoAgentProcessLeft();
          return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    });
  }
  Result<ConvQModel> model = TrainConvQFederated(
      options, [&](int round, const ConvQModel& m) { return trainer.Round(options, round, m); },
      progress);
  watching = false;  // the agents exit on the final heartbeat: no longer news
  if (watcher.joinable()) watcher.join();
  trainer.Finish();
  if (processes) processes->Stop();
  if (threads) threads->Stop();
  const coordinator::ConvQTrainerStats& stats = trainer.stats();
  std::string by_agent;
  for (const auto& [agent, shards] : stats.shards_by_agent) {
    by_agent += fmt::format("{}agent {}: {}", by_agent.empty() ? "" : ", ", agent, shards);
  }
  spdlog::info("{} rounds on agents: {} shards ({}), {} repeats, {} reassignments; messages: {}",
               stats.rounds, stats.shards, by_agent, stats.resends, stats.epochs,
               bus.TrafficSummary());
  return model;
}

}  // namespace dynapath::app
