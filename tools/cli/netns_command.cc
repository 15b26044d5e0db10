// dynapath netns: runs a command in a private network namespace, the one
// the launcher uses for a run, so tests, benchmarks and users can run
// lcm-logger, lcm-spy or any script with LCM's default udpm URL without
// touching the host network.

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "launch/private_network.h"
#include "tools/cli/commands.h"

namespace dynapath::cli {
namespace {

// What a shell returns for a command it cannot run.
constexpr int kExitCannotRun = 127;

constexpr const char* kHelp =
    "Usage: dynapath netns [--] COMMAND [ARGS...]\n"
    "\n"
    "Runs COMMAND in a private network: a new user and network namespace whose\n"
    "only interface is loopback, up with multicast and a route for 224.0.0.0/4.\n"
    "LCM's default udpm URL works inside, nothing leaves the machine, and\n"
    "commands in different private networks cannot hear each other. Inside, the\n"
    "caller appears as root; files it creates are still owned by the caller.\n"
    "\n"
    "Everything COMMAND starts shares the private network. To attach another\n"
    "program later, use nsenter (see dynapath-spy --pid).\n"
    "\n"
    "Exit status: that of COMMAND; 1 when the namespace cannot be created\n"
    "(user namespaces disabled?), 2 on bad usage, 127 when COMMAND cannot be run.\n"
    "\n"
    "Example:\n"
    "  dynapath netns -- lcm-logger --quiet run.lcmlog\n";

}  // namespace

int NetnsCommand(const std::vector<std::string>& args) {
  size_t first = 0;
  if (!args.empty()) {
    const std::string& arg = args[0];
    if (arg == "--help" || arg == "-h") {
      std::fputs(kHelp, stdout);
      return 0;
    }
    if (arg == "--") {
      first = 1;
    } else if (arg.size() > 1 && arg[0] == '-') {
      std::fprintf(stderr, "dynapath netns: unknown option %s (see dynapath netns --help)\n",
                   arg.c_str());
      return kExitUsage;
    }
  }
  if (first >= args.size()) {
    std::fputs("dynapath netns: missing COMMAND (usage: dynapath netns [--] COMMAND [ARGS...])\n",
               stderr);
    return kExitUsage;
  }

  if (Status status = launch::EnterPrivateNetwork(); !status) {
    std::fprintf(stderr, "dynapath netns: %s\n", status.error().message.c_str());
    return kExitFailure;
  }

  std::vector<char*> argv;
  argv.reserve(args.size() - first + 1);
  for (size_t i = first; i < args.size(); ++i) argv.push_back(const_cast<char*>(args[i].c_str()));
  argv.push_back(nullptr);
  std::fflush(nullptr);  // execvp discards anything still buffered
  execvp(argv[0], argv.data());
  std::fprintf(stderr, "dynapath netns: cannot run '%s': %s\n", argv[0], std::strerror(errno));
  return kExitCannotRun;
}

}  // namespace dynapath::cli
