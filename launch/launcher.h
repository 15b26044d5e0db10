#pragma once
// The two distributed ways of `dynapath run`: envsim, coordinator and N
// agents as separate processes (in a private network namespace by default,
// or on the network of --lcm-url), or all of them as threads of this process
// over memq:// (--embedded).

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "dynapath/result.h"
#include "protocol/bus.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"

namespace dynapath::agent {
class Agent;
}

namespace dynapath::launch {

// One time step of one approach, as the coordinator reports it.
struct StepReport {
  std::string approach;
  int pass = 0;  // the approach's index in the run
  int time_step = 0;
  int total_steps = 0;
};

struct DistributedRun {
  runtime::ProcessSetup process;  // run id, LCM URL, fault injection
  int agents = 1;
  int threads_per_agent = 1;
  runtime::ScenarioOptions scenario;  // envsim's
  runtime::RunOptions run;            // the coordinator's
  std::string log_level = runtime::LogOptions{}.log_level;
  std::string log_file;  // --log: record with lcm-logger
  bool private_network = true;
  // Optional: called with the coordinator's step reports (its REPORT
  // channel), on another thread; the launcher listens when this is set.
  std::function<void(const StepReport&)> on_step;
  // When >= 0, the descriptor of the lock on run.out the caller holds
  // (runtime::OutputLock): the coordinator inherits and adopts it. Otherwise
  // the coordinator locks run.out itself.
  int out_lock_fd = -1;
  // When the coordinator process is killed (a signal: SIGKILL, the OOM
  // killer, a crash) and run.run.checkpoint is set: stop the run's other
  // processes and start them all again from the last checkpoint
  // (--resume-checkpoint), at most this many times.
  int coordinator_restarts = 0;
  // When >= 0, the children's stderr goes to this descriptor (a log file)
  // instead of the launcher's.
  int child_stderr = -1;
};

// Where the processes of an --agents run talk. kHost: on the network that
// `lcm_url` or $LCM_DEFAULT_URL names. kPrivate: in a private network
// namespace this process has just entered (it must still be single-threaded;
// children inherit it). kNone: namespaces are not permitted here (a warning
// is logged): run embedded (memq://) instead.
enum class ProcessNetwork { kHost, kPrivate, kNone };
ProcessNetwork EnterProcessNetwork(const std::string& lcm_url);
// EnterProcessNetwork for run `run_id`'s processes, logging a private
// network with how to watch it (dynapath-spy --pid).
ProcessNetwork EnterRunNetwork(const std::string& lcm_url, const std::string& run_id);

// A pipe holding `text` (at most 60,000 bytes), its read end returned
// (close-on-exec) and its write end closed: a process reads it once through
// /dev/fd/N. The run's secret and each child's options (a CLI11 config
// file) go this way: unlike an argument the secret is not in
// /proc/PID/cmdline, unlike the environment it is not inherited, unlike a
// file it leaves nothing on disk. -1 on failure (errno set).
int TextPipe(const std::string& text);

// A child process the launcher started.
struct ChildProcess {
  std::string name;
  pid_t pid = -1;
  bool running = true;
  int status = 0;  // waitpid's, once it has exited
  int agent_id = 0;  // an agent's --id; 0 for the other processes
};

// Agent processes for a process that plays the coordinator's part itself
// (dynapath serve --agents N: coordinator::TrainingSession), started as
// LaunchProcesses starts a run's agents: ids 1..N, the run id, secret (over
// a pipe) and LCM URL of `process`.
struct AgentLaunch {
  runtime::ProcessSetup process;
  int agents = 1;
  int threads_per_agent = 1;
  std::string log_level = runtime::LogOptions{}.log_level;
  int child_stderr = -1;  // -1: this process's stderr
};

class AgentProcesses {
 public:
  explicit AgentProcesses(AgentLaunch launch);
  ~AgentProcesses();  // Stop(), if not done
  AgentProcesses(const AgentProcesses&) = delete;
  AgentProcesses& operator=(const AgentProcesses&) = delete;

  // Starts them; false (logged) when one could not be started (those
  // started are stopped again).
  bool Start();
  // Notes agents that exited (each once: logged, or with `on_exit` given
  // handed to it instead with the agent's id and how it ended, "was killed
  // by signal 9") and returns how many are still running.
  int Check(const std::function<void(int agent_id, const std::string& how)>& on_exit = {});
  // SIGTERM to those still running, SIGKILL after `grace`; all reaped.
  void Stop(std::chrono::milliseconds grace = std::chrono::milliseconds(500));

 private:
  AgentLaunch launch_;
  std::vector<ChildProcess> children_;
};

// N agents as threads of this process on `lcm` (memq://), as an embedded
// run has them, for a process that plays the coordinator's part itself
// (dynapath serve --embedded).
class EmbeddedAgents {
 public:
  // Subscribes their buses on `lcm`: construct before it is dispatched.
  EmbeddedAgents(lcm::LCM& lcm, const std::string& run_id, const protocol::BusOptions& bus,
                 int agents, int threads_per_agent);
  ~EmbeddedAgents();  // Stop()
  EmbeddedAgents(const EmbeddedAgents&) = delete;
  EmbeddedAgents& operator=(const EmbeddedAgents&) = delete;

  void Start();  // one thread per agent
  // Stops the agents (they also end on the coordinator's final heartbeat)
  // and joins their threads.
  void Stop();

 private:
  std::vector<std::unique_ptr<protocol::Bus>> buses_;
  std::vector<std::unique_ptr<agent::Agent>> agents_;
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
};

// A run's outcome (LaunchProcesses, RunEmbedded): Ok when it ran to its end;
// Error::Cancelled() when stopped (Ctrl-C, SIGTERM; exit status 130);
// otherwise "exit status N" (what went wrong was logged), kInvalidArgument
// for N = 2 (options a component refused), else kUnavailable.
Status OutcomeOfExit(int exit_status);

// Starts the processes, waits for the coordinator, stops every child on
// Ctrl-C or failure. With a log file, lcm-logger must be recording before
// the run starts, and a logger that dies during the run stops it (exit
// status 1, saying how much was recorded).
Status LaunchProcesses(const DistributedRun& run);
// Runs all components as threads over memq://, stopped by Ctrl-C or
// SIGTERM (protocol::StopOnSignals).
Status RunEmbedded(const DistributedRun& run, const runtime::RunPlan& plan,
                   const runtime::ScenarioSetup& scenario);
// The same, stopped when `stop` is set (a caller with signal handling of its
// own: the Python module); no signal handler is installed.
Status RunEmbedded(const DistributedRun& run, const runtime::RunPlan& plan,
                   const runtime::ScenarioSetup& scenario, const std::atomic<bool>& stop);

}  // namespace dynapath::launch
