#pragma once
// Options every process of a distributed run takes: the run id, the LCM URL,
// the run's secret and (tests only) fault injection.

#include <functional>
#include <optional>
#include <string>

#include "protocol/bus.h"
#include "protocol/limits.h"
#include "runtime/option_group.h"
#include "runtime/scenario_options.h"

namespace dynapath::runtime {

struct ProcessSetup {
  std::string run_id;
  std::string lcm_url;       // as given; "" means $LCM_DEFAULT_URL or LCM's default
  protocol::BusOptions bus;  // bus.key: the run's key
  // The secret's text, for the launcher to hand to its children; "" with
  // --insecure.
  std::string secret;
  // --fragment-size as given (the launcher hands it on); bus.fragment_size
  // holds the size in force.
  std::optional<long long> fragment_size;
};

// A new random secret for a run the launcher starts (setup.secret, bus.key).
void MakeRunSecret(ProcessSetup& setup);

// The options of every process of a run, as given.
struct ProcessOptions {
  std::optional<std::string> run_id, secret_file;
  std::string lcm_url;
  bool insecure = false;
  long long grid_cells = protocol::kMaxGridCells;
  std::optional<long long> fragment_size;  // unset: by the URL (DefaultFragmentSize)
  double fault_drop = 0.0, fault_dup = 0.0;
};
// --lcm-url alone (dynapath view).
void DeclareLcmUrlOption(OptionGroup& group, std::string& lcm_url);
// `run_id_required`: processes need --run-id, and --secret-file or
// --insecure; the launcher makes a run id and a secret unless given.
void DeclareProcessOptions(OptionGroup& group, ProcessOptions& options, bool run_id_required);
// The first four of them, which say which run on which network: --run-id,
// --lcm-url, --secret-file, --insecure (train-model: its agents' run).
void DeclareRunNetworkOptions(OptionGroup& group, ProcessOptions& options, bool run_id_required);
Result<ProcessSetup> ResolveProcessOptions(const ProcessOptions& options, bool run_id_required);
// The options of a child process that joins the run `setup` (for the
// launcher to hand on): run id, LCM URL, grid cells, fault injection; the
// secret goes separately.
ProcessOptions ChildProcessOptions(const ProcessSetup& setup);

// --threads: worker threads, the machine's hardware threads unless given.
inline constexpr long long kMaxThreads = 1024;
inline constexpr long long kMaxAgents = 256;  // of one `run` or study configuration
struct ThreadOptions {
  std::optional<long long> threads;
};
void DeclareThreadOptions(OptionGroup& group, ThreadOptions& options);
Result<int> ResolveThreads(const ThreadOptions& options);

// How a run (or each run of a study) executes: --local, --agents N,
// --embedded (which may come with --agents N).
struct ModeOptions {
  bool local = false;
  std::optional<long long> agents;
  bool embedded = false;
};
void DeclareModeOptions(OptionGroup& group, ModeOptions& options);
struct RunMode {
  enum Kind { kLocal, kAgents, kEmbedded };
  Kind kind = kLocal;
  int agents = 1;
};
Result<RunMode> ResolveMode(const ModeOptions& options, long long max_agents);

// --wait: how long a process waits for the others of its run to appear.
// Its default is the process library's own (CoordinatorOptions,
// AgentOptions, EnvSimOptions: what an embedded run uses), handed in by
// each process's command line, so the two cannot differ.
struct WaitOptions {
  explicit WaitOptions(double default_seconds) : wait(static_cast<long long>(default_seconds)) {}
  long long wait;
};
void DeclareWaitOptions(OptionGroup& group, WaitOptions& options);
Result<double> ResolveWaitSeconds(const WaitOptions& options);

// Logs of a process go to stderr, named after the process, in the project's
// format (stdout stays free for results).
void InitProcessLogging(const std::string& name);
// Prints "PROGRAM: MESSAGE" on stderr and returns `exit_code` (2: bad usage).
int ProcessError(const char* program, const std::string& message, int exit_code = 2);

// Common start of a process main: an app described by DESCRIPTION, whose
// options DECLARE puts on the group; parses a --config file and the command
// line, --help, log level. Returns -1 to continue, else the exit code to
// return. The app is made here so that a process main need not include
// CLI11, whose compilation is most of such a file's (seconds per file, more
// under the sanitizers).
int ParseProcessCommandLine(const char* program, const std::string& description,
                            const std::function<void(OptionGroup&)>& declare, const LogOptions& log,
                            int argc, char** argv);

}  // namespace dynapath::runtime
