#pragma once
// The version of the tools and the git commit they were built from, for
// `dynapath --version` and study manifests.

#include <string>

namespace dynapath::cli {

inline constexpr const char* kDynapathVersion = "0.1.0";

struct GitCommit {
  std::string commit;  // `git describe --always --dirty`, or "unknown"
  std::string source;  // "build", or "" (unknown)
};

// The commit the build was configured from (tools/common/git_commit.cmake),
// or "unknown" when the source tree was no git checkout.
GitCommit FindGitCommit();

}  // namespace dynapath::cli
