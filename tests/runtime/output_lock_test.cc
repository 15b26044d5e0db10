// One writer per output directory (runtime/output_lock.h) and the checks of
// output paths (runtime/output_check.h).

#include "runtime/output_lock.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "runtime/output_check.h"
#include "tests/temp_path.h"

namespace dynapath::runtime {
namespace {

namespace fs = std::filesystem;

class OutputLockTest : public ::testing::Test {
 protected:
  void SetUp() override { fs::create_directories(dir_); }
  void TearDown() override { fs::remove_all(dir_); }
  const fs::path dir_ = test_paths::UniqueTempPath("output_lock");
};

TEST_F(OutputLockTest, ASecondWriterIsRefusedNamingTheHolder) {
  const std::string out = (dir_ / "out" / "deep").string();  // created with its parents
  Result<OutputLock> first = OutputLock::Acquire(out, "out");
  ASSERT_TRUE(first.ok()) << first.error().message;
  std::ifstream in(out + "/" + kLockFileName);
  std::string pid, command;
  std::getline(in, pid);
  std::getline(in, command);
  EXPECT_EQ(pid, std::to_string(getpid()));
  EXPECT_FALSE(command.empty());
  // flock is per open file: a second open in this process conflicts too.
  Result<OutputLock> second = OutputLock::Acquire(out, "out");
  ASSERT_FALSE(second.ok());
  EXPECT_TRUE(second.error().IsUnavailable());
  EXPECT_EQ(second.error().subject, "out");
  EXPECT_EQ(second.error().message.rfind(
                "option --out: " + out + " is in use by pid " + pid + " (" + command + ")", 0),
            0u)
      << second.error().message;
  // Released: the file is gone and the next writer gets it.
  first = Error("released");
  EXPECT_FALSE(fs::exists(out + "/" + kLockFileName));
  EXPECT_TRUE(OutputLock::Acquire(out, "out").ok());
}

TEST_F(OutputLockTest, AStaleLockFileDoesNotBlock) {
  // A holder killed by SIGKILL leaves its file, but not its lock.
  std::ofstream(dir_ / kLockFileName) << "999999\ndynapath run --out x\n";
  Result<OutputLock> lock = OutputLock::Acquire(dir_.string(), "out");
  ASSERT_TRUE(lock.ok()) << lock.error().message;
}

TEST_F(OutputLockTest, AdoptTakesOnlyTheLockOfTheDirectory) {
  Result<OutputLock> held = OutputLock::Acquire(dir_.string(), "out");
  ASSERT_TRUE(held.ok());
  // The launcher's descriptor, as a child inherits it (the same open file).
  const int inherited = dup(held->fd());
  Result<OutputLock> adopted = OutputLock::Adopt(dir_.string(), inherited);
  ASSERT_TRUE(adopted.ok()) << adopted.error().message;
  // Another file, or a descriptor that is not open, is refused.
  const int other = open((dir_ / "other").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  Result<OutputLock> wrong = OutputLock::Adopt(dir_.string(), other);
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.error().message.find("is not the lock file"), std::string::npos);
  close(other);
  EXPECT_FALSE(OutputLock::Adopt(dir_.string(), 987654).ok());
  // An adopted lock does not remove the file; its owner does.
  adopted = Error("released");
  EXPECT_TRUE(fs::exists(dir_ / kLockFileName));
  held = Error("released");
  EXPECT_FALSE(fs::exists(dir_ / kLockFileName));
}

TEST_F(OutputLockTest, OutputPathsAreCheckedWithTheReason) {
  std::ofstream(dir_ / "file") << "x";
  fs::create_directories(dir_ / "folder");
  const std::string file = (dir_ / "file").string();
  const std::string folder = (dir_ / "folder").string();
  Status status = PrepareOutputDirectory(file, "out");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message, "option --out: " + file + " is a file, not a directory");
  status = PrepareOutputDirectory(file + "/sub", "out");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message,
            "option --out: " + file + "/sub: cannot create the directory: Not a directory");
  EXPECT_TRUE(PrepareOutputDirectory((dir_ / "new" / "out").string(), "out").ok());
  status = CheckOutputFiles(dir_.string(), {"results.csv", "folder"}, "out");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message,
            "option --out: " + folder + " is a directory, where the file folder is to be written");
  status = CheckOutputFile(folder, "log");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message, "option --log: " + folder + " is a directory, not a file");
  status = CheckOutputFile((dir_ / "missing" / "run.lcm").string(), "log");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message, "option --log: " + (dir_ / "missing" / "run.lcm").string() +
                                        ": its folder " + (dir_ / "missing").string() +
                                        " does not exist");
  EXPECT_TRUE(CheckOutputFile((dir_ / "run.lcm").string(), "log").ok());
  EXPECT_TRUE(CheckOutputFile(file, "log").ok());
  // A folder that takes no new files, whatever access() says (to root).
  status = CheckOutputFile("/proc/p.pol", "save-policy");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message.rfind(
                "option --save-policy: /proc/p.pol: its folder /proc is not writable: ", 0),
            0u)
      << status.error().message;
  EXPECT_FALSE(PrepareOutputDirectory("/proc/self", "out").ok());
  // The probe leaves nothing behind.
  for (const fs::directory_entry& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().rfind(".dynapath-probe", 0), std::string::npos);
  }
}

}  // namespace
}  // namespace dynapath::runtime
