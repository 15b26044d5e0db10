#pragma once
// The options of dynapath-envsim, declared once: its main parses them (command line
// and --config file), and the launcher (launch/launcher.cc) writes them as
// the config file it hands the process.

#include <optional>

#include "envsim/envsim.h"
#include "runtime/option_group.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"

namespace dynapath::envsim {

struct EnvSimCommandLine {
  runtime::ProcessOptions process;
  runtime::ScenarioOptions scenario;
  // Defaults are EnvSimOptions' (what an embedded run uses).
  double hz = EnvSimOptions{}.hz;
  runtime::WaitOptions wait{EnvSimOptions{}.startup_timeout_seconds};
  runtime::LogOptions log;
};
void DeclareEnvSimCommandLine(runtime::OptionGroup& group, EnvSimCommandLine& options);

}  // namespace dynapath::envsim
