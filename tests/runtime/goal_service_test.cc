#include "runtime/goal_service.h"

#include <gtest/gtest.h>

#include <memory>

#include "tests/grid_test_support.h"

namespace dynapath::runtime {
namespace {

std::shared_ptr<const RouteSnapshot> Snapshot(const Grid& grid, int64_t version, int step) {
  auto s = std::make_shared<RouteSnapshot>();
  s->grid = grid;
  s->version = version;
  s->time_step = step;
  return s;
}

goal_request_t CellGoal(int row, int col) {
  goal_request_t r{};
  r.client = "t";
  r.request_id = 1;
  r.goal_kind = goal_request_t::GOAL_CELL;
  r.goal_row = row;
  r.goal_col = col;
  return r;
}

GoalServiceConfig Config(const Grid& grid) {
  GoalServiceConfig config;
  config.frame = MapFrame{0.5, -1.0, 2.0, grid.rows(), grid.cols()};
  config.goals = {NamedGoal{"dock", false, 0, 4, 0, 0}, NamedGoal{"far", true, 0, 0, 1.25, 3.75}};
  config.max_starts = 3;
  return config;
}

// Every kind of goal and start, the bad ones with their statuses, answers
// that follow the committed grid (a wall added at version 2), counts.
TEST(GoalService, AnswersFollowCommitsAndCountBadInput) {
  Grid grid = test_grids::FromText(
      ".....\n"
      ".....\n"
      ".....\n");
  GoalService service(Config(grid));
  goal_request_t early = CellGoal(0, 4);
  EXPECT_EQ(service.Answer(early).refused, goal_reply_t::NOT_READY);
  service.OnCommit(Snapshot(grid, 1, 0));

  goal_request_t to_dock = CellGoal(0, 0);
  to_dock.goal_kind = goal_request_t::GOAL_NAMED;
  to_dock.goal_name = "dock";
  to_dock.num_starts = 1;
  to_dock.start_rows = {2};
  to_dock.start_cols = {0};
  goal_reply_t reply = service.Answer(to_dock);
  ASSERT_EQ(reply.refused, goal_reply_t::ACCEPTED);
  ASSERT_EQ(reply.goal_status, goal_reply_t::GOAL_OK);
  EXPECT_EQ(reply.version, 1);
  EXPECT_EQ(reply.cost[0], 4);  // (2,0) to (0,4): 4 moves
  EXPECT_EQ(reply.num_path, 5);

  // A wall in column 2 but for row 0, then a full wall: unreachable.
  grid.set(1, 2, Cell::kObstacle);
  grid.set(2, 2, Cell::kObstacle);
  service.OnCommit(Snapshot(grid, 2, 1));
  reply = service.Answer(to_dock);
  EXPECT_EQ(reply.version, 2);
  EXPECT_EQ(reply.cost[0], 4);  // (2,0) (1,1) (0,2) (0,3) (0,4)
  grid.set(0, 2, Cell::kObstacle);
  service.OnCommit(Snapshot(grid, 3, 2));
  reply = service.Answer(to_dock);
  EXPECT_EQ(reply.status[0], goal_reply_t::UNREACHABLE);
  EXPECT_EQ(reply.cost[0], -1);

  // Metres: x from -1, y from 2 at the bottom, 0.5 m a cell.
  goal_request_t pose = CellGoal(0, 0);
  pose.goal_kind = goal_request_t::GOAL_POSE;
  pose.goal_x = -0.75;  // col 0
  pose.goal_y = 2.25;   // the bottom row (2)
  pose.num_start_poses = 2;
  pose.start_x = {-0.25, 100.0};  // col 1, row 0; outside
  pose.start_y = {3.4, 2.1};
  reply = service.Answer(pose);
  ASSERT_EQ(reply.goal_status, goal_reply_t::GOAL_OK);
  EXPECT_EQ(reply.goal_row, 2);
  EXPECT_EQ(reply.goal_col, 0);
  EXPECT_EQ(reply.start_rows[0], 0);
  EXPECT_EQ(reply.start_cols[0], 1);
  EXPECT_EQ(reply.cost[0], 2);
  EXPECT_EQ(reply.status[1], goal_reply_t::START_OUTSIDE_MAP);
  EXPECT_DOUBLE_EQ(reply.resolution, 0.5);
  EXPECT_DOUBLE_EQ(reply.origin_x, -1.0);

  // Bad goals and starts.
  EXPECT_EQ(service.Answer(CellGoal(3, 0)).goal_status, goal_reply_t::GOAL_OUTSIDE_GRID);
  EXPECT_EQ(service.Answer(CellGoal(0, 2)).goal_status, goal_reply_t::GOAL_OBSTACLE);
  goal_request_t off = pose;
  off.goal_x = 50;
  EXPECT_EQ(service.Answer(off).goal_status, goal_reply_t::GOAL_OUTSIDE_MAP);
  goal_request_t unknown = to_dock;
  unknown.goal_name = "nowhere";
  EXPECT_EQ(service.Answer(unknown).goal_status, goal_reply_t::GOAL_UNKNOWN_NAME);
  goal_request_t starts = CellGoal(0, 0);
  starts.num_starts = 2;
  starts.start_rows = {1, -5};
  starts.start_cols = {2, 0};
  reply = service.Answer(starts);
  EXPECT_EQ(reply.status[0], goal_reply_t::START_OBSTACLE);
  EXPECT_EQ(reply.status[1], goal_reply_t::START_OUTSIDE_GRID);
  starts.num_starts = 4;
  starts.start_rows = {0, 0, 0, 0};
  starts.start_cols = {0, 0, 0, 0};
  EXPECT_EQ(service.Answer(starts).refused, goal_reply_t::TOO_MANY_STARTS);

  const GoalServiceStats stats = service.stats();
  EXPECT_EQ(stats.refused_not_ready, 1);
  EXPECT_EQ(stats.refused_too_many_starts, 1);
  EXPECT_EQ(stats.by_goal[static_cast<int>(GoalCheck::kOutsideGrid)], 1);
  EXPECT_EQ(stats.by_goal[static_cast<int>(GoalCheck::kObstacle)], 1);
  EXPECT_EQ(stats.by_goal[static_cast<int>(GoalCheck::kOutsideMap)], 1);
  EXPECT_EQ(stats.by_goal[static_cast<int>(GoalCheck::kUnknownName)], 1);
  EXPECT_EQ(stats.by_status[static_cast<int>(GoalStatus::kNoRoute)], 1);
  EXPECT_EQ(stats.by_status[static_cast<int>(GoalStatus::kStartOutsideMap)], 1);
  EXPECT_EQ(stats.by_status[static_cast<int>(GoalStatus::kStartObstacle)], 1);
  EXPECT_NE(GoalService::Summary(stats).find("goal cache:"), std::string::npos);
}

TEST(GoalService, FramesAndGoalsFiles) {
  const Grid grid(4, 6);
  Result<MapFrame> frame = ResolveMapFrame(std::nullopt, 0.25, std::string("-1.5,2"), grid);
  ASSERT_TRUE(frame);
  EXPECT_DOUBLE_EQ(frame->resolution, 0.25);
  EXPECT_DOUBLE_EQ(frame->origin_x, -1.5);
  EXPECT_DOUBLE_EQ(frame->origin_y, 2.0);
  EXPECT_FALSE(ResolveMapFrame(std::nullopt, 0.0, std::nullopt, grid));
  EXPECT_FALSE(ResolveMapFrame(std::nullopt, 1.0, std::string("1;2"), grid));
  EXPECT_FALSE(
      ResolveMapFrame(std::string("docs/examples/maps/office.yaml"), 0.5, std::nullopt, grid));
  Result<MapFrame> ros =
      ResolveMapFrame(std::string(DYNAPATH_SOURCE_DIR "/docs/examples/maps/office.yaml"),
                      std::nullopt, std::nullopt, grid);
  ASSERT_TRUE(ros) << ros.error().message;
  EXPECT_DOUBLE_EQ(ros->resolution, 0.05);
  EXPECT_FALSE(LoadGoalsFile("/nonexistent/goals", *frame));
}

}  // namespace
}  // namespace dynapath::runtime
