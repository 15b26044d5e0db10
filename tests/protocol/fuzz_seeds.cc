// Writes the seed corpora of fuzz/decode_fuzz and fuzz/round_combiner_fuzz
// (committed in fuzz/corpus/; rerun after changing a message type):
//   dynapath_fuzz_seeds fuzz/corpus
// decode_fuzz: messages of every type from the schema encoder plus real
// grid, changes and shards messages; round_combiner_fuzz: the length-
// prefixed shards_t of two agents for the fuzz target's job, two rounds.

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/learn/fedasynq.h"
#include "core/learn/region_model.h"
#include "dynapath/bfs_oracle.h"
#include "dynapath/routes.h"
#include "fuzz/combiner_job.h"
#include "protocol/convert.h"
#include "protocol/round_combiner.h"
#include "tests/protocol/message_types.h"
#include "tests/protocol/schema_encoder.h"

namespace {

using namespace dynapath;

bool Write(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return false;
  std::fwrite(bytes.data(), 1, bytes.size(), file);
  return std::fclose(file) == 0;
}

template <class T>
std::vector<uint8_t> Encoded(const T& message) {
  std::vector<uint8_t> bytes(static_cast<size_t>(message.getEncodedSize()));
  message.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: dynapath_fuzz_seeds CORPUS_DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  bool ok = true;
  protocol::testing::SchemaEncoder encoder(5);
  for (const auto& type : protocol::testing::AllMessageTypes()) {
    const protocol::schema::Type& schema = *protocol::FindSchemaType(type.name);
    for (int count = 0; count < 3; ++count) {
      ok = ok && Write(dir + "/decode_fuzz/" + type.name + "_" + std::to_string(count),
                       encoder.Encode(schema, type.hash, count));
    }
  }
  const Grid grid = *GridFromText(fuzz::kCombinerMap);
  grid_t grid_message = protocol::GridToMessage(grid);
  grid_message.run_id = "r1";
  ok = ok && Write(dir + "/decode_fuzz/grid_valid", Encoded(grid_message));
  ChangeStep step;
  step.requested_moves = 1;
  step.changes.push_back(CellChange{3, Cell::kObstacle});
  changes_t changes = protocol::ChangesToMessage(step, 1, 5);
  changes.run_id = "r1";
  ok = ok && Write(dir + "/decode_fuzz/changes_valid", Encoded(changes));

  // dynapath serve's messages, valid ones (the schema encoder's have
  // mismatched counts).
  obstacle_update_t update{};
  update.run_id = "r1";
  update.source = "lidar";
  update.sequence = 1;
  update.maze_fingerprint = static_cast<int64_t>(MazeFingerprint(grid));
  update.num_cells = 2;
  update.rows = {3, 4};
  update.cols = {5, 6};
  update.states = {obstacle_update_t::OBSTACLE, obstacle_update_t::FREE};
  ok = ok && Write(dir + "/decode_fuzz/obstacle_update_valid", Encoded(update));
  occupancy_grid_t occupancy{};
  occupancy.run_id = "r1";
  occupancy.source = "map";
  occupancy.sequence = 1;
  occupancy.rows = 3;
  occupancy.cols = 4;
  occupancy.num_cells = 12;
  occupancy.data = {0, 100, -1, 50, 0, 0, 0, 100, 100, 0, -1, 0};
  occupancy.resolution = 0.05F;
  occupancy.origin_x = -0.16;
  occupancy.origin_y = 0.0;
  ok = ok && Write(dir + "/decode_fuzz/occupancy_grid_valid", Encoded(occupancy));
  // A window of the fuzzer's 40 x 50 map, 3 cells from its origin.
  occupancy.origin_x = -0.01;
  ok = ok && Write(dir + "/decode_fuzz/occupancy_grid_window", Encoded(occupancy));
  obstacle_points_t points{};
  points.run_id = "r1";
  points.source = "lidar";
  points.sequence = 1;
  points.maze_fingerprint = static_cast<int64_t>(MazeFingerprint(grid));
  points.num_points = 3;
  points.x = {-1.0, 0.5, 2.2};  // the fuzzer's frame: 0.05 m cells from (-1, 2)
  points.y = {2.0, 3.0, 5.2};
  points.states = {obstacle_points_t::OBSTACLE, obstacle_points_t::FREE,
                   obstacle_points_t::OBSTACLE};
  ok = ok && Write(dir + "/decode_fuzz/obstacle_points_valid", Encoded(points));
  // A round of a federated training of convQ's model and an agent's shards
  // of it, valid.
  {
    ConvQTrainingOptions training;
    training.rounds = 3;
    training.mazes_per_round = 3;
    training.samples_per_maze = 16;
    training.min_side = 8;
    training.max_side = 10;
    training.learners = 3;
    model_round_t round = protocol::ModelRoundToMessage(training, 1, InitialConvQModel());
    round.run_id = "r1";
    round.num_items = 3;
    round.item_learner = {0, 1, 2};
    round.item_agent = {1, 1, 2};
    ok = ok && Write(dir + "/decode_fuzz/model_round_valid", Encoded(round));
    model_shards_t shards =
        protocol::ConvQShardsToMessage({TrainConvQLearner(training, InitialConvQModel(), 1, 0),
                                        TrainConvQLearner(training, InitialConvQModel(), 1, 1)});
    shards.run_id = "r1";
    shards.round = 1;
    shards.agent = 1;
    ok = ok && Write(dir + "/decode_fuzz/model_shards_valid", Encoded(shards));
  }
  path_request_t request{};
  request.run_id = "r1";
  request.client = "robot-7";
  request.request_id = 42;
  request.num_starts = 2;
  request.start_rows = {1, 2};
  request.start_cols = {1, 3};
  ok = ok && Write(dir + "/decode_fuzz/path_request_valid", Encoded(request));
  {
    RouteSnapshot snapshot;
    snapshot.grid = grid;
    snapshot.version = 2;
    std::vector<int32_t> queue;
    NearestStationDistances(grid, snapshot.distance, queue);
    std::vector<std::pair<int32_t, int32_t>> starts = {{1, 1}, {-1, 0}};
    std::vector<Route> routes;
    for (const auto& [row, col] : starts) {
      routes.push_back(AnswerRoute(snapshot, row, col, AnswerMode::kExact, 1000));
    }
    path_reply_t reply = protocol::ReplyToMessage("robot-7", 42, path_reply_t::ACCEPTED,
                                                  "fedAsynQ_EqAvg", &snapshot, starts, routes);
    reply.run_id = "r1";
    reply.maze_fingerprint = static_cast<int64_t>(MazeFingerprint(grid));
    ok = ok && Write(dir + "/decode_fuzz/path_reply_valid", Encoded(reply));
  }

  {
    goal_request_t goal{};
    goal.run_id = "r1";
    goal.client = "robot-7";
    goal.request_id = 43;
    goal.goal_kind = goal_request_t::GOAL_POSE;
    goal.goal_x = 2.5;
    goal.goal_y = 1.5;
    goal.num_starts = 1;
    goal.start_rows = {1};
    goal.start_cols = {1};
    goal.num_start_poses = 1;
    goal.start_x = {0.5};
    goal.start_y = {0.5};
    ok = ok && Write(dir + "/decode_fuzz/goal_request_valid", Encoded(goal));
    goal_reply_t reply{};
    reply.run_id = "r1";
    reply.client = "robot-7";
    reply.request_id = 43;
    reply.version = 2;
    reply.rows = 3;
    reply.cols = 4;
    reply.resolution = 1;
    reply.goal_row = 1;
    reply.goal_col = 2;
    reply.num_starts = 2;
    reply.start_rows = {1, 2};
    reply.start_cols = {1, 0};
    reply.status = {goal_reply_t::REACHED, goal_reply_t::START_OBSTACLE};
    reply.answered_by = {goal_reply_t::BY_SEARCH, goal_reply_t::BY_NONE};
    reply.cost = {1, -1};
    reply.path_offset = {0, 2};
    reply.path_cells = {2, 0};
    reply.num_path = 2;
    reply.path_rows = {1, 1};
    reply.path_cols = {1, 2};
    ok = ok && Write(dir + "/decode_fuzz/goal_reply_valid", Encoded(reply));
  }

  // Two rounds of the round combiner target's job (fuzz/round_combiner_fuzz.cc).
  const TrainingJob job = fuzz::CombinerTrainingJob(Averaging::kEqual);
  const RegionModel model(job);
  std::vector<std::unique_ptr<FedAsynQLearner>> learners;
  for (int k = 0; k < 4; ++k) {
    learners.push_back(std::make_unique<FedAsynQLearner>(model, k));
    learners.back()->Reset(StartingTable(job));
  }
  const StartStatistics stats(model.start_cells());
  std::vector<uint8_t> stream = {0};
  for (int64_t round = 0; round < 2; ++round) {
    for (int agent = 1; agent <= 2; ++agent) {
      shards_t message{};
      message.run_id = "r1";
      message.round = round;
      message.agent = agent;
      message.needs_round = round;
      for (int k = 2 * (agent - 1); k < 2 * agent; ++k) {
        const LearnerShard shard = learners[static_cast<size_t>(k)]->RunRound(
            stats, job.seed, round, job.federated.sync_period);
        message.shards.push_back(protocol::ShardToMessage(shard, 0, false));
      }
      message.num_shards = static_cast<int32_t>(message.shards.size());
      const std::vector<uint8_t> bytes = Encoded(message);
      if (round == 0 && agent == 1) ok = ok && Write(dir + "/decode_fuzz/shards_valid", bytes);
      stream.push_back(static_cast<uint8_t>(bytes.size() >> 8));
      stream.push_back(static_cast<uint8_t>(bytes.size()));
      stream.insert(stream.end(), bytes.begin(), bytes.end());
    }
  }
  ok = ok && Write(dir + "/round_combiner_fuzz/two_rounds", stream);
  if (!ok) std::fprintf(stderr, "dynapath_fuzz_seeds: cannot write into %s\n", dir.c_str());
  return ok ? 0 : 1;
}
