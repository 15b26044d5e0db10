// `dynapath plot|view|render`: tools built as their own executables next to
// the dynapath binary (so the launcher does not depend on SFML or Python),
// run with the same arguments (or, for `compare --plot`, as a child process).

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tools/cli/commands.h"

namespace dynapath::cli {

namespace {

// The argument strings of `tool` (its path next to this binary, then
// `args`), or none (after one error line) when it is missing.
std::optional<std::vector<std::string>> SiblingArguments(const std::string& tool,
                                                         const std::vector<std::string>& args,
                                                         const std::string& missing_hint) {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::filesystem::path path = self.parent_path() / tool;
  if (error || !std::filesystem::exists(path)) {
    std::fprintf(stderr, "dynapath: %s was not found next to dynapath (%s)\n", tool.c_str(),
                 missing_hint.c_str());
    return std::nullopt;
  }
  std::vector<std::string> strings{path.string()};
  strings.insert(strings.end(), args.begin(), args.end());
  return strings;
}

// execv's argument vector; `strings` must outlive it.
std::vector<char*> ArgumentVector(std::vector<std::string>& strings) {
  std::vector<char*> argv;
  for (std::string& arg : strings) argv.push_back(arg.data());
  argv.push_back(nullptr);
  return argv;
}

// Replaces this process with argv[0]; returns only when that fails.
int Exec(std::vector<char*>& argv) {
  execv(argv[0], argv.data());
  std::fprintf(stderr, "dynapath: cannot run %s: %s\n", argv[0], std::strerror(errno));
  return kExitFailure;
}

}  // namespace

int SiblingCommand(const std::string& tool, const std::vector<std::string>& args,
                   const std::string& missing_hint) {
  std::optional<std::vector<std::string>> strings = SiblingArguments(tool, args, missing_hint);
  if (!strings) return kExitFailure;
  std::vector<char*> argv = ArgumentVector(*strings);
  std::fflush(nullptr);
  return Exec(argv);
}

int RunSibling(const std::string& tool, const std::vector<std::string>& args,
               const std::string& missing_hint) {
  std::optional<std::vector<std::string>> strings = SiblingArguments(tool, args, missing_hint);
  if (!strings) return kExitFailure;
  std::vector<char*> argv = ArgumentVector(*strings);
  std::fflush(nullptr);
  const pid_t child = fork();
  if (child < 0) {
    std::fprintf(stderr, "dynapath: cannot run %s: %s\n", argv[0], std::strerror(errno));
    return kExitFailure;
  }
  if (child == 0) _exit(Exec(argv));
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) return kExitFailure;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : kExitFailure;
}

}  // namespace dynapath::cli
