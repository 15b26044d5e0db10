#include "tools/web/messages.h"

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

namespace dynapath::web {
namespace {

using nlohmann::json;

constexpr uint8_t kNoAction = 15;
constexpr uint8_t kNotStart = 2;

template <class T>
void Put(std::vector<uint8_t>& out, T value) {
  uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // little-endian hosts (x86, ARM)
  out.insert(out.end(), bytes, bytes + sizeof(T));
}

template <class T>
bool Get(const uint8_t*& at, const uint8_t* end, T& value) {
  if (static_cast<size_t>(end - at) < sizeof(T)) return false;
  std::memcpy(&value, at, sizeof(T));
  at += sizeof(T);
  return true;
}

void PutHeader(std::vector<uint8_t>& out, const FrameHeader& header) {
  out.push_back(static_cast<uint8_t>(header.kind));
  const size_t name = std::min<size_t>(header.approach.size(), 0xffff);
  Put<uint16_t>(out, static_cast<uint16_t>(name));
  out.insert(out.end(), header.approach.begin(), header.approach.begin() + name);
  Put<int32_t>(out, header.step);
  Put<int32_t>(out, header.rows);
  Put<int32_t>(out, header.cols);
  Put<double>(out, header.received_ms);
  Put<uint32_t>(out, static_cast<uint32_t>(header.regions.size() / 4));
  for (size_t i = 0; i + 3 < header.regions.size(); i += 4) {
    for (size_t k = 0; k < 4; ++k) Put<int32_t>(out, header.regions[i + k]);
  }
}

// Finite numbers only in JSON (NaN would make it invalid).
double Finite(double value) { return std::isfinite(value) ? value : 0.0; }

std::vector<double> FiniteAll(const std::vector<double>& values) {
  std::vector<double> out(values.size());
  for (size_t i = 0; i < values.size(); ++i) out[i] = Finite(values[i]);
  return out;
}

std::string CellString(const std::vector<int8_t>& values, char none) {
  std::string text(values.size(), none);
  for (size_t i = 0; i < values.size(); ++i) {
    if (values[i] >= 0 && values[i] <= 9) text[i] = static_cast<char>('0' + values[i]);
  }
  return text;
}

json Schema(json properties) {
  json schema = {{"type", "object"}, {"properties", std::move(properties)}};
  return schema;
}

}  // namespace

uint8_t PackCell(int8_t code, int8_t reaches, int8_t action) {
  const uint8_t c = code >= 0 && code <= 2 ? static_cast<uint8_t>(code) : 0;
  const uint8_t r = reaches == 0 || reaches == 1 ? static_cast<uint8_t>(reaches) : kNotStart;
  const uint8_t a = action >= 0 && action <= 7 ? static_cast<uint8_t>(action) : kNoAction;
  return static_cast<uint8_t>(c | (r << 2) | (a << 4));
}

std::vector<uint8_t> PackPolicy(const policy_t& policy) {
  std::vector<uint8_t> cells(policy.cells.size());
  if (policy.reaches.size() >= cells.size() && policy.actions.size() >= cells.size()) {
    // A valid policy: one branch-free pass the compiler vectorizes (a
    // 1000x1000 policy is packed at each step).
    const int8_t* code = policy.cells.data();
    const int8_t* reaches = policy.reaches.data();
    const int8_t* action = policy.actions.data();
    for (size_t i = 0; i < cells.size(); ++i) cells[i] = PackCell(code[i], reaches[i], action[i]);
    return cells;
  }
  for (size_t i = 0; i < cells.size(); ++i) {
    cells[i] = PackCell(policy.cells[i], i < policy.reaches.size() ? policy.reaches[i] : -1,
                        i < policy.actions.size() ? policy.actions[i] : -1);
  }
  return cells;
}

std::vector<uint8_t> PackCodes(const std::vector<int8_t>& codes) {
  std::vector<uint8_t> cells(codes.size());
  for (size_t i = 0; i < cells.size(); ++i) cells[i] = PackCell(codes[i], -1, -1);
  return cells;
}

std::vector<uint8_t> FullFrame(const FrameHeader& header, const std::vector<uint8_t>& cells) {
  std::vector<uint8_t> out;
  out.reserve(64 + header.approach.size() + header.regions.size() * 4 + cells.size());
  PutHeader(out, header);
  out.insert(out.end(), cells.begin(), cells.end());
  return out;
}

std::vector<uint8_t> DeltaFrame(const FrameHeader& header, const std::vector<uint8_t>& before,
                                const std::vector<uint8_t>& now) {
  std::vector<uint32_t> indices;
  const size_t n = std::min(before.size(), now.size());
  size_t i = 0;
  // Eight cells at a time where nothing changed (most of a policy, most steps).
  for (; i + 8 <= n; i += 8) {
    uint64_t a, b;
    std::memcpy(&a, before.data() + i, 8);
    std::memcpy(&b, now.data() + i, 8);
    if (a == b) continue;
    for (size_t j = i; j < i + 8; ++j) {
      if (before[j] != now[j]) indices.push_back(static_cast<uint32_t>(j));
    }
  }
  for (; i < n; ++i) {
    if (before[i] != now[i]) indices.push_back(static_cast<uint32_t>(i));
  }
  return DeltaFrame(header, indices, now);
}

std::vector<uint8_t> DeltaFrame(const FrameHeader& header, const std::vector<uint32_t>& indices,
                                const std::vector<uint8_t>& cells) {
  std::vector<uint8_t> out;
  out.reserve(64 + header.approach.size() + header.regions.size() * 4 + indices.size() * 5);
  FrameHeader delta = header;
  delta.kind = FrameKind::kDelta;
  PutHeader(out, delta);
  Put<uint32_t>(out, static_cast<uint32_t>(indices.size()));
  for (uint32_t index : indices) Put<uint32_t>(out, index);
  for (uint32_t index : indices) out.push_back(index < cells.size() ? cells[index] : 0);
  return out;
}

bool RepackPolicy(const policy_t& policy, std::vector<uint8_t>& cells,
                  std::vector<uint32_t>& changed) {
  const size_t n = cells.size();
  if (policy.cells.size() != n || policy.reaches.size() < n || policy.actions.size() < n) {
    return false;
  }
  changed.clear();
  const int8_t* code = policy.cells.data();
  const int8_t* reaches = policy.reaches.data();
  const int8_t* action = policy.actions.data();
  // Blocks of 64 cells packed in one vectorized loop, compared at once.
  constexpr size_t kBlock = 64;
  uint8_t packed[kBlock];
  for (size_t start = 0; start < n; start += kBlock) {
    const size_t m = std::min(kBlock, n - start);
    for (size_t j = 0; j < m; ++j) {
      packed[j] = PackCell(code[start + j], reaches[start + j], action[start + j]);
    }
    if (std::memcmp(packed, cells.data() + start, m) == 0) continue;
    for (size_t j = 0; j < m; ++j) {
      if (packed[j] != cells[start + j]) {
        cells[start + j] = packed[j];
        changed.push_back(static_cast<uint32_t>(start + j));
      }
    }
  }
  return true;
}

bool ParseFrame(const uint8_t* data, size_t size, FrameHeader& header,
                std::vector<uint32_t>& indices, std::vector<uint8_t>& cells) {
  const uint8_t* at = data;
  const uint8_t* end = data + size;
  uint8_t kind = 0;
  uint16_t name = 0;
  uint32_t regions = 0;
  if (!Get(at, end, kind) || kind < 1 || kind > 3 || !Get(at, end, name)) return false;
  if (static_cast<size_t>(end - at) < name) return false;
  header.kind = static_cast<FrameKind>(kind);
  header.approach.assign(reinterpret_cast<const char*>(at), name);
  at += name;
  if (!Get(at, end, header.step) || !Get(at, end, header.rows) || !Get(at, end, header.cols) ||
      !Get(at, end, header.received_ms) || !Get(at, end, regions)) {
    return false;
  }
  if (header.rows < 0 || header.cols < 0 || regions > static_cast<size_t>(end - at) / 16) {
    return false;
  }
  header.regions.assign(size_t{regions} * 4, 0);
  for (int32_t& value : header.regions) Get(at, end, value);
  const uint64_t total = static_cast<uint64_t>(header.rows) * static_cast<uint64_t>(header.cols);
  indices.clear();
  cells.clear();
  if (header.kind == FrameKind::kDelta) {
    uint32_t count = 0;
    if (!Get(at, end, count) || static_cast<uint64_t>(end - at) != uint64_t{count} * 5) {
      return false;
    }
    indices.resize(count);
    for (uint32_t& index : indices) Get(at, end, index);
    cells.assign(at, end);
    for (uint32_t index : indices) {
      if (index >= total) return false;
    }
    return true;
  }
  if (static_cast<uint64_t>(end - at) != total) return false;
  cells.assign(at, end);
  return true;
}

bool ApplyDelta(const std::vector<uint32_t>& indices, const std::vector<uint8_t>& packed,
                std::vector<uint8_t>& cells) {
  if (indices.size() != packed.size()) return false;
  for (size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] >= cells.size()) return false;
    cells[indices[i]] = packed[i];
  }
  return true;
}

std::string ReportJson(const step_report_t& r, double received_ms) {
  json message = {{"t", "report"},
                  {"run", r.run_id},
                  {"approach", r.approach},
                  {"size", r.size_label},
                  {"difficulty", r.difficulty},
                  {"pass", r.pass},
                  {"step", r.time_step},
                  {"steps", r.total_steps},
                  {"changes", r.num_changes},
                  {"initial", Finite(r.initial_seconds)},
                  {"adapt", Finite(r.adapt_seconds)},
                  {"success", Finite(r.success_rate)},
                  {"length", Finite(r.average_path_length)},
                  {"trained", r.nodes_trained},
                  {"level", r.highest_level},
                  {"rx", received_ms}};
  return message.dump();
}

std::string ServiceJson(const char* kind, const ServiceWindow& w) {
  json message = {{"t", "service"},          {"kind", kind},         {"end", w.end_ms},
                  {"requests", w.requests},  {"replies", w.replies}, {"rate", w.per_second},
                  {"p50", w.p50_ms},         {"p99", w.p99_ms},      {"max", w.max_ms},
                  {"unmatched", w.unmatched}};
  return message.dump();
}

std::string ChangesJson(const changes_t& c, double received_ms) {
  json message = {{"t", "changes"},   {"step", c.time_step}, {"steps", c.total_steps},
                  {"cells", c.cells}, {"codes", c.codes},    {"rx", received_ms}};
  return message.dump();
}

std::string PathsJson(const path_reply_t& reply, double received_ms, int max_paths) {
  json paths = json::array();
  for (int i = 0; i < reply.num_starts && i < max_paths; ++i) {
    json cells = json::array();
    const int offset = reply.path_offset[i];
    for (int k = 0; k < reply.path_cells[i]; ++k) {
      cells.push_back(reply.path_rows[offset + k]);
      cells.push_back(reply.path_cols[offset + k]);
    }
    paths.push_back({{"r", reply.start_rows[i]},
                     {"c", reply.start_cols[i]},
                     {"status", reply.status[i]},
                     {"cells", std::move(cells)}});
  }
  json message = {{"t", "paths"},
                  {"client", reply.client},
                  {"step", reply.time_step},
                  {"approach", reply.approach},
                  {"paths", std::move(paths)},
                  {"rx", received_ms}};
  return message.dump();
}

std::string UpdatesJson(const obstacle_update_t& u, double received_ms) {
  json message = {{"t", "updates"}, {"source", u.source}, {"rows", u.rows},
                  {"cols", u.cols}, {"states", u.states}, {"rx", received_ms}};
  return message.dump();
}

std::string PointsJson(const obstacle_points_t& u, double received_ms) {
  json message = {{"t", "points"},       {"source", u.source},  {"sequence", u.sequence},
                  {"x", FiniteAll(u.x)}, {"y", FiniteAll(u.y)}, {"states", u.states},
                  {"rx", received_ms}};
  return message.dump();
}

std::string FrameJson(double resolution, double origin_x, double origin_y) {
  json message = {{"t", "frame"},
                  {"resolution", Finite(resolution)},
                  {"origin_x", Finite(origin_x)},
                  {"origin_y", Finite(origin_y)}};
  return message.dump();
}

std::string HelloJson(const std::string& run_id, const std::string& version, int max_clients) {
  json message = {
      {"t", "hello"}, {"run", run_id}, {"version", version}, {"maxClients", max_clients}};
  return message.dump();
}

const std::vector<FoxgloveChannel>& FoxgloveChannels() {
  static const std::vector<FoxgloveChannel> channels = [] {
    const json integer = {{"type", "integer"}};
    const json number = {{"type", "number"}};
    const json text = {{"type", "string"}};
    const json integers = {{"type", "array"}, {"items", integer}};
    std::vector<FoxgloveChannel> list;
    list.push_back({1, "/grid", "dynapath.Grid",
                    Schema({{"run_id", text},
                            {"rows", integer},
                            {"cols", integer},
                            {"total_steps", integer},
                            {"cells",
                             {{"type", "string"},
                              {"description",
                               "row-major, one digit per cell: 0 obstacle, 1 free, "
                               "2 station"}}}})
                        .dump()});
    list.push_back(
        {2, "/policy", "dynapath.Policy",
         Schema({{"run_id", text},
                 {"approach", text},
                 {"time_step", integer},
                 {"rows", integer},
                 {"cols", integer},
                 {"cells", {{"type", "string"}, {"description", "0 obstacle, 1 free, 2 station"}}},
                 {"actions",
                  {{"type", "string"},
                   {"description", "greedy action per cell: 0-7 N NE E SE S SW W NW, '.' none"}}},
                 {"reaches",
                  {{"type", "string"},
                   {"description", "1 reaches a station, 0 fails, '.' not a start"}}},
                 {"regions",
                  {{"type", "array"},
                   {"items", Schema({{"row0", integer},
                                     {"col0", integer},
                                     {"rows", integer},
                                     {"cols", integer}})}}}})
             .dump()});
    list.push_back({3, "/report", "dynapath.StepReport",
                    Schema({{"run_id", text},
                            {"approach", text},
                            {"size_label", text},
                            {"difficulty", text},
                            {"pass", integer},
                            {"time_step", integer},
                            {"total_steps", integer},
                            {"num_changes", integer},
                            {"initial_seconds", number},
                            {"adapt_seconds", number},
                            {"success_rate", number},
                            {"average_path_length", number},
                            {"nodes_trained", integer},
                            {"highest_level", integer}})
                        .dump()});
    list.push_back({4, "/changes", "dynapath.Changes",
                    Schema({{"run_id", text},
                            {"time_step", integer},
                            {"total_steps", integer},
                            {"cells", integers},
                            {"codes", integers}})
                        .dump()});
    list.push_back(
        {5, "/paths", "dynapath.Paths",
         Schema({{"run_id", text},
                 {"client", text},
                 {"approach", text},
                 {"time_step", integer},
                 {"paths",
                  {{"type", "array"},
                   {"items", Schema({{"row", integer},
                                     {"col", integer},
                                     {"status", integer},
                                     {"length", integer},
                                     {"cells", {{"type", "array"}, {"items", integers}}}})}}}})
             .dump()});
    list.push_back({6, "/map_updates", "dynapath.MapUpdates",
                    Schema({{"run_id", text},
                            {"source", text},
                            {"sequence", integer},
                            {"rows", integers},
                            {"cols", integers},
                            {"states", integers}})
                        .dump()});
    list.push_back(
        {7, "/map_points", "dynapath.MapPoints",
         Schema({{"run_id", text},
                 {"source", text},
                 {"sequence", integer},
                 {"x",
                  {{"type", "array"},
                   {"items", number},
                   {"description", "metres in the map's frame, to the right"}}},
                 {"y",
                  {{"type", "array"},
                   {"items", number},
                   {"description", "metres in the map's frame, up"}}},
                 {"states",
                  {{"type", "array"}, {"items", integer}, {"description", "0 obstacle, 1 free"}}}})
             .dump()});
    return list;
  }();
  return channels;
}

uint32_t FoxgloveChannelId(std::string_view topic) {
  for (const FoxgloveChannel& channel : FoxgloveChannels()) {
    if (channel.topic == topic) return channel.id;
  }
  return 0;
}

std::string_view FoxgloveTopicOf(std::string_view lcm_name) {
  if (lcm_name == "ENV_GRID") return "/grid";
  if (lcm_name == "POLICY") return "/policy";
  if (lcm_name == "REPORT") return "/report";
  if (lcm_name == "ENV_CHANGES") return "/changes";
  if (lcm_name == "PATH_REPLY") return "/paths";
  if (lcm_name == "MAP_UPDATES") return "/map_updates";
  if (lcm_name == "MAP_POINTS") return "/map_points";
  return "";
}

std::string GridFoxglove(const grid_t& grid) {
  json message = {{"run_id", grid.run_id},
                  {"rows", grid.rows},
                  {"cols", grid.cols},
                  {"total_steps", grid.total_steps},
                  {"cells", CellString(grid.cells, '0')}};
  return message.dump();
}

std::string PolicyFoxglove(const policy_t& p) {
  json regions = json::array();
  for (int i = 0; i < p.num_regions; ++i) {
    regions.push_back({{"row0", p.region_row0[i]},
                       {"col0", p.region_col0[i]},
                       {"rows", p.region_rows[i]},
                       {"cols", p.region_cols[i]}});
  }
  json message = {{"run_id", p.run_id},
                  {"approach", p.approach},
                  {"time_step", p.time_step},
                  {"rows", p.rows},
                  {"cols", p.cols},
                  {"cells", CellString(p.cells, '0')},
                  {"actions", CellString(p.actions, '.')},
                  {"reaches", CellString(p.reaches, '.')},
                  {"regions", std::move(regions)}};
  return message.dump();
}

std::string ReportFoxglove(const step_report_t& r) {
  json message = {{"run_id", r.run_id},
                  {"approach", r.approach},
                  {"size_label", r.size_label},
                  {"difficulty", r.difficulty},
                  {"pass", r.pass},
                  {"time_step", r.time_step},
                  {"total_steps", r.total_steps},
                  {"num_changes", r.num_changes},
                  {"initial_seconds", Finite(r.initial_seconds)},
                  {"adapt_seconds", Finite(r.adapt_seconds)},
                  {"success_rate", Finite(r.success_rate)},
                  {"average_path_length", Finite(r.average_path_length)},
                  {"nodes_trained", r.nodes_trained},
                  {"highest_level", r.highest_level}};
  return message.dump();
}

std::string ChangesFoxglove(const changes_t& c) {
  json message = {{"run_id", c.run_id},
                  {"time_step", c.time_step},
                  {"total_steps", c.total_steps},
                  {"cells", c.cells},
                  {"codes", c.codes}};
  return message.dump();
}

std::string PathsFoxglove(const path_reply_t& reply) {
  json paths = json::array();
  for (int i = 0; i < reply.num_starts; ++i) {
    json cells = json::array();
    const int offset = reply.path_offset[i];
    for (int k = 0; k < reply.path_cells[i]; ++k) {
      cells.push_back({reply.path_rows[offset + k], reply.path_cols[offset + k]});
    }
    paths.push_back({{"row", reply.start_rows[i]},
                     {"col", reply.start_cols[i]},
                     {"status", reply.status[i]},
                     {"length", reply.length[i]},
                     {"cells", std::move(cells)}});
  }
  json message = {{"run_id", reply.run_id},
                  {"client", reply.client},
                  {"approach", reply.approach},
                  {"time_step", reply.time_step},
                  {"paths", std::move(paths)}};
  return message.dump();
}

std::string UpdatesFoxglove(const obstacle_update_t& u) {
  json message = {{"run_id", u.run_id}, {"source", u.source}, {"sequence", u.sequence},
                  {"rows", u.rows},     {"cols", u.cols},     {"states", u.states}};
  return message.dump();
}

std::string PointsFoxglove(const obstacle_points_t& u) {
  json message = {{"run_id", u.run_id},  {"source", u.source},  {"sequence", u.sequence},
                  {"x", FiniteAll(u.x)}, {"y", FiniteAll(u.y)}, {"states", u.states}};
  return message.dump();
}

ClientMessage ParseClientMessage(std::string_view text, size_t max_items) {
  ClientMessage result;
  auto malformed = [&](std::string why) {
    result = ClientMessage{};
    result.kind = ClientMessage::kMalformed;
    result.why = std::move(why);
    return result;
  };
  json message = json::parse(text.begin(), text.end(), nullptr, /*allow_exceptions=*/false);
  if (message.is_discarded()) return malformed("not JSON");
  if (!message.is_object()) return malformed("not a JSON object");
  auto op = message.find("op");
  if (op == message.end() || !op->is_string()) return malformed("no string \"op\"");
  result.op = op->get<std::string>();
  auto u32 = [](const json& value, uint32_t& out) {
    if (!value.is_number_unsigned()) return false;
    const uint64_t number = value.get<uint64_t>();
    if (number > 0xffffffffULL) return false;
    out = static_cast<uint32_t>(number);
    return true;
  };
  if (result.op == "subscribe") {
    auto list = message.find("subscriptions");
    if (list == message.end() || !list->is_array()) return malformed("no \"subscriptions\" array");
    if (list->size() > max_items) return malformed("too many subscriptions");
    for (const json& item : *list) {
      uint32_t id = 0, channel = 0;
      if (!item.is_object() || !item.contains("id") || !item.contains("channelId") ||
          !u32(item["id"], id) || !u32(item["channelId"], channel)) {
        return malformed("a subscription needs unsigned 32-bit \"id\" and \"channelId\"");
      }
      result.subscribe.emplace_back(id, channel);
    }
    result.kind = ClientMessage::kSubscribe;
    return result;
  }
  if (result.op == "unsubscribe") {
    auto list = message.find("subscriptionIds");
    if (list == message.end() || !list->is_array()) {
      return malformed("no \"subscriptionIds\" array");
    }
    if (list->size() > max_items) return malformed("too many subscription ids");
    for (const json& item : *list) {
      uint32_t id = 0;
      if (!u32(item, id)) return malformed("a subscription id must be an unsigned 32-bit integer");
      result.unsubscribe.push_back(id);
    }
    result.kind = ClientMessage::kUnsubscribe;
    return result;
  }
  result.kind = ClientMessage::kUnsupported;
  return result;
}

std::string MessageDataFrame(uint32_t subscription, uint64_t time_ns, std::string_view payload) {
  std::string frame;
  frame.reserve(13 + payload.size());
  frame.push_back('\x01');
  for (int i = 0; i < 4; ++i) frame.push_back(static_cast<char>((subscription >> (8 * i)) & 0xff));
  for (int i = 0; i < 8; ++i) frame.push_back(static_cast<char>((time_ns >> (8 * i)) & 0xff));
  frame.append(payload);
  return frame;
}

}  // namespace dynapath::web
