#pragma once
// Options every process of a distributed run takes: the run id, the LCM URL,
// the run's secret and (tests only) fault injection.

#include <string>

#include "lcmtypes/protocol/bus.h"
#include "runtime/arg_parser.h"

namespace dynapath::runtime {

struct ProcessSetup {
  std::string run_id;
  std::string lcm_url;       // as given; "" means $LCM_DEFAULT_URL or LCM's default
  protocol::BusOptions bus;  // bus.key: the run's key
  // The secret's text, for the launcher to hand to its children; "" with
  // --insecure.
  std::string secret;
};

// A new random secret for a run the launcher starts (setup.secret, bus.key).
void MakeRunSecret(ProcessSetup& setup);

// `run_id_required`: processes need --run-id, and --secret-file or
// --insecure; the launcher makes a run id and a secret unless given.
void AddProcessOptions(ArgParser& parser, bool run_id_required);
const std::vector<std::string>& ProcessOptionNames();  // to forward
Result<ProcessSetup> ResolveProcessOptions(const ArgParser& parser, bool run_id_required);

// Logs of a process go to stderr, named after the process, in the project's
// format (stdout stays free for results).
void InitProcessLogging(const std::string& name);
// Prints "PROGRAM: MESSAGE" on stderr and returns `exit_code` (2: bad usage).
int ProcessError(const char* program, const std::string& message, int exit_code = 2);

// Common start of a process main: parse, --help, log level. Returns -1 to
// continue, else the exit code to return.
int ParseProcessArgs(ArgParser& parser, const std::vector<std::string>& args, const char* program);

}  // namespace dynapath::runtime
