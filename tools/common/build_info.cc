#include "tools/common/build_info.h"

#include <cstdio>
#include <filesystem>

#if __has_include("dynapath_git_commit.h")
#include "dynapath_git_commit.h"
#endif

namespace dynapath::cli {

GitCommit FindGitCommit() {
#ifdef DYNAPATH_GIT_COMMIT
  if (std::string(DYNAPATH_GIT_COMMIT) != "" && std::string(DYNAPATH_GIT_COMMIT) != "unknown") {
    return {DYNAPATH_GIT_COMMIT, "build"};
  }
#endif
  // This file is tools/common/build_info.cc of the source tree.
  const std::filesystem::path file(__FILE__);
  std::error_code error;
  if (!file.is_absolute()) return {"unknown", ""};
  const std::filesystem::path root = file.parent_path().parent_path().parent_path();
  if (!std::filesystem::exists(root / ".git", error)) return {"unknown", ""};
  std::string quoted = "'";
  for (const char c : root.string()) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  quoted += "'";
  const std::string command = "git -C " + quoted + " describe --always --dirty 2>/dev/null";
  std::FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return {"unknown", ""};
  char buffer[256] = {};
  std::string output;
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  const int status = pclose(pipe);
  while (!output.empty() && (output.back() == '\n' || output.back() == '\r')) output.pop_back();
  if (status != 0 || output.empty()) return {"unknown", ""};
  return {output, "source tree at run time"};
}

}  // namespace dynapath::cli
