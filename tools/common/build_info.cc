#include "tools/common/build_info.h"

#include "dynapath_git_commit.h"

namespace dynapath::cli {

GitCommit FindGitCommit() {
  const std::string commit = DYNAPATH_GIT_COMMIT;
  if (commit.empty() || commit == "unknown") return {"unknown", ""};
  return {commit, "build"};
}

}  // namespace dynapath::cli
