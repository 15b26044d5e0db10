// `dynapath run|experiment --approach py:MODULE:CLASS`: a run with an
// approach written in Python is handed over to the Python module built
// alongside (`python3 -m dynapath run|experiment ARGS`, python/dynapath/
// __main__.py), which runs it in its own process through the same C++
// run driver, evaluation and study code, the rows beside the built-in ones.
//
// Why a hand-off and not an embedded interpreter: embedding Python would
// make the dynapath binary (and every machine that runs a study, an agent
// or a service) depend on libpython and on the module's ABI; with the
// hand-off only runs that name a py: approach need Python, and the binary
// stays the same whether or not the module was built.

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "tools/cli/commands.h"

#ifndef DYNAPATH_PYTHON_EXECUTABLE
#define DYNAPATH_PYTHON_EXECUTABLE ""
#endif

namespace dynapath::cli {

namespace fs = std::filesystem;

bool NamesPythonApproach(const std::vector<std::string>& args, const std::string& option) {
  for (size_t i = 0; i < args.size(); ++i) {
    std::string value;
    if (args[i] == option && i + 1 < args.size()) {
      value = args[i + 1];
    } else if (args[i].rfind(option + "=", 0) == 0) {
      value = args[i].substr(option.size() + 1);
    } else {
      continue;
    }
    size_t start = 0;
    while (start <= value.size()) {
      const size_t comma = std::min(value.find(',', start), value.size());
      const size_t first = value.find_first_not_of(' ', start);
      if (first != std::string::npos && first < comma && value.compare(first, 3, "py:") == 0) {
        return true;
      }
      start = comma + 1;
    }
  }
  return false;
}

int PythonCommand(const std::string& command, const std::vector<std::string>& args) {
  // The module as the build lays it out: build/python/dynapath beside
  // build/tools/dynapath (python/CMakeLists.txt).
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  const fs::path modules = self.parent_path().parent_path() / "python";
  const std::string python = DYNAPATH_PYTHON_EXECUTABLE;
  if (error || python.empty() || !fs::exists(modules / "dynapath" / "__main__.py", error)) {
    std::fprintf(stderr,
                 "dynapath %s: a py: approach needs the Python module dynapath, which was not "
                 "built with this dynapath (install python3-dev, pybind11-dev and python3-numpy, "
                 "then build the target dynapath_python; docs/howto/PYTHON.md)\n",
                 command.c_str());
    return kExitUsage;
  }
  const char* old_path = std::getenv("PYTHONPATH");
  std::string path = modules.string();
  if (old_path != nullptr && *old_path != '\0') path += std::string(":") + old_path;
  setenv("PYTHONPATH", path.c_str(), 1);
  std::vector<std::string> strings{python, "-m", "dynapath", command};
  strings.insert(strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& arg : strings) argv.push_back(arg.data());
  argv.push_back(nullptr);
  std::fflush(nullptr);
  execv(argv[0], argv.data());
  std::fprintf(stderr, "dynapath %s: cannot run %s: %s\n", command.c_str(), python.c_str(),
               std::strerror(errno));
  return kExitFailure;
}

}  // namespace dynapath::cli
