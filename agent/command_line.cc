#include "agent/command_line.h"

namespace dynapath::agent {

void DeclareAgentCommandLine(runtime::OptionGroup& group, AgentCommandLine& o) {
  runtime::DeclareProcessOptions(group, o.process, true);
  group.Option("--id", o.id, "N", "agent id, unique within the run", "random");
  runtime::DeclareThreadOptions(group, o.threads);
  runtime::DeclareWaitOptions(group, o.wait);
  runtime::DeclareLogOptions(group, o.log);
}

}  // namespace dynapath::agent
