#include "protocol/validate.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "dynapath/convq_model.h"
#include "dynapath/learner_options.h"
#include "dynapath/learners.h"
#include "dynapath/mdp.h"
#include "protocol/convert.h"
#include "protocol/fragments.h"
#include "protocol/limits.h"
#include "protocol/varint.h"

namespace dynapath::protocol {
namespace {

bool Count(int32_t count, size_t size) { return count >= 0 && static_cast<size_t>(count) == size; }

template <typename V>
bool Finite(const std::vector<V>& values) {
  for (V v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

bool Codes(const std::vector<int8_t>& codes) {
  for (int8_t c : codes) {
    if (c < 0 || c > 2) return false;
  }
  return true;
}

bool GridSize(int32_t rows, int32_t cols) {
  return rows >= 1 && cols >= 1 && rows <= kMaxGridSide && cols <= kMaxGridSide;
}

// Every region and count computed from received fields is computed in 64
// bits: int32 fields near INT_MAX must not wrap into range.
int64_t Wide(int32_t value) { return value; }

// [first, first + length) lies inside [0, limit).
bool Inside(int32_t first, int32_t length, int32_t limit) {
  return first >= 0 && length >= 1 && Wide(first) + Wide(length) <= Wide(limit);
}

}  // namespace

Status Validate(const heartbeat_t& m) {
  if (m.role < heartbeat_t::ROLE_COORDINATOR || m.role > heartbeat_t::ROLE_ENVSIM) {
    return Error::Corrupt("unknown role");
  }
  if (m.state < heartbeat_t::STATE_RUNNING || m.state > heartbeat_t::STATE_FAILED) {
    return Error::Corrupt("unknown state");
  }
  if (m.sender < 0 || m.threads < 0 || m.epoch < 0) return Error::Corrupt("negative field");
  return Ok{};
}

Status Validate(const step_request_t& m) {
  if (m.pass < 0 || m.time_step < 0) return Error::Corrupt("negative pass or time step");
  return Ok{};
}

Status Validate(const grid_t& m) {
  if (!GridSize(m.rows, m.cols)) return Error::Corrupt("bad grid size");
  if (Wide(m.num_cells) != Wide(m.rows) * Wide(m.cols) || !Count(m.num_cells, m.cells.size())) {
    return Error::Corrupt("cell count does not match rows x cols");
  }
  if (!Codes(m.cells)) return Error::Corrupt("bad cell code");
  if (m.total_steps < 0 || m.pass < 0) return Error::Corrupt("negative steps or pass");
  return Ok{};
}

Status Validate(const changes_t& m) {
  if (m.time_step < 1 || m.time_step > m.total_steps) {
    return Error::Corrupt("time step out of range");
  }
  if (!Count(m.num_changes, m.cells.size()) || m.codes.size() != m.cells.size()) {
    return Error::Corrupt("change count mismatch");
  }
  if (m.requested_moves < 0 || m.pass < 0) return Error::Corrupt("negative field");
  for (int32_t cell : m.cells) {
    if (cell < 0 || Wide(cell) >= Wide(kMaxGridSide) * kMaxGridSide) {
      return Error::Corrupt("cell out of range");
    }
  }
  if (!Codes(m.codes)) return Error::Corrupt("bad cell code");
  return Ok{};
}

Status Validate(const job_batch_t& m) {
  if (m.batch_id < 0 || m.epoch < 0) return Error::Corrupt("negative batch or epoch");
  const std::optional<LearnerKind> kind = LearnerKindFromWire(m.kind);
  if (!kind) return Error::Corrupt("unknown learner kind");
  if (!BootstrapFromWire(m.bootstrap) || !AveragingFromWire(m.averaging)) {
    return Error::Corrupt("bad bootstrap or averaging");
  }
  const std::optional<QPrecision> precision = PrecisionFromWire(m.precision);
  if (!precision) return Error::Corrupt("unknown table precision");
    // The ranges of core/include/dynapath/learner_options.h.
#define DYNAPATH_CHECK_OPTION(group, member, type, default_value, report, min, max, help) \
  if (!learner_option::InRange<type>(m.member, min, max)) {                               \
    return Error::Corrupt("bad " group " option " #member);                               \
  }
#define DYNAPATH_CHECK_FEDASYNQ_OPTION(...) DYNAPATH_CHECK_OPTION("federated", __VA_ARGS__)
#define DYNAPATH_CHECK_SINGLE_AGENT_OPTION(...) DYNAPATH_CHECK_OPTION("single-agent", __VA_ARGS__)
  DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_CHECK_FEDASYNQ_OPTION)
  DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_CHECK_SINGLE_AGENT_OPTION)
#undef DYNAPATH_CHECK_SINGLE_AGENT_OPTION
#undef DYNAPATH_CHECK_FEDASYNQ_OPTION
#undef DYNAPATH_CHECK_OPTION
  if (!Count(m.num_jobs, m.jobs.size())) return Error::Corrupt("job count mismatch");
  for (const job_t& job : m.jobs) {
    if (!GridSize(job.grid_rows, job.grid_cols) || !Inside(job.row0, job.rows, job.grid_rows) ||
        !Inside(job.col0, job.cols, job.grid_cols)) {
      return Error::Corrupt("job region outside its grid");
    }
    if (job.node < 0) return Error::Corrupt("negative node");
    if (Wide(job.num_cells) != Wide(job.rows) * Wide(job.cols) ||
        !Count(job.num_cells, job.codes.size())) {
      return Error::Corrupt("job cell count mismatch");
    }
    if (!Codes(job.codes)) return Error::Corrupt("bad cell code");
    // The table travels in the batch's precision, or not at all (zeros).
    const int32_t table_size =
        *precision == QPrecision::kFloat ? job.num_values : job.num_wide_values;
    const int32_t other_size =
        *precision == QPrecision::kFloat ? job.num_wide_values : job.num_values;
    if (!Count(job.num_values, job.values.size()) ||
        !Count(job.num_wide_values, job.wide_values.size()) || other_size != 0 ||
        (table_size != 0 && Wide(table_size) != Wide(job.num_cells) * kNumActions)) {
      return Error::Corrupt("job table size mismatch");
    }
    if (!Finite(job.values) || !Finite(job.wide_values)) {
      return Error::Corrupt("job table not finite");
    }
    if (job.start_round < 0) return Error::Corrupt("negative start round");
    if (!Count(job.num_starts, job.attempts.size()) ||
        job.successes.size() != job.attempts.size()) {
      return Error::Corrupt("start statistics size mismatch");
    }
    for (size_t i = 0; i < job.attempts.size(); ++i) {
      if (job.attempts[i] < 0 || job.successes[i] < 0 || job.successes[i] > job.attempts[i]) {
        return Error::Corrupt("bad start statistics");
      }
    }
  }
  if (!Count(m.num_items, m.item_job.size()) || m.item_learner.size() != m.item_job.size() ||
      m.item_agent.size() != m.item_job.size()) {
    return Error::Corrupt("item count mismatch");
  }
  for (int32_t i = 0; i < m.num_items; ++i) {
    if (m.item_job[i] < 0 || m.item_job[i] >= m.num_jobs) {
      return Error::Corrupt("item job out of range");
    }
    if (m.item_learner[i] < -1 || m.item_learner[i] >= m.learners) {
      return Error::Corrupt("item learner out of range");
    }
    // Only a learner that trains in rounds can be split over agents.
    if (m.item_learner[i] >= 0 && !TrainsInRounds(*kind))
      return Error::Corrupt("split item of a whole-job learner");
    if (m.item_agent[i] < 0) return Error::Corrupt("negative agent id");
  }
  return Ok{};
}

Status Validate(const shards_t& m) {
  if (m.batch_id < 0 || m.epoch < 0 || m.round < 0 || m.agent < 0 || m.needs_round < 0) {
    return Error::Corrupt("negative field");
  }
  if (!Count(m.num_shards, m.shards.size())) return Error::Corrupt("shard count mismatch");
  std::vector<uint32_t> decoded;
  for (const learner_shard_t& s : m.shards) {
    if (s.job < 0 || s.learner < 0 || s.steps < 0 || s.start_cell < -1) {
      return Error::Corrupt("negative field in a shard");
    }
    if (!Count(s.entry_bytes, s.entry_gaps.size()) ||
        !DecodeAscending(s.entry_gaps, s.num_entries, decoded)) {
      return Error::Corrupt("shard entries malformed");
    }
    // One value per entry, all float or all double.
    if (!Count(s.num_values, s.values.size()) || !Count(s.num_wide_values, s.wide_values.size()) ||
        (s.num_values != 0 && s.num_wide_values != 0) ||
        Wide(s.num_values) + Wide(s.num_wide_values) != Wide(s.num_entries)) {
      return Error::Corrupt("shard values malformed");
    }
    if (!Count(s.visit_bytes, s.visits.size()) ||
        (s.visit_bytes != 0 && !DecodeCounts(s.visits, s.num_entries, decoded))) {
      return Error::Corrupt("shard visit counts malformed");
    }
    if (!Finite(s.values) || !Finite(s.wide_values)) {
      return Error::Corrupt("shard value not finite");
    }
  }
  return Ok{};
}

namespace {
// Ok when weights[first, first + kConvQWeightCount) are a model inside its bounds.
Status ModelWeights(const std::vector<double>& weights, size_t first) {
  std::array<double, kConvQWeightCount> w{};
  for (size_t i = 0; i < kConvQWeightCount; ++i) w[i] = weights[first + i];
  if (Status checked = CheckConvQModel(ConvQModelFromWeights(w)); !checked) {
    return Error::Corrupt(checked.error().message);
  }
  return Ok{};
}
}  // namespace

Status Validate(const model_round_t& m) {
  if (m.epoch < 0 || m.round < 1 || m.round > m.rounds || m.seed < 0) {
    return Error::Corrupt("epoch, round or seed out of range");
  }
  if (m.rounds > 10000 || m.mazes < 1 || m.mazes > 4096 || m.samples < 1 || m.samples > 1000000) {
    return Error::Corrupt("training sizes out of range");
  }
  if (m.min_side < 2 || m.min_side > m.max_side || m.max_side > kMaxModelMazeSide) {
    return Error::Corrupt("maze sides out of range");
  }
  if (m.learners < 1 || m.learners > kMaxModelLearners) {
    return Error::Corrupt("learner count out of range");
  }
  if (!Count(m.num_weights, m.weights.size()) ||
      m.num_weights != static_cast<int32_t>(kConvQWeightCount)) {
    return Error::Corrupt("weight count mismatch");
  }
  if (Status model = ModelWeights(m.weights, 0); !model) return model.error().Prefixed("model: ");
  if (!Count(m.num_items, m.item_learner.size()) || !Count(m.num_items, m.item_agent.size()) ||
      m.num_items > m.learners) {
    return Error::Corrupt("item count mismatch");
  }
  std::vector<bool> seen(static_cast<size_t>(m.learners), false);
  for (int i = 0; i < m.num_items; ++i) {
    const int32_t learner = m.item_learner[static_cast<size_t>(i)];
    if (learner < 0 || learner >= m.learners || seen[static_cast<size_t>(learner)]) {
      return Error::Corrupt("item learner out of range or repeated");
    }
    seen[static_cast<size_t>(learner)] = true;
    if (m.item_agent[static_cast<size_t>(i)] < 0) return Error::Corrupt("negative item agent");
  }
  return Ok{};
}

Status Validate(const model_shards_t& m) {
  if (m.epoch < 0 || m.round < 1 || m.agent < 0) return Error::Corrupt("negative field");
  if (m.num_shards < 1 || m.num_shards > kMaxModelLearners ||
      !Count(m.num_shards, m.learner.size()) || !Count(m.num_shards, m.samples.size()) ||
      !Count(m.num_shards, m.squared_error.size())) {
    return Error::Corrupt("shard count mismatch");
  }
  if (!Count(m.num_weights, m.weights.size()) ||
      Wide(m.num_weights) != Wide(m.num_shards) * static_cast<int64_t>(kConvQWeightCount)) {
    return Error::Corrupt("weight count mismatch");
  }
  for (size_t i = 0; i < m.learner.size(); ++i) {
    if (m.learner[i] < 0 || m.learner[i] >= kMaxModelLearners) {
      return Error::Corrupt("learner out of range");
    }
    if (m.samples[i] < 0) return Error::Corrupt("negative sample count");
    if (!std::isfinite(m.squared_error[i]) || m.squared_error[i] < 0) {
      return Error::Corrupt("squared error not finite or negative");
    }
    if (Status model = ModelWeights(m.weights, i * kConvQWeightCount); !model) {
      return model.error().Prefixed("shard of learner " + std::to_string(m.learner[i]) + ": ");
    }
  }
  return Ok{};
}

Status Validate(const job_result_t& m) {
  if (m.batch_id < 0 || m.epoch < 0 || m.agent < 0 || m.job < 0) {
    return Error::Corrupt("negative field");
  }
  if (m.episodes_or_rounds < 0 || m.steps < 0) return Error::Corrupt("negative counts");
  if (!Count(m.num_values, m.values.size()) || !Count(m.num_wide_values, m.wide_values.size()) ||
      m.num_values % kNumActions != 0 || m.num_wide_values % kNumActions != 0 ||
      (m.num_values != 0 && m.num_wide_values != 0)) {
    return Error::Corrupt("table size mismatch");
  }
  if (!Finite(m.values) || !Finite(m.wide_values)) return Error::Corrupt("table not finite");
  return Ok{};
}

Status Validate(const fragment_t& m) {
  if (m.count < 1 || m.index < 0 || m.index >= m.count) return Error::Corrupt("bad fragment index");
  if (m.total_size < 1 || m.offset < 0 || !Count(m.size, m.data.size()) ||
      static_cast<int64_t>(m.offset) + m.size > m.total_size) {
    return Error::Corrupt("bad fragment size");
  }
  if (m.group_size < 0 || m.group_size == 1) return Error::Corrupt("bad parity group size");
  if (m.parity &&
      (m.group_size == 0 || m.index >= ParityGroups(m.count, m.group_size) || m.offset != 0)) {
    return Error::Corrupt("bad parity piece");
  }
  return Ok{};
}

Status Validate(const fragment_nack_t& m) {
  if (m.count < 1 || m.channel.empty() || m.channel.size() > 256) {
    return Error::Corrupt("bad nack header");
  }
  if (!Count(m.bitmap_size, m.missing.size()) || Wide(m.bitmap_size) != (Wide(m.count) + 7) / 8) {
    return Error::Corrupt("nack bitmap size mismatch");
  }
  return Ok{};
}

Status Validate(const step_report_t& m) {
  if (m.time_step < 0 || m.time_step > m.total_steps || m.pass < 0) {
    return Error::Corrupt("bad time step");
  }
  if (!std::isfinite(m.success_rate) || !std::isfinite(m.average_path_length) ||
      !std::isfinite(m.adapt_seconds) || !std::isfinite(m.initial_seconds)) {
    return Error::Corrupt("figure not finite");
  }
  return Ok{};
}

Status Validate(const policy_t& m) {
  if (!GridSize(m.rows, m.cols)) return Error::Corrupt("bad grid size");
  if (Wide(m.num_cells) != Wide(m.rows) * Wide(m.cols) || !Count(m.num_cells, m.cells.size()) ||
      m.actions.size() != m.cells.size() || m.reaches.size() != m.cells.size()) {
    return Error::Corrupt("cell count mismatch");
  }
  if (!Codes(m.cells)) return Error::Corrupt("bad cell code");
  for (size_t i = 0; i < m.cells.size(); ++i) {
    if (m.actions[i] < -1 || m.actions[i] >= kNumActions) return Error::Corrupt("bad action");
    if (m.reaches[i] < -1 || m.reaches[i] > 1) return Error::Corrupt("bad reach flag");
  }
  if (!Count(m.num_regions, m.region_row0.size()) || m.region_col0.size() != m.region_row0.size() ||
      m.region_rows.size() != m.region_row0.size() ||
      m.region_cols.size() != m.region_row0.size()) {
    return Error::Corrupt("region count mismatch");
  }
  for (int32_t i = 0; i < m.num_regions; ++i) {
    if (!Inside(m.region_row0[i], m.region_rows[i], m.rows) ||
        !Inside(m.region_col0[i], m.region_cols[i], m.cols)) {
      return Error::Corrupt("region outside the grid");
    }
  }
  return Ok{};
}

namespace {

bool PeerName(const std::string& name) { return !name.empty() && name.size() <= kMaxPeerNameChars; }

}  // namespace

Status Validate(const obstacle_update_t& m) {
  if (!PeerName(m.source)) return Error::Corrupt("source name must have 1-64 characters");
  if (m.sequence < 1) return Error::Corrupt("sequence numbers start at 1");
  if (m.num_cells < 0 || m.num_cells > kMaxUpdateCells) return Error::Corrupt("too many cells");
  if (!Count(m.num_cells, m.rows.size()) || m.cols.size() != m.rows.size() ||
      m.states.size() != m.rows.size()) {
    return Error::Corrupt("cell count mismatch");
  }
  return Ok{};
}

Status Validate(const obstacle_points_t& m) {
  if (!PeerName(m.source)) return Error::Corrupt("source name must have 1-64 characters");
  if (m.sequence < 1) return Error::Corrupt("sequence numbers start at 1");
  if (m.num_points < 0 || m.num_points > kMaxUpdateCells) return Error::Corrupt("too many points");
  if (!Count(m.num_points, m.x.size()) || m.y.size() != m.x.size() ||
      m.states.size() != m.x.size()) {
    return Error::Corrupt("point count mismatch");
  }
  for (size_t i = 0; i < m.x.size(); ++i) {
    if (!std::isfinite(m.x[i]) || !std::isfinite(m.y[i])) {
      return Error::Corrupt("non-finite coordinate");
    }
  }
  return Ok{};
}

Status Validate(const occupancy_grid_t& m) {
  if (!PeerName(m.source)) return Error::Corrupt("source name must have 1-64 characters");
  if (m.sequence < 1) return Error::Corrupt("sequence numbers start at 1");
  if (!std::isfinite(m.resolution) || !(m.resolution > 0)) {
    return Error::Corrupt("resolution must be finite and above 0");
  }
  if (!std::isfinite(m.origin_x) || !std::isfinite(m.origin_y)) {
    return Error::Corrupt("non-finite origin");
  }
  if (!GridSize(m.rows, m.cols)) return Error::Corrupt("bad grid size");
  if (Wide(m.num_cells) != Wide(m.rows) * Wide(m.cols) || !Count(m.num_cells, m.data.size())) {
    return Error::Corrupt("cell count does not match rows x cols");
  }
  return Ok{};
}

Status Validate(const path_request_t& m) {
  if (!PeerName(m.client)) return Error::Corrupt("client name must have 1-64 characters");
  // No starts: a probe (the service's maze, version and step).
  if (m.num_starts < 0 || m.num_starts > kMaxRequestStarts) {
    return Error::Corrupt("bad number of starts");
  }
  if (!Count(m.num_starts, m.start_rows.size()) || m.start_cols.size() != m.start_rows.size()) {
    return Error::Corrupt("start count mismatch");
  }
  return Ok{};
}

Status Validate(const path_reply_t& m) {
  if (!PeerName(m.client)) return Error::Corrupt("client name must have 1-64 characters");
  if (m.refused < path_reply_t::ACCEPTED || m.refused > path_reply_t::NOT_READY) {
    return Error::Corrupt("unknown refusal");
  }
  const size_t n = m.start_rows.size();
  if (!Count(m.num_starts, n) || m.start_cols.size() != n || m.status.size() != n ||
      m.answered_by.size() != n || m.length.size() != n || m.path_offset.size() != n ||
      m.path_cells.size() != n) {
    return Error::Corrupt("start count mismatch");
  }
  if (!Count(m.num_path, m.path_rows.size()) || m.path_cols.size() != m.path_rows.size()) {
    return Error::Corrupt("path count mismatch");
  }
  for (size_t i = 0; i < n; ++i) {
    if (m.status[i] < path_reply_t::REACHED || m.status[i] > path_reply_t::OVER_BUDGET) {
      return Error::Corrupt("unknown status");
    }
    if (m.answered_by[i] < path_reply_t::BY_NONE || m.answered_by[i] > path_reply_t::BY_EXACT) {
      return Error::Corrupt("unknown answerer");
    }
    if (m.path_offset[i] < 0 || m.path_cells[i] < 0 ||
        Wide(m.path_offset[i]) + Wide(m.path_cells[i]) > Wide(m.num_path)) {
      return Error::Corrupt("path outside the reply");
    }
  }
  return Ok{};
}

Status Validate(const goal_request_t& m) {
  if (!PeerName(m.client)) return Error::Corrupt("client name must have 1-64 characters");
  if (m.goal_kind < goal_request_t::GOAL_CELL || m.goal_kind > goal_request_t::GOAL_NAMED) {
    return Error::Corrupt("unknown goal kind");
  }
  if (m.goal_kind == goal_request_t::GOAL_NAMED && !PeerName(m.goal_name)) {
    return Error::Corrupt("goal name must have 1-64 characters");
  }
  if (m.goal_name.size() > kMaxPeerNameChars) return Error::Corrupt("goal name too long");
  if (m.num_starts < 0 || m.num_starts > kMaxRequestStarts || m.num_start_poses < 0 ||
      m.num_start_poses > kMaxRequestStarts ||
      Wide(m.num_starts) + Wide(m.num_start_poses) > kMaxRequestStarts) {
    return Error::Corrupt("bad number of starts");
  }
  if (!Count(m.num_starts, m.start_rows.size()) || m.start_cols.size() != m.start_rows.size() ||
      !Count(m.num_start_poses, m.start_x.size()) || m.start_y.size() != m.start_x.size()) {
    return Error::Corrupt("start count mismatch");
  }
  // Non-finite coordinates are the service's to answer (outside the map).
  return Ok{};
}

Status Validate(const goal_reply_t& m) {
  if (!PeerName(m.client)) return Error::Corrupt("client name must have 1-64 characters");
  if (m.refused < goal_reply_t::ACCEPTED || m.refused > goal_reply_t::NOT_READY) {
    return Error::Corrupt("unknown refusal");
  }
  if (m.goal_status < goal_reply_t::GOAL_OK || m.goal_status > goal_reply_t::GOAL_UNKNOWN_NAME) {
    return Error::Corrupt("unknown goal status");
  }
  const size_t n = m.start_rows.size();
  if (!Count(m.num_starts, n) || m.start_cols.size() != n || m.status.size() != n ||
      m.answered_by.size() != n || m.cost.size() != n || m.path_offset.size() != n ||
      m.path_cells.size() != n) {
    return Error::Corrupt("start count mismatch");
  }
  if (!Count(m.num_path, m.path_rows.size()) || m.path_cols.size() != m.path_rows.size()) {
    return Error::Corrupt("path count mismatch");
  }
  for (size_t i = 0; i < n; ++i) {
    if (m.status[i] < goal_reply_t::REACHED || m.status[i] > goal_reply_t::OVER_BUDGET) {
      return Error::Corrupt("unknown status");
    }
    if (m.answered_by[i] < goal_reply_t::BY_NONE || m.answered_by[i] > goal_reply_t::BY_SEARCH) {
      return Error::Corrupt("unknown answerer");
    }
    if (m.path_offset[i] < 0 || m.path_cells[i] < 0 ||
        Wide(m.path_offset[i]) + Wide(m.path_cells[i]) > Wide(m.num_path)) {
      return Error::Corrupt("path outside the reply");
    }
  }
  return Ok{};
}

}  // namespace dynapath::protocol
