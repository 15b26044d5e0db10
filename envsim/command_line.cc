#include "envsim/command_line.h"

namespace dynapath::envsim {

void DeclareEnvSimCommandLine(runtime::OptionGroup& group, EnvSimCommandLine& o) {
  runtime::DeclareProcessOptions(group, o.process, true);
  runtime::DeclareScenarioOptions(group, o.scenario);
  group.Option("--hz", o.hz, "RATE", "free-running: time steps per second (0: lock-step)");
  runtime::DeclareWaitOptions(group, o.wait);
  runtime::DeclareLogOptions(group, o.log);
}

}  // namespace dynapath::envsim
