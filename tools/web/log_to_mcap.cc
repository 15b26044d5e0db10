// LogToMcap: an LCM log's run messages as MCAP (tools/web/mcap_writer.h).

#include <cstring>
#include <map>
#include <optional>

#include "dynapath/fragment_t.hpp"
#include "protocol/auth.h"
#include "protocol/decode.h"
#include "protocol/fragments.h"
#include "protocol/limits.h"
#include "protocol/log_reader.h"
#include "protocol/validate.h"
#include "tools/web/mcap_writer.h"
#include "tools/web/messages.h"

namespace dynapath::web {
namespace {

// "DYNAPATH/<run>/<NAME>" -> (run, NAME); nullopt for other channels.
std::optional<std::pair<std::string, std::string>> SplitChannel(const std::string& channel) {
  constexpr std::string_view kPrefix = "DYNAPATH/";
  if (channel.rfind(kPrefix, 0) != 0) return std::nullopt;
  const size_t slash = channel.find('/', kPrefix.size());
  if (slash == std::string::npos || slash == kPrefix.size()) return std::nullopt;
  return std::pair{channel.substr(kPrefix.size(), slash - kPrefix.size()),
                   channel.substr(slash + 1)};
}

int64_t Fingerprint(const uint8_t* data, size_t size) {
  if (size < 8) return 0;
  uint64_t value = 0;
  for (int i = 0; i < 8; ++i) value = (value << 8) | data[i];  // LCM: big-endian
  return static_cast<int64_t>(value);
}

// The JSON of one whole message on channel `name`, or nullopt (dropped:
// `dropped` set, or not shown: other channel).
template <class T, class F>
std::optional<std::string> Convert(const std::vector<uint8_t>& bytes, const std::string& run,
                                   bool& dropped, F to_json) {
  T message;
  if (!protocol::DecodeExactly(bytes.data(), static_cast<int>(bytes.size()), message) ||
      message.run_id != run || !protocol::Validate(message).ok()) {
    dropped = true;
    return std::nullopt;
  }
  return to_json(message);
}

std::optional<std::string> ToJson(const std::string& name, const std::string& run,
                                  const std::vector<uint8_t>& bytes, bool& dropped) {
  if (name == "ENV_GRID") return Convert<grid_t>(bytes, run, dropped, GridFoxglove);
  if (name == "POLICY") return Convert<policy_t>(bytes, run, dropped, PolicyFoxglove);
  if (name == "REPORT") return Convert<step_report_t>(bytes, run, dropped, ReportFoxglove);
  if (name == "ENV_CHANGES") return Convert<changes_t>(bytes, run, dropped, ChangesFoxglove);
  if (name == "PATH_REPLY") return Convert<path_reply_t>(bytes, run, dropped, PathsFoxglove);
  if (name == "MAP_UPDATES") {
    return Convert<obstacle_update_t>(bytes, run, dropped, UpdatesFoxglove);
  }
  if (name == "MAP_POINTS") {
    return Convert<obstacle_points_t>(bytes, run, dropped, PointsFoxglove);
  }
  return std::nullopt;
}

}  // namespace

Result<McapExport> LogToMcap(const std::string& in, const std::string& out) {
  Result<protocol::LogReader> reader = protocol::LogReader::Open(in);
  if (!reader) return reader.error();
  Result<McapWriter> writer = McapWriter::Create(out, "dynapath log-to-mcap");
  if (!writer) return writer.error();
  for (const FoxgloveChannel& channel : FoxgloveChannels()) {
    const uint16_t id = static_cast<uint16_t>(channel.id);
    if (Status s = writer->AddSchema(id, channel.schema_name, "jsonschema", channel.schema); !s) {
      return s.error();
    }
    if (Status s = writer->AddChannel(id, id, channel.topic, "json"); !s) return s.error();
  }
  protocol::FragmentAssembler fragments(protocol::BusFragmentLimits(protocol::kMaxGridCells));
  std::map<uint32_t, uint32_t> sequences;
  McapExport result;
  for (;;) {
    Result<std::optional<protocol::LogEvent>> next = reader->Next();
    if (!next) return next.error();
    if (!next->has_value()) break;
    protocol::LogEvent& event = **next;
    ++result.events;
    std::optional<std::pair<std::string, std::string>> parts = SplitChannel(event.channel);
    if (!parts || FoxgloveTopicOf(parts->second).empty()) {
      ++result.skipped;
      continue;
    }
    const auto& [run, name] = *parts;
    const int size = protocol::PayloadSize(event.data.data(), static_cast<int>(event.data.size()));
    std::vector<uint8_t> bytes(event.data.begin(), event.data.begin() + size);
    if (Fingerprint(bytes.data(), bytes.size()) == static_cast<int64_t>(fragment_t::getHash())) {
      fragment_t fragment;
      if (!protocol::DecodeExactly(bytes.data(), static_cast<int>(bytes.size()), fragment) ||
          fragment.run_id != run || !protocol::Validate(fragment).ok()) {
        ++result.dropped;
        continue;
      }
      // The log's clock (microseconds) in the assembler's (milliseconds).
      protocol::FragmentAssembler::Outcome outcome =
          fragments.Add(event.channel, fragment, event.timestamp / 1000);
      if (outcome.kind == protocol::FragmentAssembler::Outcome::Kind::kDropped) ++result.dropped;
      if (outcome.kind != protocol::FragmentAssembler::Outcome::Kind::kComplete) {
        ++result.skipped;
        continue;
      }
      bytes = std::move(outcome.bytes);
    }
    bool dropped = false;
    std::optional<std::string> json = ToJson(name, run, bytes, dropped);
    if (!json) {
      ++(dropped ? result.dropped : result.skipped);
      continue;
    }
    const uint32_t channel = FoxgloveChannelId(FoxgloveTopicOf(name));
    const uint64_t time_ns = static_cast<uint64_t>(std::max<int64_t>(event.timestamp, 0)) * 1000;
    if (Status s = writer->AddMessage(static_cast<uint16_t>(channel), sequences[channel]++, time_ns,
                                      time_ns, *json);
        !s) {
      return s.error();
    }
    ++result.messages;
  }
  if (Status s = writer->Finish(); !s) return s.error();
  return result;
}

}  // namespace dynapath::web
