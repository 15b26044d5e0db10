// dynapath serve's messages: validation, conversions, and a round trip of
// each through the Bus over memq:// (authenticated; another key dropped
// and counted).

#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include "dynapath/bfs_oracle.h"
#include "protocol/bus.h"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "protocol/decode.h"
#include "protocol/limits.h"
#include "protocol/validate.h"
#include "tests/protocol/validation_problem.h"

namespace dynapath::protocol {
namespace {

obstacle_update_t Update() {
  obstacle_update_t m{};
  m.run_id = "r";
  m.source = "lidar";
  m.sequence = 1;
  m.maze_fingerprint = 77;
  m.num_cells = 2;
  m.rows = {0, 2};
  m.cols = {1, 3};
  m.states = {obstacle_update_t::OBSTACLE, obstacle_update_t::FREE};
  return m;
}

TEST(ServiceMessages, ObstacleUpdateValidationAndConversion) {
  obstacle_update_t m = Update();
  EXPECT_EQ(ValidationProblem(m), "");
  Result<MapUpdate, UpdateError> update = UpdateFromMessage(m, 3, 4, 77);
  ASSERT_TRUE(update.ok());
  ASSERT_EQ(update->changes.size(), 2u);
  EXPECT_EQ(update->changes[0], (CellChange{1, Cell::kObstacle}));
  EXPECT_EQ(update->changes[1], (CellChange{11, Cell::kFree}));
  EXPECT_EQ(update->source, "lidar");

  obstacle_update_t outside = m;
  outside.cols[1] = 4;
  Result<MapUpdate, UpdateError> refused = UpdateFromMessage(outside, 3, 4, 77);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().why, UpdateRefusal::kOutsideGrid);
  EXPECT_EQ(refused.error().error.message, "cell (2, 4) outside the 3x4 grid");
  obstacle_update_t unknown = m;
  unknown.states[0] = 2;
  refused = UpdateFromMessage(unknown, 3, 4, 77);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().why, UpdateRefusal::kUnknownState);
  EXPECT_EQ(refused.error().error.message, "unknown state 2");
  // Made for another maze: refused whole, whatever its cells.
  Result<MapUpdate, UpdateError> foreign = UpdateFromMessage(m, 3, 4, 78);
  ASSERT_FALSE(foreign.ok());
  EXPECT_EQ(foreign.error().why, UpdateRefusal::kOtherMaze);
  EXPECT_NE(foreign.error().error.message.find(FingerprintText(77)), std::string::npos);
  // A step's changes as an update, and back.
  const ChangeStep step{0, {{1, Cell::kObstacle}, {11, Cell::kFree}}};
  const obstacle_update_t sent = UpdateToMessage(step, 4, "feed", 3, 77);
  EXPECT_EQ(ValidationProblem(sent), "");
  EXPECT_EQ(sent.sequence, 3);
  Result<MapUpdate, UpdateError> back = UpdateFromMessage(sent, 3, 4, 77);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->changes, step.changes);

  obstacle_update_t bad = m;
  bad.sequence = 0;
  EXPECT_NE(ValidationProblem(bad), "");
  bad = m;
  bad.source = std::string(65, 'x');
  EXPECT_NE(ValidationProblem(bad), "");
  bad = m;
  bad.num_cells = 3;
  EXPECT_NE(ValidationProblem(bad), "");
  bad = m;
  bad.num_cells = kMaxUpdateCells + 1;
  bad.rows.resize(static_cast<size_t>(bad.num_cells));
  bad.cols.resize(bad.rows.size());
  bad.states.resize(bad.rows.size());
  EXPECT_NE(ValidationProblem(bad), "");
}

TEST(ServiceMessages, OccupancyGridIsRosLayoutWithThresholds) {
  Grid map(2, 3);
  map.set(0, 0, Cell::kStation);
  occupancy_grid_t m{};
  m.run_id = "r";
  m.source = "map";
  m.sequence = 1;
  m.rows = 2;
  m.cols = 3;
  m.num_cells = 6;
  // Data row 0 is the map's bottom row (row 1), row 1 its top (row 0).
  m.data = {100, 10, 30, /*top:*/ 100, -1, 66};
  ASSERT_EQ(ValidationProblem(m), "");
  Result<MapUpdate, UpdateError> update = UpdateFromOccupancyGrid(m, map, {});
  ASSERT_TRUE(update.ok());
  // (1,0) obstacle, (1,1) free, (1,2) 0.30 unchanged; (0,0) a station left
  // out, (0,1) unknown, (0,2) 0.66 obstacle.
  const std::vector<CellChange> expected = {
      {3, Cell::kObstacle}, {4, Cell::kFree}, {2, Cell::kObstacle}};
  EXPECT_EQ(update->changes, expected);
  m.cols = 2;
  m.num_cells = 4;
  m.data.resize(4);
  Result<MapUpdate, UpdateError> refused = UpdateFromOccupancyGrid(m, map, {});
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().why, UpdateRefusal::kGridShape);
  EXPECT_EQ(refused.error().error.message, "occupancy grid of 2x2 cells for a 2x3 map");
}

TEST(ServiceMessages, RequestsAndReplies) {
  path_request_t request{};
  request.client = "robot";
  request.request_id = 1;
  request.num_starts = 1;
  request.start_rows = {0};
  request.start_cols = {0};
  EXPECT_EQ(ValidationProblem(request), "");
  request.num_starts = 0;  // a probe
  request.start_rows.clear();
  request.start_cols.clear();
  EXPECT_EQ(ValidationProblem(request), "");
  request.num_starts = -1;
  EXPECT_NE(ValidationProblem(request), "");

  const Grid grid = *GridFromText("C..\n.#.\n...\n");
  RouteSnapshot snapshot;
  snapshot.grid = grid;
  snapshot.version = 4;
  snapshot.time_step = 3;
  std::vector<int32_t> queue;
  NearestStationDistances(grid, snapshot.distance, queue);
  const std::vector<std::pair<int32_t, int32_t>> starts = {{2, 2}, {1, 1}, {5, 0}};
  std::vector<Route> routes;
  for (const auto& [r, c] : starts)
    routes.push_back(AnswerRoute(snapshot, r, c, AnswerMode::kExact, 99));
  const path_reply_t reply =
      ReplyToMessage("robot", 9, path_reply_t::ACCEPTED, "x", &snapshot, starts, routes);
  EXPECT_EQ(ValidationProblem(reply), "");
  EXPECT_EQ(reply.version, 4);
  EXPECT_EQ(reply.time_step, 3);
  ASSERT_EQ(reply.num_starts, 3);
  EXPECT_EQ(reply.status[0], path_reply_t::REACHED);
  EXPECT_EQ(reply.length[0], 3);  // around the obstacle
  EXPECT_EQ(reply.path_cells[0], 4);
  EXPECT_EQ(reply.path_rows[0], 2);
  EXPECT_EQ(reply.path_rows[3], 0);  // ends on the station
  EXPECT_EQ(reply.path_cols[3], 0);
  EXPECT_EQ(reply.status[1], path_reply_t::START_OBSTACLE);
  EXPECT_EQ(reply.status[2], path_reply_t::OUTSIDE_GRID);
  EXPECT_EQ(reply.answered_by[0], path_reply_t::BY_EXACT);
  // The core enums are the wire's values.
  EXPECT_EQ(static_cast<int8_t>(RouteStatus::kOverBudget), path_reply_t::OVER_BUDGET);
  EXPECT_EQ(static_cast<int8_t>(AnsweredBy::kLearned), path_reply_t::BY_LEARNED);
  const path_reply_t refused =
      ReplyToMessage("robot", 9, path_reply_t::TOO_MANY_STARTS, "x", &snapshot, starts, routes);
  EXPECT_EQ(refused.num_starts, 0);
  EXPECT_EQ(ValidationProblem(refused), "");
  path_reply_t broken = reply;
  broken.path_offset[0] = reply.num_path;
  EXPECT_NE(ValidationProblem(broken), "");
}

TEST(ServiceMessages, BusDeliversAuthenticatedUpdatesAndDropsOthers) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  BusOptions secure;
  secure.key = *KeyFromSecretText(std::string(40, 'a'));
  Bus service(lcm, "r", secure);
  int received = 0;
  service.Subscribe<obstacle_update_t>(channel::kMapUpdates,
                                       [&](obstacle_update_t&) { ++received; });
  BusOptions other;
  other.key = *KeyFromSecretText(std::string(40, 'b'));
  Bus good(lcm, "r", secure), forger(lcm, "r", other);
  good.Publish(channel::kMapUpdates, Update());
  forger.Publish(channel::kMapUpdates, Update());
  for (int i = 0; i < 4; ++i) lcm.handleTimeout(10);
  EXPECT_EQ(received, 1);
  EXPECT_EQ(service.counters().unauthenticated, 1);
}

}  // namespace
}  // namespace dynapath::protocol
