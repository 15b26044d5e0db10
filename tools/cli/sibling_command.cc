// `dynapath plot|view|render`: tools built as their own executables next to
// the dynapath binary (so the launcher does not depend on SFML or Python),
// run with the same arguments (or, for `compare --plot`, as a child process).

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "tools/cli/commands.h"

namespace dynapath::cli {

namespace {

// The path of `tool` next to this binary, or empty (after one error line).
std::filesystem::path SiblingPath(const std::string& tool, const std::string& missing_hint) {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::filesystem::path path = self.parent_path() / tool;
  if (error || !std::filesystem::exists(path)) {
    std::fprintf(stderr, "dynapath: %s was not found next to dynapath (%s)\n", tool.c_str(),
                 missing_hint.c_str());
    return {};
  }
  return path;
}

// execv's argument vector; `strings` must outlive it.
std::vector<char*> ArgumentVector(std::vector<std::string>& strings) {
  std::vector<char*> argv;
  for (std::string& arg : strings) argv.push_back(arg.data());
  argv.push_back(nullptr);
  return argv;
}

}  // namespace

int SiblingCommand(const std::string& tool, const std::vector<std::string>& args,
                   const std::string& missing_hint) {
  const std::filesystem::path path = SiblingPath(tool, missing_hint);
  if (path.empty()) return kExitFailure;
  std::vector<std::string> argv_strings{path.string()};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv = ArgumentVector(argv_strings);
  std::fflush(nullptr);
  execv(argv[0], argv.data());
  std::fprintf(stderr, "dynapath: cannot run %s: %s\n", path.c_str(), std::strerror(errno));
  return kExitFailure;
}

int RunSibling(const std::string& tool, const std::vector<std::string>& args,
               const std::string& missing_hint) {
  const std::filesystem::path path = SiblingPath(tool, missing_hint);
  if (path.empty()) return kExitFailure;
  std::vector<std::string> argv_strings{path.string()};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv = ArgumentVector(argv_strings);
  std::fflush(nullptr);
  const pid_t child = fork();
  if (child < 0) {
    std::fprintf(stderr, "dynapath: cannot run %s: %s\n", path.c_str(), std::strerror(errno));
    return kExitFailure;
  }
  if (child == 0) {
    execv(argv[0], argv.data());
    std::fprintf(stderr, "dynapath: cannot run %s: %s\n", path.c_str(), std::strerror(errno));
    _exit(kExitFailure);
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) return kExitFailure;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : kExitFailure;
}

}  // namespace dynapath::cli
