// study.log's sink: a line that cannot be written (a full disk) is kept
// and written when there is room again; what is still missing is said.

#include "study/study_log.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spdlog/logger.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>

#include "dynapath/text_file.h"
#include "tests/temp_path.h"

namespace dynapath::study {
namespace {

TEST(StudyLogSinkTest, LinesAFullDiskRefusedAreWrittenLaterAndMissingOnesAreSaid) {
  const std::string path = test_paths::UniqueTempPath("study.log");
  // /dev/full refuses every write with ENOSPC: a full disk.
  const int fd = open("/dev/full", O_WRONLY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  auto sink = std::make_shared<StudyLogSink>(fd);
  sink->set_pattern("%v");
  spdlog::logger logger("study_log_test", sink);
  logger.info("first");
  logger.info("second");
  logger.flush();
  EXPECT_EQ(sink->missing().pending, 13u);  // "first\n" and "second\n"
  EXPECT_EQ(sink->MissingText("study.log"),
            "study.log: 13 bytes of log lines could not be written: No space left on device");
  // Room again: the same descriptor now reaches a file.
  const int file = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  ASSERT_GE(file, 0);
  ASSERT_EQ(dup2(file, fd), fd);
  close(file);
  logger.info("third");
  EXPECT_EQ(sink->MissingText("study.log"), "");
  EXPECT_EQ(*ReadTextFile(path), "first\nsecond\nthird\n");
  close(fd);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace dynapath::study
