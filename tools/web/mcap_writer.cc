#include "tools/web/mcap_writer.h"

#include <cerrno>
#include <cstring>

namespace dynapath::web {
namespace {

void U8(std::string& out, uint8_t value) { out.push_back(static_cast<char>(value)); }
template <class T>
void Little(std::string& out, T value) {
  for (size_t i = 0; i < sizeof(T); ++i) {
    out.push_back(static_cast<char>((static_cast<uint64_t>(value) >> (8 * i)) & 0xff));
  }
}
void String(std::string& out, std::string_view text) {
  Little<uint32_t>(out, static_cast<uint32_t>(text.size()));
  out.append(text);
}

}  // namespace

Result<McapWriter> McapWriter::Create(const std::string& path, const std::string& library) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) {
    const int error = errno;
    return Error::File(error, "cannot write " + path + ": " + std::strerror(error));
  }
  McapWriter writer(path, file);
  if (std::fwrite(kMcapMagic, 1, 8, file) != 8) return Error::Io("cannot write " + path);
  std::string header;
  String(header, "");  // profile
  String(header, library);
  if (Status status = writer.Record(0x01, header); !status) return status.error();
  return writer;
}

McapWriter::McapWriter(McapWriter&& other) noexcept
    : path_(std::move(other.path_)), file_(other.file_) {
  other.file_ = nullptr;
}

McapWriter::~McapWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

Status McapWriter::Record(uint8_t opcode, const std::string& content) {
  std::string record;
  U8(record, opcode);
  Little<uint64_t>(record, content.size());
  record += content;
  if (file_ == nullptr || std::fwrite(record.data(), 1, record.size(), file_) != record.size()) {
    return Error::Io("cannot write " + path_);
  }
  return Ok{};
}

Status McapWriter::AddSchema(uint16_t id, std::string_view name, std::string_view encoding,
                             std::string_view data) {
  std::string content;
  Little<uint16_t>(content, id);
  String(content, name);
  String(content, encoding);
  String(content, data);  // uint32 length-prefixed bytes
  return Record(0x03, content);
}

Status McapWriter::AddChannel(uint16_t id, uint16_t schema_id, std::string_view topic,
                              std::string_view message_encoding) {
  std::string content;
  Little<uint16_t>(content, id);
  Little<uint16_t>(content, schema_id);
  String(content, topic);
  String(content, message_encoding);
  Little<uint32_t>(content, 0);  // metadata: an empty map
  return Record(0x04, content);
}

Status McapWriter::AddMessage(uint16_t channel_id, uint32_t sequence, uint64_t log_time_ns,
                              uint64_t publish_time_ns, std::string_view data) {
  std::string content;
  content.reserve(22 + data.size());
  Little<uint16_t>(content, channel_id);
  Little<uint32_t>(content, sequence);
  Little<uint64_t>(content, log_time_ns);
  Little<uint64_t>(content, publish_time_ns);
  content.append(data);
  return Record(0x05, content);
}

Status McapWriter::Finish() {
  std::string data_end;
  Little<uint32_t>(data_end, 0);  // data section CRC: 0, not computed
  if (Status status = Record(0x0F, data_end); !status) return status;
  std::string footer;
  Little<uint64_t>(footer, 0);  // summary start: no summary section
  Little<uint64_t>(footer, 0);  // summary offset start
  Little<uint32_t>(footer, 0);  // summary CRC
  if (Status status = Record(0x02, footer); !status) return status;
  if (std::fwrite(kMcapMagic, 1, 8, file_) != 8) return Error::Io("cannot write " + path_);
  const int closed = std::fclose(file_);
  file_ = nullptr;
  if (closed != 0) return Error::Io("cannot write " + path_);
  return Ok{};
}

}  // namespace dynapath::web
