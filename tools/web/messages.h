#pragma once
// What `dynapath web` and `dynapath log-to-mcap` make of a run's messages:
//
//   * the page's binary frames: a policy (or the maze) packed one byte per
//     cell, whole or as the cells that changed since the last one;
//   * the page's JSON messages (reports, changes, paths, map updates);
//   * the Foxglove channels' JSON messages and their JSON schemas.
//
// Pure functions, no I/O: the server and the MCAP export share them.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "dynapath/changes_t.hpp"
#include "dynapath/grid_t.hpp"
#include "dynapath/obstacle_points_t.hpp"
#include "dynapath/obstacle_update_t.hpp"
#include "dynapath/path_reply_t.hpp"
#include "dynapath/policy_t.hpp"
#include "dynapath/step_report_t.hpp"
#include "tools/web/service_latency.h"

namespace dynapath::web {

// One cell in one byte: bits 0-1 the cell's code (0 obstacle, 1 free,
// 2 station), bits 2-3 whether its policy reaches a station (0 fails,
// 1 reaches, 2 not a start), bits 4-7 its greedy action (0-7: N, NE, E, SE,
// S, SW, W, NW; 15 none).
uint8_t PackCell(int8_t code, int8_t reaches, int8_t action);
std::vector<uint8_t> PackPolicy(const policy_t& policy);
// A maze alone (grid_t cells): no policy (reaches 2, action 15).
std::vector<uint8_t> PackCodes(const std::vector<int8_t>& codes);

// The page's binary frames (little-endian):
//   u8 kind | u16 n | approach (n bytes) | i32 step | i32 rows | i32 cols |
//   f64 received (ms since the epoch, when the server got the message) |
//   u32 regions | regions x (i32 row0, i32 col0, i32 rows, i32 cols) | body
// kFull's body: rows*cols packed cells; kDelta's: u32 k | k x u32 index |
// k x u8 packed cell; kMaze: rows*cols packed cells of the maze without a
// policy (approach "").
enum class FrameKind : uint8_t { kFull = 1, kDelta = 2, kMaze = 3 };
struct FrameHeader {
  FrameKind kind = FrameKind::kFull;
  std::string approach;
  int32_t step = 0, rows = 0, cols = 0;
  double received_ms = 0;
  std::vector<int32_t> regions;  // 4 per region: row0, col0, rows, cols
};
std::vector<uint8_t> FullFrame(const FrameHeader& header, const std::vector<uint8_t>& cells);
// The cells of `now` that differ from `before` (same size).
std::vector<uint8_t> DeltaFrame(const FrameHeader& header, const std::vector<uint8_t>& before,
                                const std::vector<uint8_t>& now);
// The listed cells of `cells`, as a kDelta frame.
std::vector<uint8_t> DeltaFrame(const FrameHeader& header, const std::vector<uint32_t>& indices,
                                const std::vector<uint8_t>& cells);
// Packs `policy` into `cells` in place (PackPolicy's values), in one pass:
// `changed` gets the indices of the cells whose value changed. False, and
// nothing changed, unless the policy has exactly cells.size() cells (with
// their actions and outcomes).
bool RepackPolicy(const policy_t& policy, std::vector<uint8_t>& cells,
                  std::vector<uint32_t>& changed);
// Reads a frame back (tests, fuzzing): false when it is not one.
bool ParseFrame(const uint8_t* data, size_t size, FrameHeader& header,
                std::vector<uint32_t>& indices, std::vector<uint8_t>& cells);
// Applies a parsed kDelta to `cells`; false when an index is outside.
bool ApplyDelta(const std::vector<uint32_t>& indices, const std::vector<uint8_t>& packed,
                std::vector<uint8_t>& cells);

// The page's JSON text messages ("t" names the kind).
std::string ReportJson(const step_report_t& report, double received_ms);
std::string ChangesJson(const changes_t& changes, double received_ms);
std::string PathsJson(const path_reply_t& reply, double received_ms, int max_paths);
std::string UpdatesJson(const obstacle_update_t& update, double received_ms);
// An obstacle update in metres ("t":"points": x, y, states as sent); the
// page places the points with the map's frame once it has one.
std::string PointsJson(const obstacle_points_t& update, double received_ms);
// {"t":"frame"}: the map's frame (metres a cell, the bottom-left corner of
// the grid) as the service states it in its goal replies.
std::string FrameJson(double resolution, double origin_x, double origin_y);
// {"t":"service","kind":KIND, ...}: one closed window of the service's
// latency; KIND "path" (PATH_REQUEST to PATH_REPLY) or "goal" (GOAL_...).
std::string ServiceJson(const char* kind, const ServiceWindow& window);
std::string HelloJson(const std::string& run_id, const std::string& version, int max_clients);

// Foxglove channels: topic, schema name, JSON schema.
struct FoxgloveChannel {
  uint32_t id;
  std::string topic, schema_name, schema;
};
const std::vector<FoxgloveChannel>& FoxgloveChannels();
// The channel id of a topic, 0 when none.
uint32_t FoxgloveChannelId(std::string_view topic);
// The LCM channel suffix (REPORT, POLICY, ...) a topic comes from.
std::string_view FoxgloveTopicOf(std::string_view lcm_name);

// The Foxglove messages (the schemas' JSON).
std::string GridFoxglove(const grid_t& grid);
std::string PolicyFoxglove(const policy_t& policy);
std::string ReportFoxglove(const step_report_t& report);
std::string ChangesFoxglove(const changes_t& changes);
std::string PathsFoxglove(const path_reply_t& reply);
std::string UpdatesFoxglove(const obstacle_update_t& update);
std::string PointsFoxglove(const obstacle_points_t& update);

// What a Foxglove client may send (text frames): subscribe and unsubscribe.
// Anything else is kUnsupported (answered with a status message); bytes
// that are not a JSON object with a string "op", or whose fields have the
// wrong types, are kMalformed (the connection is closed).
struct ClientMessage {
  enum Kind { kSubscribe, kUnsubscribe, kUnsupported, kMalformed } kind = kMalformed;
  std::vector<std::pair<uint32_t, uint32_t>> subscribe;  // (subscription id, channel id)
  std::vector<uint32_t> unsubscribe;                     // subscription ids
  std::string op;                                        // as sent (kUnsupported)
  std::string why;                                       // kMalformed
};
// At most `max_items` subscriptions per message (more: kMalformed).
ClientMessage ParseClientMessage(std::string_view text, size_t max_items = 256);

// Foxglove's messageData frame: 0x01 | u32 subscription | u64 time (ns) | payload.
std::string MessageDataFrame(uint32_t subscription, uint64_t time_ns, std::string_view payload);

}  // namespace dynapath::web
