// The checked LCM log reader: reads what lcm::LogFile writes, and a corrupt
// or truncated log is one error naming the byte offset (liblcm's reader
// crashed on an event length of 0x7fffffff: calloc(datalen + 1) wraps).

#include "protocol/log_reader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "protocol/log_scenario.h"

namespace dynapath::protocol {
namespace {

class LogReaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = ::testing::TempDir() + "log_reader_" + std::to_string(getpid()) + ".lcm";
  }
  void TearDown() override { std::remove(path_.c_str()); }

  void WriteLog(int events) {
    lcm::LogFile log(path_, "w");
    ASSERT_TRUE(log.good());
    for (int i = 0; i < events; ++i) {
      std::string channel = "DYNAPATH/r/CH" + std::to_string(i);
      std::vector<uint8_t> data(static_cast<size_t>(10 + i), static_cast<uint8_t>(i));
      lcm::LogEvent event{};
      event.eventnum = i;
      event.timestamp = 1000 + i;
      event.channel = channel;
      event.datalen = static_cast<int32_t>(data.size());
      event.data = data.data();
      ASSERT_EQ(log.writeEvent(&event), 0);
    }
  }
  std::vector<uint8_t> Bytes() {
    std::ifstream in(path_, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  void Put(const std::vector<uint8_t>& bytes) {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  }
  // Reads every event; the error, or "" at a clean end.
  std::string ReadAll(int* events = nullptr) {
    Result<LogReader> log = LogReader::Open(path_);
    if (!log) return log.error().message;
    int n = 0;
    while (true) {
      auto next = log->Next();
      if (!next) return next.error().message;
      if (!*next) break;
      EXPECT_EQ((*next)->channel, "DYNAPATH/r/CH" + std::to_string(n));
      EXPECT_EQ((*next)->data.size(), static_cast<size_t>(10 + n));
      EXPECT_EQ((*next)->timestamp, 1000 + n);
      ++n;
    }
    if (events != nullptr) *events = n;
    return "";
  }

  std::string path_;
};

TEST_F(LogReaderTest, ReadsWhatLcmWrites) {
  WriteLog(3);
  int events = 0;
  EXPECT_EQ(ReadAll(&events), "");
  EXPECT_EQ(events, 3);
}

TEST_F(LogReaderTest, HugeEventLengthIsAnErrorWithItsOffset) {
  WriteLog(2);
  std::vector<uint8_t> bytes = Bytes();
  // The second event starts after the first: header 28 + channel 14 + data 10.
  const size_t second = 28 + 14 + 10;
  for (int i = 0; i < 4; ++i) bytes[second + 24 + i] = i == 0 ? 0x7f : 0xff;
  Put(bytes);
  const std::string error = ReadAll();
  EXPECT_NE(error.find("at byte " + std::to_string(second)), std::string::npos) << error;
  EXPECT_NE(error.find("event length 2147483647"), std::string::npos) << error;
  // The readers built on it report the same error instead of crashing.
  Result<LoggedScenario> scenario = ReadScenarioLog(path_);
  ASSERT_FALSE(scenario);
  EXPECT_NE(scenario.error().message.find("at byte 52"), std::string::npos);
}

TEST_F(LogReaderTest, TruncatedAndCorruptLogsAreErrorsWithOffsets) {
  WriteLog(2);
  const std::vector<uint8_t> whole = Bytes();
  for (size_t cut = 1; cut < whole.size(); ++cut) {
    Put(std::vector<uint8_t>(whole.begin(), whole.begin() + static_cast<ptrdiff_t>(cut)));
    const std::string error = ReadAll();
    if (cut == 52) {
      EXPECT_EQ(error, "");  // ends cleanly after the first event
    } else {
      EXPECT_NE(error.find("corrupt at byte " + std::string(cut < 52 ? "0" : "52")),
                std::string::npos)
          << cut << ": " << error;
    }
  }
  std::vector<uint8_t> bad = whole;
  bad[52] ^= 0xff;  // the second event's sync word
  Put(bad);
  EXPECT_NE(ReadAll().find("at byte 52: no sync word"), std::string::npos);
  bad = whole;
  bad[20] = 0x80;  // negative channel length
  Put(bad);
  EXPECT_NE(ReadAll().find("at byte 0: channel length"), std::string::npos);
  Put({'n', 'o', 't', ' ', 'a', ' ', 'l', 'o', 'g', ' ', 'a', 't', ' ', 'a',
       'l', 'l', '.', '.', '.', '.', '.', '.', '.', '.', '.', '.', '.', '.'});
  EXPECT_NE(ReadAll().find("not an LCM log"), std::string::npos);
}

TEST_F(LogReaderTest, DirectoriesAndMissingFilesAreErrors) {
  EXPECT_NE(ReadAll().find("cannot open log"), std::string::npos);
  path_ = ::testing::TempDir();
  EXPECT_NE(ReadAll().find("is a directory"), std::string::npos);
  path_ = "/nonexistent-dynapath-log";
}

}  // namespace
}  // namespace dynapath::protocol
