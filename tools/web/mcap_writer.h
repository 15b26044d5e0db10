#pragma once
// A minimal MCAP writer (https://mcap.dev/spec): the magic, a Header, Schema
// and Channel records, Message records, Data End, a Footer without a summary
// section, the magic again. No chunks, no compression, no index: readers
// (Foxglove, the mcap CLI) scan the data section.

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "dynapath/result.h"

namespace dynapath::web {

inline constexpr char kMcapMagic[] = "\x89MCAP0\r\n";  // 8 bytes

class McapWriter {
 public:
  // Creates `path` (replacing it) and writes the magic and the Header.
  static Result<McapWriter> Create(const std::string& path, const std::string& library);
  McapWriter(McapWriter&& other) noexcept;
  McapWriter& operator=(McapWriter&&) = delete;
  ~McapWriter();

  Status AddSchema(uint16_t id, std::string_view name, std::string_view encoding,
                   std::string_view data);
  Status AddChannel(uint16_t id, uint16_t schema_id, std::string_view topic,
                    std::string_view message_encoding);
  Status AddMessage(uint16_t channel_id, uint32_t sequence, uint64_t log_time_ns,
                    uint64_t publish_time_ns, std::string_view data);
  // Data End, Footer, magic; closes the file.
  Status Finish();

 private:
  McapWriter(std::string path, std::FILE* file) : path_(std::move(path)), file_(file) {}
  Status Record(uint8_t opcode, const std::string& content);

  std::string path_;
  std::FILE* file_ = nullptr;
};

// The statistics of one export.
struct McapExport {
  int64_t events = 0;    // events of the LCM log
  int64_t messages = 0;  // MCAP messages written
  int64_t skipped = 0;   // events of other channels or runs, and fragments
  int64_t dropped = 0;   // undecodable or invalid messages
};

// Writes the messages of the LCM log `in` (every run's, or `run_id`'s) that
// `dynapath web` shows as MCAP at `out`, on the Foxglove channels of
// tools/web/messages.h (JSON with JSON schemas). Fragmented messages are
// reassembled; trailers are stripped unverified (a log is what was
// recorded). Errors: `in` cannot be read or is corrupt; `out` cannot be
// written.
Result<McapExport> LogToMcap(const std::string& in, const std::string& out);

}  // namespace dynapath::web
