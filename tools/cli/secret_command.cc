// dynapath secret FILE: makes a run's secret for processes started by hand
// (docs/howto/DISTRIBUTED.md, "Authenticated runs").

#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "protocol/auth.h"
#include "runtime/option_group.h"
#include "tools/cli/commands.h"

namespace dynapath::cli {

int SecretCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Writes a new random secret (256 bits, as hex) to FILE, created with mode\n"
      "600; an existing FILE is left alone. Give the same file with\n"
      "--secret-file to every process of a run started by hand (envsim,\n"
      "coordinator, agents, `dynapath run --agents N`). `dynapath run` makes a\n"
      "secret of its own for the processes it starts.",
      "dynapath secret");
  std::string file;
  app.add_option("FILE", file, "the file to write")->required();
  if (int code = runtime::ParseCommandLine(app, args, "dynapath secret"); code >= 0) return code;
  if (file.empty()) {
    std::fprintf(stderr, "dynapath secret: give one FILE to write (see --help)\n");
    return kExitUsage;
  }
  if (Status status = protocol::WriteNewSecretFile(file); !status) {
    std::fprintf(stderr, "dynapath secret: %s\n", status.error().message.c_str());
    return kExitFailure;
  }
  return 0;
}

}  // namespace dynapath::cli
