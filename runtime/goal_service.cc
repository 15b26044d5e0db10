#include "runtime/goal_service.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "dynapath/ros_map.h"
#include "dynapath/text_file.h"
#include "runtime/path_service.h"

namespace dynapath::runtime {

GoalService::GoalService(GoalServiceConfig config)
    : config_(std::move(config)), planner_(config_.planner) {
  for (const NamedGoal& goal : config_.goals) {
    int row = goal.row, col = goal.col;
    if (goal.metres && !config_.frame.CellAt(goal.x, goal.y, &row, &col)) {
      row = col = -1;  // LoadGoalsFile refuses these; a caller's own are answered outside
    }
    named_[goal.name] = {row, col};
  }
  stats_.cache = planner_.stats();
}

void GoalService::OnCommit(const std::shared_ptr<const RouteSnapshot>& snapshot) {
  std::lock_guard lock(mutex_);
  const Grid* old = planner_.grid();
  const Grid& grid = snapshot->grid;
  if (old == nullptr || old->rows() != grid.rows() || old->cols() != grid.cols() ||
      old->codes() != grid.codes()) {
    changed_.clear();
    if (old != nullptr && old->size() == grid.size()) {
      const std::vector<uint8_t>& a = old->codes();
      const std::vector<uint8_t>& b = grid.codes();
      for (size_t i = 0; i < a.size(); ++i) {
        if (a[i] != b[i]) changed_.push_back(static_cast<int>(i));
      }
    }
    planner_.Update(std::shared_ptr<const Grid>(snapshot, &snapshot->grid), changed_);
  }
  snapshot_ = snapshot;  // keeps the planner's grid alive
  version_ = snapshot->version;
  time_step_ = snapshot->time_step;
}

goal_reply_t GoalService::Answer(const goal_request_t& request) {
  goal_reply_t m{};
  m.client = request.client;
  m.request_id = request.request_id;
  m.goal_row = m.goal_col = -1;
  std::lock_guard lock(mutex_);
  ++stats_.requests;
  const MapFrame& frame = config_.frame;
  m.rows = frame.rows;
  m.cols = frame.cols;
  m.resolution = frame.resolution;
  m.origin_x = frame.origin_x;
  m.origin_y = frame.origin_y;
  m.version = version_;
  m.time_step = time_step_;
  if (planner_.grid() == nullptr) {
    m.refused = goal_reply_t::NOT_READY;
    ++stats_.refused_not_ready;
    return m;
  }
  const int64_t starts = int64_t{request.num_starts} + request.num_start_poses;
  if (starts > config_.max_starts) {
    m.refused = goal_reply_t::TOO_MANY_STARTS;
    ++stats_.refused_too_many_starts;
    return m;
  }
  // The goal's cell.
  GoalCheck check = GoalCheck::kOk;
  int goal_row = -1, goal_col = -1;
  if (request.goal_kind == goal_request_t::GOAL_CELL) {
    goal_row = request.goal_row;
    goal_col = request.goal_col;
  } else if (request.goal_kind == goal_request_t::GOAL_POSE) {
    if (!frame.CellAt(request.goal_x, request.goal_y, &goal_row, &goal_col)) {
      check = GoalCheck::kOutsideMap;
    }
  } else if (auto it = named_.find(request.goal_name); it != named_.end()) {
    goal_row = it->second.first;
    goal_col = it->second.second;
  } else {
    check = GoalCheck::kUnknownName;
  }
  if (check == GoalCheck::kOk) check = planner_.CheckGoal(goal_row, goal_col);
  if (check != GoalCheck::kOutsideMap && check != GoalCheck::kUnknownName &&
      planner_.grid()->InBounds(goal_row, goal_col)) {
    m.goal_row = goal_row;
    m.goal_col = goal_col;
  }
  m.goal_status = static_cast<int8_t>(check);
  ++stats_.by_goal[static_cast<size_t>(check)];
  if (check != GoalCheck::kOk) {
    stats_.cache = planner_.stats();
    return m;
  }
  size_t budget = config_.reply_budget;
  auto add = [&](int row, int col, const GoalPath& path) {
    m.start_rows.push_back(row);
    m.start_cols.push_back(col);
    m.status.push_back(static_cast<int8_t>(path.status));
    m.answered_by.push_back(static_cast<int8_t>(path.source));
    m.cost.push_back(path.cost);
    m.path_offset.push_back(static_cast<int32_t>(m.path_rows.size()));
    m.path_cells.push_back(static_cast<int32_t>(path.cells.size()));
    const Grid& grid = *planner_.grid();
    for (int32_t cell : path.cells) {
      m.path_rows.push_back(grid.RowOf(cell));
      m.path_cols.push_back(grid.ColOf(cell));
    }
    budget -= std::min(budget, path.cells.size());
    ++stats_.by_status[static_cast<size_t>(path.status)];
    if (path.status == GoalStatus::kReached) {
      if (path.source == GoalSource::kField) ++stats_.by_field;
      if (path.source == GoalSource::kSearch) ++stats_.by_search;
    }
  };
  for (int32_t i = 0; i < request.num_starts; ++i) {
    const int row = request.start_rows[static_cast<size_t>(i)];
    const int col = request.start_cols[static_cast<size_t>(i)];
    add(row, col, planner_.Plan(row, col, goal_row, goal_col, budget));
  }
  for (int32_t i = 0; i < request.num_start_poses; ++i) {
    int row = -1, col = -1;
    if (!frame.CellAt(request.start_x[static_cast<size_t>(i)],
                      request.start_y[static_cast<size_t>(i)], &row, &col)) {
      GoalPath outside;
      outside.status = GoalStatus::kStartOutsideMap;
      add(-1, -1, outside);
      continue;
    }
    add(row, col, planner_.Plan(row, col, goal_row, goal_col, budget));
  }
  m.num_starts = static_cast<int32_t>(m.start_rows.size());
  m.num_path = static_cast<int32_t>(m.path_rows.size());
  stats_.cache = planner_.stats();
  return m;
}

void GoalService::RecordLatency(int64_t micros) {
  std::lock_guard lock(mutex_);
  stats_.latency.Add(micros);
}

GoalServiceStats GoalService::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

std::string GoalService::Summary(const GoalServiceStats& s) {
  std::string text = "goals: " + std::to_string(s.requests) + " requests (refused " +
                     std::to_string(s.refused_too_many_starts) + " too many starts, " +
                     std::to_string(s.refused_not_ready) + " not ready; goals: ";
  for (int i = 0; i < kGoalCheckCount; ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(s.by_goal[i]) + " " + GoalCheckName(static_cast<GoalCheck>(i));
  }
  text += "; starts: ";
  for (int i = 0; i < kGoalStatusCount; ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(s.by_status[i]) + " " + GoalStatusName(static_cast<GoalStatus>(i));
  }
  text += "; reached from a field " + std::to_string(s.by_field) + ", by search " +
          std::to_string(s.by_search) + ")\n";
  const GoalCacheStats& c = s.cache;
  char line[640];
  std::snprintf(line, sizeof line,
                "goal cache: %lld hits, %lld misses, %lld evictions, %lld fields built (%lld "
                "being built), %lld repaired, %lld rebuilt, %lld dropped as dearer to repair "
                "than to search; %lld fields and %lld landmarks in %.1f MB (peak %.1f, "
                "cap %.1f); %lld searches, %lld proved unreachable\n",
                static_cast<long long>(c.hits), static_cast<long long>(c.misses),
                static_cast<long long>(c.evictions), static_cast<long long>(c.builds),
                static_cast<long long>(c.pending), static_cast<long long>(c.repairs),
                static_cast<long long>(c.rebuilds), static_cast<long long>(c.dropped_costly),
                static_cast<long long>(c.fields), static_cast<long long>(c.landmarks),
                static_cast<double>(c.bytes) / 1048576.0,
                static_cast<double>(c.peak_bytes) / 1048576.0,
                static_cast<double>(c.cap_bytes) / 1048576.0, static_cast<long long>(c.searches),
                static_cast<long long>(c.proved_unreachable));
  text += line;
  text += PathService::LatencyLine("goal", s.latency, "requests");
  return text;
}

Result<MapFrame> ResolveMapFrame(const std::optional<std::string>& maze_path,
                                 const std::optional<double>& resolution,
                                 const std::optional<std::string>& origin, const Grid& grid) {
  MapFrame frame;
  frame.rows = grid.rows();
  frame.cols = grid.cols();
  if (maze_path && IsRosMapPath(*maze_path)) {
    if (resolution || origin) {
      return Error(
          "--resolution and --origin are for maps without a frame: a ROS map's YAML sets both");
    }
    Result<std::string> yaml = ReadTextFile(*maze_path);
    if (!yaml) return yaml.error();
    Result<RosMapInfo> info = ParseRosMapYaml(*yaml);
    if (!info) return Error(*maze_path + ": " + info.error().message);
    frame.resolution = info->resolution;
    frame.origin_x = info->origin[0];
    frame.origin_y = info->origin[1];
  } else {
    frame.resolution = resolution.value_or(1.0);
    if (origin) {
      const size_t comma = origin->find(',');
      char* end_x = nullptr;
      char* end_y = nullptr;
      const std::string xs = origin->substr(0, comma);
      const std::string ys = comma == std::string::npos ? "" : origin->substr(comma + 1);
      frame.origin_x = std::strtod(xs.c_str(), &end_x);
      frame.origin_y = std::strtod(ys.c_str(), &end_y);
      if (comma == std::string::npos || xs.empty() || ys.empty() ||
          end_x != xs.c_str() + xs.size() || end_y != ys.c_str() + ys.size()) {
        return Error("--origin must be X,Y in metres, got '" + *origin + "'");
      }
    }
  }
  if (Status ok = CheckFrame(frame.resolution, frame.origin_x, frame.origin_y); !ok) {
    return Error("the map's frame: " + ok.error().message);
  }
  return frame;
}

Result<std::vector<NamedGoal>> LoadGoalsFile(const std::string& path, const MapFrame& frame) {
  Result<std::string> text = ReadTextFile(path);
  if (!text) return text.error();
  if (text->size() > (size_t{16} << 20)) return Error(path + ": larger than 16 MiB");
  Result<std::vector<NamedGoal>> goals = ParseGoalsText(*text);
  if (!goals) return Error(path + ": " + goals.error().message);
  for (const NamedGoal& goal : *goals) {
    int row = goal.row, col = goal.col;
    if (goal.metres && !frame.CellAt(goal.x, goal.y, &row, &col)) {
      return Error(path + ": goal '" + goal.name + "' lies outside the map");
    }
    if (row < 0 || row >= frame.rows || col < 0 || col >= frame.cols) {
      return Error(path + ": goal '" + goal.name + "' lies outside the grid");
    }
  }
  return goals;
}

void DeclareGoalOptions(OptionGroup& group, GoalOptions& options) {
  group.Option("--goals", options.goals_file, "FILE",
               "named goals for goal requests, one per line: NAME ROW,COL (a cell) or NAME X,Y "
               "(metres, numbers with a point)");
  group.Option("--goal-cache-mb", options.cache_mb, "MB",
               "memory of the goal distance fields, landmarks and fields being built included "
               "(2 bytes a free cell each; 0-65536, 0: every goal searched)",
               "256");
  DeclareMapFrameOptions(group, options.resolution, options.origin);
}

void DeclareMapFrameOptions(OptionGroup& group, std::optional<double>& resolution,
                            std::optional<std::string>& origin) {
  group.Option("--resolution", resolution, "METRES",
               "metres per cell of a map without a frame, for poses, obstacle points and "
               "occupancy grids (a ROS map's YAML has its own)",
               "1");
  group.Option("--origin", origin, "X,Y",
               "metres of the bottom-left corner of the map's bottom-left cell (maps without a "
               "frame)",
               "0,0");
}

Result<GoalServiceConfig> ResolveGoalOptions(const GoalOptions& options,
                                             const std::optional<std::string>& maze_path,
                                             const Grid& grid) {
  GoalServiceConfig config;
  const double mb = options.cache_mb.value_or(256);
  if (!(mb >= 0 && mb <= 65536)) {
    return Error::Option("goal-cache-mb", "must be between 0 and 65536");
  }
  config.planner.cache_bytes = static_cast<size_t>(mb * 1024 * 1024);
  Result<MapFrame> frame = ResolveMapFrame(maze_path, options.resolution, options.origin, grid);
  if (!frame) return frame.error();
  config.frame = *frame;
  if (options.goals_file) {
    Result<std::vector<NamedGoal>> goals = LoadGoalsFile(*options.goals_file, config.frame);
    if (!goals) return Error("--goals " + goals.error().message);
    config.goals = std::move(*goals);
  }
  return config;
}

}  // namespace dynapath::runtime
