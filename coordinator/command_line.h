#pragma once
// The options of dynapath-coordinator, declared once: its main parses them (command line
// and --config file), and the launcher (launch/launcher.cc) writes them as
// the config file it hands the process.

#include <optional>

#include "coordinator/coordinator.h"
#include "runtime/option_group.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"

namespace dynapath::coordinator {

// Defaults are CoordinatorOptions' (what an embedded run uses).
struct CoordinatorCommandLine {
  runtime::ProcessOptions process;
  runtime::RunOptions run;
  long long agents = CoordinatorOptions{}.min_agents;
  runtime::WaitOptions wait{CoordinatorOptions{}.agent_wait_seconds};
  long long give_up = static_cast<long long>(CoordinatorOptions{}.give_up_seconds);
  runtime::LogOptions log;
  long long out_lock_fd = -1;  // the launcher's lock on --out (runtime/output_lock.h)
};
void DeclareCoordinatorCommandLine(runtime::OptionGroup& group, CoordinatorCommandLine& options);

}  // namespace dynapath::coordinator
