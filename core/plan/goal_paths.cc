#include "dynapath/goal_paths.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <utility>

namespace dynapath {
// A queue by integer level, smallest first; among equal levels the last
// pushed first (in A*, the deepest of equal f). Cheapest when the levels
// taken never go down (each repair phase; A* with a consistent heuristic).
template <class Item>
class LevelLists {
 public:
  bool empty() const { return size_ == 0; }
  void push(int32_t level, Item item) {
    if (static_cast<size_t>(level) >= lists_.size()) lists_.resize(static_cast<size_t>(level) + 1);
    lists_[static_cast<size_t>(level)].push_back(item);
    if (size_ == 0 || level < at_) at_ = level;
    ++size_;
  }
  std::pair<int32_t, Item> pop() {
    while (lists_[static_cast<size_t>(at_)].empty()) ++at_;
    std::vector<Item>& list = lists_[static_cast<size_t>(at_)];
    const Item item = list.back();
    list.pop_back();
    --size_;
    return {at_, item};
  }
  void clear() {
    if (size_ > 0) {
      for (auto& list : lists_) list.clear();
    }
    size_ = 0;
    at_ = 0;
  }

 private:
  std::vector<std::vector<Item>> lists_;
  size_t size_ = 0;
  int32_t at_ = 0;
};

class GoalPlanner::LevelQueue : public LevelLists<int> {};
class GoalPlanner::OpenList : public LevelLists<std::pair<int32_t, int32_t>> {};

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

namespace {

// The in-grid neighbours of `v`, in action order.
template <class F>
inline void ForEachNeighbour(int rows, int cols, int v, F f) {
  const int row = v / cols, col = v % cols;
  for (int a = 0; a < 8; ++a) {
    const int r = row + kDr[a], c = col + kDc[a];
    if (r < 0 || r >= rows || c < 0 || c >= cols) continue;
    f(r * cols + c);
  }
}

// The distances to `goal` over the free-cell index `slot` (values[slot[v]],
// T's largest value: none). False when a distance exceeds `limit` (the
// values are then unusable).
template <class T>
bool BuildValues(const Grid& grid, const int32_t* slot, size_t slots, int goal, int32_t limit,
                 std::vector<T>& values, std::vector<int32_t>& queue) {
  constexpr T kNone = std::numeric_limits<T>::max();
  values.assign(slots, kNone);
  queue.clear();
  if (grid.at(goal) == Cell::kObstacle) return true;
  const int rows = grid.rows(), cols = grid.cols();
  const uint8_t* cells = grid.codes().data();
  constexpr auto kObstacle = static_cast<uint8_t>(Cell::kObstacle);
  values[static_cast<size_t>(slot[goal])] = 0;
  queue.push_back(goal);
  bool fits = true;
  for (size_t head = 0; head < queue.size() && fits; ++head) {
    const int u = queue[head];
    const int32_t next = static_cast<int32_t>(values[static_cast<size_t>(slot[u])]) + 1;
    ForEachNeighbour(rows, cols, u, [&](int v) {
      if (cells[v] == kObstacle) return;
      T& x = values[static_cast<size_t>(slot[v])];
      if (x != kNone) return;
      if (next > limit) {
        fits = false;
        return;
      }
      x = static_cast<T>(next);
      queue.push_back(v);
    });
  }
  return fits;
}

enum class RepairEnd { kExact, kOverflow };

// Restores exact distances to `goal` after the cells `changed` changed
// (DynamicDistances::Repair's two phases, over the free-cell index; every
// cell free now has a slot below values.size()). kOverflow when a distance
// exceeds `limit` (the values are then unusable); `written`: the values
// written.
template <class T, class Queue>
RepairEnd RepairValues(const Grid& grid, const int32_t* slot, int goal, int32_t limit,
                       std::vector<T>& values, const std::vector<int>& changed, Queue& queue,
                       std::vector<int>& withdrawn, int64_t* written) {
  constexpr T kNone = std::numeric_limits<T>::max();
  const int rows = grid.rows(), cols = grid.cols();
  const uint8_t* cells = grid.codes().data();
  constexpr auto kObstacle = static_cast<uint8_t>(Cell::kObstacle);
  int64_t writes = 0;
  const auto get = [&](int v) -> int32_t {
    const int32_t s = slot[v];
    if (s < 0) return -1;
    const T x = values[static_cast<size_t>(s)];
    return x == kNone ? -1 : static_cast<int32_t>(x);
  };
  const auto put = [&](int v, int32_t x) {
    ++writes;
    values[static_cast<size_t>(slot[v])] = x < 0 ? kNone : static_cast<T>(x);
  };
  const auto blocked = [&](int v) { return cells[v] == kObstacle; };
  queue.clear();
  withdrawn.clear();
  // Phase 1: withdraw unsupported values, lowest old value first.
  for (int v : changed) {
    if (get(v) >= 0) queue.push(get(v), v);
  }
  while (!queue.empty()) {
    // Not structured bindings: clang 14 (the fuzz build) cannot capture
    // one in a lambda.
    const std::pair<int32_t, int> top = queue.pop();
    const int32_t level = top.first;
    const int v = top.second;
    if (get(v) != level) continue;
    bool supported = !blocked(v) && v == goal;
    if (!blocked(v) && !supported) {
      ForEachNeighbour(rows, cols, v, [&](int w) {
        if (get(w) == level - 1) supported = true;
      });
    }
    if (supported) continue;
    put(v, -1);
    withdrawn.push_back(v);
    ForEachNeighbour(rows, cols, v, [&](int p) {
      if (get(p) == level + 1) queue.push(level + 1, p);
    });
  }
  // Phase 2: the best value of every withdrawn or changed cell from its
  // neighbours, then relax outwards in increasing order of value.
  RepairEnd end = RepairEnd::kExact;
  const auto seed = [&](int v) {
    if (blocked(v)) {
      if (get(v) >= 0) put(v, -1);
      return;
    }
    int32_t best = get(v);
    if (v == goal) {
      best = 0;
    } else {
      ForEachNeighbour(rows, cols, v, [&](int w) {
        const int32_t d = get(w);
        if (d >= 0 && (best < 0 || d + 1 < best)) best = d + 1;
      });
    }
    if (best > limit) {
      end = RepairEnd::kOverflow;
      return;
    }
    if (best >= 0 && best != get(v)) put(v, best);
    if (best >= 0) queue.push(best, v);
  };
  for (int v : withdrawn) seed(v);
  for (int v : changed) seed(v);
  withdrawn.clear();
  while (!queue.empty() && end == RepairEnd::kExact) {
    const std::pair<int32_t, int> top = queue.pop();
    const int32_t level = top.first;
    const int u = top.second;
    if (get(u) != level) continue;
    const int32_t next = level + 1;
    ForEachNeighbour(rows, cols, u, [&](int p) {
      if (blocked(p) || p == goal) return;
      const int32_t d = get(p);
      if (d >= 0 && d <= next) return;
      if (next > limit) {
        end = RepairEnd::kOverflow;
        return;
      }
      put(p, next);
      queue.push(next, p);
    });
  }
  queue.clear();
  *written = writes;
  return end;
}

}  // namespace

struct GoalPlanner::Field {
  int goal = 0;
  int64_t update = 0;  // the grid update its distances are exact for
  uint64_t used = 0;   // clock_ at the last use
  int64_t asks = 0;    // since it was made (halved with the miss counts)
  bool wide = false;   // 4 bytes a cell (a distance above narrow_limit)
  double repair_cost = -1;  // distances written per repair (a moving average)
  std::vector<uint16_t> narrow;
  std::vector<uint32_t> wide_values;
  size_t slots() const { return wide ? wide_values.size() : narrow.size(); }
  static size_t BytesFor(size_t slots, bool wide) { return sizeof(Field) + (wide ? 4 : 2) * slots; }
  size_t Bytes() const { return BytesFor(slots(), wide); }
};

GoalPlanner::GoalPlanner(GoalPlannerOptions options)
    : options_(options),
      levels_(std::make_unique<LevelQueue>()),
      open_(std::make_unique<OpenList>()) {
  options_.hot_after = std::max(1, options_.hot_after);
  options_.log_batches = std::max<size_t>(1, options_.log_batches);
  options_.narrow_limit = std::clamp<int32_t>(options_.narrow_limit, 1, 65534);
  stats_.cap_bytes = options_.cache_bytes;
}

GoalPlanner::~GoalPlanner() {
  StopBuilder();
  {
    std::lock_guard<std::mutex> lock(build_mutex_);
    stop_ = true;
  }
  build_cv_.notify_all();
  if (builder_.joinable()) builder_.join();
}

int32_t GoalPlanner::Value(const Field& field, int cell) const {
  const int32_t s = slot_[static_cast<size_t>(cell)];
  if (s < 0 || static_cast<size_t>(s) >= field.slots()) return -1;
  if (field.wide) {
    const uint32_t x = field.wide_values[static_cast<size_t>(s)];
    return x == std::numeric_limits<uint32_t>::max() ? -1 : static_cast<int32_t>(x);
  }
  const uint16_t x = field.narrow[static_cast<size_t>(s)];
  return x == std::numeric_limits<uint16_t>::max() ? -1 : static_cast<int32_t>(x);
}

void GoalPlanner::MakeField(Field& field, const Grid& grid, size_t slots) const {
  // Called on the builder thread too: its own scratch.
  std::vector<int32_t> queue;
  queue.reserve(slots);
  field.wide = false;
  field.wide_values.clear();
  if (BuildValues(grid, slot_.data(), slots, field.goal, options_.narrow_limit, field.narrow,
                  queue)) {
    return;
  }
  field.narrow = {};
  field.wide = true;
  BuildValues(grid, slot_.data(), slots, field.goal, std::numeric_limits<int32_t>::max() - 1,
              field.wide_values, queue);
}

void GoalPlanner::StopBuilder() {
  std::unique_lock<std::mutex> lock(build_mutex_);
  jobs_.clear();
  idle_cv_.wait(lock, [&] { return !building_; });
  built_.clear();
}

void GoalPlanner::BuilderLoop() {
  std::unique_lock<std::mutex> lock(build_mutex_);
  for (;;) {
    build_cv_.wait(lock, [&] { return stop_ || !jobs_.empty(); });
    if (stop_) return;
    BuildJob job = std::move(jobs_.front());
    jobs_.pop_front();
    building_ = true;
    lock.unlock();
    auto field = std::make_unique<Field>();
    field->goal = job.goal;
    field->update = job.update;
    MakeField(*field, *job.grid, job.slots);
    job.grid.reset();
    lock.lock();
    built_.push_back(std::move(field));
    building_ = false;
    idle_cv_.notify_all();
  }
}

void GoalPlanner::Request(int goal) {
  const size_t bytes = Field::BytesFor(slots_, false);
  pending_[goal] = bytes;
  stats_.bytes += bytes;
  stats_.peak_bytes = std::max(stats_.peak_bytes, stats_.bytes);
  stats_.pending = static_cast<int64_t>(pending_.size());
  ++stats_.queued;
  {
    std::lock_guard<std::mutex> lock(build_mutex_);
    jobs_.push_back(BuildJob{goal, updates_, slots_, grid_});
    if (!builder_.joinable()) builder_ = std::thread([this] { BuilderLoop(); });
  }
  build_cv_.notify_one();
}

void GoalPlanner::Adopt() {
  if (pending_.empty()) return;
  std::vector<std::unique_ptr<Field>> done;
  {
    std::lock_guard<std::mutex> lock(build_mutex_);
    done.swap(built_);
  }
  for (auto& field : done) {
    auto it = pending_.find(field->goal);
    if (it == pending_.end()) continue;  // dropped (a new grid size)
    stats_.bytes -= it->second;
    pending_.erase(it);
    ++stats_.builds;
    if (field->wide) ++stats_.widened;
    const size_t bytes = field->Bytes();
    auto old = fields_.find(field->goal);
    if (old != fields_.end()) {  // made again: replaces the older one
      if (old->second->update >= field->update) continue;
      field->used = old->second->used;
      field->asks = old->second->asks;
      stats_.bytes -= old->second->Bytes();
      fields_.erase(old);
      --stats_.fields;
    } else {
      field->used = clock_;
      field->asks = options_.hot_after;
    }
    if (!Evict(bytes)) continue;  // no room after all: the goal stays cold
    stats_.bytes += bytes;
    stats_.peak_bytes = std::max(stats_.peak_bytes, stats_.bytes);
    ++stats_.fields;
    fields_[field->goal] = std::move(field);
  }
  stats_.pending = static_cast<int64_t>(pending_.size());
}

void GoalPlanner::WaitForBuilds() {
  {
    std::unique_lock<std::mutex> lock(build_mutex_);
    idle_cv_.wait(lock, [&] { return jobs_.empty() && !building_; });
  }
  Adopt();
}

void GoalPlanner::Update(std::shared_ptr<const Grid> grid, const std::vector<int>& changed) {
  const bool resized =
      grid_ == nullptr || grid->rows() != grid_->rows() || grid->cols() != grid_->cols();
  grid_ = std::move(grid);
  ++updates_;
  if (resized) {
    StopBuilder();  // the builder reads slot_
    fields_.clear();
    pending_.clear();
    landmarks_.clear();
    misses_.clear();
    log_.clear();
    log_floor_ = updates_;
    grid_since_ = updates_;
    stats_.bytes = 0;
    stats_.fields = 0;
    stats_.pending = 0;
    const size_t n = static_cast<size_t>(grid_->size());
    slot_.assign(n, -1);
    slots_ = 0;
    for (int v = 0; v < grid_->size(); ++v) {
      if (grid_->at(v) != Cell::kObstacle)
        slot_[static_cast<size_t>(v)] = static_cast<int32_t>(slots_++);
    }
    stats_.indexed_cells = static_cast<int64_t>(slots_);
    g_.assign(n, 0);
    parent_.assign(n, -1);
    stamp_.assign(n, 0u);
    epoch_ = 0;
    PlaceLandmarks();
    return;
  }
  Adopt();
  for (int v : changed) {
    if (v < 0 || v >= grid_->size()) continue;
    if (slot_[static_cast<size_t>(v)] < 0 && grid_->at(v) != Cell::kObstacle) {
      slot_[static_cast<size_t>(v)] = static_cast<int32_t>(slots_++);
    }
  }
  stats_.indexed_cells = static_cast<int64_t>(slots_);
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
  // Held as if every cell were indexed: the landmarks stay within half the
  // cache however the index grows.
  const size_t bytes = Field::BytesFor(static_cast<size_t>(grid.size()), false);
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
    MakeField(*field, grid, slots_);
    if (field->wide) ++stats_.widened;
    int32_t best = 0;
    next = -1;
    for (int v = 0; v < grid.size(); ++v) {
      const int32_t d = Value(*field, v);
      if (d < 0) continue;
      if (nearest[v] < 0 || d < nearest[v]) nearest[v] = d;
      if (nearest[v] > best) {
        best = nearest[v];
        next = v;
      }
    }
    stats_.bytes += field->Bytes();
    landmarks_.push_back(std::move(field));
    ++stats_.landmarks;
  }
  stats_.peak_bytes = std::max(stats_.peak_bytes, stats_.bytes);
}

GoalCheck GoalPlanner::CheckGoal(int row, int col) const {
  if (grid_ == nullptr || !grid_->InBounds(row, col)) return GoalCheck::kOutsideGrid;
  if (grid_->at(row, col) == Cell::kObstacle) return GoalCheck::kObstacle;
  return GoalCheck::kOk;
}

bool GoalPlanner::Bring(Field& field, bool landmark) {
  if (field.update == updates_) return true;
  const Grid& grid = *grid_;
  // The index grew since: room for the new cells (none of them reached yet;
  // they are all among the changed cells).
  const size_t grown = Field::BytesFor(slots_, field.wide);
  if (grown > field.Bytes()) {
    const size_t more = grown - field.Bytes();
    if (!Evict(more, &field) && !landmark) return false;
    stats_.bytes += more;
    stats_.peak_bytes = std::max(stats_.peak_bytes, stats_.bytes);
    if (field.wide) {
      field.wide_values.resize(slots_, std::numeric_limits<uint32_t>::max());
    } else {
      field.narrow.resize(slots_, std::numeric_limits<uint16_t>::max());
    }
  }
  bool kept = false;
  if (field.update >= log_floor_) {
    std::vector<int> changed;
    for (const Batch& batch : log_) {
      if (batch.update > field.update) {
        changed.insert(changed.end(), batch.cells.begin(), batch.cells.end());
      }
    }
    int64_t written = 0;
    const RepairEnd end =
        field.wide
            ? RepairValues(grid, slot_.data(), field.goal, std::numeric_limits<int32_t>::max() - 1,
                           field.wide_values, changed, *levels_, withdrawn_, &written)
            : RepairValues(grid, slot_.data(), field.goal, options_.narrow_limit, field.narrow,
                           changed, *levels_, withdrawn_, &written);
    ++stats_.repairs;
    if (!landmark) {
      const double w = static_cast<double>(written);
      field.repair_cost = field.repair_cost < 0 ? w : 0.75 * field.repair_cost + 0.25 * w;
      repair_cost_ = field_repairs_++ == 0 ? w : 0.99 * repair_cost_ + 0.01 * w;
    }
    kept = end == RepairEnd::kExact;
  }
  if (!kept) {
    // Behind the log, or a distance above the narrow limit: made again.
    ++stats_.rebuilds;
    if (!landmark && options_.background_builds) return false;
    const size_t before = field.Bytes();
    MakeField(field, grid, slots_);
    if (field.wide) ++stats_.widened;
    stats_.bytes = stats_.bytes - before + field.Bytes();
    stats_.peak_bytes = std::max(stats_.peak_bytes, stats_.bytes);
  }
  field.update = updates_;
  return true;
}

bool GoalPlanner::Evict(size_t need, const Field* keep) {
  while (stats_.bytes + need > options_.cache_bytes) {
    auto oldest = fields_.end();
    for (auto it = fields_.begin(); it != fields_.end(); ++it) {
      if (it->second.get() == keep) continue;
      if (oldest == fields_.end() || it->second->used < oldest->second->used) oldest = it;
    }
    if (oldest == fields_.end()) return false;
    stats_.bytes -= oldest->second->Bytes();
    fields_.erase(oldest);
    --stats_.fields;
    ++stats_.evictions;
  }
  return true;
}

GoalPlanner::Field* GoalPlanner::HotField(int goal) {
  if (++clock_ % (uint64_t{1} << 17) == 0) {  // forget old popularity
    for (auto& [g, field] : fields_) field->asks /= 2;
    for (auto& [g, count] : misses_) count /= 2;
  }
  Adopt();
  if (auto it = fields_.find(goal); it != fields_.end()) {
    Field& field = *it->second;
    field.used = clock_;
    ++field.asks;
    if (Bring(field, /*landmark=*/false)) {
      ++stats_.hits;
      // Dearer to keep than its searches: dropped after this answer, and
      // not made again before many more misses (the count recovers as
      // popularity is halved).
      drop_after_answer_ =
          options_.drop_costly_fields && searches_ >= 16 && field.repair_cost > search_cost_;
      return &field;
    }
    // Dropped (it could not be kept): made again after `hot_after` more
    // misses.
    stats_.bytes -= field.Bytes();
    fields_.erase(it);
    --stats_.fields;
    ++stats_.misses;
    return nullptr;
  }
  ++stats_.misses;
  if (pending_.count(goal) != 0) return nullptr;  // being made
  const size_t bytes = Field::BytesFor(slots_, false);
  size_t landmark_bytes = 0;
  for (const auto& landmark : landmarks_) landmark_bytes += landmark->Bytes();
  if (landmark_bytes + bytes > options_.cache_bytes) return nullptr;  // no room
  if (misses_.size() >= 65536) misses_.clear();  // bounded: forget old cold goals
  const int asked = ++misses_[goal];
  if (asked < options_.hot_after) return nullptr;
  if (options_.background_builds && pending_.size() >= 256) return nullptr;  // builder busy
  // Full: the least recently used field makes room, but only for a goal
  // asked more often than it (a frequency admission filter): goals asked
  // about as often as each other do not evict each other in turn.
  if (stats_.bytes + bytes > options_.cache_bytes) {
    auto oldest = fields_.end();
    for (auto it = fields_.begin(); it != fields_.end(); ++it) {
      if (oldest == fields_.end() || it->second->used < oldest->second->used) oldest = it;
    }
    if (oldest != fields_.end() && asked <= oldest->second->asks) return nullptr;
    if (!Evict(bytes)) return nullptr;
  }
  misses_.erase(goal);
  // Repairs on this map dearer than searches: no field, but one in 64 as a
  // probe that keeps the estimate current.
  if (options_.drop_costly_fields && field_repairs_ >= 16 && searches_ >= 16 &&
      repair_cost_ > search_cost_ && ++probe_ % 64 != 0) {
    ++stats_.not_made_costly;
    misses_[goal] = -1024;
    return nullptr;
  }
  if (options_.background_builds) {
    Request(goal);
    return nullptr;
  }
  auto field = std::make_unique<Field>();
  field->goal = goal;
  field->used = clock_;
  field->asks = asked;
  field->update = updates_;
  MakeField(*field, *grid_, slots_);
  if (field->wide) ++stats_.widened;
  ++stats_.builds;
  stats_.bytes += field->Bytes();
  if (!Evict(0, field.get())) {  // wider than the room made for it
    stats_.bytes -= field->Bytes();
    return nullptr;
  }
  stats_.peak_bytes = std::max(stats_.peak_bytes, stats_.bytes);
  ++stats_.fields;
  Field* raw = field.get();
  fields_.emplace(goal, std::move(field));
  return raw;
}

GoalPath GoalPlanner::FromField(const Field& field, int start, size_t budget) const {
  GoalPath path;
  path.source = GoalSource::kField;
  const int32_t d = Value(field, start);
  if (d < 0) {
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
      if (grid.InBounds(r, c) && Value(field, grid.Index(r, c)) == left - 1) {
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

template <class H>
GoalPath GoalPlanner::AStar(int start, int goal, size_t budget, H h) {
  const Grid& grid = *grid_;
  if (++epoch_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    epoch_ = 1;
  }
  GoalPath path;
  path.source = GoalSource::kSearch;
  // Smallest f first, then the last pushed (the deepest of equal f).
  OpenList& open = *open_;
  open.clear();
  const int32_t h_start = h(start, grid.RowOf(start), grid.ColOf(start));
  if (h_start < 0) {
    path.status = GoalStatus::kNoRoute;
    return path;
  }
  stamp_[start] = epoch_;
  g_[start] = 0;
  parent_[start] = -1;
  open.push(h_start, {0, start});
  while (!open.empty()) {
    const std::pair<int32_t, int32_t> entry = open.pop().second;
    const int32_t g = entry.first;
    const int v = entry.second;
    if (g != g_[v]) continue;  // a stale entry
    ++stats_.expanded;
    if (v == goal) {
      open.clear();
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
      open.push(g + 1 + hw, {g + 1, w});
    }
  }
  path.status = GoalStatus::kNoRoute;
  return path;
}

GoalPath GoalPlanner::Search(int start, int goal, size_t budget) {
  ++stats_.searches;
  const Grid& grid = *grid_;
  const int gr = grid.RowOf(goal), gc = grid.ColOf(goal);
  landmark_goal_.clear();
  landmark_start_.clear();
  std::vector<const Field*> marks;
  for (const auto& landmark : landmarks_) {
    Bring(*landmark, /*landmark=*/true);
    const int32_t at_goal = Value(*landmark, goal);
    const int32_t at_start = Value(*landmark, start);
    if ((at_goal < 0) != (at_start < 0)) {
      ++stats_.proved_unreachable;  // one of them is in the landmark's component
      GoalPath path;
      path.source = GoalSource::kSearch;
      path.status = GoalStatus::kNoRoute;
      return path;
    }
    if (at_goal < 0) continue;
    marks.push_back(landmark.get());
    landmark_goal_.push_back(at_goal);
    landmark_start_.push_back(std::abs(at_start - at_goal));
  }
  // The landmarks that bound the start's distance best (ties to the first
  // placed), at most `active_landmarks`.
  const size_t active = options_.active_landmarks > 0
                            ? std::min(marks.size(), static_cast<size_t>(options_.active_landmarks))
                            : marks.size();
  if (active < marks.size()) {
    std::vector<size_t> order(marks.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t x, size_t y) { return landmark_start_[x] > landmark_start_[y]; });
    std::vector<const Field*> best_marks;
    std::vector<int32_t> best_goal;
    for (size_t k = 0; k < active; ++k) {
      best_marks.push_back(marks[order[k]]);
      best_goal.push_back(landmark_goal_[order[k]]);
    }
    marks.swap(best_marks);
    landmark_goal_.swap(best_goal);
  }

  landmark_start_.clear();
  const int64_t expanded_before = stats_.expanded;
  GoalPath path = AStar(start, goal, budget, [&](int v, int r, int c) {
    int32_t best = Chebyshev(r, c, gr, gc);
    for (size_t i = 0; i < marks.size(); ++i) {
      const int32_t d = Value(*marks[i], v);
      // Not reached by a landmark that reaches the goal: no path from v.
      if (d < 0) return int32_t{-1};
      best = std::max(best, std::abs(d - landmark_goal_[i]));
    }
    return best;
  });
  ++searches_;
  const double expanded = static_cast<double>(stats_.expanded - expanded_before);
  search_cost_ = searches_ == 1 ? expanded : 0.99 * search_cost_ + 0.01 * expanded;
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
  if (Field* field = HotField(goal)) {
    GoalPath answer = FromField(*field, start, budget);
    if (drop_after_answer_) {
      drop_after_answer_ = false;
      ++stats_.dropped_costly;
      stats_.bytes -= field->Bytes();
      fields_.erase(goal);
      --stats_.fields;
      misses_[goal] = -1024;
    }
    return answer;
  }
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
