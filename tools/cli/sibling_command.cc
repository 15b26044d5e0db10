// `dynapath plot|view|render`: tools built as their own executables next to
// the dynapath binary (so the launcher does not depend on SFML or Python),
// run with the same arguments.

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "tools/cli/commands.h"

namespace dynapath::cli {

int SiblingCommand(const std::string& tool, const std::vector<std::string>& args,
                   const std::string& missing_hint) {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::filesystem::path path = self.parent_path() / tool;
  if (error || !std::filesystem::exists(path)) {
    std::fprintf(stderr, "dynapath: %s was not found next to dynapath (%s)\n", tool.c_str(),
                 missing_hint.c_str());
    return kExitFailure;
  }
  std::vector<std::string> argv_strings{path.string()};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& arg : argv_strings) argv.push_back(arg.data());
  argv.push_back(nullptr);
  std::fflush(nullptr);
  execv(argv[0], argv.data());
  std::fprintf(stderr, "dynapath: cannot run %s: %s\n", path.c_str(), std::strerror(errno));
  return kExitFailure;
}

}  // namespace dynapath::cli
