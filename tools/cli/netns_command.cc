// dynapath netns: runs a command in a private network namespace, the one
// the launcher uses for a run, so tests, benchmarks and users can run
// lcm-logger, lcm-spy or any script with LCM's default udpm URL without
// touching the host network.

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "launch/private_network.h"
#include "runtime/option_group.h"
#include "tools/cli/commands.h"

namespace dynapath::cli {
namespace {

// What a shell returns for a command it cannot run.
constexpr int kExitCannotRun = 127;
constexpr const char* kNetnsProgram = "dynapath netns";

constexpr const char* kDescription =
    "Runs COMMAND in a private network: a new user and network namespace whose\n"
    "only interface is loopback, up with multicast and a route for 224.0.0.0/4.\n"
    "LCM's default udpm URL works inside, nothing leaves the machine, and\n"
    "commands in different private networks cannot hear each other. Inside, the\n"
    "caller appears as root; files it creates are still owned by the caller.\n"
    "\n"
    "Everything COMMAND starts shares the private network. To attach another\n"
    "program later, use nsenter (see dynapath-spy --pid).";

constexpr const char* kFooter =
    "Exit status: that of COMMAND; 1 when the namespace cannot be created\n"
    "(user namespaces disabled?), 2 on bad usage, 127 when COMMAND cannot be run.\n"
    "\n"
    "Example:\n"
    "  dynapath netns -- lcm-logger --quiet run.lcmlog";

// CLI11's usage line shows the options; the command line after them cannot
// be a CLI11 positional (that would take COMMAND's own options as netns's),
// so the usage line gets it here.
class CommandUsage : public CLI::Formatter {
 public:
  std::string make_usage(const CLI::App* app, std::string name) const override {
    std::string usage = CLI::Formatter::make_usage(app, std::move(name));
    usage.insert(usage.find_last_not_of('\n') + 1, " [--] COMMAND [ARGS...]");
    return usage;
  }
};

// The command in what CLI11's prefix mode leaves after netns's options: it
// stops at the first argument it does not know, which is the command, an
// unknown option (an error) or "--" before the command.
Result<std::vector<std::string>> CommandOf(std::vector<std::string> rest) {
  if (!rest.empty() && rest.front() == "--") {
    rest.erase(rest.begin());
  } else if (!rest.empty() && rest.front().size() > 1 && rest.front()[0] == '-') {
    return Error{"unknown option " + rest.front() + " (see dynapath netns --help)"};
  }
  if (rest.empty()) return Error{"missing COMMAND (usage: dynapath netns [--] COMMAND [ARGS...])"};
  return rest;
}

// Replaces this process with `command`; returns only when it cannot run.
int Exec(const std::vector<std::string>& command) {
  std::vector<char*> argv;
  argv.reserve(command.size() + 1);
  for (const std::string& arg : command) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  std::fflush(nullptr);  // execvp discards anything still buffered
  execvp(argv[0], argv.data());
  std::fprintf(stderr, "%s: cannot run '%s': %s\n", kNetnsProgram, argv[0], std::strerror(errno));
  return kExitCannotRun;
}

}  // namespace

int NetnsCommand(const std::vector<std::string>& args) {
  CLI::App app(kDescription, kNetnsProgram);
  app.formatter(std::make_shared<CommandUsage>());
  app.footer(kFooter);
  app.prefix_command();
  if (int code = runtime::ParseCommandLine(app, args, kNetnsProgram); code >= 0) return code;
  Result<std::vector<std::string>> command = CommandOf(app.remaining());
  if (!command) {
    std::fprintf(stderr, "%s: %s\n", kNetnsProgram, command.error().message.c_str());
    return kExitUsage;
  }
  if (Status status = launch::EnterPrivateNetwork(); !status) {
    std::fprintf(stderr, "%s: %s\n", kNetnsProgram, status.error().message.c_str());
    return kExitFailure;
  }
  return Exec(*command);
}

}  // namespace dynapath::cli
