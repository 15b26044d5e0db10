#pragma once
// The two distributed ways of `dynapath run`: envsim, coordinator and N
// agents as separate processes (in a private network namespace by default,
// or on the network of --lcm-url), or all of them as threads of this process
// over memq:// (--embedded).

#include <string>
#include <vector>

#include "tools/common/process_options.h"
#include "tools/common/run_driver.h"
#include "tools/common/scenario_options.h"

namespace dynapath::cli {

struct DistributedRun {
  ProcessSetup process;  // run id, LCM URL, fault injection
  int agents = 1;
  int threads_per_agent = 1;
  std::vector<std::string> envsim_args;       // scenario options to forward
  std::vector<std::string> coordinator_args;  // run options to forward
  std::string log_level = "info";
  std::string log_file;  // --log: record with lcm-logger
  bool private_network = true;
};

// Starts the processes, waits for the coordinator, stops every child on
// Ctrl-C or failure. Returns the exit code.
int LaunchProcesses(const DistributedRun& run);
// Runs all components as threads over memq://.
int RunEmbedded(const DistributedRun& run, const RunPlan& plan, const ScenarioSetup& scenario);

}  // namespace dynapath::cli
