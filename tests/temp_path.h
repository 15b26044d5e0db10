#pragma once
// A scratch path of the running test's own. ctest runs every GoogleTest case as
// its own process, two at a time (-j2), so a fixed name under TempDir() is
// shared by concurrent cases and one case's cleanup removes the other's files.
// The name carries the suite, the test and the pid, so no two cases collide.

#include <gtest/gtest.h>
#include <unistd.h>

#include <string>

namespace dynapath::test_paths {

inline std::string UniqueTempPath(const std::string& name) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string owner = info != nullptr
                          ? std::string(info->test_suite_name()) + "." + info->name()
                          : std::string("no_test");
  for (char& c : owner) {
    if (c == '/') c = '_';  // parameterised names contain slashes
  }
  std::string dir = ::testing::TempDir();
  if (!dir.empty() && dir.back() != '/') dir += '/';
  return dir + name + "_" + owner + "_" + std::to_string(::getpid());
}

}  // namespace dynapath::test_paths
