// dynapath serve's messages: validation, conversions, and a round trip of
// each through the Bus over memq:// (authenticated; another key dropped
// and counted).

#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>
#include <limits>
#include <utility>
#include <vector>

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
  const MapFrame frame{0.5, -1.0, 2.0, 2, 3};
  occupancy_grid_t m{};
  m.run_id = "r";
  m.source = "map";
  m.sequence = 1;
  m.resolution = 0.5F;
  m.origin_x = -1.0;
  m.origin_y = 2.0;
  m.rows = 2;
  m.cols = 3;
  m.num_cells = 6;
  // Data row 0 is the map's bottom row (row 1), row 1 its top (row 0).
  m.data = {100, 10, 30, /*top:*/ 100, -1, 66};
  ASSERT_EQ(ValidationProblem(m), "");
  Result<MapUpdate, UpdateError> update = UpdateFromOccupancyGrid(m, map, frame, {});
  ASSERT_TRUE(update.ok());
  // (1,0) obstacle, (1,1) free, (1,2) 0.30 unchanged; (0,0) a station left
  // out, (0,1) unknown, (0,2) 0.66 obstacle.
  const std::vector<CellChange> expected = {
      {3, Cell::kObstacle}, {4, Cell::kFree}, {2, Cell::kObstacle}};
  EXPECT_EQ(update->changes, expected);
  // Another resolution, an origin between the map's cell corners.
  occupancy_grid_t other = m;
  other.resolution = 0.25F;
  Result<MapUpdate, UpdateError> refused = UpdateFromOccupancyGrid(other, map, frame, {});
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().why, UpdateRefusal::kResolution);
  EXPECT_EQ(refused.error().error.message,
            "occupancy grid of 0.25 m a cell for a map of 0.5 m a cell");
  other = m;
  other.origin_x = -0.75;
  refused = UpdateFromOccupancyGrid(other, map, frame, {});
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().why, UpdateRefusal::kOffLattice);
  other = m;
  other.origin_y = 2.0 + 1e-9;  // rounding of a publisher's arithmetic: on the lattice
  EXPECT_TRUE(UpdateFromOccupancyGrid(other, map, frame, {}).ok());
  // Wholly beside the map (right of it, then below it).
  other = m;
  other.origin_x = -1.0 + 3 * 0.5;
  refused = UpdateFromOccupancyGrid(other, map, frame, {});
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().why, UpdateRefusal::kGridShape);
  other = m;
  other.origin_y = 2.0 - 2 * 0.5;
  refused = UpdateFromOccupancyGrid(other, map, frame, {});
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().why, UpdateRefusal::kGridShape);
  EXPECT_EQ(refused.error().error.message,
            "occupancy grid of 2x3 cells covers no cell of the map (its origin is cell (-2, 0) "
            "from the map's bottom-left)");
  // An origin far beyond any integer (the fuzzer's find: its cell was cast
  // to an integer for the message).
  other = m;
  other.origin_x = 1e300;
  refused = UpdateFromOccupancyGrid(other, map, frame, {});
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().why, UpdateRefusal::kGridShape);
  EXPECT_NE(refused.error().error.message.find("(0, 2e+300)"), std::string::npos)
      << refused.error().error.message;
  // Validation: a resolution must be above 0, the origin finite.
  other = m;
  other.resolution = 0;
  EXPECT_NE(ValidationProblem(other), "");
  other = m;
  other.origin_x = std::numeric_limits<double>::infinity();
  EXPECT_NE(ValidationProblem(other), "");
}

TEST(ServiceMessages, OccupancyGridWindowsUpdateTheCellsTheyCover) {
  // A 4 x 5 map of 0.1 m cells whose bottom-left corner is at (2, -3) m.
  const Grid map(4, 5);
  const MapFrame frame{0.1, 2.0, -3.0, 4, 5};
  occupancy_grid_t m{};
  m.source = "costmap";
  m.sequence = 1;
  m.resolution = 0.1F;
  m.rows = 2;
  m.cols = 2;
  m.num_cells = 4;
  m.data = {100, 0, /*its top row:*/ 0, 100};
  // Its origin 3 cells right of and 1 cell above the map's: data (0,0) is
  // map column 3 of the row above the bottom (row 2), data (1,1) is
  // column 4 of row 1.
  m.origin_x = 2.0 + 3 * 0.1;
  m.origin_y = -3.0 + 1 * 0.1;
  Result<MapUpdate, UpdateError> update = UpdateFromOccupancyGrid(m, map, frame, {});
  ASSERT_TRUE(update.ok());
  std::vector<CellChange> expected = {{map.Index(2, 3), Cell::kObstacle},
                                      {map.Index(2, 4), Cell::kFree},
                                      {map.Index(1, 3), Cell::kFree},
                                      {map.Index(1, 4), Cell::kObstacle}};
  EXPECT_EQ(update->changes, expected);
  // Over the map's top-right corner: only data (0,0) is on the map (row 0,
  // column 4); the rest is ignored.
  m.origin_x = 2.0 + 4 * 0.1;
  m.origin_y = -3.0 + 3 * 0.1;
  update = UpdateFromOccupancyGrid(m, map, frame, {});
  ASSERT_TRUE(update.ok());
  expected = {{map.Index(0, 4), Cell::kObstacle}};
  EXPECT_EQ(update->changes, expected);
  // Over the bottom-left corner: only data (1,1) is on the map (row 3,
  // column 0).
  m.origin_x = 2.0 - 0.1;
  m.origin_y = -3.0 - 0.1;
  update = UpdateFromOccupancyGrid(m, map, frame, {});
  ASSERT_TRUE(update.ok());
  expected = {{map.Index(3, 0), Cell::kObstacle}};
  EXPECT_EQ(update->changes, expected);
  // Larger than the map on every side, at an offset: the map's cells only,
  // in the order of the grid's data.
  occupancy_grid_t big = m;
  big.rows = 8;
  big.cols = 9;
  big.num_cells = 72;
  big.data.assign(72, 0);
  big.data[static_cast<size_t>(2 * 9 + 3)] = 100;  // grid row 2 from the bottom, column 3
  big.origin_x = 2.0 - 2 * 0.1;
  big.origin_y = -3.0 - 1 * 0.1;
  update = UpdateFromOccupancyGrid(big, map, frame, {});
  ASSERT_TRUE(update.ok());
  ASSERT_EQ(update->changes.size(), 20u);
  // Map row 2 (second from the bottom), column 1.
  int obstacles = 0;
  for (const CellChange& change : update->changes) {
    if (change.code == Cell::kObstacle) {
      ++obstacles;
      EXPECT_EQ(change.cell, map.Index(2, 1));
    }
  }
  EXPECT_EQ(obstacles, 1);
  EXPECT_EQ(update->changes.front().cell, map.Index(3, 0));
  EXPECT_EQ(update->changes.back().cell, map.Index(0, 4));
}

TEST(ServiceMessages, ObstaclePointsBecomeTheCellsHoldingThem) {
  // A 3 x 4 map of 0.5 m cells whose bottom-left corner is at (-1, 2) m:
  // x from -1 to 1, y from 2 to 3.5.
  const MapFrame frame{0.5, -1.0, 2.0, 3, 4};
  obstacle_points_t m{};
  m.run_id = "r";
  m.source = "lidar";
  m.sequence = 1;
  m.maze_fingerprint = 77;
  m.num_points = 4;
  // The bottom-left corner itself; a point on a border between columns 1
  // and 2 (the right one's); the top-right cell just inside; a cell centre.
  m.x = {-1.0, 0.0, 0.999, -0.75};
  m.y = {2.0, 2.75, 3.499, 3.25};
  m.states = {obstacle_points_t::OBSTACLE, obstacle_points_t::FREE, obstacle_points_t::OBSTACLE,
              obstacle_points_t::FREE};
  ASSERT_EQ(ValidationProblem(m), "");
  Result<MapUpdate, UpdateError> update = UpdateFromPoints(m, frame, 77);
  ASSERT_TRUE(update.ok());
  const std::vector<CellChange> expected = {{2 * 4 + 0, Cell::kObstacle},
                                            {1 * 4 + 2, Cell::kFree},
                                            {0 * 4 + 3, Cell::kObstacle},
                                            {0 * 4 + 0, Cell::kFree}};
  EXPECT_EQ(update->changes, expected);
  EXPECT_EQ(update->source, "lidar");
  EXPECT_EQ(update->sequence, 1);
  // The top and right borders of the map are outside it; so is anything
  // below or left of the origin.
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{
           {1.0, 2.5}, {0.0, 3.5}, {-1.0001, 2.5}, {0.0, 1.9999}}) {
    obstacle_points_t outside = m;
    outside.x[1] = x;
    outside.y[1] = y;
    Result<MapUpdate, UpdateError> refused = UpdateFromPoints(outside, frame, 77);
    ASSERT_FALSE(refused.ok()) << x << "," << y;
    EXPECT_EQ(refused.error().why, UpdateRefusal::kOutsideGrid);
  }
  obstacle_points_t outside = m;
  outside.x[1] = 1.0;
  EXPECT_EQ(UpdateFromPoints(outside, frame, 77).error().error.message,
            "point (1, 2.75) m outside the map (0.5 m a cell, origin -1, 2)");
  obstacle_points_t unknown = m;
  unknown.states[0] = 2;
  Result<MapUpdate, UpdateError> refused = UpdateFromPoints(unknown, frame, 77);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().why, UpdateRefusal::kUnknownState);
  refused = UpdateFromPoints(m, frame, 78);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().why, UpdateRefusal::kOtherMaze);

  obstacle_points_t bad = m;
  bad.sequence = 0;
  EXPECT_NE(ValidationProblem(bad), "");
  bad = m;
  bad.source = "";
  EXPECT_NE(ValidationProblem(bad), "");
  bad = m;
  bad.num_points = 5;
  EXPECT_NE(ValidationProblem(bad), "");
  bad = m;
  bad.y.pop_back();
  EXPECT_NE(ValidationProblem(bad), "");
  bad = m;
  bad.x[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(ValidationProblem(bad), "");
  bad = m;
  bad.num_points = kMaxUpdateCells + 1;
  bad.x.resize(static_cast<size_t>(bad.num_points));
  bad.y.resize(bad.x.size());
  bad.states.resize(bad.x.size());
  EXPECT_NE(ValidationProblem(bad), "");
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
  int points_received = 0;
  service.Subscribe<obstacle_points_t>(channel::kMapPoints,
                                       [&](obstacle_points_t&) { ++points_received; });
  BusOptions other;
  other.key = *KeyFromSecretText(std::string(40, 'b'));
  Bus good(lcm, "r", secure), forger(lcm, "r", other);
  good.Publish(channel::kMapUpdates, Update());
  forger.Publish(channel::kMapUpdates, Update());
  for (int i = 0; i < 4; ++i) lcm.handleTimeout(10);
  EXPECT_EQ(received, 1);
  EXPECT_EQ(service.counters().unauthenticated, 1);
  // Points in metres likewise.
  obstacle_points_t points{};
  points.run_id = "r";
  points.source = "lidar";
  points.sequence = 1;
  points.num_points = 1;
  points.x = {0.5};
  points.y = {0.5};
  points.states = {obstacle_points_t::OBSTACLE};
  good.Publish(channel::kMapPoints, points);
  forger.Publish(channel::kMapPoints, points);
  for (int i = 0; i < 4; ++i) lcm.handleTimeout(10);
  EXPECT_EQ(points_received, 1);
  EXPECT_EQ(service.counters().unauthenticated, 2);
}

}  // namespace
}  // namespace dynapath::protocol
