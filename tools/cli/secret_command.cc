// dynapath secret FILE: makes a run's secret for processes started by hand
// (docs/DISTRIBUTED.md, "Authenticated runs").

#include <cstdio>
#include <string>
#include <vector>

#include "lcmtypes/protocol/auth.h"
#include "runtime/arg_parser.h"
#include "tools/cli/commands.h"

namespace dynapath::cli {

int SecretCommand(const std::vector<std::string>& args) {
  runtime::ArgParser parser(
      "dynapath secret FILE",
      "Writes a new random secret (256 bits, as hex) to FILE, created with mode\n"
      "600; an existing FILE is left alone. Give the same file with\n"
      "--secret-file to every process of a run started by hand (envsim,\n"
      "coordinator, agents, `dynapath run --agents N`). `dynapath run` makes a\n"
      "secret of its own for the processes it starts.");
  // The parser takes options only: FILE is the one argument.
  if (args.size() == 1 && (args[0] == "--help" || args[0] == "-h")) {
    std::fputs(parser.Help().c_str(), stdout);
    return 0;
  }
  if (args.size() != 1 || args[0].empty() || args[0][0] == '-') {
    std::fprintf(stderr, "dynapath secret: give one FILE to write (see --help)\n");
    return kExitUsage;
  }
  if (Status status = protocol::WriteNewSecretFile(args[0]); !status) {
    std::fprintf(stderr, "dynapath secret: %s\n", status.error().message.c_str());
    return kExitFailure;
  }
  return 0;
}

}  // namespace dynapath::cli
