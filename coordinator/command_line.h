#pragma once
// The options of dynapath-coordinator, declared once: its main parses them (command line
// and --config file), and the launcher (launch/launcher.cc) writes them as
// the config file it hands the process.

#include <optional>

#include "runtime/option_group.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"

namespace dynapath::coordinator {

struct CoordinatorCommandLine {
  runtime::ProcessOptions process;
  runtime::RunOptions run;
  long long agents = 1;
  runtime::WaitOptions wait;
  long long give_up = 60;
  runtime::LogOptions log;
};
void DeclareCoordinatorCommandLine(runtime::OptionGroup& group, CoordinatorCommandLine& options);

}  // namespace dynapath::coordinator
