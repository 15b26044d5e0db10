#include "app/model_training.h"

#include <spdlog/spdlog.h>

#include <memory>

#include "app/resources.h"
#include "coordinator/convq_trainer.h"
#include "launch/launcher.h"
#include "launch/private_network.h"
#include "protocol/dispatcher.h"
#include "runtime/process_options.h"

namespace dynapath::app {

Status EnterModelTrainingNetwork() { return launch::EnterPrivateNetwork(); }

Result<ConvQModel> TrainModelOnAgentProcesses(
    const ConvQTrainingOptions& options, int agents, const std::atomic<bool>& stop,
    const std::function<void(const ConvQTrainingRound&)>& progress) {
  Result<runtime::ProcessSetup> setup =
      runtime::ResolveProcessOptions(runtime::ProcessOptions{}, false);
  if (!setup) return setup.error();
  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(setup->lcm_url);
  if (!lcm) return Error::Unavailable(lcm.error().message);
  protocol::Bus bus(**lcm, setup->run_id, setup->bus);
  coordinator::ConvQTrainerOptions trainer_options;
  trainer_options.min_agents = agents;
  coordinator::ConvQTrainer trainer(bus, trainer_options);
  trainer.set_stop(&stop);
  protocol::Dispatcher dispatcher(**lcm);
  trainer.Start();
  launch::AgentLaunch launch;
  launch.process = *setup;
  launch.agents = agents;
  launch.threads_per_agent = ThreadsPerAgent(options.threads, agents);
  launch.log_level = "warn";
  launch::AgentProcesses processes(launch);
  if (!processes.Start()) {
    trainer.Finish();
    return Error::Unavailable("the agent processes could not be started");
  }
  spdlog::info("run {}: {} agent processes in a private network", setup->run_id, agents);
  Result<ConvQModel> model = TrainConvQFederated(
      options,
      [&](int round, const ConvQModel& m) {
        processes.Check();  // an agent that exited is logged; its learners are reassigned
        return trainer.Round(options, round, m);
      },
      progress);
  trainer.Finish();
  processes.Stop();
  const coordinator::ConvQTrainerStats& stats = trainer.stats();
  spdlog::info("{} rounds on agents: {} shards, {} repeats, {} reassignments; messages: {}",
               stats.rounds, stats.shards, stats.resends, stats.epochs, bus.TrafficSummary());
  return model;
}

}  // namespace dynapath::app
