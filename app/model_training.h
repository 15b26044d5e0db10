#pragma once
// `dynapath train-model --learners K --agents N` below its command line:
// convQ's model trained federated on N dynapath-agent processes over LCM
// (coordinator::ConvQTrainer), the agents started as `run --agents` starts
// them (launch::AgentProcesses: the run's secret over a pipe), in a private
// network namespace: the processes of the training and nothing else are on
// it. The model is TrainConvQModel's with the same options, bit for bit.

#include <atomic>
#include <functional>

#include "dynapath/convq_training.h"
#include "dynapath/result.h"

namespace dynapath::app {

// Moves this process into a new private network namespace (it must still
// be single-threaded; launch::EnterPrivateNetwork). Call before
// TrainModelOnAgentProcesses.
Status EnterModelTrainingNetwork();

// Trains on `agents` agent processes (options.learners > 0), each with
// options.threads / agents threads; `progress` after every round. Errors:
// kCancelled once `stop` is set, kUnavailable when the agents cannot be
// started, none appears, or a round makes no progress (the reason said).
Result<ConvQModel> TrainModelOnAgentProcesses(
    const ConvQTrainingOptions& options, int agents, const std::atomic<bool>& stop,
    const std::function<void(const ConvQTrainingRound&)>& progress);

}  // namespace dynapath::app
