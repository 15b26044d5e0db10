#include "dynapath/goal_paths.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <queue>
#include <set>
#include <tuple>
#include <utility>

#include "core/plan/dynamic_distances.h"
#include "core/plan/incremental_oracle.h"

namespace dynapath {
namespace {

constexpr int kDr[8] = {-1, -1, 0, 1, 1, 1, 0, -1};
constexpr int kDc[8] = {0, 1, 1, 1, 0, -1, -1, -1};

int32_t Chebyshev(int r0, int c0, int r1, int c1) {
  return std::max(std::abs(r0 - r1), std::abs(c0 - c1));
}

}  // namespace

bool MapFrame::CellAt(double x, double y, int* row, int* col) const {
  if (!std::isfinite(x) || !std::isfinite(y) || !(resolution > 0)) return false;
  const double fc = std::floor((x - origin_x) / resolution);
  const double fr_up = std::floor((y - origin_y) / resolution);  // 0 = bottom row
  if (fc < 0 || fc >= cols || fr_up < 0 || fr_up >= rows) return false;
  *col = static_cast<int>(fc);
  *row = rows - 1 - static_cast<int>(fr_up);
  return true;
}

Status CheckFrame(double resolution, double origin_x, double origin_y) {
  if (!std::isfinite(resolution) || resolution <= 0 || resolution > 1000) {
    return Error("the resolution must be a number of metres per cell above 0 and at most 1000");
  }
  if (!std::isfinite(origin_x) || !std::isfinite(origin_y) || std::abs(origin_x) > 1e9 ||
      std::abs(origin_y) > 1e9) {
    return Error("the origin must be two finite numbers of metres (at most 1e9)");
  }
  return Ok{};
}

const char* GoalStatusName(GoalStatus status) {
  switch (status) {
    case GoalStatus::kReached:
      return "reached";
    case GoalStatus::kNoRoute:
      return "unreachable";
    case GoalStatus::kStartObstacle:
      return "start_obstacle";
    case GoalStatus::kStartOutsideGrid:
      return "outside_grid";
    case GoalStatus::kStartOutsideMap:
      return "outside_map";
    case GoalStatus::kOverBudget:
      return "over_budget";
  }
  return "unknown";
}

const char* GoalCheckName(GoalCheck check) {
  switch (check) {
    case GoalCheck::kOk:
      return "ok";
    case GoalCheck::kOutsideGrid:
      return "goal_outside_grid";
    case GoalCheck::kObstacle:
      return "goal_obstacle";
    case GoalCheck::kOutsideMap:
      return "goal_outside_map";
    case GoalCheck::kUnknownName:
      return "unknown_goal";
  }
  return "unknown";
}

struct GoalPlanner::Field {
  int goal = 0;
  int64_t update = 0;  // the grid update its distances are exact for
  uint64_t used = 0;   // clock_ at the last use
  int64_t asks = 0;    // since it was made (halved with the miss counts)
  DynamicDistances distances;
  // What a field holds: its values and repair stamps, 4 bytes a cell each.
  static size_t Bytes(int cells) { return sizeof(Field) + size_t{8} * static_cast<size_t>(cells); }
};

GoalPlanner::GoalPlanner(GoalPlannerOptions options) : options_(options) {
  options_.hot_after = std::max(1, options_.hot_after);
  options_.log_batches = std::max<size_t>(1, options_.log_batches);
  stats_.cap_bytes = options_.cache_bytes;
}

GoalPlanner::~GoalPlanner() = default;

void GoalPlanner::Update(std::shared_ptr<const Grid> grid, const std::vector<int>& changed) {
  const bool resized =
      grid_ == nullptr || grid->rows() != grid_->rows() || grid->cols() != grid_->cols();
  grid_ = std::move(grid);
  ++updates_;
  if (resized) {
    fields_.clear();
    landmarks_.clear();
    misses_.clear();
    log_.clear();
    log_floor_ = updates_;
    stats_.bytes = 0;
    stats_.fields = 0;
    const size_t n = static_cast<size_t>(grid_->size());
    g_.assign(n, 0);
    parent_.assign(n, -1);
    stamp_.assign(n, 0u);
    epoch_ = 0;
    PlaceLandmarks();
    return;
  }
  log_.push_back(Batch{updates_, changed});
  if (log_.size() > options_.log_batches) {
    log_floor_ = log_.front().update;
    log_.erase(log_.begin());
  }
}

void GoalPlanner::PlaceLandmarks() {
  landmarks_.clear();
  stats_.landmarks = 0;
  const Grid& grid = *grid_;
  const size_t bytes = Field::Bytes(grid.size());
  const int fit = static_cast<int>(std::min<size_t>(
      static_cast<size_t>(std::max(0, options_.landmarks)), options_.cache_bytes / 2 / bytes));
  // Farthest-point selection: the first free cell, then each time the cell
  // farthest from every landmark so far (cells none of them reaches
  // skipped). Deterministic.
  int next = -1;
  for (int v = 0; v < grid.size() && next < 0; ++v) {
    if (grid.at(v) != Cell::kObstacle) next = v;
  }
  std::vector<int32_t> nearest(static_cast<size_t>(grid.size()), -1);
  while (next >= 0 && static_cast<int>(landmarks_.size()) < fit) {
    auto field = std::make_unique<Field>();
    field->goal = next;
    field->update = updates_;
    field->distances.Build(GoalMoves(grid, next), /*limit=*/0);
    int32_t best = 0;
    next = -1;
    for (int v = 0; v < grid.size(); ++v) {
      const int32_t d = field->distances.value(v);
      if (d == DynamicDistances::kNone) continue;
      if (nearest[v] < 0 || d < nearest[v]) nearest[v] = d;
      if (nearest[v] > best) {
        best = nearest[v];
        next = v;
      }
    }
    landmarks_.push_back(std::move(field));
    stats_.bytes += bytes;
    ++stats_.landmarks;
  }
  stats_.peak_bytes = std::max(stats_.peak_bytes, stats_.bytes);
}

GoalCheck GoalPlanner::CheckGoal(int row, int col) const {
  if (grid_ == nullptr || !grid_->InBounds(row, col)) return GoalCheck::kOutsideGrid;
  if (grid_->at(row, col) == Cell::kObstacle) return GoalCheck::kObstacle;
  return GoalCheck::kOk;
}

void GoalPlanner::Bring(Field& field) {
  if (field.update == updates_) return;
  const GoalMoves graph(*grid_, field.goal);
  if (field.update < log_floor_) {
    field.distances.Build(graph, /*limit=*/0);
    ++stats_.rebuilds;
  } else {
    std::vector<int> changed;
    for (const Batch& batch : log_) {
      if (batch.update > field.update) {
        changed.insert(changed.end(), batch.cells.begin(), batch.cells.end());
      }
    }
    field.distances.Repair(graph, changed);
    ++stats_.repairs;
  }
  field.update = updates_;
}

void GoalPlanner::Evict(size_t need) {
  while (!fields_.empty() && stats_.bytes + need > options_.cache_bytes) {
    auto oldest = fields_.begin();
    for (auto it = fields_.begin(); it != fields_.end(); ++it) {
      if (it->second->used < oldest->second->used) oldest = it;
    }
    fields_.erase(oldest);
    stats_.bytes -= Field::Bytes(grid_->size());
    --stats_.fields;
    ++stats_.evictions;
  }
}

GoalPlanner::Field* GoalPlanner::HotField(int goal) {
  if (++clock_ % (uint64_t{1} << 17) == 0) {  // forget old popularity
    for (auto& [g, field] : fields_) field->asks /= 2;
    for (auto& [g, count] : misses_) count /= 2;
  }
  if (auto it = fields_.find(goal); it != fields_.end()) {
    ++stats_.hits;
    Field& field = *it->second;
    field.used = clock_;
    ++field.asks;
    Bring(field);
    return &field;
  }
  ++stats_.misses;
  const size_t bytes = Field::Bytes(grid_->size());
  if (landmarks_.size() * bytes + bytes > options_.cache_bytes) return nullptr;  // no room
  if (misses_.size() >= 65536) misses_.clear();  // bounded: forget old cold goals
  const int asked = ++misses_[goal];
  if (asked < options_.hot_after) return nullptr;
  // Full: the least recently used field makes room, but only for a goal
  // asked more often than it (a frequency admission filter): goals asked
  // about as often as each other do not evict each other in turn.
  if (stats_.bytes + bytes > options_.cache_bytes) {
    auto oldest = fields_.begin();
    for (auto it = fields_.begin(); it != fields_.end(); ++it) {
      if (it->second->used < oldest->second->used) oldest = it;
    }
    if (asked <= oldest->second->asks) return nullptr;
    Evict(bytes);
  }
  misses_.erase(goal);
  auto field = std::make_unique<Field>();
  field->goal = goal;
  field->used = clock_;
  field->asks = asked;
  field->update = updates_;
  field->distances.Build(GoalMoves(*grid_, goal), /*limit=*/0);
  ++stats_.builds;
  stats_.bytes += bytes;
  stats_.peak_bytes = std::max(stats_.peak_bytes, stats_.bytes);
  ++stats_.fields;
  Field* raw = field.get();
  fields_.emplace(goal, std::move(field));
  return raw;
}

GoalPath GoalPlanner::FromField(const Field& field, int start, size_t budget) const {
  GoalPath path;
  path.source = GoalSource::kField;
  const int32_t d = field.distances.value(start);
  if (d == DynamicDistances::kNone) {
    path.status = GoalStatus::kNoRoute;
    return path;
  }
  if (static_cast<size_t>(d) + 1 > budget) {
    path.status = GoalStatus::kOverBudget;
    return path;
  }
  const Grid& grid = *grid_;
  path.cells.reserve(static_cast<size_t>(d) + 1);
  int v = start;
  path.cells.push_back(v);
  for (int32_t left = d; left > 0; --left) {
    const int row = grid.RowOf(v), col = grid.ColOf(v);
    int next = -1;
    for (int a = 0; a < 8 && next < 0; ++a) {
      const int r = row + kDr[a], c = col + kDc[a];
      if (grid.InBounds(r, c) && field.distances.value(grid.Index(r, c)) == left - 1) {
        next = grid.Index(r, c);
      }
    }
    v = next;  // exists: the field is exact
    path.cells.push_back(v);
  }
  path.status = GoalStatus::kReached;
  path.cost = d;
  return path;
}

GoalPath GoalPlanner::Search(int start, int goal, size_t budget) {
  ++stats_.searches;
  const Grid& grid = *grid_;
  if (++epoch_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    epoch_ = 1;
  }
  const int gr = grid.RowOf(goal), gc = grid.ColOf(goal);
  GoalPath path;
  path.source = GoalSource::kSearch;
  landmark_goal_.clear();
  std::vector<const DynamicDistances*> marks;
  for (const auto& landmark : landmarks_) {
    Bring(*landmark);
    const int32_t at_goal = landmark->distances.value(goal);
    const int32_t at_start = landmark->distances.value(start);
    if ((at_goal == DynamicDistances::kNone) != (at_start == DynamicDistances::kNone)) {
      ++stats_.proved_unreachable;  // one of them is in the landmark's component
      path.status = GoalStatus::kNoRoute;
      return path;
    }
    if (at_goal == DynamicDistances::kNone) continue;
    marks.push_back(&landmark->distances);
    landmark_goal_.push_back(at_goal);
  }
  const auto h = [&](int v, int r, int c) {
    int32_t best = Chebyshev(r, c, gr, gc);
    for (size_t i = 0; i < marks.size(); ++i) {
      const int32_t d = marks[i]->value(v);
      // Not reached by a landmark that reaches the goal: no path from v.
      if (d == DynamicDistances::kNone) return int32_t{-1};
      best = std::max(best, std::abs(d - landmark_goal_[i]));
    }
    return best;
  };
  // (f, -g, cell): smallest f first, then the deepest (ties to larger g).
  using Entry = std::tuple<int32_t, int32_t, int32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  stamp_[start] = epoch_;
  g_[start] = 0;
  parent_[start] = -1;
  open.emplace(h(start, grid.RowOf(start), grid.ColOf(start)), 0, start);
  while (!open.empty()) {
    const auto [f, neg_g, v] = open.top();
    open.pop();
    const int32_t g = -neg_g;
    if (g != g_[v]) continue;  // a stale entry
    ++stats_.expanded;
    if (v == goal) {
      if (static_cast<size_t>(g) + 1 > budget) {
        path.status = GoalStatus::kOverBudget;
        return path;
      }
      path.cells.resize(static_cast<size_t>(g) + 1);
      int u = goal;
      for (int32_t i = g; i >= 0; --i) {
        path.cells[static_cast<size_t>(i)] = u;
        u = parent_[u];
      }
      path.status = GoalStatus::kReached;
      path.cost = g;
      return path;
    }
    const int row = grid.RowOf(v), col = grid.ColOf(v);
    for (int a = 0; a < 8; ++a) {
      const int r = row + kDr[a], c = col + kDc[a];
      if (!grid.InBounds(r, c)) continue;
      const int w = grid.Index(r, c);
      if (grid.at(w) == Cell::kObstacle) continue;
      if (stamp_[w] == epoch_ && g_[w] <= g + 1) continue;
      const int32_t hw = h(w, r, c);
      if (hw < 0) continue;
      stamp_[w] = epoch_;
      g_[w] = g + 1;
      parent_[w] = v;
      open.emplace(g + 1 + hw, -(g + 1), w);
    }
  }
  path.status = GoalStatus::kNoRoute;
  return path;
}

GoalPath GoalPlanner::Plan(int start_row, int start_col, int goal_row, int goal_col,
                           size_t budget) {
  GoalPath path;
  if (grid_ == nullptr || !grid_->InBounds(start_row, start_col)) {
    path.status = GoalStatus::kStartOutsideGrid;
    return path;
  }
  if (grid_->at(start_row, start_col) == Cell::kObstacle) {
    path.status = GoalStatus::kStartObstacle;
    return path;
  }
  if (CheckGoal(goal_row, goal_col) != GoalCheck::kOk) return path;  // kUnreachable
  const int start = grid_->Index(start_row, start_col);
  const int goal = grid_->Index(goal_row, goal_col);
  if (Field* field = HotField(goal)) return FromField(*field, start, budget);
  return Search(start, goal, budget);
}

int32_t FreshGoalDistance(const Grid& grid, int start, int goal) {
  if (grid.at(start) == Cell::kObstacle || grid.at(goal) == Cell::kObstacle) return -1;
  std::vector<int32_t> dist(static_cast<size_t>(grid.size()), -1);
  std::vector<int32_t> queue;
  queue.reserve(static_cast<size_t>(grid.size()));
  dist[start] = 0;
  queue.push_back(start);
  for (size_t head = 0; head < queue.size(); ++head) {
    const int v = queue[head];
    if (v == goal) return dist[v];
    const int row = grid.RowOf(v), col = grid.ColOf(v);
    for (int a = 0; a < 8; ++a) {
      const int r = row + kDr[a], c = col + kDc[a];
      if (!grid.InBounds(r, c)) continue;
      const int w = grid.Index(r, c);
      if (dist[w] >= 0 || grid.at(w) == Cell::kObstacle) continue;
      dist[w] = dist[v] + 1;
      queue.push_back(w);
    }
  }
  return -1;
}

namespace {

bool GoalNameOk(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char ch : name) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                    (ch >= '0' && ch <= '9') || ch == '_' || ch == '-' || ch == '.';
    if (!ok) return false;
  }
  return true;
}

bool ParseInt(const std::string& s, int* out) {
  if (s.empty() || s.size() > 10) return false;
  size_t i = s[0] == '-' ? 1 : 0;
  if (i == s.size()) return false;
  long long v = 0;
  for (; i < s.size(); ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    v = v * 10 + (s[i] - '0');
  }
  if (s[0] == '-') v = -v;
  if (v < -1000000000LL || v > 1000000000LL) return false;
  *out = static_cast<int>(v);
  return true;
}

bool ParseMetres(const std::string& s, double* out) {
  if (s.empty() || s.size() > 32) return false;
  for (char ch : s) {
    if (!((ch >= '0' && ch <= '9') || ch == '.' || ch == '-' || ch == '+')) return false;
  }
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(v) || std::abs(v) > 1e9) return false;
  *out = v;
  return true;
}

}  // namespace

Result<std::vector<NamedGoal>> ParseGoalsText(const std::string& text) {
  std::vector<NamedGoal> goals;
  std::set<std::string> names;
  size_t line_no = 0;
  size_t pos = 0;
  while (pos <= text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    while (!line.empty() && (line.back() == ' ' || line.back() == '\t' || line.back() == '\r')) {
      line.pop_back();
    }
    size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    line = line.substr(first);
    const std::string where = "line " + std::to_string(line_no) + ": ";
    const size_t space = line.find_first_of(" \t");
    if (space == std::string::npos) return Error(where + "expected NAME ROW,COL or NAME X,Y");
    NamedGoal goal;
    goal.name = line.substr(0, space);
    std::string at = line.substr(line.find_first_not_of(" \t", space));
    if (!GoalNameOk(goal.name)) {
      return Error(where + "a goal's name is 1-64 characters of A-Z a-z 0-9 _ . -");
    }
    const size_t comma = at.find(',');
    if (comma == std::string::npos || at.find_first_of(" \t") != std::string::npos) {
      return Error(where + "expected NAME ROW,COL (cells) or NAME X,Y (metres, with a point)");
    }
    const std::string a = at.substr(0, comma), b = at.substr(comma + 1);
    const bool da = a.find('.') != std::string::npos, db = b.find('.') != std::string::npos;
    if (da != db) {
      return Error(where + "both numbers are cells (integers) or both metres (with a point)");
    }
    goal.metres = da;
    const bool ok = goal.metres ? ParseMetres(a, &goal.x) && ParseMetres(b, &goal.y)
                                : ParseInt(a, &goal.row) && ParseInt(b, &goal.col);
    if (!ok) return Error(where + "bad coordinates '" + at + "'");
    if (!names.insert(goal.name).second) {
      return Error(where + "goal '" + goal.name + "' is named twice");
    }
    if (goals.size() >= 65536) return Error(where + "more than 65536 goals");
    goals.push_back(std::move(goal));
  }
  return goals;
}

}  // namespace dynapath
