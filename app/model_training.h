#pragma once
// `dynapath train-model --learners K` on agents, below its command line:
// convQ's model trained federated on N agents (coordinator::ConvQTrainer
// plays the coordinator's part in this process), either dynapath-agent
// processes over LCM started as `run --agents` starts them
// (launch::AgentProcesses: the run's secret over a pipe), in a private
// network namespace of their own or on --lcm-url's network (where agents
// started elsewhere with the same run id and secret join too), or threads
// of this process over memq:// (--embedded, launch::EmbeddedAgents). The
// model is TrainConvQModel's with the same options, bit for bit.

#include <atomic>
#include <functional>

#include "dynapath/convq_training.h"
#include "dynapath/result.h"
#include "runtime/process_options.h"

namespace dynapath::app {

// What train-model was given for its agents.
struct ModelTrainingAgentOptions {
  int agents = 1;                   // --agents N (1 with --embedded alone)
  bool embedded = false;            // --embedded
  runtime::ProcessOptions process;  // --run-id, --lcm-url, --secret-file, --insecure
};

// Them, checked (PlanModelTrainingAgents).
struct ModelTrainingAgents {
  int agents = 1;
  bool embedded = false;
  runtime::ProcessSetup process;  // run id, LCM URL, secret
  bool secret_given = false;      // --secret-file or --insecure: others can join
};

// Checks the options once, before any work: an error names its option
// (Error::subject) and says what is wrong. --lcm-url with --embedded and
// agent processes on memq:// are refused.
Result<ModelTrainingAgents> PlanModelTrainingAgents(const ModelTrainingAgentOptions& options);

// For agent processes: without an LCM URL (--lcm-url, $LCM_DEFAULT_URL)
// moves this process into a new private network namespace (it must still
// be single-threaded; children inherit it). Where namespaces are not
// permitted the agents become threads over memq:// (`run` does the same),
// with a warning. Nothing to do for embedded agents.
void EnterModelTrainingNetwork(ModelTrainingAgents& plan);

// Trains on the agents (options.learners > 0), options.threads shared out
// between them; `progress` after every round. Agent processes this process
// started that exit are seen at once (their exit status or signal logged)
// and their learners reassigned; with none left, and no agent started
// elsewhere live, the training fails at once. Errors: kCancelled once
// `stop` is set, kUnavailable when the agents cannot be started, none
// appears, or a round makes no progress (the reason said).
Result<ConvQModel> TrainModelOnAgents(
    const ConvQTrainingOptions& options, const ModelTrainingAgents& plan,
    const std::atomic<bool>& stop, const std::function<void(const ConvQTrainingRound&)>& progress);

}  // namespace dynapath::app
