#pragma once
// Conversions between core/ values and messages. The encodings are exact
// (floats travel as floats, the double tables of --semantics report as
// doubles), which is what keeps distributed results equal to in-process ones.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dynapath/change_sequence.h"
#include "dynapath/changes_t.hpp"
#include "dynapath/convq_training.h"
#include "dynapath/experiment.h"
#include "dynapath/federated_job.h"
#include "dynapath/goal_paths.h"
#include "dynapath/grid.h"
#include "dynapath/grid_t.hpp"
#include "dynapath/job_batch_t.hpp"
#include "dynapath/learner_shard_t.hpp"
#include "dynapath/map_update.h"
#include "dynapath/model_round_t.hpp"
#include "dynapath/model_shards_t.hpp"
#include "dynapath/obstacle_points_t.hpp"
#include "dynapath/obstacle_update_t.hpp"
#include "dynapath/occupancy_grid_t.hpp"
#include "dynapath/path_reply_t.hpp"
#include "dynapath/planner.h"
#include "dynapath/policy_t.hpp"
#include "dynapath/region.h"
#include "dynapath/routes.h"
#include "dynapath/start_statistics.h"
#include "dynapath/step_report_t.hpp"
#include "dynapath/trainer.h"
#include "dynapath/training_job.h"

namespace dynapath::protocol {

// Where a federated job (re)starts: the shared table and start statistics
// after `round` completed rounds.
struct JobProgress {
  int64_t round = 0;
  QTable table;                               // empty: the job's warm start
  std::vector<uint32_t> attempts, successes;  // empty: fresh statistics
};

// Each enum of a batch's header to its wire value, and back (nullopt: no
// enumerator has that wire value). The ...ToWire functions are exhaustive
// switches, so a new enumerator does not compile until it has a wire value.
int8_t LearnerKindToWire(LearnerKind kind);  // job_batch_t::KIND_*
std::optional<LearnerKind> LearnerKindFromWire(int8_t wire);
int8_t BootstrapToWire(Bootstrap bootstrap);  // 0 in-grid, 1 in-region, 2 all stored
std::optional<Bootstrap> BootstrapFromWire(int8_t wire);
int8_t AveragingToWire(Averaging averaging);  // 0 equal, 1 importance
std::optional<Averaging> AveragingFromWire(int8_t wire);

// Fills the batch header (options) from `config`.
void SetBatchOptions(const LearnerConfig& config, job_batch_t& batch);
// Appends `job` (restarting from `progress`) to the batch.
void AddJob(const TrainingJob& job, const JobProgress& progress, job_batch_t& batch);

// The index-th job of a batch as a TrainingJob (warm start = the table it
// restarts from) and where it restarts. Fails when the job is inconsistent
// (e.g. statistics that do not match the region's start cells).
struct ReceivedJob {
  TrainingJob job;
  int64_t start_round = 0;
  std::vector<uint32_t> attempts, successes;
};
Result<ReceivedJob> JobFromBatch(const job_batch_t& batch, int index);

// The wire's PRECISION_* of a table precision, and back (as above).
int8_t PrecisionToWire(QPrecision precision);
std::optional<QPrecision> PrecisionFromWire(int8_t wire);

// A table into a message's (num_values, values, num_wide_values,
// wide_values), by its precision (job_t, job_result_t).
template <typename Message>
void PutTable(const QTable& table, Message& m) {
  m.values.clear();
  m.wide_values.clear();
  if (table.precision() == QPrecision::kFloat) {
    m.values = table.values();
  } else {
    m.wide_values = table.wide_values();
  }
  m.num_values = static_cast<int32_t>(m.values.size());
  m.num_wide_values = static_cast<int32_t>(m.wide_values.size());
}
// The table of `cells` cells and `precision` a (validated) message carries;
// nullopt when it carries no such table (other size or precision).
template <typename Message>
std::optional<QTable> GetTable(const Message& m, int cells, QPrecision precision) {
  const size_t size = static_cast<size_t>(cells) * kNumActions;
  QTable table(cells, precision);
  if (precision == QPrecision::kFloat) {
    if (m.values.size() != size || !m.wide_values.empty()) return std::nullopt;
    table.values() = m.values;
  } else {
    if (m.wide_values.size() != size || !m.values.empty()) return std::nullopt;
    table.wide_values() = m.wide_values;
  }
  return table;
}

learner_shard_t ShardToMessage(const LearnerShard& shard, int job, bool with_visits);
// Visits absent (equal averaging does not use them) become 1 each.
LearnerShard ShardFromMessage(const learner_shard_t& message, int64_t round);

// A round of a federated training of convQ's model (no items: the trainer
// adds them), and back: the training options (threads 1, averaging unset:
// the agents do not average) and the round's model. Messages validated.
model_round_t ModelRoundToMessage(const ConvQTrainingOptions& options, int round,
                                  const ConvQModel& model);
ConvQTrainingOptions ConvQOptionsFromRound(const model_round_t& message);
ConvQModel ConvQModelFromRound(const model_round_t& message);
// Shards of one agent in one round (run id, epoch, round and agent left to
// the caller), and back.
model_shards_t ConvQShardsToMessage(const std::vector<ConvQShard>& shards);
std::vector<ConvQShard> ConvQShardsFromMessage(const model_shards_t& message);

grid_t GridToMessage(const Grid& grid);
Grid GridFromMessage(const grid_t& message);  // message validated
changes_t ChangesToMessage(const ChangeStep& step, int time_step, int total_steps);
// Fails when a cell lies outside a rows x cols grid.
Result<ChangeStep> ChangesFromMessage(const changes_t& message, int rows, int cols);

// The REPORT message of a step's last record (coordinator and service
// alike). `total_steps`: the run's last step (a service, which has none,
// gives the step itself).
step_report_t StepReportToMessage(const std::string& run_id, const std::string& approach,
                                  const ApproachRun& run, const StepRecord& record, int pass,
                                  int total_steps);

// The POLICY message of one step (coordinator and service alike):
// `picture` null for approaches without a table (actions and reaches -1).
policy_t PolicyToMessage(const std::string& run_id, const std::string& approach, int pass,
                         int time_step, const Grid& grid, const PolicyPicture* picture,
                         const std::vector<Region>& trained_regions);

// A (validated) obstacle update for a rows x cols grid whose maze at step 0
// has fingerprint `maze` (MazeFingerprint). Fails, saying why (the refusal
// counted and the error told), when the update names another maze, a cell
// lies outside the grid or a state is neither OBSTACLE nor FREE; the update
// is then refused whole.
Result<MapUpdate, UpdateError> UpdateFromMessage(const obstacle_update_t& message, int rows,
                                                 int cols, uint64_t maze);
// One time step's changes of a `cols`-wide grid as the obstacle update
// that `source` sends as its `sequence`-th, made for the maze of
// fingerprint `maze` (the service's, from its replies); run_id and utime
// are the caller's.
obstacle_update_t UpdateToMessage(const ChangeStep& step, int cols, const std::string& source,
                                  int64_t sequence, uint64_t maze);
// Occupancy thresholds (ROS map_server's meaning and defaults): a value p
// (0..100, percent) is an obstacle when p / 100 > occupied, free when
// p / 100 < free, else (and -1, unknown) it changes nothing.
struct OccupancyThresholds {
  double occupied = 0.65;
  double free = 0.196;
};
// A (validated) occupancy grid as an update of `map` (the service's grid:
// its size and stations) in the map's `frame`: one change per map cell
// under a grid cell whose value is decidedly free or occupied, stations
// left out (they never change). The grid may be a window of the map: data
// row 0 is the grid's bottom row (ROS's origin, see occupancy_grid_t.lcm),
// its bottom-left cell the map cell holding its origin; its cells outside
// the map are ignored (not counted). Fails with kResolution when its
// resolution is not the frame's (within 1e-6 relative), kOffLattice when
// its origin is more than a thousandth of a cell off the map's cell
// corners, kGridShape when it covers no cell of the map.
Result<MapUpdate, UpdateError> UpdateFromOccupancyGrid(const occupancy_grid_t& message,
                                                       const Grid& map, const MapFrame& frame,
                                                       const OccupancyThresholds& thresholds);
// A (validated) obstacle update in metres for the map of `frame` whose
// maze at step 0 has fingerprint `maze`: each point becomes the cell
// holding it (MapFrame::CellAt). Fails as UpdateFromMessage does: a point
// outside the map is kOutsideGrid, and the update is then refused whole.
Result<MapUpdate, UpdateError> UpdateFromPoints(const obstacle_points_t& message,
                                                const MapFrame& frame, uint64_t maze);
// The obstacle update in metres that `source` sends as its `sequence`-th,
// made for the maze of fingerprint `maze`: the points (x, y) of `blocked`
// become obstacles, those of `freed` free, in that order; run_id and utime
// are the caller's.
obstacle_points_t PointsToMessage(const std::vector<std::pair<double, double>>& blocked,
                                  const std::vector<std::pair<double, double>>& freed,
                                  const std::string& source, int64_t sequence, uint64_t maze);

// The reply to request (`client`, `request_id`): `refused` one of
// path_reply_t's ACCEPTED, TOO_MANY_STARTS, NOT_READY; `snapshot` (null
// when not ready) the policy every route came from, `starts` and `routes`
// one per start (empty when refused).
path_reply_t ReplyToMessage(const std::string& client, int64_t request_id, int8_t refused,
                            const std::string& approach, const RouteSnapshot* snapshot,
                            const std::vector<std::pair<int32_t, int32_t>>& starts,
                            const std::vector<Route>& routes);

}  // namespace dynapath::protocol
