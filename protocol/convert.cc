#include "protocol/convert.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "dynapath/learners.h"
#include "protocol/varint.h"

namespace dynapath::protocol {

namespace {

// The enumerator of `all` whose wire value is `wire`.
template <typename Enum, size_t N>
std::optional<Enum> FromWire(int8_t wire, const Enum (&all)[N], int8_t (*to_wire)(Enum)) {
  for (Enum value : all) {
    if (to_wire(value) == wire) return value;
  }
  return std::nullopt;
}

constexpr QPrecision kAllPrecisions[] = {QPrecision::kFloat, QPrecision::kDouble};
constexpr Bootstrap kAllBootstraps[] = {Bootstrap::kInGrid, Bootstrap::kInRegion,
                                        Bootstrap::kAllStored};
constexpr Averaging kAllAveragings[] = {Averaging::kEqual, Averaging::kImportance};

}  // namespace

int8_t LearnerKindToWire(LearnerKind kind) {
  switch (kind) {
    case LearnerKind::kSingleAgent:
      return job_batch_t::KIND_SINGLE_AGENT;
    case LearnerKind::kFedAsynQ:
      return job_batch_t::KIND_FEDASYNQ;
  }
  std::abort();  // not an enumerator: a broken invariant, not input
}

std::optional<LearnerKind> LearnerKindFromWire(int8_t wire) {
  return FromWire(wire, kAllLearnerKinds, &LearnerKindToWire);
}

int8_t PrecisionToWire(QPrecision precision) {
  switch (precision) {
    case QPrecision::kFloat:
      return job_batch_t::PRECISION_FLOAT;
    case QPrecision::kDouble:
      return job_batch_t::PRECISION_DOUBLE;
  }
  std::abort();  // as above
}

std::optional<QPrecision> PrecisionFromWire(int8_t wire) {
  return FromWire(wire, kAllPrecisions, &PrecisionToWire);
}

// 0, 1, 2 as job_batch_t.lcm's comment says (it predates 2; the field is an
// int8 either way, so the fingerprint is unchanged).
int8_t BootstrapToWire(Bootstrap bootstrap) {
  switch (bootstrap) {
    case Bootstrap::kInGrid:
      return 0;
    case Bootstrap::kInRegion:
      return 1;
    case Bootstrap::kAllStored:
      return 2;
  }
  std::abort();  // as above
}

std::optional<Bootstrap> BootstrapFromWire(int8_t wire) {
  return FromWire(wire, kAllBootstraps, &BootstrapToWire);
}

int8_t AveragingToWire(Averaging averaging) {
  switch (averaging) {
    case Averaging::kEqual:
      return 0;
    case Averaging::kImportance:
      return 1;
  }
  std::abort();  // as above
}

std::optional<Averaging> AveragingFromWire(int8_t wire) {
  return FromWire(wire, kAllAveragings, &AveragingToWire);
}

void SetBatchOptions(const LearnerConfig& config, job_batch_t& batch) {
  batch.kind = LearnerKindToWire(config.kind);
  batch.bootstrap = BootstrapToWire(config.bootstrap);
  batch.averaging = AveragingToWire(config.federated.averaging);
  // Every option of core/include/dynapath/learner_options.h to its field of the same name.
#define DYNAPATH_SINGLE_AGENT_TO_WIRE(member, ...) batch.member = config.single_agent.member;
#define DYNAPATH_FEDASYNQ_TO_WIRE(member, ...) batch.member = config.federated.member;
  DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_SINGLE_AGENT_TO_WIRE)
  DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_FEDASYNQ_TO_WIRE)
#undef DYNAPATH_SINGLE_AGENT_TO_WIRE
#undef DYNAPATH_FEDASYNQ_TO_WIRE
}

void AddJob(const TrainingJob& job, const JobProgress& progress, job_batch_t& batch) {
  job_t m{};
  m.node = job.node;
  m.row0 = job.region.r0;
  m.col0 = job.region.c0;
  m.rows = job.region.rows();
  m.cols = job.region.cols();
  m.grid_rows = job.grid_rows;
  m.grid_cols = job.grid_cols;
  m.seed = static_cast<int64_t>(job.seed);
  m.num_cells = static_cast<int32_t>(job.codes.size());
  m.codes.assign(job.codes.begin(), job.codes.end());
  m.start_round = progress.round;
  // Every job of a batch is of the run's precision.
  batch.precision = PrecisionToWire(job.precision);
  const QTable& table = progress.table.cells() == 0 ? job.warm_start : progress.table;
  // An all-zero table (never trained) travels as nothing.
  if (table.cells() != 0 && !table.AllZero()) PutTable(table, m);  // else both counts stay 0
  m.attempts.assign(progress.attempts.begin(), progress.attempts.end());
  m.successes.assign(progress.successes.begin(), progress.successes.end());
  m.num_starts = static_cast<int32_t>(m.attempts.size());
  batch.jobs.push_back(std::move(m));
  batch.num_jobs = static_cast<int32_t>(batch.jobs.size());
}

Result<ReceivedJob> JobFromBatch(const job_batch_t& batch, int index) {
  const job_t& m = batch.jobs[static_cast<size_t>(index)];
  ReceivedJob received;
  TrainingJob& job = received.job;
  job.node = m.node;
  job.region = Region{m.row0, m.row0 + m.rows - 1, m.col0, m.col0 + m.cols - 1};
  job.codes.assign(m.codes.begin(), m.codes.end());
  job.grid_rows = m.grid_rows;
  job.grid_cols = m.grid_cols;
  // The header's enums: Validate has refused unknown values, and an
  // unvalidated batch gets an error here, never a default.
  const std::optional<LearnerKind> kind = LearnerKindFromWire(batch.kind);
  const std::optional<Bootstrap> bootstrap = BootstrapFromWire(batch.bootstrap);
  const std::optional<Averaging> averaging = AveragingFromWire(batch.averaging);
  const std::optional<QPrecision> precision = PrecisionFromWire(batch.precision);
  if (!kind || !bootstrap || !averaging || !precision) {
    return Error::Corrupt(
        "job batch: unknown learner kind, bootstrap, averaging or table precision");
  }
  job.kind = *kind;
  job.bootstrap = *bootstrap;
  job.federated.averaging = *averaging;
  job.precision = *precision;
  // No table (a never-trained region travels as nothing) means zeros;
  // Validate has checked that a table present is of the batch's precision
  // and the region's size.
  job.warm_start =
      GetTable(m, m.num_cells, job.precision).value_or(QTable(m.num_cells, job.precision));
  job.seed = static_cast<uint64_t>(m.seed);
  // Every option of core/include/dynapath/learner_options.h from its field of the same name.
#define DYNAPATH_SINGLE_AGENT_FROM_WIRE(member, ...) job.single_agent.member = batch.member;
#define DYNAPATH_FEDASYNQ_FROM_WIRE(member, ...) job.federated.member = batch.member;
  DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_SINGLE_AGENT_FROM_WIRE)
  DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_FEDASYNQ_FROM_WIRE)
#undef DYNAPATH_SINGLE_AGENT_FROM_WIRE
#undef DYNAPATH_FEDASYNQ_FROM_WIRE
  if (Status checked = CheckJob(job); !checked) {
    return checked.error().Prefixed("job " + std::to_string(index) + ": ");
  }
  received.start_round = m.start_round;
  received.attempts.assign(m.attempts.begin(), m.attempts.end());
  received.successes.assign(m.successes.begin(), m.successes.end());
  if (m.num_starts > 0) {
    if (static_cast<size_t>(m.num_starts) != StartCellCount(job)) {
      return Error::Corrupt("job " + std::to_string(index) +
                            ": start statistics do not match the region's start cells");
    }
  }
  if (TrainsInRounds(job.kind) &&
      received.start_round > FederatedRounds(job.region, job.federated)) {
    return Error::Corrupt("job " + std::to_string(index) + ": start round beyond the job's rounds");
  }
  return received;
}

learner_shard_t ShardToMessage(const LearnerShard& shard, int job, bool with_visits) {
  learner_shard_t m{};
  m.job = job;
  m.learner = shard.learner;
  m.num_entries = static_cast<int32_t>(shard.entries.size());
  m.entry_gaps = EncodeAscending(shard.entries);
  m.entry_bytes = static_cast<int32_t>(m.entry_gaps.size());
  m.values = shard.values;
  m.num_values = static_cast<int32_t>(m.values.size());
  m.wide_values = shard.wide_values;
  m.num_wide_values = static_cast<int32_t>(m.wide_values.size());
  if (with_visits) m.visits = EncodeCounts(shard.visits);
  m.visit_bytes = static_cast<int32_t>(m.visits.size());
  m.start_cell = shard.start_cell;
  m.reached_station = shard.reached_station;
  m.steps = shard.steps;
  return m;
}

LearnerShard ShardFromMessage(const learner_shard_t& m, int64_t round) {
  LearnerShard shard;
  shard.learner = m.learner;
  shard.round = round;
  // The message was validated: the encodings decode.
  DecodeAscending(m.entry_gaps, m.num_entries, shard.entries);
  shard.values = m.values;
  shard.wide_values = m.wide_values;
  if (m.visit_bytes > 0) {
    DecodeCounts(m.visits, m.num_entries, shard.visits);
  } else {
    shard.visits.assign(shard.entries.size(), 1u);
  }
  shard.start_cell = m.start_cell;
  shard.reached_station = m.reached_station;
  shard.steps = m.steps;
  return shard;
}

grid_t GridToMessage(const Grid& grid) {
  grid_t m{};
  m.rows = grid.rows();
  m.cols = grid.cols();
  m.num_cells = grid.size();
  m.cells.assign(grid.codes().begin(), grid.codes().end());
  return m;
}

Grid GridFromMessage(const grid_t& m) {
  Grid grid(m.rows, m.cols);
  for (int i = 0; i < m.num_cells; ++i) grid.set(i, static_cast<Cell>(m.cells[i]));
  return grid;
}

changes_t ChangesToMessage(const ChangeStep& step, int time_step, int total_steps) {
  changes_t m{};
  m.time_step = time_step;
  m.total_steps = total_steps;
  m.requested_moves = step.requested_moves;
  m.num_changes = static_cast<int32_t>(step.changes.size());
  for (const CellChange& change : step.changes) {
    m.cells.push_back(change.cell);
    m.codes.push_back(static_cast<int8_t>(change.code));
  }
  return m;
}

Result<ChangeStep> ChangesFromMessage(const changes_t& m, int rows, int cols) {
  ChangeStep step;
  step.requested_moves = m.requested_moves;
  for (int i = 0; i < m.num_changes; ++i) {
    if (m.cells[i] >= rows * cols) {
      return Error::Corrupt("change of time step " + std::to_string(m.time_step) +
                            " outside the grid");
    }
    step.changes.push_back(CellChange{m.cells[i], static_cast<Cell>(m.codes[i])});
  }
  return step;
}

step_report_t StepReportToMessage(const std::string& run_id, const std::string& approach,
                                  const ApproachRun& run, const StepRecord& record, int pass,
                                  int total_steps) {
  step_report_t report{};
  report.run_id = run_id;
  report.approach = approach;
  report.size_label = run.size_label;
  report.difficulty = run.difficulty_label;
  report.pass = pass;
  report.time_step = record.time_step;
  report.total_steps = total_steps;
  report.num_changes = record.num_changes;
  report.initial_seconds = run.initial_seconds;
  report.adapt_seconds = record.adapt_seconds;
  report.success_rate = record.success_rate;
  report.average_path_length = record.average_path_length;
  report.nodes_trained = record.nodes_trained;
  report.highest_level = record.highest_level;
  return report;
}

policy_t PolicyToMessage(const std::string& run_id, const std::string& approach, int pass,
                         int time_step, const Grid& grid, const PolicyPicture* picture,
                         const std::vector<Region>& trained_regions) {
  policy_t policy{};
  policy.run_id = run_id;
  policy.approach = approach;
  policy.pass = pass;
  policy.time_step = time_step;
  policy.rows = grid.rows();
  policy.cols = grid.cols();
  policy.num_cells = grid.size();
  policy.cells.assign(grid.codes().begin(), grid.codes().end());
  if (picture != nullptr) {
    policy.actions = picture->actions;
    policy.reaches = picture->reaches;
  } else {
    policy.actions.assign(policy.cells.size(), -1);
    policy.reaches.assign(policy.cells.size(), -1);
  }
  for (const Region& region : trained_regions) {
    policy.region_row0.push_back(region.r0);
    policy.region_col0.push_back(region.c0);
    policy.region_rows.push_back(region.rows());
    policy.region_cols.push_back(region.cols());
  }
  policy.num_regions = static_cast<int32_t>(policy.region_row0.size());
  return policy;
}

obstacle_update_t UpdateToMessage(const ChangeStep& step, int cols, const std::string& source,
                                  int64_t sequence, uint64_t maze) {
  obstacle_update_t m{};
  m.source = source;
  m.sequence = sequence;
  m.maze_fingerprint = static_cast<int64_t>(maze);
  for (const CellChange& change : step.changes) {
    m.rows.push_back(change.cell / cols);
    m.cols.push_back(change.cell % cols);
    m.states.push_back(change.code == Cell::kObstacle ? obstacle_update_t::OBSTACLE
                                                      : obstacle_update_t::FREE);
  }
  m.num_cells = static_cast<int32_t>(m.rows.size());
  return m;
}

namespace {

// An obstacle update of either kind (cells or points, whose states share
// their values) for the maze of fingerprint `maze`: `cell_of(i)` is the
// grid index of the message's i-th entry, or why it is refused. Refused
// whole at its first bad entry.
template <class Message, class CellOf>
Result<MapUpdate, UpdateError> UpdateOf(const Message& m, int count, uint64_t maze,
                                        CellOf cell_of) {
  if (static_cast<uint64_t>(m.maze_fingerprint) != maze) {
    return UpdateError{UpdateRefusal::kOtherMaze,
                       Error("an update for the maze of fingerprint " +
                             FingerprintText(static_cast<uint64_t>(m.maze_fingerprint)) + ", not " +
                             FingerprintText(maze))};
  }
  MapUpdate update;
  update.source = m.source;
  update.sequence = m.sequence;
  update.utime = m.utime;
  update.changes.reserve(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    Result<int32_t, UpdateError> cell = cell_of(i);
    if (!cell) return cell.error();
    if (m.states[i] != Message::OBSTACLE && m.states[i] != Message::FREE) {
      return UpdateError{UpdateRefusal::kUnknownState,
                         Error("unknown state " + std::to_string(m.states[i]))};
    }
    const Cell code = m.states[i] == Message::FREE ? Cell::kFree : Cell::kObstacle;
    update.changes.push_back(CellChange{*cell, code});
  }
  return update;
}

}  // namespace

Result<MapUpdate, UpdateError> UpdateFromMessage(const obstacle_update_t& m, int rows, int cols,
                                                 uint64_t maze) {
  return UpdateOf(m, m.num_cells, maze, [&](int i) -> Result<int32_t, UpdateError> {
    const int32_t row = m.rows[i], col = m.cols[i];
    if (row < 0 || row >= rows || col < 0 || col >= cols) {
      return UpdateError{
          UpdateRefusal::kOutsideGrid,
          Error("cell (" + std::to_string(row) + ", " + std::to_string(col) + ") outside the " +
                std::to_string(rows) + "x" + std::to_string(cols) + " grid")};
    }
    return row * cols + col;
  });
}

obstacle_points_t PointsToMessage(const std::vector<std::pair<double, double>>& blocked,
                                  const std::vector<std::pair<double, double>>& freed,
                                  const std::string& source, int64_t sequence, uint64_t maze) {
  obstacle_points_t m{};
  m.source = source;
  m.sequence = sequence;
  m.maze_fingerprint = static_cast<int64_t>(maze);
  for (const auto& [points, state] : {std::pair{&blocked, obstacle_points_t::OBSTACLE},
                                      std::pair{&freed, obstacle_points_t::FREE}}) {
    for (const auto& [x, y] : *points) {
      m.x.push_back(x);
      m.y.push_back(y);
      m.states.push_back(state);
    }
  }
  m.num_points = static_cast<int32_t>(m.x.size());
  return m;
}

Result<MapUpdate, UpdateError> UpdateFromPoints(const obstacle_points_t& m, const MapFrame& frame,
                                                uint64_t maze) {
  return UpdateOf(m, m.num_points, maze, [&](int i) -> Result<int32_t, UpdateError> {
    int row = 0, col = 0;
    if (!frame.CellAt(m.x[i], m.y[i], &row, &col)) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "point (%g, %g) m outside the map (%g m a cell, origin %g, %g)", m.x[i], m.y[i],
                    frame.resolution, frame.origin_x, frame.origin_y);
      return UpdateError{UpdateRefusal::kOutsideGrid, Error(text)};
    }
    return row * frame.cols + col;
  });
}

Result<MapUpdate, UpdateError> UpdateFromOccupancyGrid(const occupancy_grid_t& m, const Grid& map,
                                                       const MapFrame& frame,
                                                       const OccupancyThresholds& thresholds) {
  const double resolution = frame.resolution;
  if (!(std::abs(static_cast<double>(m.resolution) - resolution) <= 1e-6 * resolution)) {
    char text[120];
    std::snprintf(text, sizeof text, "occupancy grid of %g m a cell for a map of %g m a cell",
                  static_cast<double>(m.resolution), resolution);
    return UpdateError{UpdateRefusal::kResolution, Error(text)};
  }
  // The grid's origin in cells of the map from the map's origin.
  const double dx = (m.origin_x - frame.origin_x) / resolution;
  const double dy = (m.origin_y - frame.origin_y) / resolution;
  const double col0 = std::round(dx), bottom0 = std::round(dy);
  if (!(std::abs(dx - col0) <= 1e-3 && std::abs(dy - bottom0) <= 1e-3)) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "occupancy grid origin (%g, %g) m is not on the map's cell corners "
                  "(origin %g, %g, %g m a cell)",
                  m.origin_x, m.origin_y, frame.origin_x, frame.origin_y, resolution);
    return UpdateError{UpdateRefusal::kOffLattice, Error(text)};
  }
  if (col0 >= map.cols() || col0 + m.cols <= 0 || bottom0 >= map.rows() || bottom0 + m.rows <= 0) {
    // The origin's cell as a double: a far origin (1e300 m) has no integer.
    char text[200];
    std::snprintf(text, sizeof text,
                  "occupancy grid of %dx%d cells covers no cell of the map (its origin is cell "
                  "(%.15g, %.15g) from the map's bottom-left)",
                  m.rows, m.cols, bottom0, col0);
    return UpdateError{UpdateRefusal::kGridShape, Error(text)};
  }
  // Now within (-grid side, map side): the overlap in the grid's own cells.
  const int c0 = static_cast<int>(col0), b0 = static_cast<int>(bottom0);
  const int first_col = std::max(0, -c0), end_col = std::min(m.cols, map.cols() - c0);
  const int first_row = std::max(0, -b0), end_row = std::min(m.rows, map.rows() - b0);
  MapUpdate update;
  update.source = m.source;
  update.sequence = m.sequence;
  update.utime = m.utime;
  for (int j = first_row; j < end_row; ++j) {
    const int row = map.rows() - 1 - (b0 + j);  // ROS: data row 0 at the bottom
    for (int i = first_col; i < end_col; ++i) {
      const int8_t value =
          m.data[static_cast<size_t>(j) * static_cast<size_t>(m.cols) + static_cast<size_t>(i)];
      if (value < 0 || value > 100) continue;  // unknown
      const double p = value / 100.0;
      const int cell = map.Index(row, c0 + i);
      if (map.at(cell) == Cell::kStation) continue;
      if (p > thresholds.occupied) {
        update.changes.push_back(CellChange{cell, Cell::kObstacle});
      } else if (p < thresholds.free) {
        update.changes.push_back(CellChange{cell, Cell::kFree});
      }
    }
  }
  return update;
}

path_reply_t ReplyToMessage(const std::string& client, int64_t request_id, int8_t refused,
                            const std::string& approach, const RouteSnapshot* snapshot,
                            const std::vector<std::pair<int32_t, int32_t>>& starts,
                            const std::vector<Route>& routes) {
  path_reply_t m{};
  m.client = client;
  m.request_id = request_id;
  m.refused = refused;
  m.approach = approach;
  if (snapshot != nullptr) {
    m.version = snapshot->version;
    m.time_step = snapshot->time_step;
  }
  const size_t n = refused == path_reply_t::ACCEPTED ? std::min(starts.size(), routes.size()) : 0;
  m.num_starts = static_cast<int32_t>(n);
  size_t cells = 0;
  for (size_t i = 0; i < n; ++i) cells += routes[i].cells.size();
  m.path_rows.reserve(cells);
  m.path_cols.reserve(cells);
  for (size_t i = 0; i < n; ++i) {
    const Route& route = routes[i];
    m.start_rows.push_back(starts[i].first);
    m.start_cols.push_back(starts[i].second);
    m.status.push_back(static_cast<int8_t>(route.status));
    m.answered_by.push_back(static_cast<int8_t>(route.answered_by));
    m.length.push_back(route.length);
    m.path_offset.push_back(static_cast<int32_t>(m.path_rows.size()));
    m.path_cells.push_back(static_cast<int32_t>(route.cells.size()));
    for (int cell : route.cells) {
      m.path_rows.push_back(snapshot->grid.RowOf(cell));
      m.path_cols.push_back(snapshot->grid.ColOf(cell));
    }
  }
  m.num_path = static_cast<int32_t>(m.path_rows.size());
  return m;
}

model_round_t ModelRoundToMessage(const ConvQTrainingOptions& options, int round,
                                  const ConvQModel& model) {
  model_round_t m{};
  m.round = round;
  m.seed = static_cast<int64_t>(options.seed);
  m.rounds = options.rounds;
  m.mazes = options.mazes_per_round;
  m.samples = options.samples_per_maze;
  m.min_side = options.min_side;
  m.max_side = options.max_side;
  m.learners = options.learners;
  const std::array<double, kConvQWeightCount> weights = ConvQWeights(model);
  m.weights.assign(weights.begin(), weights.end());
  m.num_weights = static_cast<int32_t>(m.weights.size());
  return m;
}

ConvQTrainingOptions ConvQOptionsFromRound(const model_round_t& m) {
  ConvQTrainingOptions options;
  options.seed = static_cast<uint64_t>(m.seed);
  options.threads = 1;
  options.rounds = m.rounds;
  options.mazes_per_round = m.mazes;
  options.samples_per_maze = m.samples;
  options.min_side = m.min_side;
  options.max_side = m.max_side;
  options.learners = m.learners;
  return options;
}

ConvQModel ConvQModelFromRound(const model_round_t& m) {
  std::array<double, kConvQWeightCount> weights{};
  for (size_t i = 0; i < kConvQWeightCount; ++i) weights[i] = m.weights[i];
  return ConvQModelFromWeights(weights);
}

model_shards_t ConvQShardsToMessage(const std::vector<ConvQShard>& shards) {
  model_shards_t m{};
  for (const ConvQShard& shard : shards) {
    m.learner.push_back(shard.learner);
    m.samples.push_back(shard.samples);
    m.squared_error.push_back(shard.squared_error);
    for (double weight : ConvQWeights(shard.model)) m.weights.push_back(weight);
  }
  m.num_shards = static_cast<int32_t>(shards.size());
  m.num_weights = static_cast<int32_t>(m.weights.size());
  return m;
}

std::vector<ConvQShard> ConvQShardsFromMessage(const model_shards_t& m) {
  std::vector<ConvQShard> shards(m.learner.size());
  for (size_t i = 0; i < shards.size(); ++i) {
    shards[i].learner = m.learner[i];
    shards[i].samples = m.samples[i];
    shards[i].squared_error = m.squared_error[i];
    std::array<double, kConvQWeightCount> weights{};
    for (size_t w = 0; w < kConvQWeightCount; ++w) {
      weights[w] = m.weights[i * kConvQWeightCount + w];
    }
    shards[i].model = ConvQModelFromWeights(weights);
  }
  return shards;
}

}  // namespace dynapath::protocol
