// The atomic writer: every failure names the file and the operating
// system's reason, and leaves no temporary file behind.

#include "dynapath/text_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/temp_path.h"

namespace dynapath {
namespace {

namespace fs = std::filesystem;

size_t Entries(const fs::path& dir) {
  return static_cast<size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST(TextFileTest, WritesAtomicallyAndLeavesNoTemporaryFile) {
  const fs::path dir = test_paths::UniqueTempPath("text_file");
  fs::create_directories(dir);
  const std::string path = (dir / "a.txt").string();
  ASSERT_TRUE(WriteTextFileAtomically(path, "first\n").ok());
  ASSERT_TRUE(WriteTextFileAtomically(path, "second\n").ok());
  Result<std::string> read = ReadTextFile(path);
  ASSERT_TRUE(read.ok());
  EXPECT_EQ(*read, "second\n");
  EXPECT_EQ(Entries(dir), 1u);
  fs::remove_all(dir);
}

TEST(TextFileTest, FailuresNameTheFileAndTheReason) {
  const fs::path dir = test_paths::UniqueTempPath("text_file");
  fs::create_directories(dir / "sub");
  // A missing folder: the system's reason, an I/O error.
  const std::string missing = (dir / "missing" / "x.csv").string();
  Status status = WriteTextFileAtomically(missing, "x");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message, missing + ": cannot write: No such file or directory");
  EXPECT_TRUE(status.error().IsIo());
  // A folder where the file should be.
  status = WriteTextFileAtomically((dir / "sub").string(), "x");
  ASSERT_FALSE(status.ok());
  EXPECT_TRUE(status.error().IsIo());
  EXPECT_NE(status.error().message.find("is a directory"), std::string::npos)
      << status.error().message;
  EXPECT_EQ(Entries(dir), 1u);  // no temporary file left
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dynapath
