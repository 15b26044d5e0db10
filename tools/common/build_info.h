#pragma once
// The version of the tools and the git commit they were built from, for
// `dynapath --version` and study manifests.

#include <string>

namespace dynapath::cli {

inline constexpr const char* kDynapathVersion = "0.1.0";

struct GitCommit {
  std::string commit;  // `git describe --always --dirty`, or "unknown"
  std::string source;  // "build", "source tree at run time" or "" (unknown)
};

// The commit embedded by the build when it generated dynapath_git_commit.h
// (defining DYNAPATH_GIT_COMMIT) on the include path; otherwise
// `git describe --always --dirty` of the source tree this file was compiled
// from, asked now (it may have changed since the build); else "unknown".
GitCommit FindGitCommit();

}  // namespace dynapath::cli
