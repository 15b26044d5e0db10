#pragma once
// The options of dynapath-agent, declared once: its main parses them (command line
// and --config file), and the launcher (launch/launcher.cc) writes them as
// the config file it hands the process.

#include <optional>

#include "agent/agent.h"
#include "runtime/option_group.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"

namespace dynapath::agent {

struct AgentCommandLine {
  runtime::ProcessOptions process;
  std::optional<long long> id;
  runtime::ThreadOptions threads;
  runtime::WaitOptions wait{AgentOptions{}.startup_timeout_seconds};  // an embedded agent's
  runtime::LogOptions log;
};
void DeclareAgentCommandLine(runtime::OptionGroup& group, AgentCommandLine& options);

}  // namespace dynapath::agent
