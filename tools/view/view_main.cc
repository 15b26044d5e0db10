// dynapath-view: a live window on a run's policy. Subscribes to
// DYNAPATH/<run>/POLICY, draws the latest policy of the chosen approach.
// Run directly or as `dynapath view`.

#include <fcntl.h>
#include <sched.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "runtime/option_group.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"
#include "tools/view/policy_drawing.h"
#include "tools/view/policy_feed.h"
#include "tools/view/view_options.h"
#include "tools/view/viewer.h"

namespace {

using namespace dynapath;

constexpr const char* kProgram = "dynapath-view";
constexpr int kExitFailure = 1;

bool SameNamespace(const std::string& a, const std::string& b) {
  struct stat first {
  }, second{};
  return stat(a.c_str(), &first) == 0 && stat(b.c_str(), &second) == 0 &&
         first.st_dev == second.st_dev && first.st_ino == second.st_ino;
}

// Joins the network namespace of process `pid` (a `dynapath run` launcher
// that made a private network for its run), as dynapath-spy does with
// `nsenter --user --net --preserve-credentials`: first its user namespace
// when it has its own (an unprivileged launcher's), keeping our credentials,
// then its network. Must run while the process has one thread.
Status EnterNetworkOf(const std::string& pid) {
  const std::string ns = "/proc/" + pid + "/ns/";
  if (access(("/proc/" + pid).c_str(), F_OK) != 0) {
    return Error::NotFound("no process with pid " + pid + " (is the run still going?)");
  }
  auto join = [&](const char* name, int type) -> Status {
    const int fd = open((ns + name).c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
      const int error = errno;
      return Error::File(error,
                         std::string("cannot open ") + ns + name + ": " + std::strerror(error));
    }
    const int result = setns(fd, type);
    const int error = errno;
    close(fd);
    if (result != 0)
      return Error::Io(std::string("cannot join its ") + name +
                       " namespace: " + std::strerror(error));
    return Ok{};
  };
  if (!SameNamespace(ns + "user", "/proc/self/ns/user")) {
    // A launcher that ran as root without user namespaces has only a network
    // namespace; root can join it directly.
    if (Status status = join("user", CLONE_NEWUSER); !status && geteuid() != 0) {
      return status.error().Prefixed("cannot enter the network of process " + pid + ": ");
    }
  }
  if (Status status = join("net", CLONE_NEWNET); !status) {
    return status.error().Prefixed("cannot enter the network of process " + pid + ": ");
  }
  return Ok{};
}

Result<std::pair<int, int>> ParseWindowSize(const std::string& text) {
  int width = 0, height = 0;
  char rest = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &width, &height, &rest) != 2 || width < 160 ||
      height < 120 || width > 8192 || height > 8192) {
    return Error::Option("window",
                         "needs WIDTHxHEIGHT between 160x120 and 8192x8192, got '" + text + "'");
  }
  return std::pair{width, height};
}

int Run(const std::vector<std::string>& args) {
  view::ShowOptions show;
  std::string lcm_url;
  std::optional<std::string> pid_given;
  std::string window_given = "960x760";
  std::optional<std::string> screenshot;
  long long frames_given = 1;
  long long timeout_given = 60;
  runtime::LogOptions log;
  const int parsed = runtime::ParseCommandLine(
      kProgram, "dynapath view",
      "A live window on a run's policy: the latest POLICY message of an approach, drawn\n"
      "like `dynapath render` draws them. Keys: Tab/PageUp/PageDown or 1-9 pick the\n"
      "approach, A follows the latest one, wheel or +/- zoom, drag or arrows pan, F fits,\n"
      "Q or Escape quit. A run in its private network (the default of dynapath run\n"
      "--agents N): give the pid its launcher logs, --pid PID.",
      [&](runtime::OptionGroup& group) {
        view::DeclareShowOptions(group, show);
        runtime::DeclareLcmUrlOption(group, lcm_url);
        group.Option("--pid", pid_given, "PID",
                     "join the private network of this process (a running `dynapath run`)");
        group.Option("--window", window_given, "WxH", "window size");
        group.Option(
            "--screenshot", screenshot, "FILE",
            "save what the window shows as a PNG once --frames policies arrived, and exit");
        group.Option("--frames", frames_given, "N", "policies to receive before the screenshot");
        group.Option("--timeout", timeout_given, "SEC",
                     "screenshot mode: give up after SEC seconds (exit 1)");
        runtime::DeclareLogOptions(group, log);
      },
      args);
  if (parsed >= 0) return parsed;
  if (Status status = runtime::ApplyLogLevel(log); !status) {
    return runtime::ProcessError(kProgram, status.error().message);
  }

  view::ViewerOptions options;
  if (Status status = view::CheckShowOptions(show); !status) {
    return runtime::ProcessError(kProgram, status.error().message);
  }
  const std::string run_id = show.run_id.value_or("");
  Result<int> cell = view::ResolveCellOption(show.cell_px);
  if (!cell) return runtime::ProcessError(kProgram, cell.error().message);
  options.cell_px = *cell;
  Result<std::pair<int, int>> window = ParseWindowSize(window_given);
  if (!window) return runtime::ProcessError(kProgram, window.error().message);
  options.window_width = window->first;
  options.window_height = window->second;
  options.approach = show.approach.value_or("");
  options.screenshot = screenshot.value_or("");
  Result<long long> frames = runtime::InRange("frames", frames_given, 0, 1, 1000000);
  if (!frames) return runtime::ProcessError(kProgram, frames.error().message);
  options.screenshot_after = static_cast<int>(*frames);
  Result<long long> timeout = runtime::InRange("timeout", timeout_given, 0, 1, 86400);
  if (!timeout) return runtime::ProcessError(kProgram, timeout.error().message);
  options.timeout_seconds = static_cast<double>(*timeout);
  if (screenshot && options.screenshot.empty()) {
    return runtime::ProcessError(kProgram, "option --screenshot needs a file name");
  }

  if (pid_given) {
    const std::string& pid = *pid_given;
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos) {
      return runtime::ProcessError(kProgram, "option --pid needs a process id, got '" + pid + "'");
    }
    // Still one thread: setns into a user namespace requires it.
    if (Status status = EnterNetworkOf(pid); !status) {
      return runtime::ProcessError(kProgram, status.error().message, kExitFailure);
    }
    spdlog::info("joined the network of process {}", pid);
  }

  // SFML aborts the process when it cannot open a display: say so first.
  const char* display = std::getenv("DISPLAY");
  if (display == nullptr || *display == '\0') {
    return runtime::ProcessError(
        kProgram,
        "no display (DISPLAY is not set): dynapath view opens a window; use "
        "`dynapath render LOG --out DIR` for pictures without one (or xvfb-run)",
        kExitFailure);
  }

  options.lcm_url = protocol::ResolveLcmUrl(lcm_url);
  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(options.lcm_url);
  if (!lcm) return runtime::ProcessError(kProgram, lcm.error().message, kExitFailure);
  view::PolicyFeed feed(**lcm, run_id);
  protocol::Dispatcher dispatcher(**lcm);
  spdlog::info("listening for DYNAPATH/{}/POLICY on {}", run_id.empty() ? "*" : run_id,
               options.lcm_url);
  const int code = view::RunViewer(feed, options);
  if (feed.dropped() > 0) {
    spdlog::warn("dropped {} invalid or undecodable POLICY message(s)", feed.dropped());
  }
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  dynapath::runtime::InitProcessLogging(kProgram);
  try {
    return Run(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const std::exception& error) {
    return dynapath::runtime::ProcessError(kProgram, error.what(), kExitFailure);
  }
}
