#include "protocol/log_reader.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>

namespace dynapath::protocol {
namespace {

constexpr uint32_t kSyncWord = 0xEDA1DA01;
constexpr int64_t kHeaderBytes = 4 + 8 + 8 + 4 + 4;

int64_t BigEndian(const uint8_t* p, int bytes) {
  uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) value = (value << 8) | p[i];
  const int shift = 64 - 8 * bytes;
  return static_cast<int64_t>(value << shift) >> shift;
}

}  // namespace

Result<LogReader> LogReader::Open(const std::string& path) {
  struct stat info {};
  if (stat(path.c_str(), &info) != 0) {
    const int error = errno;
    return Error::File(error, "cannot open log " + path + ": " + std::strerror(error));
  }
  if (S_ISDIR(info.st_mode)) return Error::Io(path + " is a directory, not an LCM log");
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    const int error = errno;
    return Error::File(error, "cannot open log " + path + ": " + std::strerror(error));
  }
  return LogReader(path, file, static_cast<int64_t>(info.st_size));
}

Error LogReader::Corrupt(int64_t offset, const std::string& what) const {
  return Error::Corrupt("log " + path_ + " is corrupt at byte " + std::to_string(offset) + ": " +
                        what);
}

Result<std::optional<LogEvent>> LogReader::Next() {
  const int64_t start = offset_;
  uint8_t header[kHeaderBytes];
  const size_t got = std::fread(header, 1, sizeof header, file_.get());
  if (got == 0 && std::feof(file_.get())) return std::optional<LogEvent>();
  if (got != sizeof header) {
    return Corrupt(start, "the log ends inside an event header (" + std::to_string(got) + " of " +
                              std::to_string(kHeaderBytes) + " bytes)");
  }
  if (static_cast<uint32_t>(BigEndian(header, 4)) != kSyncWord) {
    return Corrupt(start, start == 0 ? "not an LCM log (no sync word)" : "no sync word");
  }
  LogEvent event;
  event.offset = start;
  event.number = BigEndian(header + 4, 8);
  event.timestamp = BigEndian(header + 12, 8);
  const int64_t channel_bytes = BigEndian(header + 20, 4);
  const int64_t data_bytes = BigEndian(header + 24, 4);
  if (channel_bytes < 1 || channel_bytes > kMaxChannelBytes) {
    return Corrupt(start, "channel length " + std::to_string(channel_bytes) + " (1 to " +
                              std::to_string(kMaxChannelBytes) + ")");
  }
  if (data_bytes < 0 || data_bytes > kMaxEventBytes) {
    return Corrupt(start, "event length " + std::to_string(data_bytes) + " (0 to " +
                              std::to_string(kMaxEventBytes) + ")");
  }
  const int64_t left = size_ - (start + kHeaderBytes);
  if (channel_bytes + data_bytes > left) {
    return Corrupt(start, "the event announces " + std::to_string(channel_bytes + data_bytes) +
                              " bytes, the log has " + std::to_string(left) + " left (truncated?)");
  }
  event.channel.resize(static_cast<size_t>(channel_bytes));
  event.data.resize(static_cast<size_t>(data_bytes));
  if (std::fread(event.channel.data(), 1, event.channel.size(), file_.get()) !=
          event.channel.size() ||
      std::fread(event.data.data(), 1, event.data.size(), file_.get()) != event.data.size()) {
    return Corrupt(start, "read error or the log shrank while being read");
  }
  offset_ = start + kHeaderBytes + channel_bytes + data_bytes;
  return std::optional<LogEvent>(std::move(event));
}

}  // namespace dynapath::protocol
