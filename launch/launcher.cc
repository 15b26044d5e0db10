#include "launch/launcher.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <optional>
#include <thread>

#include "agent/agent.h"
#include "agent/command_line.h"
#include "coordinator/command_line.h"
#include "coordinator/coordinator.h"
#include "dynapath/step_report_t.hpp"
#include "envsim/command_line.h"
#include "envsim/envsim.h"
#include "launch/logger_drain.h"
#include "launch/private_network.h"
#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "protocol/log_reader.h"
#include "runtime/checkpoint_file.h"

namespace dynapath::launch {
namespace {

namespace fs = std::filesystem;

// The process binaries: next to this one (installed), or in the build tree
// (build/tools/dynapath -> build/<name>/dynapath-<name>), or $DYNAPATH_BIN_DIR.
std::string FindBinary(const std::string& name) {
  const std::string file = "dynapath-" + name;
  if (const char* dir = std::getenv("DYNAPATH_BIN_DIR"); dir != nullptr && *dir != '\0') {
    return (fs::path(dir) / file).string();
  }
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    for (const fs::path& candidate :
         {self.parent_path() / file, self.parent_path().parent_path() / name / file}) {
      if (fs::exists(candidate, error)) return candidate.string();
    }
  }
  return file;  // from PATH
}

using Child = ChildProcess;

// The child that records the run's messages (--log).
constexpr const char* kRecorder = "recorder";

// Starts `argv`. `keep_fds`: TextPipes the child keeps open across exec
// (argv or its config names them as /dev/fd/N).
// `stdout_fd` (>= 0): its stdout too.
pid_t Spawn(const std::vector<std::string>& argv, int stderr_fd,
            const std::vector<int>& keep_fds = {}, int stdout_fd = -1) {
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid != 0) return pid;
  // Child: die with the launcher, whatever kills it.
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) _exit(1);
  if (stderr_fd >= 0 && dup2(stderr_fd, STDERR_FILENO) < 0) _exit(126);
  if (stdout_fd >= 0 && dup2(stdout_fd, STDOUT_FILENO) < 0) _exit(126);
  for (int fd : keep_fds) {
    if (fcntl(fd, F_SETFD, 0) != 0) _exit(126);
  }
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  execvp(args[0], args.data());
  std::fprintf(stderr, "dynapath: cannot start %s: %s\n", argv[0].c_str(), std::strerror(errno));
  _exit(127);
}

// After the coordinator failed: whether its restarts are spent and how to
// finish the run when a checkpoint exists (else nothing to resume from).
std::string ResumeHint(int status, const DistributedRun& run, int restarts) {
  const std::string& dir = run.run.checkpoint;
  if (dir.empty()) return "";
  std::string hint;
  if (WIFSIGNALED(status)) {
    hint = restarts == 0 && run.coordinator_restarts == 0
               ? "; no restarts (--restart-coordinator 0)"
               : "; its restarts are spent (--restart-coordinator " +
                     std::to_string(run.coordinator_restarts) + ")";
  }
  std::error_code error;
  if (!std::filesystem::exists(dir + "/" + runtime::kCheckpointFileName, error)) {
    return hint + "; " + dir + " holds no checkpoint yet";
  }
  return hint + "; finish the run from its last checkpoint with: dynapath run --resume " + dir;
}

// What every child of a run is started with.
struct ChildStart {
  const runtime::ProcessSetup& process;
  const std::string& log_level;
  int child_stderr;  // -1: the launcher's stderr
};

// Starts a child with its options as one config file: `options` is its
// command-line struct, written by the same declaration its main parses
// with. With a secret, the run's secret goes over a pipe of its own
// (--secret-file /dev/fd/N), or --insecure when the run has none.
// `visible`: more arguments besides --config.
// `inherit`: descriptors (close-on-exec here) the child keeps, not closed.
// Appends it to `children`; false (logged) when it could not be started.
template <class Options, class Declare>
bool StartChild(const ChildStart& run, std::vector<Child>& children, const std::string& name,
                const std::string& binary, Options& options, Declare declare,
                std::vector<std::string> visible, std::vector<int> inherit) {
  std::vector<int> fds;
  auto close_fds = [&] {
    for (int fd : fds) close(fd);
  };
  options.process = runtime::ChildProcessOptions(run.process);
  options.log.log_level = run.log_level;
  if (run.process.secret.empty()) {
    options.process.insecure = true;
  } else {
    const int secret_fd = TextPipe(run.process.secret + "\n");
    if (secret_fd < 0) {
      spdlog::error("cannot hand the run's secret to {}: {}", name, std::strerror(errno));
      return false;
    }
    fds.push_back(secret_fd);
    options.process.secret_file = "/dev/fd/" + std::to_string(secret_fd);
  }
  runtime::ConfigWriter writer;
  runtime::OptionGroup group(writer);
  declare(group, options);
  if (Status status = writer.status(); !status) {
    spdlog::error("cannot hand {} its options: {}", name, status.error().message);
    close_fds();
    return false;
  }
  const int config_fd = TextPipe(writer.Text());
  if (config_fd < 0) {
    spdlog::error("cannot hand {} its options: {}", name, std::strerror(errno));
    close_fds();
    return false;
  }
  fds.push_back(config_fd);
  std::vector<std::string> argv = {binary, "--config", "/dev/fd/" + std::to_string(config_fd)};
  // The config is complete; the run id, how the secret arrives and an
  // agent's id are repeated as arguments so that ps and pgrep tell a run's
  // processes apart and show that the secret came over a pipe (the tests
  // find processes this way).
  argv.insert(argv.end(), {"--run-id", run.process.run_id});
  if (options.process.secret_file) {
    argv.insert(argv.end(), {"--secret-file", *options.process.secret_file});
  } else {
    argv.push_back("--insecure");
  }
  argv.insert(argv.end(), visible.begin(), visible.end());
  std::vector<int> kept = fds;
  kept.insert(kept.end(), inherit.begin(), inherit.end());
  const pid_t pid = Spawn(argv, run.child_stderr, kept);
  close_fds();
  if (pid < 0) return false;
  children.push_back(Child{name, pid});
  return true;
}

// Starts agent `id` of a run with `threads` threads.
bool StartAgent(const ChildStart& run, std::vector<Child>& children, int id, int threads) {
  agent::AgentCommandLine options;
  options.threads.threads = threads;
  if (!StartChild(run, children, "agent " + std::to_string(id), FindBinary("agent"), options,
                  agent::DeclareAgentCommandLine, {"--id", std::to_string(id)}, {})) {
    return false;
  }
  children.back().agent_id = id;
  return true;
}

std::string Describe(int status) {
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "was killed by signal " + std::to_string(WTERMSIG(status));
  return "stopped";
}

bool Succeeded(int status) { return WIFEXITED(status) && WEXITSTATUS(status) == 0; }

// Reaps exited children; returns false when none is left running.
void Reap(std::vector<Child>& children) {
  int status = 0;
  pid_t pid;
  while ((pid = waitpid(-1, &status, WNOHANG)) > 0) {
    for (Child& child : children) {
      if (child.pid == pid && child.running) {
        child.running = false;
        child.status = status;
      }
    }
  }
}

// SIGTERM (the recorder then writes what it holds and closes its file),
// then SIGKILL after `grace`.
void StopAll(std::vector<Child>& children, std::chrono::milliseconds grace) {
  for (Child& child : children) {
    if (child.running) kill(child.pid, SIGTERM);
  }
  const auto deadline = std::chrono::steady_clock::now() + grace;
  while (std::chrono::steady_clock::now() < deadline) {
    Reap(children);
    bool any = false;
    for (const Child& child : children) any = any || child.running;
    if (!any) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  for (Child& child : children) {
    if (child.running) {
      spdlog::warn("{} did not stop; killing it", child.name);
      kill(child.pid, SIGKILL);
    }
  }
  for (Child& child : children) {
    if (child.running) {
      waitpid(child.pid, &child.status, 0);
      child.running = false;
    }
  }
}

protocol::BusOptions BusOptionsWithKey(const protocol::RunKey& key) {
  protocol::BusOptions options;
  options.key = key;
  return options;
}

// Passes the coordinator's step reports of a run to a callback.
class ReportListener {
 public:
  ReportListener(lcm::LCM& lcm, const std::string& run_id, const protocol::RunKey& key,
                 std::function<void(const StepReport&)> on_step)
      : bus_(lcm, run_id, BusOptionsWithKey(key)) {
    bus_.Subscribe<step_report_t>(
        protocol::channel::kReport, [on_step = std::move(on_step)](step_report_t& report) {
          on_step(StepReport{report.approach, report.pass, report.time_step, report.total_steps});
        });
  }

 private:
  protocol::Bus bus_;
};

// "12 messages, 3456 bytes" of an LCM log (what can be read of it).
std::string RecordedSoFar(const std::string& path) {
  Result<protocol::LogReader> reader = protocol::LogReader::Open(path);
  if (!reader) return reader.error().message;
  long long events = 0;
  while (true) {
    Result<std::optional<protocol::LogEvent>> event = reader->Next();
    if (!event || !*event) break;
    ++events;
  }
  return std::to_string(events) + " messages, " + std::to_string(reader->size()) + " bytes";
}

}  // namespace

int TextPipe(const std::string& text) {
  // A pipe holds 64 KiB before a write blocks; options are a few hundred bytes.
  if (text.size() > 60000) {
    errno = E2BIG;
    return -1;
  }
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) return -1;
  const bool written = write(fds[1], text.data(), text.size()) == static_cast<ssize_t>(text.size());
  close(fds[1]);
  if (!written) {
    close(fds[0]);
    return -1;
  }
  return fds[0];
}

ProcessNetwork EnterProcessNetwork(const std::string& lcm_url) {
  if (!lcm_url.empty() || std::getenv("LCM_DEFAULT_URL") != nullptr) return ProcessNetwork::kHost;
  if (Status status = EnterPrivateNetwork(); !status) {
    spdlog::warn("{}; running embedded (memq://) instead", status.error().message);
    return ProcessNetwork::kNone;
  }
  return ProcessNetwork::kPrivate;
}

ProcessNetwork EnterRunNetwork(const std::string& lcm_url, const std::string& run_id) {
  const ProcessNetwork network = EnterProcessNetwork(lcm_url);
  if (network == ProcessNetwork::kPrivate) {
    spdlog::info("run {} in a private network; watch it with: dynapath-spy --pid {}", run_id,
                 getpid());
  }
  return network;
}

Status OutcomeOfExit(int exit_status) {
  if (exit_status == 0) return Ok{};
  if (exit_status == 130) return Error::Cancelled();
  return Error("exit status " + std::to_string(exit_status),
               exit_status == 2 ? Error::Code::kInvalidArgument : Error::Code::kUnavailable);
}

namespace {

// The processes' run, by exit status (LaunchProcesses).
int LaunchProcessesExit(const DistributedRun& run) {
  {
    // A value a config file cannot carry fails the run before anything starts.
    runtime::ConfigWriter check;
    runtime::OptionGroup group(check);
    runtime::ProcessOptions process = runtime::ChildProcessOptions(run.process);
    runtime::ScenarioOptions scenario = run.scenario;
    runtime::RunOptions plan = run.run;
    runtime::DeclareProcessOptions(group, process, true);
    runtime::DeclareScenarioOptions(group, scenario);
    runtime::DeclareRunOptions(group, plan);
    if (Status status = check.status(); !status) {
      spdlog::error("cannot start the run's processes: {}", status.error().message);
      return 1;
    }
  }
  const std::atomic<bool>& stop = protocol::StopOnSignals();
  // Listen to the run's reports before its processes start.
  std::unique_ptr<lcm::LCM> report_lcm;
  std::optional<ReportListener> listener;
  std::optional<protocol::Dispatcher> report_dispatcher;
  if (run.on_step) {
    Result<std::unique_ptr<lcm::LCM>> opened = protocol::OpenLcm(run.process.lcm_url);
    if (opened) {
      report_lcm = std::move(*opened);
      listener.emplace(*report_lcm, run.process.run_id, run.process.bus.key, run.on_step);
      report_dispatcher.emplace(*report_lcm);
    } else {
      spdlog::warn("no progress reports: {}", opened.error().message);
    }
  }
  std::vector<Child> children;
  const ChildStart child_start{run.process, run.log_level, run.child_stderr};
  auto start = [&](const std::string& name, const std::string& binary, auto& options, auto declare,
                   std::vector<std::string> visible = {}, std::vector<int> inherit = {}) {
    return StartChild(child_start, children, name, binary, options, declare, std::move(visible),
                      std::move(inherit));
  };
  if (!run.log_file.empty()) {
    // It records the bytes as sent, tags included; its own lines are
    // warnings and errors only.
    const std::string url = protocol::ResolveLcmUrl(run.process.lcm_url);
    const pid_t pid = Spawn({FindBinary("recorder"), "--lcm-url=" + url,
                             "--channel=DYNAPATH/" + run.process.run_id + "/.*",
                             "--file=" + run.log_file, "--force", "--log-level=warn"},
                            run.child_stderr);
    if (pid >= 0) children.push_back(Child{kRecorder, pid});
    // The run starts once the recorder listens, or its first messages (the
    // maze, step 0) could go unrecorded on a loaded machine. Where /proc
    // cannot tell, a moment's grace.
    const std::optional<int> port = UdpmPort(url);
    bool subscribed = true;
    if (pid >= 0 && port && HasUdpSocketOnPort(pid, *port).has_value()) {
      const auto asked = std::chrono::steady_clock::now();
      subscribed = WaitForLoggerToSubscribe(pid, *port, std::chrono::seconds(30));
      spdlog::debug("the recorder {} after {} ms", subscribed ? "listening" : "not listening",
                    std::chrono::duration_cast<std::chrono::milliseconds>(
                        std::chrono::steady_clock::now() - asked)
                        .count());
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
    // The log was asked for: a recorder that could not start (not
    // installed, the file not writable) fails the run before anything runs.
    Reap(children);
    if (pid < 0 || !children.back().running) {
      spdlog::error(
          "the recorder (dynapath-recorder) {}; nothing recorded in {}: stopping the run",
          pid < 0 ? std::string("could not be started") : Describe(children.back().status),
          run.log_file);
      return 1;
    }
    if (!subscribed) {
      spdlog::warn(
          "the recorder has not subscribed after 30 s; the run starts, and {} may miss "
          "its first messages",
          run.log_file);
    }
  }
  // The run's own processes (not the recorder), started again on a restart.
  auto start_run_processes = [&](bool resume) {
    coordinator::CoordinatorCommandLine coordinator_options;
    coordinator_options.run = run.run;
    coordinator_options.run.resume_checkpoint = run.run.resume_checkpoint || resume;
    coordinator_options.agents = run.agents;
    coordinator_options.out_lock_fd = run.out_lock_fd;
    std::vector<int> coordinator_fds;
    if (run.out_lock_fd >= 0) coordinator_fds.push_back(run.out_lock_fd);
    bool started = start("coordinator", FindBinary("coordinator"), coordinator_options,
                         coordinator::DeclareCoordinatorCommandLine, {}, coordinator_fds);
    envsim::EnvSimCommandLine envsim_options;
    envsim_options.scenario = run.scenario;
    started = started && start("envsim", FindBinary("envsim"), envsim_options,
                               envsim::DeclareEnvSimCommandLine);
    for (int i = 1; i <= run.agents && started; ++i) {
      started = StartAgent(child_start, children, i, run.threads_per_agent);
    }
    return started;
  };
  if (!start_run_processes(
          false)) {  // the run cannot go on without one of them: stop the others now
    StopAll(children, std::chrono::milliseconds(3000));
    return 1;
  }
  int restarts = 0;
  // After the coordinator was killed: the others stopped and forgotten, and
  // all of them started again from the checkpoint. False when that failed.
  auto restart = [&](const Child& coordinator) {
    ++restarts;
    spdlog::warn(
        "the coordinator {}; starting the run's processes again from the last checkpoint in {} "
        "(restart {} of at most {})",
        Describe(coordinator.status), run.run.checkpoint, restarts, run.coordinator_restarts);
    std::vector<Child> kept, stopped;
    for (Child& child : children) (child.name == kRecorder ? kept : stopped).push_back(child);
    StopAll(stopped, std::chrono::milliseconds(3000));
    children = std::move(kept);
    if (start_run_processes(true)) return true;
    StopAll(children, std::chrono::milliseconds(3000));
    return false;
  };

  int exit_code = 0;
  std::vector<bool> reported(children.size(), false);
  while (true) {
    Reap(children);
    if (stop) {
      spdlog::warn("interrupted: stopping the run");
      StopAll(children, std::chrono::milliseconds(5000));
      return 130;
    }
    bool finished = false;
    for (size_t i = 0; i < children.size(); ++i) {
      Child& child = children[i];
      if (child.running || reported[i]) continue;
      reported[i] = true;
      if (child.name == "coordinator") {
        if (WIFSIGNALED(child.status) && !run.run.checkpoint.empty() &&
            restarts < run.coordinator_restarts && !stop) {
          const Child killed = child;
          if (!restart(killed)) return 1;
          reported.assign(children.size(), false);
          break;  // the children changed: look again
        }
        finished = true;
        if (!Succeeded(child.status)) {
          spdlog::error("the coordinator {}{}", Describe(child.status),
                        ResumeHint(child.status, run, restarts));
          exit_code = 1;
        }
      } else if (child.name == "envsim") {
        if (!Succeeded(child.status)) {
          spdlog::error("envsim {}; stopping the run", Describe(child.status));
          exit_code = 1;
          finished = true;
        }
      } else if (child.name == kRecorder) {
        // The log was asked for: a run without its record is a failed run.
        spdlog::error(
            "the recorder {} during the run; {} holds only what it recorded until then "
            "({}); stopping the run",
            Describe(child.status), run.log_file, RecordedSoFar(run.log_file));
        StopAll(children, std::chrono::milliseconds(5000));
        return 1;
      } else if (!Succeeded(child.status)) {
        // Agents are replaceable: the coordinator reassigns their work.
        spdlog::warn("{} {}; the run goes on without it", child.name, Describe(child.status));
      }
    }
    if (finished) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  // The others exit by themselves once they hear the coordinator's final
  // heartbeat; give them a moment, then stop whatever is left. A failed
  // run's coordinator may have sent none (killed): stop them at once.
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(exit_code == 0 ? 3000 : 0);
  while (std::chrono::steady_clock::now() < deadline) {
    Reap(children);
    bool any = false;
    for (const Child& child : children) any = any || (child.running && child.name != kRecorder);
    if (!any) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // The run's processes first: once they are gone, all they sent is on the
  // recorder's socket or in its hands. It is stopped when its sockets are
  // empty and its file has stopped growing, and then writes whatever LCM
  // still holds for it (at most 10 s) before it exits.
  std::vector<Child> recorder, others;
  for (Child& child : children) (child.name == kRecorder ? recorder : others).push_back(child);
  StopAll(others, std::chrono::milliseconds(3000));
  for (const Child& child : recorder) {
    if (child.running &&
        !WaitForLoggerToDrain(child.pid, run.log_file, std::chrono::milliseconds(300),
                              std::chrono::milliseconds(5000))) {
      spdlog::warn("the recorder is still busy after 5 s; its last messages may be missing from {}",
                   run.log_file);
    }
  }
  StopAll(recorder, std::chrono::milliseconds(15000));
  for (const Child& child : recorder) {
    if (!Succeeded(child.status)) {
      spdlog::error("the recorder {} while writing its last messages; {} holds {}",
                    Describe(child.status), run.log_file, RecordedSoFar(run.log_file));
      return 1;
    }
    spdlog::info("recorded the run's messages in {} ({})", run.log_file,
                 RecordedSoFar(run.log_file));
  }
  return exit_code;
}

// The embedded run, by exit status (RunEmbedded).
int RunEmbeddedExit(const DistributedRun& run, const runtime::RunPlan& plan,
                    const runtime::ScenarioSetup& scenario, const std::atomic<bool>& stop) {
  // One memq:// instance: a second one in this process would hear nothing.
  lcm::LCM lcm("memq://");
  if (!lcm.good()) {
    spdlog::error("cannot open LCM memq://");
    return 1;
  }
  protocol::BusOptions bus_options = run.process.bus;
  bus_options.fragment_above = 0;
  protocol::Bus envsim_bus(lcm, run.process.run_id, bus_options);
  protocol::Bus coordinator_bus(lcm, run.process.run_id, bus_options);
  envsim::EnvSim sim(
      envsim_bus,
      envsim::ScenarioInfo{scenario.scenario, scenario.labels, scenario.seed, scenario.source},
      envsim::EnvSimOptions{});
  EmbeddedAgents agents(lcm, run.process.run_id, bus_options, run.agents, run.threads_per_agent);
  coordinator::CoordinatorOptions options;
  options.plan = plan;
  options.min_agents = run.agents;
  coordinator::Coordinator coordinator(coordinator_bus, options);

  std::optional<ReportListener> listener;
  if (run.on_step) listener.emplace(lcm, run.process.run_id, run.process.bus.key, run.on_step);

  protocol::Dispatcher dispatcher(lcm);
  std::atomic<bool> stop_components{false};
  std::vector<std::thread> threads;
  threads.emplace_back([&] { sim.Run(stop_components); });
  agents.Start();
  const int code = coordinator.Run(stop);
  // They exit on the coordinator's final heartbeat; the flag is a backstop.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  stop_components = true;
  for (std::thread& thread : threads) thread.join();
  agents.Stop();
  return stop ? 130 : code;
}

}  // namespace

Status LaunchProcesses(const DistributedRun& run) {
  return OutcomeOfExit(LaunchProcessesExit(run));
}

Status RunEmbedded(const DistributedRun& run, const runtime::RunPlan& plan,
                   const runtime::ScenarioSetup& scenario) {
  return OutcomeOfExit(RunEmbeddedExit(run, plan, scenario, protocol::StopOnSignals()));
}

Status RunEmbedded(const DistributedRun& run, const runtime::RunPlan& plan,
                   const runtime::ScenarioSetup& scenario, const std::atomic<bool>& stop) {
  return OutcomeOfExit(RunEmbeddedExit(run, plan, scenario, stop));
}

AgentProcesses::AgentProcesses(AgentLaunch launch) : launch_(std::move(launch)) {}

AgentProcesses::~AgentProcesses() { Stop(); }

bool AgentProcesses::Start() {
  const ChildStart child_start{launch_.process, launch_.log_level, launch_.child_stderr};
  for (int i = 1; i <= launch_.agents; ++i) {
    if (!StartAgent(child_start, children_, i, launch_.threads_per_agent)) {
      Stop(std::chrono::milliseconds(3000));
      return false;
    }
  }
  return true;
}

int AgentProcesses::Check(
    const std::function<void(int agent_id, const std::string& how)>& on_exit) {
  int running = 0;
  for (Child& child : children_) {
    if (!child.running) continue;
    int status = 0;
    if (waitpid(child.pid, &status, WNOHANG) == child.pid) {
      child.running = false;
      child.status = status;
      if (on_exit) {
        on_exit(child.agent_id, Describe(status));
      } else {
        spdlog::warn("{} {}; training goes on without it", child.name, Describe(status));
      }
      continue;
    }
    ++running;
  }
  return running;
}

void AgentProcesses::Stop(std::chrono::milliseconds grace) {
  StopAll(children_, grace);
  children_.clear();
}

EmbeddedAgents::EmbeddedAgents(lcm::LCM& lcm, const std::string& run_id,
                               const protocol::BusOptions& bus, int agents, int threads_per_agent) {
  for (int i = 1; i <= agents; ++i) {
    buses_.push_back(std::make_unique<protocol::Bus>(lcm, run_id, bus));
    agent::AgentOptions options;
    options.id = i;
    options.threads = threads_per_agent;
    agents_.push_back(std::make_unique<agent::Agent>(*buses_.back(), options));
  }
}

EmbeddedAgents::~EmbeddedAgents() { Stop(); }

void EmbeddedAgents::Start() {
  if (!threads_.empty()) return;
  for (auto& agent : agents_) {
    threads_.emplace_back([this, a = agent.get()] { a->Run(stop_); });
  }
}

void EmbeddedAgents::Stop() {
  stop_ = true;
  for (std::thread& thread : threads_) thread.join();
  threads_.clear();
}

}  // namespace dynapath::launch
