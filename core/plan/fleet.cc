#include "dynapath/fleet.h"

#include <algorithm>
#include <numeric>
#include <string>
#include <utility>

#include "core/plan/dynamic_distances.h"
#include "core/plan/incremental_oracle.h"
#include "dynapath/thread_pool.h"

namespace dynapath {
namespace {

constexpr int32_t kFar = 1 << 30;  // the key of a cell with no distance

}  // namespace

struct Fleet::Fields {
  DynamicDistances stations;
  std::vector<DynamicDistances> goals;
  std::unique_ptr<ThreadPool> pool;
};

Fleet::Fleet(const Grid& grid, const FleetOptions& options)
    : grid_(grid), options_(options), fields_(std::make_unique<Fields>()) {}

Fleet::~Fleet() = default;

Result<std::unique_ptr<Fleet>> Fleet::Create(const Grid& grid, const FleetOptions& options) {
  if (options.robots < 1) return Error{"a fleet needs at least 1 robot"};
  if (!(options.delay_probability >= 0.0 && options.delay_probability < 1.0)) {
    return Error{"the delay probability must be in [0, 1)"};
  }
  if (options.threads < 1) return Error{"threads must be at least 1"};
  if (options.robots > (1 << 24)) return Error{"at most 16777216 robots"};
  if (options.goals.empty() && options.goal_count < 1) {
    return Error{"the goal pool needs at least 1 goal"};
  }
  std::unique_ptr<Fleet> fleet(new Fleet(grid, options));
  Fields& fields = *fleet->fields_;
  fields.stations.Build(GridMoves(fleet->grid_), 0);
  const std::vector<int32_t>& station = fields.stations.values();

  // Candidate cells: free (not a station) and reaching a station.
  std::vector<int> reaching;
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (grid.at(cell) == Cell::kFree && station[cell] > 0) reaching.push_back(cell);
  }
  if (options.starts.empty() && static_cast<long long>(reaching.size()) < options.robots) {
    return Error{"the map has " + std::to_string(reaching.size()) +
                 " free cells that reach a station, fewer than the " +
                 std::to_string(options.robots) + " robots"};
  }
  // The first `count` cells of a seeded partial shuffle of `cells`.
  auto draw = [](std::vector<int> cells, int count, uint64_t seed) {
    Rng random(seed);
    for (int i = 0; i < count; ++i) {
      const size_t j =
          static_cast<size_t>(i) + random.Below(static_cast<uint32_t>(cells.size() - i));
      std::swap(cells[static_cast<size_t>(i)], cells[j]);
    }
    cells.resize(static_cast<size_t>(count));
    return cells;
  };
  if (!options.goals.empty()) {
    for (int cell : options.goals) {
      if (cell < 0 || cell >= grid.size() || grid.at(cell) != Cell::kFree) {
        return Error{"goal cell " + std::to_string(cell) + " is not a free cell of the map"};
      }
    }
    fleet->goals_ = options.goals;
  } else {
    const int count = std::min<int>(options.goal_count, static_cast<int>(reaching.size()));
    if (count == 0) return Error{"no free cell of the map reaches a station: no goal to draw"};
    fleet->goals_ = draw(reaching, count, DeriveSeed({options.seed, 2}));
  }
  std::vector<int> starts;
  if (!options.starts.empty()) {
    if (static_cast<int>(options.starts.size()) != options.robots) {
      return Error{"give one start cell per robot"};
    }
    std::vector<uint8_t> taken(static_cast<size_t>(grid.size()), 0);
    for (int cell : options.starts) {
      if (cell < 0 || cell >= grid.size() || grid.at(cell) == Cell::kObstacle) {
        return Error{"start cell " + std::to_string(cell) + " is not a free cell of the map"};
      }
      if (taken[static_cast<size_t>(cell)]++) {
        return Error{"two robots start on cell " + std::to_string(cell)};
      }
    }
    starts = options.starts;
  } else {
    starts = draw(reaching, options.robots, DeriveSeed({options.seed, 1}));
  }
  if (!options.first_goals.empty()) {
    if (static_cast<int>(options.first_goals.size()) != options.robots) {
      return Error{"give one first goal per robot"};
    }
    for (int g : options.first_goals) {
      if (g < -1 || g >= static_cast<int>(fleet->goals_.size())) {
        return Error{"first goal " + std::to_string(g) + " is not an index of the goal pool"};
      }
    }
  }

  const double field_bytes = static_cast<double>(fleet->goals_.size() + 1) *
                             static_cast<double>(grid.size()) * kFieldBytesPerCell;
  if (field_bytes > static_cast<double>(kMaxFieldBytes)) {
    return Error{"the fleet's distance fields would take " +
                 std::to_string(static_cast<long long>(field_bytes / (1 << 20))) +
                 " MiB ((goals + 1) x cells x 8 bytes), more than " +
                 std::to_string(kMaxFieldBytes >> 20) + " MiB: give fewer goals"};
  }
  fields.goals.resize(fleet->goals_.size());
  if (options.threads > 1) fields.pool = std::make_unique<ThreadPool>(options.threads);
  auto build = [&](int g) {
    fields.goals[static_cast<size_t>(g)].Build(
        GoalMoves(fleet->grid_, fleet->goals_[static_cast<size_t>(g)]), 0);
  };
  if (fields.pool) {
    fields.pool->ParallelFor(static_cast<int>(fleet->goals_.size()), build);
  } else {
    for (int g = 0; g < static_cast<int>(fleet->goals_.size()); ++g) build(g);
  }

  const size_t n = static_cast<size_t>(options.robots);
  fleet->robots_.resize(n);
  fleet->occupant_.assign(static_cast<size_t>(grid.size()), -1);
  fleet->claimed_.assign(static_cast<size_t>(grid.size()), -1);
  fleet->next_.assign(n, -1);
  fleet->tie_.resize(n);
  Rng ties(DeriveSeed({options.seed, 3}));
  for (size_t i = 0; i < n; ++i) {
    fleet->robots_[i].cell = starts[i];
    if (!options.first_goals.empty() && options.first_goals[i] >= 0) {
      fleet->robots_[i].to_station = false;
      fleet->robots_[i].goal = options.first_goals[i];
    }
    fleet->occupant_[static_cast<size_t>(starts[i])] = static_cast<int>(i);
    fleet->tie_[i] = ties.Next();
  }
  fleet->order_.resize(n);
  fleet->move_.before.resize(n);
  fleet->move_.after.resize(n);
  fleet->move_.delayed.resize(n);
  fleet->random_ = Rng(DeriveSeed({options.seed, 4}));
  return fleet;
}

int32_t Fleet::StationDistance(int cell) const { return fields_->stations.value(cell); }

int32_t Fleet::TargetDistance(int robot, int cell) const {
  const FleetRobot& r = robots_[static_cast<size_t>(robot)];
  if (r.to_station) return fields_->stations.value(cell);
  return fields_->goals[static_cast<size_t>(r.goal)].value(cell);
}

void Fleet::ApplyChanges(const ChangeStep& step) {
  if (step.changes.empty()) return;
  std::vector<int> changed;
  changed.reserve(step.changes.size());
  for (const CellChange& change : step.changes) {
    grid_.set(change.cell, change.code);
    changed.push_back(change.cell);
  }
  Fields& fields = *fields_;
  const int count = static_cast<int>(fields.goals.size()) + 1;
  auto repair = [&](int f) {
    if (f == 0) {
      fields.stations.Repair(GridMoves(grid_), changed);
    } else {
      fields.goals[static_cast<size_t>(f - 1)].Repair(
          GoalMoves(grid_, goals_[static_cast<size_t>(f - 1)]), changed);
    }
  };
  if (fields.pool) {
    fields.pool->ParallelFor(count, repair);
  } else {
    for (int f = 0; f < count; ++f) repair(f);
  }
  for (const CellChange& change : step.changes) {
    if (change.code != Cell::kObstacle) continue;
    // A changed cell appears once per change: count each robot once.
    for (const FleetRobot& robot : robots_) {
      if (robot.cell == change.cell) ++overruns_;
    }
  }
}

void Fleet::NextTask(FleetRobot& robot) {
  ++robot.tasks_done;
  ++tasks_done_;
  if (robot.first_done < 0) robot.first_done = tick_;
  robot.task_started = tick_;
  if (robot.to_station) {
    robot.to_station = false;
    const uint32_t count = static_cast<uint32_t>(goals_.size());
    robot.goal = static_cast<int>(random_.Below(count));
    if (goals_[static_cast<size_t>(robot.goal)] == robot.cell) {
      robot.goal = (robot.goal + 1) % static_cast<int>(count);
    }
  } else {
    robot.to_station = true;
  }
}

bool Fleet::Crosses(int from, int to) const {
  const int cols = grid_.cols();
  const int fr = from / cols, fc = from % cols, tr = to / cols, tc = to % cols;
  if (fr == tr || fc == tc) return false;
  const int a = fr * cols + tc;  // the two other cells of the 2x2 square
  const int b = tr * cols + fc;
  const int ka = occupant_[static_cast<size_t>(a)];
  if (ka >= 0 && next_[static_cast<size_t>(ka)] == b) return true;
  const int kb = occupant_[static_cast<size_t>(b)];
  return kb >= 0 && next_[static_cast<size_t>(kb)] == a;
}

bool Fleet::Pibt(int robot, int parent, const std::vector<int>& preferred) {
  const size_t i = static_cast<size_t>(robot);
  const int from = robots_[i].cell;
  struct Candidate {
    int32_t key;
    int occupied;
    uint32_t tie;
    int cell;
  };
  Candidate candidates[9];
  int count = 0;
  const int want = preferred.empty() ? -1 : preferred[i];
  auto add = [&](int cell) {
    if (cell != from && grid_.at(cell) == Cell::kObstacle) return;
    const int32_t d = TargetDistance(robot, cell);
    if (d < 0 && cell != from) return;
    int32_t key = d < 0 ? kFar : d;
    if (cell == want) key = -1;
    candidates[count++] = {key, occupant_[static_cast<size_t>(cell)] >= 0 && cell != from ? 1 : 0,
                           static_cast<uint32_t>(random_.Next() >> 32), cell};
  };
  add(from);
  GridMoves(grid_).ForEachSuccessor(from, add);
  auto before = [](const Candidate& a, const Candidate& b) {
    if (a.key != b.key) return a.key < b.key;
    if (a.occupied != b.occupied) return a.occupied < b.occupied;
    return a.tie < b.tie;
  };
  for (int c = 1; c < count; ++c) {  // insertion sort of at most 9
    const Candidate moving = candidates[c];
    int at = c;
    for (; at > 0 && before(moving, candidates[at - 1]); --at) candidates[at] = candidates[at - 1];
    candidates[at] = moving;
  }
  for (int c = 0; c < count; ++c) {
    const int v = candidates[c].cell;
    if (claimed_[static_cast<size_t>(v)] >= 0) continue;
    if (parent >= 0 && v == robots_[static_cast<size_t>(parent)].cell) continue;
    const int k = occupant_[static_cast<size_t>(v)];
    if (k >= 0 && k != robot && next_[static_cast<size_t>(k)] == from) continue;  // a swap
    if (Crosses(from, v)) continue;
    next_[i] = v;
    claimed_[static_cast<size_t>(v)] = robot;
    claimed_cells_.push_back(v);
    if (k >= 0 && k != robot && next_[static_cast<size_t>(k)] < 0 && !Pibt(k, robot, preferred)) {
      continue;  // k stays on v (and claimed it): try the next cell
    }
    return true;
  }
  next_[i] = from;
  claimed_[static_cast<size_t>(from)] = robot;
  claimed_cells_.push_back(from);
  return false;
}

void Fleet::PlanPibt(const std::vector<int>& preferred) {
  const size_t n = robots_.size();
  std::fill(next_.begin(), next_.end(), -1);
  std::iota(order_.begin(), order_.end(), 0);
  // Highest priority first: robots an obstacle stands on, then the longest
  // on their task, then a fixed random order.
  std::sort(order_.begin(), order_.end(), [&](int a, int b) {
    const FleetRobot& ra = robots_[static_cast<size_t>(a)];
    const FleetRobot& rb = robots_[static_cast<size_t>(b)];
    const bool oa = grid_.at(ra.cell) == Cell::kObstacle;
    const bool ob = grid_.at(rb.cell) == Cell::kObstacle;
    if (oa != ob) return oa;
    if (ra.task_started != rb.task_started) return ra.task_started < rb.task_started;
    return tie_[static_cast<size_t>(a)] < tie_[static_cast<size_t>(b)];
  });
  for (size_t k = 0; k < n; ++k) {
    const int robot = order_[k];
    if (next_[static_cast<size_t>(robot)] < 0) Pibt(robot, -1, preferred);
  }
}

void Fleet::PlanIgnoringConflicts(const std::vector<int>& preferred) {
  for (size_t i = 0; i < robots_.size(); ++i) {
    const int from = robots_[i].cell;
    const int want = preferred.empty() ? -1 : preferred[i];
    int best = from;
    int32_t best_distance = TargetDistance(static_cast<int>(i), from);
    if (best_distance < 0) best_distance = kFar;
    bool wanted = false;
    GridMoves(grid_).ForEachSuccessor(from, [&](int cell) {
      if (wanted || grid_.at(cell) == Cell::kObstacle) return;
      const int32_t d = TargetDistance(static_cast<int>(i), cell);
      if (cell == want) {
        best = cell;
        wanted = true;
      } else if (d >= 0 && d < best_distance) {
        best = cell;
        best_distance = d;
      }
    });
    next_[i] = best;
  }
}

void Fleet::ApplyDelays() {
  const size_t n = robots_.size();
  std::vector<uint8_t>& delayed = move_.delayed;
  std::fill(delayed.begin(), delayed.end(), 0);
  if (options_.delay_probability <= 0.0) return;
  for (size_t i = 0; i < n; ++i) {
    if (next_[i] == robots_[i].cell) continue;
    if (random_.Uniform() < options_.delay_probability) {
      delayed[i] = 1;
      next_[i] = robots_[i].cell;
      ++delays_;
    }
  }
  if (options_.ignore_conflicts) return;
  // A robot that stays keeps its cell: whoever planned to enter it stays
  // too, and so on along chains and rotations.
  for (int cell : claimed_cells_) claimed_[static_cast<size_t>(cell)] = -1;
  claimed_cells_.clear();
  for (size_t i = 0; i < n; ++i) {
    if (next_[i] == robots_[i].cell) continue;
    claimed_[static_cast<size_t>(next_[i])] = static_cast<int>(i);
    claimed_cells_.push_back(next_[i]);
  }
  std::vector<int> staying;
  for (size_t i = 0; i < n; ++i) {
    if (next_[i] == robots_[i].cell) staying.push_back(static_cast<int>(i));
  }
  while (!staying.empty()) {
    const int s = staying.back();
    staying.pop_back();
    const size_t cell = static_cast<size_t>(robots_[static_cast<size_t>(s)].cell);
    const int entering = claimed_[cell];
    if (entering >= 0 && entering != s) {
      next_[static_cast<size_t>(entering)] = robots_[static_cast<size_t>(entering)].cell;
      ++held_;
      staying.push_back(entering);
    }
    claimed_[cell] = s;
    claimed_cells_.push_back(static_cast<int>(cell));
  }
}

const JointMove& Fleet::Tick(const std::vector<int>& preferred) {
  const size_t n = robots_.size();
  // A goal that no longer reaches (walled off, or an obstacle on it): the
  // robot takes another (one draw per tick).
  for (size_t i = 0; i < n; ++i) {
    FleetRobot& robot = robots_[i];
    if (!robot.to_station && grid_.at(robot.cell) != Cell::kObstacle &&
        TargetDistance(static_cast<int>(i), robot.cell) < 0) {
      robot.goal = static_cast<int>(random_.Below(static_cast<uint32_t>(goals_.size())));
    }
  }
  static const std::vector<int> kNoPreference;
  const std::vector<int>& want = preferred.size() == n ? preferred : kNoPreference;
  if (options_.ignore_conflicts) {
    PlanIgnoringConflicts(want);
  } else {
    PlanPibt(want);
  }
  ApplyDelays();
  for (int cell : claimed_cells_) claimed_[static_cast<size_t>(cell)] = -1;
  claimed_cells_.clear();
  ++tick_;
  for (size_t i = 0; i < n; ++i) {
    FleetRobot& robot = robots_[i];
    move_.before[i] = robot.cell;
    move_.after[i] = next_[i];
    if (!options_.ignore_conflicts &&
        occupant_[static_cast<size_t>(robot.cell)] == static_cast<int>(i)) {
      occupant_[static_cast<size_t>(robot.cell)] = -1;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    FleetRobot& robot = robots_[i];
    robot.cell = next_[i];
    if (!options_.ignore_conflicts)
      occupant_[static_cast<size_t>(robot.cell)] = static_cast<int>(i);
    const bool arrived = robot.to_station ? grid_.at(robot.cell) == Cell::kStation
                                          : robot.cell == goals_[static_cast<size_t>(robot.goal)];
    if (arrived) NextTask(robot);
  }
  return move_;
}

}  // namespace dynapath
