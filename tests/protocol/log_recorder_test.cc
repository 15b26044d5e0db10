// The recorder of `run --log` (protocol/log_recorder.h): every message its
// subscription received is written, in order, in the LCM log format
// LogReader reads; bad arguments and write errors are refused with one
// clear error.

#include "protocol/log_recorder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "protocol/log_reader.h"

namespace dynapath::protocol {
namespace {

namespace fs = std::filesystem;

class LogRecorderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("log_recorder_test_" + std::to_string(getpid()));
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  std::string Path(const std::string& name) const { return (folder_ / name).string(); }

  // Dispatches until LCM has nothing left for `lcm`'s subscriptions.
  static void HandleAll(lcm::LCM& lcm) {
    while (lcm.handleTimeout(0) > 0) {
    }
  }

  static std::vector<LogEvent> ReadAll(const std::string& path) {
    Result<LogReader> reader = LogReader::Open(path);
    EXPECT_TRUE(reader) << reader.error().message;
    std::vector<LogEvent> events;
    if (!reader) return events;
    while (true) {
      Result<std::optional<LogEvent>> event = reader->Next();
      EXPECT_TRUE(event) << event.error().message;
      if (!event || !*event) break;
      events.push_back(std::move(**event));
    }
    return events;
  }

  fs::path folder_;
};

std::string Payload(int i) { return "message " + std::to_string(i) + std::string(i % 97, 'x'); }

// Everything published before the recorder got to it is written, in
// order, with its channel and bytes, and only the matching channels.
// (memq:// queues without LCM's limit of 30 per subscription: that the
// recorder lifts it over udpm is recorder_end_to_end's case.)
TEST_F(LogRecorderTest, WritesEveryMatchingMessageInOrder) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  constexpr int kMessages = 2000;
  {
    Result<std::unique_ptr<LogRecorder>> recorder =
        LogRecorder::Open(lcm, "DYNAPATH/run1/.*", Path("run.lcm"), false);
    ASSERT_TRUE(recorder) << recorder.error().message;
    for (int i = 0; i < kMessages; ++i) {
      const std::string data = Payload(i);
      lcm.publish(i % 2 == 0 ? "DYNAPATH/run1/REPORT" : "DYNAPATH/run1/POLICY", data.data(),
                  static_cast<unsigned>(data.size()));
      lcm.publish("DYNAPATH/run2/REPORT", data.data(), static_cast<unsigned>(data.size()));
    }
    HandleAll(lcm);
    EXPECT_EQ((*recorder)->events(), kMessages);
    ASSERT_TRUE((*recorder)->Flush());
  }
  const std::vector<LogEvent> events = ReadAll(Path("run.lcm"));
  ASSERT_EQ(events.size(), static_cast<size_t>(kMessages));
  for (int i = 0; i < kMessages; ++i) {
    const LogEvent& event = events[static_cast<size_t>(i)];
    EXPECT_EQ(event.number, i);
    EXPECT_EQ(event.channel, i % 2 == 0 ? "DYNAPATH/run1/REPORT" : "DYNAPATH/run1/POLICY");
    EXPECT_EQ(std::string(event.data.begin(), event.data.end()), Payload(i));
    if (i > 0) {
      EXPECT_GE(event.timestamp, events[static_cast<size_t>(i) - 1].timestamp);
    }
  }
}

TEST_F(LogRecorderTest, RefusesAnExistingFileUnlessToldToOverwrite) {
  lcm::LCM lcm("memq://");
  std::ofstream(Path("kept.lcm")) << "someone's log";
  Result<std::unique_ptr<LogRecorder>> refused =
      LogRecorder::Open(lcm, ".*", Path("kept.lcm"), false);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().message, "the log " + Path("kept.lcm") +
                                         " exists; give another name, or --force to overwrite it");
  EXPECT_EQ(fs::file_size(Path("kept.lcm")), 13u);
  Result<std::unique_ptr<LogRecorder>> overwriting =
      LogRecorder::Open(lcm, ".*", Path("kept.lcm"), true);
  ASSERT_TRUE(overwriting) << overwriting.error().message;
  EXPECT_EQ(fs::file_size(Path("kept.lcm")), 0u);
}

TEST_F(LogRecorderTest, RefusesWhatItCannotRecordInto) {
  lcm::LCM lcm("memq://");
  Result<std::unique_ptr<LogRecorder>> folder = LogRecorder::Open(lcm, ".*", Path(""), true);
  ASSERT_FALSE(folder);
  EXPECT_EQ(folder.error().message, "cannot write the log " + Path("") + ": it is a folder");
  Result<std::unique_ptr<LogRecorder>> missing =
      LogRecorder::Open(lcm, ".*", Path("no/such/folder/run.lcm"), false);
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().message, "cannot write the log " + Path("no/such/folder/run.lcm") +
                                         ": No such file or directory");
  Result<std::unique_ptr<LogRecorder>> empty = LogRecorder::Open(lcm, ".*", "", false);
  ASSERT_FALSE(empty);
  EXPECT_EQ(empty.error().message, "the log file name is empty");
  Result<std::unique_ptr<LogRecorder>> pattern =
      LogRecorder::Open(lcm, "DYNAPATH/(run", Path("run.lcm"), false);
  ASSERT_FALSE(pattern);
  EXPECT_NE(pattern.error().message.find("the channel pattern 'DYNAPATH/(run' is not a regular"),
            std::string::npos)
      << pattern.error().message;
  EXPECT_FALSE(fs::exists(Path("run.lcm")));
}

// A full disk is reported (and what was written counted), not ignored.
TEST_F(LogRecorderTest, ReportsAWriteError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  lcm::LCM lcm("memq://");
  Result<std::unique_ptr<LogRecorder>> recorder = LogRecorder::Open(lcm, ".*", "/dev/full", true);
  ASSERT_TRUE(recorder) << recorder.error().message;
  lcm.publish("A", "x", 1);
  HandleAll(lcm);
  Status flushed = (*recorder)->Flush();
  ASSERT_FALSE(flushed);
  EXPECT_EQ(flushed.error().message,
            "cannot write the log /dev/full: No space left on device (after 1 message)");
  EXPECT_FALSE((*recorder)->status());
}

}  // namespace
}  // namespace dynapath::protocol
