// _dynapath: the C++ side of the Python package dynapath (python/dynapath).
// Mazes (generated exactly as `dynapath maze` does, or loaded from every
// format the CLI reads), the MDP of SPEC section 2 for one walker, many
// walkers and several robots, and policy files. The package's Python files
// add the spaces, the dict-shaped multi-robot API and the docs users read.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <tuple>
#include <variant>
#include <vector>

#include "app/resources.h"
#include "dynapath/approach.h"
#include "dynapath/bfs_oracle.h"
#include "dynapath/change_sequence.h"
#include "dynapath/grid.h"
#include "dynapath/limits.h"
#include "dynapath/mdp.h"
#include "dynapath/obstacle_points_t.hpp"
#include "dynapath/obstacle_update_t.hpp"
#include "dynapath/path_reply_t.hpp"
#include "dynapath/policy_evaluation.h"
#include "dynapath/policy_state.h"
#include "dynapath/results_csv.h"
#include "dynapath/rng.h"
#include "dynapath/routes.h"
#include "launch/launcher.h"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "python/src/walker_world.h"
#include "runtime/option_group.h"
#include "runtime/output_check.h"
#include "runtime/output_lock.h"
#include "runtime/policy_file.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"
#include "runtime/service_client.h"
#include "study/study_config.h"
#include "study/study_plan.h"
#include "study/study_results.h"

namespace py = pybind11;

namespace dynapath::python {
namespace {

// An Error as the Python exception a caller expects: a missing file is
// FileNotFoundError, an unreadable one OSError, anything else ValueError.
[[noreturn]] void Raise(const Error& error) {
  PyObject* type = PyExc_ValueError;
  if (error.IsNotFound()) type = PyExc_FileNotFoundError;
  if (error.IsIo()) type = PyExc_OSError;
  if (error.IsInternal() || error.IsUnavailable() || error.IsCancelled()) {
    type = PyExc_RuntimeError;
  }
  PyErr_SetString(type, error.message.c_str());
  throw py::error_already_set();
}

template <typename T>
T Take(Result<T> result) {
  if (!result) Raise(result.error());
  return std::move(*result);
}

void Check(const Status& status) {
  if (!status) Raise(status.error());
}

// A count option of the CLI (--stations, --movers): an int or "N" / "P%".
using CountArg = std::optional<std::variant<long long, std::string>>;
std::optional<std::string> CountText(const CountArg& count) {
  if (!count) return std::nullopt;
  if (const long long* number = std::get_if<long long>(&*count)) return std::to_string(*number);
  return std::get<std::string>(*count);
}

// A read-only or writable numpy view of `data`, kept alive by `owner`.
template <typename T>
py::array View(const T* data, std::vector<py::ssize_t> shape, py::handle owner, bool writable) {
  py::array_t<T> array(shape, {}, data, owner);
  if (!writable) {
    array.attr("setflags")(py::arg("write") = false);
  }
  return array;
}

// ---------------------------------------------------------------- Maze

struct Maze {
  Scenario scenario;
  std::string source;  // how it was made, as `dynapath maze` prints it
  uint64_t seed = 0;
  RunLabels labels;  // the result files' Size and Difficulty
};

Maze FromSetup(runtime::ScenarioSetup setup) {
  return Maze{std::move(setup.scenario), std::move(setup.source), setup.seed,
              std::move(setup.labels)};
}

Maze Generate(long long size, const std::string& difficulty, std::optional<long long> seed,
              std::optional<long long> cols, std::optional<long long> steps) {
  runtime::ScenarioOptions options;
  options.size = size;
  options.difficulty = difficulty;
  options.seed = seed;
  options.cols = cols;
  options.steps = steps;
  return FromSetup(Take(runtime::ResolveScenario(options)));
}

Maze Load(const std::string& path, const CountArg& stations, const CountArg& movers,
          std::optional<std::string> stations_file, std::optional<std::string> changes,
          std::optional<long long> seed, std::optional<long long> steps, bool allow_unreachable,
          bool force_changes) {
  runtime::ScenarioOptions options;
  options.maze = path;
  options.stations = CountText(stations);
  options.movers = CountText(movers);
  options.stations_file = std::move(stations_file);
  options.changes = std::move(changes);
  options.seed = seed;
  options.steps = steps;
  options.allow_unreachable = allow_unreachable;
  options.force_changes = force_changes;
  return FromSetup(Take(runtime::ResolveScenario(options)));
}

using CodesArg = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;

// A grid from a (rows, cols) array of cell codes, checked.
Grid GridOfCodes(const CodesArg& codes) {
  if (codes.ndim() != 2 || codes.shape(0) < 1 || codes.shape(1) < 1) {
    throw std::invalid_argument("the grid must be a non-empty 2-D array (rows, cols)");
  }
  if (codes.shape(0) > kMaxGridSide || codes.shape(1) > kMaxGridSide) {
    throw std::invalid_argument("the grid's sides must be at most " + std::to_string(kMaxGridSide));
  }
  Grid grid(static_cast<int>(codes.shape(0)), static_cast<int>(codes.shape(1)));
  const int64_t* values = codes.data();
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (values[cell] < 0 || values[cell] > 2) {
      throw std::invalid_argument("cell " + std::to_string(cell) + " has code " +
                                  std::to_string(values[cell]) +
                                  "; codes are 0 (obstacle), 1 (free), 2 (station)");
    }
    grid.set(cell, static_cast<Cell>(values[cell]));
  }
  return grid;
}

// A maze from a (rows, cols) array of cell codes and optional changes.
Maze FromArray(CodesArg codes,
               std::optional<std::vector<std::pair<py::array_t<int64_t, py::array::forcecast>,
                                                   py::array_t<int64_t, py::array::forcecast>>>>
                   changes) {
  const Grid grid = GridOfCodes(codes);
  Maze maze;
  maze.scenario.grid = grid;
  maze.source = "from an array";
  maze.labels = {SizeLabel(grid.rows(), grid.cols()), "Custom"};
  if (changes) {
    for (size_t t = 0; t < changes->size(); ++t) {
      const auto& [cells, new_codes] = (*changes)[t];
      if (cells.ndim() != 1 || new_codes.ndim() != 1 || cells.shape(0) != new_codes.shape(0)) {
        throw std::invalid_argument("time step " + std::to_string(t + 1) +
                                    ": cells and codes must be 1-D arrays of one length");
      }
      ChangeStep step;
      for (py::ssize_t i = 0; i < cells.shape(0); ++i) {
        const int64_t cell = cells.at(i), code = new_codes.at(i);
        if (cell < 0 || cell >= grid.size() || code < 0 || code > 2) {
          throw std::invalid_argument("time step " + std::to_string(t + 1) + ": change " +
                                      std::to_string(i) + " (cell " + std::to_string(cell) +
                                      ", code " + std::to_string(code) + ") is out of range");
        }
        step.changes.push_back({static_cast<int>(cell), static_cast<Cell>(code)});
      }
      step.requested_moves = static_cast<int>(step.changes.size() / 2);
      maze.scenario.changes.steps.push_back(std::move(step));
    }
    Check(CheckChangesFit(maze.scenario.changes, grid));
  }
  return maze;
}

py::array GridView(py::object self) {
  const Grid& grid = self.cast<const Maze&>().scenario.grid;
  return View(reinterpret_cast<const int8_t*>(grid.codes().data()), {grid.rows(), grid.cols()},
              self, false);
}

py::list Changes(const Maze& maze, std::optional<long long> steps) {
  const auto& all = maze.scenario.changes.steps;
  size_t count = all.size();
  if (steps) {
    if (*steps < 0) throw std::invalid_argument("steps must be >= 0");
    count = std::min(count, static_cast<size_t>(*steps));
  }
  py::list out;
  for (size_t t = 0; t < count; ++t) {
    const auto& changes = all[t].changes;
    py::array_t<int32_t> cells(static_cast<py::ssize_t>(changes.size()));
    py::array_t<int8_t> codes(static_cast<py::ssize_t>(changes.size()));
    for (size_t i = 0; i < changes.size(); ++i) {
      cells.mutable_at(i) = changes[i].cell;
      codes.mutable_at(i) = static_cast<int8_t>(changes[i].code);
    }
    out.append(py::make_tuple(cells, codes));
  }
  return out;
}

py::array GridAt(const Maze& maze, long long step) {
  const auto& steps = maze.scenario.changes.steps;
  if (step < 0 || static_cast<size_t>(step) > steps.size()) {
    throw std::out_of_range("step must be in 0.." + std::to_string(steps.size()));
  }
  Grid grid = maze.scenario.grid;
  for (long long t = 0; t < step; ++t) ApplyChanges(steps[t], grid);
  py::array_t<int8_t> out({grid.rows(), grid.cols()});
  std::copy(grid.codes().begin(), grid.codes().end(),
            reinterpret_cast<uint8_t*>(out.mutable_data()));
  return out;
}

// ---------------------------------------------------------------- walkers

uint64_t FreshSeed() {
  std::random_device device;
  return (static_cast<uint64_t>(device()) << 32) ^ device();
}

// The random stream of an environment reset with `seed` (walker i of a
// vector environment reset with seed s gets seed s + i, as Gymnasium's
// vector environments do).
Rng StreamOf(uint64_t seed) { return Rng(DeriveSeed({seed, 0x5059u})); }

int CheckedAction(long long action) {
  if (action < 0 || action >= kNumActions) {
    throw std::invalid_argument("action must be in 0..7 (N, NE, E, SE, S, SW, W, NW), got " +
                                std::to_string(action));
  }
  return static_cast<int>(action);
}

std::shared_ptr<const World> MakeWorld(const Maze& maze, std::optional<int> steps_per_change,
                                       std::optional<int> max_steps) {
  const Grid& grid = maze.scenario.grid;
  return std::make_shared<const World>(maze.scenario, steps_per_change.value_or(0),
                                       max_steps.value_or(4 * std::max(grid.rows(), grid.cols())));
}

// A start cell drawn from `rng`, or options["start"] = (row, col), a free cell.
int StartCell(const World& world, Rng& rng, const py::object& options) {
  if (!options.is_none()) {
    py::dict dict = options.cast<py::dict>();
    if (dict.contains("start")) {
      auto [row, col] = dict["start"].cast<std::pair<int, int>>();
      if (row < 0 || row >= world.rows() || col < 0 || col >= world.cols() ||
          world.GridAt(0)[static_cast<size_t>(row) * world.cols() + col] != kFreeCode) {
        throw std::invalid_argument("options['start'] = (" + std::to_string(row) + ", " +
                                    std::to_string(col) + ") is not a free cell of the maze");
      }
      return row * world.cols() + col;
    }
  }
  const auto& free = world.free_cells();
  return free[rng.Below(static_cast<uint32_t>(free.size()))];
}

py::array Observation(int row, int col) {
  py::array_t<int64_t> obs(2);
  int64_t* data = obs.mutable_data();
  data[0] = row;
  data[1] = col;
  return obs;
}

class GridEnvCore {
 public:
  GridEnvCore(const Maze& maze, std::optional<int> steps_per_change, std::optional<int> max_steps)
      : world_(MakeWorld(maze, steps_per_change, max_steps)), rng_(StreamOf(FreshSeed())) {}

  py::tuple Reset(std::optional<uint64_t> seed, const py::object& options) {
    if (seed) rng_ = StreamOf(*seed);
    const int cell = StartCell(*world_, rng_, options);
    row_ = cell / world_->cols();
    col_ = cell % world_->cols();
    steps_ = 0;
    running_ = true;
    py::dict info;
    info["time_step"] = 0;
    return py::make_tuple(Observation(row_, col_), info);
  }

  py::tuple Step(long long action_given) {
    const int action = CheckedAction(action_given);
    if (!running_) throw std::runtime_error("the episode is over (or never began): call reset()");
    const int time = world_->TimeAfter(steps_);
    const MoveOutcome out =
        Move(world_->GridAt(time), world_->rows(), world_->cols(), row_, col_, action);
    row_ = out.row;
    col_ = out.col;
    ++steps_;
    const bool truncated = !out.terminated && steps_ >= world_->max_steps();
    running_ = !out.terminated && !truncated;
    py::dict info;
    info["time_step"] = world_->TimeAfter(steps_);
    return py::make_tuple(Observation(row_, col_), out.reward, out.terminated, truncated, info);
  }

  const World& world() const { return *world_; }
  int64_t steps() const { return steps_; }

 private:
  std::shared_ptr<const World> world_;
  Rng rng_;
  int row_ = 0, col_ = 0;
  int64_t steps_ = 0;
  bool running_ = false;
};

class VectorEnvCore {
 public:
  VectorEnvCore(const Maze& maze, int num_envs, std::optional<int> steps_per_change,
                std::optional<int> max_steps)
      : world_(MakeWorld(maze, steps_per_change, max_steps)) {
    if (num_envs < 1) throw std::invalid_argument("num_envs must be >= 1");
    walkers_.resize(static_cast<size_t>(num_envs));
    const uint64_t seed = FreshSeed();
    for (size_t i = 0; i < walkers_.size(); ++i) walkers_[i].rng = StreamOf(seed + i);
  }

  int num_envs() const { return static_cast<int>(walkers_.size()); }

  py::tuple Reset(std::optional<uint64_t> seed, const py::object& options) {
    const py::ssize_t n = num_envs();
    py::array_t<int64_t> obs({n, py::ssize_t{2}});
    int64_t* o = obs.mutable_data();
    for (py::ssize_t i = 0; i < n; ++i) {
      Walker& w = walkers_[i];
      if (seed) w.rng = StreamOf(*seed + static_cast<uint64_t>(i));
      Begin(w, StartCell(*world_, w.rng, options));
      o[2 * i] = w.row;
      o[2 * i + 1] = w.col;
    }
    began_ = true;
    return py::make_tuple(obs, py::dict());
  }

  // One move of every walker, in one call; a walker whose episode ends is
  // reset at once (its next start is the observation; infos hold the last).
  py::tuple Step(py::array_t<int64_t, py::array::c_style | py::array::forcecast> actions) {
    const py::ssize_t n = num_envs();
    if (actions.ndim() != 1 || actions.shape(0) != n) {
      throw std::invalid_argument("actions must be a 1-D array of num_envs = " + std::to_string(n) +
                                  " actions");
    }
    if (!began_) throw std::runtime_error("call reset() before step()");
    const int64_t* a = actions.data();
    for (py::ssize_t i = 0; i < n; ++i) {
      if (a[i] < 0 || a[i] >= kNumActions) {
        throw std::invalid_argument("actions[" + std::to_string(i) + "] = " + std::to_string(a[i]) +
                                    " is not an action in 0..7");
      }
    }
    py::array_t<int64_t> obs({n, py::ssize_t{2}});
    py::array_t<double> rewards(n);
    py::array_t<bool> terminated(n), truncated(n), final_mask(n);
    py::array_t<int64_t> final_obs({n, py::ssize_t{2}});
    int64_t* o = obs.mutable_data();
    int64_t* f = final_obs.mutable_data();
    double* r = rewards.mutable_data();
    bool* term = terminated.mutable_data();
    bool* trunc = truncated.mutable_data();
    bool* mask = final_mask.mutable_data();
    const World& world = *world_;
    const int rows = world.rows(), cols = world.cols(), max_steps = world.max_steps();
    const bool dynamic = world.steps_per_change() > 0;
    const uint8_t* grid0 = world.GridAt(0);
    const auto& free = world.free_cells();
    const auto free_count = static_cast<uint32_t>(free.size());
    {
      py::gil_scoped_release release;
      for (py::ssize_t i = 0; i < n; ++i) {
        Walker& w = walkers_[i];
        const uint8_t* grid = dynamic ? world.GridAt(world.TimeAfter(w.steps)) : grid0;
        const MoveOutcome out = Move(grid, rows, cols, w.row, w.col, static_cast<int>(a[i]));
        ++w.steps;
        const bool cut = !out.terminated && w.steps >= max_steps;
        r[i] = out.reward;
        term[i] = out.terminated;
        trunc[i] = cut;
        mask[i] = out.terminated || cut;
        f[2 * i] = out.row;
        f[2 * i + 1] = out.col;
        if (mask[i]) {
          const int cell = free[w.rng.Below(free_count)];
          w.row = cell / cols;
          w.col = cell % cols;
          w.steps = 0;
        } else {
          w.row = out.row;
          w.col = out.col;
        }
        o[2 * i] = w.row;
        o[2 * i + 1] = w.col;
      }
    }
    py::dict infos;
    infos["final_observation"] = final_obs;
    infos["_final_observation"] = final_mask;
    return py::make_tuple(obs, rewards, terminated, truncated, infos);
  }

  const World& world() const { return *world_; }

 private:
  struct Walker {
    int row = 0, col = 0;
    int64_t steps = 0;
    Rng rng{0};
  };
  void Begin(Walker& w, int cell) const {
    w.row = cell / world_->cols();
    w.col = cell % world_->cols();
    w.steps = 0;
  }

  std::shared_ptr<const World> world_;
  std::vector<Walker> walkers_;
  bool began_ = false;  // reset() was called
};

// Several robots on one maze, one move each, decided as if simultaneous:
// in the order given, a robot's move is a bump when its target is outside,
// an obstacle, a cell any active robot held before this step, or a cell an
// earlier robot moved to in this step (so swaps and head-on moves bump).
py::tuple StepRobots(const World& world, int64_t steps,
                     py::array_t<int64_t, py::array::c_style | py::array::forcecast> positions,
                     py::array_t<int64_t, py::array::c_style | py::array::forcecast> actions) {
  const py::ssize_t n = actions.size();
  if (positions.ndim() != 2 || positions.shape(0) != n || positions.shape(1) != 2) {
    throw std::invalid_argument("positions must be (robots, 2) and actions (robots,)");
  }
  const int64_t* p = positions.data();
  const int64_t* a = actions.data();
  std::vector<int> action(static_cast<size_t>(n));
  for (py::ssize_t i = 0; i < n; ++i) action[i] = CheckedAction(a[i]);
  py::array_t<int64_t> moved({n, py::ssize_t{2}});
  py::array_t<double> rewards(n);
  py::array_t<bool> terminated(n);
  int64_t* m = moved.mutable_data();
  const uint8_t* grid = world.GridAt(world.TimeAfter(steps));
  for (py::ssize_t i = 0; i < n; ++i) {
    auto held = [&](int row, int col) {
      for (py::ssize_t j = 0; j < n; ++j) {
        if (j != i && p[2 * j] == row && p[2 * j + 1] == col) return true;  // before the step
        if (j < i && m[2 * j] == row && m[2 * j + 1] == col) return true;   // claimed now
      }
      return false;
    };
    const MoveOutcome out = Move(grid, world.rows(), world.cols(), static_cast<int>(p[2 * i]),
                                 static_cast<int>(p[2 * i + 1]), action[i], held);
    m[2 * i] = out.row;
    m[2 * i + 1] = out.col;
    rewards.mutable_at(i) = out.reward;
    terminated.mutable_at(i) = out.terminated;
  }
  return py::make_tuple(moved, rewards, terminated);
}

// ---------------------------------------------------------------- policies

std::string PrecisionName(QPrecision precision) {
  return precision == QPrecision::kFloat ? "float" : "double";
}

py::array QView(py::object self) {
  PolicyState& s = self.cast<PolicyState&>();
  const std::vector<py::ssize_t> shape{s.rows, s.cols, kNumActions};
  if (s.precision == QPrecision::kFloat) {
    return View(s.table.values().data(), shape, self, true);
  }
  return View(s.table.wide_values().data(), shape, self, true);
}

// A writable view of one of a policy's per-node vectors.
template <typename T>
py::array FieldView(py::object self, std::vector<T> PolicyState::*field) {
  std::vector<T>& values = self.cast<PolicyState&>().*field;
  return View(values.data(), {static_cast<py::ssize_t>(values.size())}, self, true);
}

// ---------------------------------------------------------------- runs

// What a run in progress shares with its Python approaches: the stop flag
// (Ctrl-C, or an approach that raised) and the first exception raised.
struct RunControl {
  std::atomic<bool> stop{false};
  std::exception_ptr error;
};

// An approach written in Python (dynapath.run's approaches): its
// initialize(grid) and adapt(grid, changed_cells) return the policy, one
// action per cell (0..7, -1 for none), or None to have the object's
// `actions` attribute read; core's policy evaluation scores it as every
// approach's, the path from a cell following its action. Calls run under
// the GIL; Evaluate does not need it.
class PythonPlanner : public Planner {
 public:
  PythonPlanner(py::object approach, int rows, int cols, RunControl& control)
      : approach_(std::move(approach)), control_(control) {
    // One buffer for the whole run, refreshed before every call: a Python
    // approach that keeps it reads the current grid, never freed memory.
    py::array_t<int8_t> buffer({rows, cols});
    grid_data_ = buffer.mutable_data();
    buffer.attr("setflags")(py::arg("write") = false);
    grid_view_ = std::move(buffer);
  }
  ~PythonPlanner() override {
    py::gil_scoped_acquire gil;
    approach_ = py::object();
    grid_view_ = py::object();
    actions_ = py::object();
  }

  StepDetails Initialize(const Grid& grid) override {
    Call(grid, nullptr);
    return {};
  }
  StepDetails Adapt(const Grid& grid, const std::vector<int>& changed_cells) override {
    Call(grid, &changed_cells);
    return {};
  }
  PolicyScore Evaluate(const Grid& grid) override {
    if (actions_data_ == nullptr) return {};  // the approach raised: the run stops
    evaluator_.Evaluate(grid, actions_data_, depths_);
    return ScoreGrid(grid, depths_);
  }

 private:
  void Call(const Grid& grid, const std::vector<int>* changed_cells) {
    py::gil_scoped_acquire gil;
    if (control_.error) return;
    try {
      std::memcpy(grid_data_, grid.codes().data(), static_cast<size_t>(grid.size()));
      py::object result;
      if (changed_cells == nullptr) {
        result = approach_.attr("initialize")(grid_view_);
      } else {
        py::array_t<int32_t> changed(static_cast<py::ssize_t>(changed_cells->size()),
                                     changed_cells->data());
        result = approach_.attr("adapt")(grid_view_, changed);
      }
      if (result.is_none()) result = approach_.attr("actions");
      TakeActions(result, grid);
    } catch (...) {
      actions_ = py::object();
      actions_data_ = nullptr;
      control_.error = std::current_exception();
      control_.stop = true;
    }
  }

  // Keeps `result` itself when it is int8 and C-contiguous (no copy), else
  // an int8 copy; either way checks its shape and values.
  void TakeActions(py::handle result, const Grid& grid) {
    py::array array = py::array::ensure(result);
    if (!array) throw std::invalid_argument("an approach must return a numpy array of actions");
    if (!array.dtype().is(py::dtype::of<int8_t>()) || !(array.flags() & py::array::c_style)) {
      array = py::array_t<int8_t, py::array::c_style | py::array::forcecast>::ensure(array);
    }
    const bool grid_shaped =
        array.ndim() == 2 && array.shape(0) == grid.rows() && array.shape(1) == grid.cols();
    if (!grid_shaped && !(array.ndim() == 1 && array.shape(0) == grid.size())) {
      throw std::invalid_argument("the actions must have the maze's shape (" +
                                  std::to_string(grid.rows()) + ", " + std::to_string(grid.cols()) +
                                  ") or (" + std::to_string(grid.size()) + ",)");
    }
    const int8_t* data = static_cast<const int8_t*>(array.data());
    // -1..7 is 0..8 shifted: one branch-free pass (vectorised), the
    // offending cell searched only when there is one.
    uint8_t worst = 0;
    for (int cell = 0; cell < grid.size(); ++cell) {
      worst = std::max(worst, static_cast<uint8_t>(static_cast<uint8_t>(data[cell]) + 1));
    }
    if (worst > kNumActions) {
      const int8_t* bad = std::find_if(data, data + grid.size(),
                                       [](int8_t a) { return a < -1 || a >= kNumActions; });
      throw std::invalid_argument("cell " + std::to_string(bad - data) + " has action " +
                                  std::to_string(*bad) +
                                  "; actions are 0..7 (N, NE, E, SE, S, SW, W, NW) or -1");
    }
    actions_ = std::move(array);
    actions_data_ = data;
  }

  py::object approach_;
  RunControl& control_;
  py::object grid_view_;
  int8_t* grid_data_ = nullptr;
  py::object actions_;  // the array the last call returned, held while scored
  const int8_t* actions_data_ = nullptr;
  PolicyEvaluator evaluator_;
  PolicyDepths depths_;
};

// Runs `work` (which returns when done or when control.stop is set) on a
// thread of its own while this one waits without the GIL, checking for
// Ctrl-C every 50 ms. Returns true when a Ctrl-C stopped it (its
// KeyboardInterrupt is pending, for the caller to raise after cleaning up).
template <typename Work>
bool RunWithoutGil(RunControl& control, Work work) {
  bool done = false;
  std::mutex mutex;
  std::condition_variable finished;
  bool interrupted = false;
  py::gil_scoped_release release;
  std::thread worker([&] {
    work();
    std::lock_guard lock(mutex);
    done = true;
    finished.notify_all();
  });
  std::unique_lock lock(mutex);
  while (!finished.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; })) {
    if (interrupted) continue;
    lock.unlock();
    {
      py::gil_scoped_acquire gil;
      // A pending signal's handler raises (KeyboardInterrupt): stop the
      // run, the exception staying set for after it.
      if (PyErr_CheckSignals() != 0) {
        interrupted = true;
        control.stop = true;
      }
    }
    lock.lock();
  }
  lock.unlock();
  worker.join();
  return interrupted;
}

// A Python approach of a run: (the built-in names listed before it,
// comma-separated; label; the object, or a class to make one of for each
// run).
using ExternalArg = std::tuple<std::string, std::string, py::object>;

// Runs `plan` with the Python approaches `external` added (a class is
// instantiated for this run) as `dynapath run --local`: RunLocal, which
// writes plan.out_dir's files. `builtin`: whether --approach named any.
std::vector<ApproachRun> RunWithPython(runtime::RunPlan plan, const runtime::ScenarioSetup& setup,
                                       int threads, bool builtin,
                                       const std::vector<ExternalArg>& external) {
  if (!builtin) plan.approaches.clear();
  RunControl control;
  for (const auto& [names_before, label, approach] : external) {
    // Its place: after the built-in approaches listed before it ("all"
    // and repeated names counted as --approach counts them).
    const size_t before = names_before.empty() ? 0 : Take(ParseApproachList(names_before)).size();
    py::object instance = py::isinstance<py::type>(approach) ? approach() : approach;
    plan.external.push_back(
        {label,
         std::make_shared<PythonPlanner>(std::move(instance), setup.scenario.grid.rows(),
                                         setup.scenario.grid.cols(), control),
         before});
  }
  std::optional<Result<std::vector<ApproachRun>>> runs;
  const bool interrupted = RunWithoutGil(
      control, [&] { runs.emplace(runtime::RunLocal(plan, setup, threads, {}, &control.stop)); });
  plan.external.clear();  // the planners drop their Python objects here
  if (interrupted) throw py::error_already_set();
  if (control.error) std::rethrow_exception(control.error);
  return Take(std::move(*runs));
}

// dynapath.run: `args` are `dynapath run`'s options (the package builds
// them from its keywords), `builtin` whether --approach names any, and
// `external` the Python approaches. Returns the texts of results.csv and
// results_detailed.csv.
std::pair<std::string, std::string> Run(const Maze& maze, std::vector<std::string> args,
                                        bool builtin, std::vector<ExternalArg> external) {
  CLI::App app;
  runtime::RunOptions options;
  runtime::ThreadOptions thread_options;
  runtime::OptionGroup group(app);
  runtime::DeclareRunOptions(group, options);
  runtime::DeclareThreadOptions(group, thread_options);
  Check(runtime::ParseArguments(app, std::move(args)));
  const runtime::RunPlan plan = Take(runtime::ResolveRunOptions(options));
  const int threads = Take(runtime::ResolveThreads(thread_options));
  const runtime::ScenarioSetup setup{maze.scenario, maze.labels, maze.seed, maze.source};
  const std::vector<ApproachRun> done = RunWithPython(plan, setup, threads, builtin, external);
  return {SummaryResultsCsv(done), DetailedResultsCsv(done)};
}

// `python3 -m dynapath run ARGS` (what `dynapath run --approach py:...`
// hands off to): `dynapath run`'s maze, run, thread and log options, in one
// process (--local; --agents and --embedded are refused), with the Python
// approaches `external` the package took out of --approach. Writes the
// result files to --out as the CLI does; returns the --out directory.
std::string CliRun(std::vector<std::string> args, bool builtin, std::vector<ExternalArg> external) {
  CLI::App app;
  runtime::OptionGroup group(app);
  runtime::ModeOptions mode;
  runtime::DeclareModeOptions(group, mode);
  runtime::ScenarioOptions scenario;
  runtime::DeclareScenarioOptions(group, scenario);
  runtime::RunOptions options;
  runtime::DeclareRunOptions(group, options);
  runtime::ThreadOptions thread_options;
  runtime::DeclareThreadOptions(group, thread_options);
  runtime::LogOptions log;
  runtime::DeclareLogOptions(group, log);
  Check(runtime::ParseArguments(app, std::move(args)));
  if (mode.agents || mode.embedded) {
    throw std::invalid_argument(
        "a Python approach (py:) runs in this process: --agents and --embedded are not "
        "available with it (use --local)");
  }
  Check(runtime::ApplyLogLevel(log));
  const runtime::ScenarioSetup setup = Take(runtime::ResolveScenario(scenario));
  const runtime::RunPlan plan = Take(runtime::ResolveRunOptions(options));
  const int threads = Take(runtime::ResolveThreads(thread_options));
  spdlog::info("maze {} {} ({}), {} time steps, {} approaches ({} in Python), {} threads",
               setup.labels.size_label, setup.labels.difficulty_label, setup.source,
               setup.scenario.changes.steps.size(),
               (builtin ? plan.approaches.size() : 0) + external.size(), external.size(), threads);
  RunWithPython(plan, setup, threads, builtin, external);
  return plan.out_dir;
}

// The study files dynapath.experiment writes (those of `dynapath experiment`
// but its manifest and log).
const std::vector<std::string>& ExperimentFiles() {
  static const std::vector<std::string> files = {
      "results.csv",      "results_detailed.csv",      "repeats.csv",      "summary.csv",
      "edge_results.csv", "edge_results_detailed.csv", "edge_repeats.csv", "edge_summary.csv"};
  return files;
}

// A configuration of a study run as `dynapath experiment --embedded` runs
// it (tools/study's RunConfiguration): envsim, the coordinator and the
// agents as threads over memq://, each configuration a run of its own id
// and secret; Ctrl-C stops it (KeyboardInterrupt).
void RunEmbedded(const study::StudyOptions& options, const study::StudyConfiguration& configuration,
                 const runtime::RunPlan& plan, const runtime::ScenarioSetup& setup) {
  launch::DistributedRun run;
  run.process.run_id = protocol::NewRunId();
  runtime::MakeRunSecret(run.process);
  run.process.bus.max_grid_cells = app::GridCap(setup.scenario.grid);
  run.agents = options.mode.agents;
  run.threads_per_agent = app::ThreadsPerAgent(options.threads, options.mode.agents);
  run.scenario = runtime::ScenarioOptionsOf(study::ScenarioSpecOf(configuration));
  run.log_level = options.log.log_level;
  spdlog::info("run {}: envsim, coordinator and {} agents as threads over memq://",
               run.process.run_id, run.agents);
  RunControl control;
  std::optional<Status> ran;
  const bool interrupted = RunWithoutGil(
      control, [&] { ran.emplace(launch::RunEmbedded(run, plan, setup, control.stop)); });
  if (interrupted) throw py::error_already_set();
  if (!*ran && !ran->error().IsCancelled()) {
    throw std::runtime_error("the embedded run failed (" + ran->error().message + ")");
  }
}

// dynapath.experiment and `python3 -m dynapath experiment ARGS`: a study of
// `dynapath experiment`'s options `args` (its own declaration and
// resolution, --config included), every configuration run in this process
// as `dynapath experiment --local` (or --embedded) runs it (the same plan,
// maze options and run options per configuration), the Python approaches
// `external` beside the built-in ones (--local only), and the merged files and repeats' statistics
// written by the study library itself. No manifest, log or resume: each call runs the whole study.
// Returns the --out directory.
std::string Experiment(std::vector<std::string> args, bool builtin,
                       std::vector<ExternalArg> external) {
  CLI::App app;
  runtime::OptionGroup group(app);
  study::StudyCommandLine given;
  study::DeclareStudyCommandLine(group, given);
  std::optional<std::string> config_path;
  study::DeclareStudyConfigOption(group, config_path);
  Check(runtime::ParseArguments(app, std::move(args)));
  if ((given.mode.agents || given.mode.embedded) && !external.empty()) {
    throw std::invalid_argument(
        "a study with a Python approach runs in this process: --agents and --embedded are not "
        "available with it (use --local)");
  }
  if (given.mode.agents && !given.mode.embedded) {
    throw std::invalid_argument(
        "--agents N starts agent processes in a private network of their own, which a Python "
        "process cannot enter: use mode='embedded' (agents as threads over memq://) or run "
        "`dynapath experiment --agents N` and read its files (dynapath.StudyResult)");
  }
  const study::GivenStudyOptions command_line = Take(study::CommandLineStudyOptions(app, given));
  study::GivenStudyOptions file_options;
  if (config_path) {
    const study::ConfigFile file = Take(study::ReadConfigFile(*config_path));
    file_options = Take(study::StudyFileOptions(file));
  }
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const study::StudyOptions options = Take(
      study::ResolveStudyOptions(study::MergeStudyOptions(file_options, command_line), hardware));
  if (!options.sweeps.empty()) {
    throw std::invalid_argument(
        "parameter sweeps (a list in the study file) are not available with Python approaches; "
        "run one study per value");
  }
  Check(runtime::ApplyLogLevel(options.log));
  const std::vector<study::StudyConfiguration> plan = study::MakeStudyPlan(options);
  const std::string out = options.out;
  Check(runtime::PrepareOutputDirectory(out, "out"));
  const runtime::OutputLock lock = Take(runtime::OutputLock::Acquire(out, "out"));
  Check(runtime::CheckOutputFiles(out, ExperimentFiles(), "out"));
  // A study of `dynapath experiment` there would be left with a manifest
  // that no longer describes its files.
  if (std::filesystem::exists(std::filesystem::path(out) / "manifest.json")) {
    throw std::invalid_argument("option --out: " + out +
                                " holds a study of `dynapath experiment` (manifest.json); give "
                                "another directory");
  }

  std::vector<std::string> main_dirs, edge_dirs;
  std::vector<study::RepeatFiles> main_repeats, edge_repeats;
  bool has_edge = false;
  for (size_t i = 0; i < plan.size(); ++i) {
    const study::StudyConfiguration& configuration = plan[i];
    const std::string directory = out + "/" + configuration.Directory();
    Check(runtime::PrepareOutputDirectory(directory, "out"));
    spdlog::info("configuration {}/{} {}", i + 1, plan.size(), configuration.Label());
    const runtime::ScenarioSetup setup =
        Take(runtime::ResolveScenario(study::ScenarioSpecOf(configuration)));
    const runtime::RunPlan run_plan = study::RunPlanOf(options, configuration, directory);
    if (options.mode.kind == runtime::RunMode::kEmbedded) {
      RunEmbedded(options, configuration, run_plan, setup);
    } else {
      RunWithPython(run_plan, setup, options.threads, builtin, external);
    }
    has_edge = has_edge || configuration.edge_case;
    if (configuration.repeat == 1) {
      (configuration.edge_case ? edge_dirs : main_dirs).push_back(directory);
    }
    (configuration.edge_case ? edge_repeats : main_repeats)
        .push_back({directory, configuration.repeat, configuration.seed,
                    configuration.learner_seed.value_or(configuration.seed)});
  }
  const bool repeats = options.repeats > 1;
  Check(study::MergeResultFiles(main_dirs, out, ""));
  if (repeats) Check(study::WriteRepeatFiles(main_repeats, out, ""));
  if (has_edge) {
    Check(study::MergeResultFiles(edge_dirs, out, "edge_"));
    if (repeats) Check(study::WriteRepeatFiles(edge_repeats, out, "edge_"));
  }
  return out;
}

// ---------------------------------------------------------------- service client

// dynapath.ServiceClient: runtime's client of `dynapath serve` (the one
// `dynapath query` and `feed` use), so the bus, its authentication trailer
// and the fragmenting are the C++ ones; liblcm is linked here (Debian 12
// has no Python LCM binding). Waits release the GIL.
class PythonServiceClient {
 public:
  PythonServiceClient(const std::string& run_id, const std::string& lcm_url,
                      std::optional<std::string> secret_file, bool insecure,
                      std::optional<std::string> name) {
    if (lcm_url.empty()) {
      throw std::invalid_argument(
          "lcm_url is required (the service's --lcm-url, e.g. 'udpm://239.255.76.67:7667?ttl=0')");
    }
    runtime::ProcessOptions options;
    options.run_id = run_id;
    options.lcm_url = lcm_url;
    options.secret_file = std::move(secret_file);
    options.insecure = insecure;
    process_ = Take(runtime::ResolveProcessOptions(options, true));
    source_ = name ? *name : "python-" + std::to_string(getpid());
    if (source_.empty() || source_.size() > 64) {
      throw std::invalid_argument("client must be 1-64 characters, got '" + source_ + "'");
    }
    client_ =
        Take(runtime::ServiceClient::Open(process_, source_, runtime::ServiceClient::kRepliesOnly));
  }

  // One path per start: a dict as `dynapath query --json` prints it.
  py::list Query(const std::vector<std::pair<int32_t, int32_t>>& starts, double timeout) {
    if (starts.empty()) throw std::invalid_argument("query needs at least one start (row, col)");
    if (starts.size() > 65536) throw std::invalid_argument("at most 65536 starts per query");
    const path_reply_t reply = Ask(starts, timeout);
    if (reply.refused != path_reply_t::ACCEPTED) {
      throw std::runtime_error(
          reply.refused == path_reply_t::NOT_READY
              ? "the service has no policy yet (still training its first) after timeout"
              : "the service refused the query: more starts than its --max-starts (64 by "
                "default); ask in smaller batches");
    }
    py::list paths;
    for (int i = 0; i < reply.num_starts; ++i) {
      py::array_t<int32_t> cells({static_cast<py::ssize_t>(reply.path_cells[i]), py::ssize_t{2}});
      auto view = cells.mutable_unchecked<2>();
      for (int k = 0; k < reply.path_cells[i]; ++k) {
        const size_t at = static_cast<size_t>(reply.path_offset[i] + k);
        view(k, 0) = reply.path_rows[at];
        view(k, 1) = reply.path_cols[at];
      }
      py::dict path;
      path["start"] = py::make_tuple(reply.start_rows[i], reply.start_cols[i]);
      path["status"] = RouteStatusName(static_cast<RouteStatus>(reply.status[i]));
      path["length"] = reply.length[i];
      path["path"] = std::move(cells);
      path["version"] = reply.version;
      path["step"] = reply.time_step;
      path["answered_by"] = AnsweredByName(static_cast<AnsweredBy>(reply.answered_by[i]));
      paths.append(std::move(path));
    }
    return paths;
  }

  // The service's maze fingerprint, approach, version and step.
  py::dict Probe(double timeout) {
    const path_reply_t reply = Ask({}, timeout);
    if (reply.refused == path_reply_t::NOT_READY) {
      throw std::runtime_error("the service has no policy yet (still training its first)");
    }
    py::dict info;
    info["maze_fingerprint"] = FingerprintText(static_cast<uint64_t>(reply.maze_fingerprint));
    info["approach"] = reply.approach;
    info["version"] = reply.version;
    info["step"] = reply.time_step;
    return info;
  }

  // Publishes one obstacle update (the cells `blocked` become obstacles,
  // `freed` free), made for the service's maze; returns its sequence number.
  int64_t Update(const std::vector<std::pair<int32_t, int32_t>>& blocked,
                 const std::vector<std::pair<int32_t, int32_t>>& freed, double timeout) {
    if (blocked.empty() && freed.empty()) throw std::invalid_argument("an update changes no cell");
    if (blocked.size() + freed.size() > static_cast<size_t>(protocol::kMaxGridCells)) {
      throw std::invalid_argument("too many cells in one update");
    }
    if (!fingerprint_) fingerprint_ = static_cast<uint64_t>(Ask({}, timeout).maze_fingerprint);
    obstacle_update_t update{};
    update.run_id = process_.run_id;
    update.source = source_;
    update.sequence = ++sequence_;
    update.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                       std::chrono::system_clock::now().time_since_epoch())
                       .count();
    update.maze_fingerprint = static_cast<int64_t>(*fingerprint_);
    for (const auto& [cells, state] : {std::pair{&blocked, obstacle_update_t::OBSTACLE},
                                       std::pair{&freed, obstacle_update_t::FREE}}) {
      for (const auto& [row, col] : *cells) {
        update.rows.push_back(row);
        update.cols.push_back(col);
        update.states.push_back(state);
      }
    }
    update.num_cells = static_cast<int32_t>(update.rows.size());
    client_->bus().Publish(protocol::channel::kMapUpdates, update);
    return update.sequence;
  }

  // The same in metres in the map's frame (obstacle_points_t on
  // MAP_POINTS): the service turns each point into the cell holding it.
  // Its sequence numbers are the same counter as Update's.
  int64_t UpdateXy(const std::vector<std::pair<double, double>>& blocked,
                   const std::vector<std::pair<double, double>>& freed, double timeout) {
    if (blocked.empty() && freed.empty()) throw std::invalid_argument("an update changes no cell");
    if (blocked.size() + freed.size() > static_cast<size_t>(protocol::kMaxUpdateCells)) {
      throw std::invalid_argument("too many points in one update");
    }
    for (const auto* points : {&blocked, &freed}) {
      for (const auto& [x, y] : *points) {
        if (!std::isfinite(x) || !std::isfinite(y)) {
          throw std::invalid_argument("a point's x and y must be finite metres");
        }
      }
    }
    if (!fingerprint_) fingerprint_ = static_cast<uint64_t>(Ask({}, timeout).maze_fingerprint);
    obstacle_points_t update =
        protocol::PointsToMessage(blocked, freed, source_, ++sequence_, *fingerprint_);
    update.run_id = process_.run_id;
    update.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                       std::chrono::system_clock::now().time_since_epoch())
                       .count();
    client_->bus().Publish(protocol::channel::kMapPoints, update);
    return update.sequence;
  }

  // Probes until the service's policy is of time step `step` or later;
  // returns the step.
  int WaitForStep(int step, double timeout) {
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(timeout));
    while (true) {
      const double left =
          std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
      if (left <= 0) break;
      const path_reply_t reply = Ask({}, left);
      if (reply.refused != path_reply_t::NOT_READY && reply.time_step >= step) {
        return reply.time_step;
      }
      py::gil_scoped_release release;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    throw std::runtime_error("the service did not reach time step " + std::to_string(step) +
                             " within the timeout");
  }

 private:
  // A reply (NOT_READY only when the timeout ran out before a policy), or
  // an error; a second service answering differently is an error too.
  path_reply_t Ask(const std::vector<std::pair<int32_t, int32_t>>& starts, double timeout) {
    if (!(timeout > 0)) throw std::invalid_argument("timeout must be > 0 seconds");
    std::optional<path_reply_t> reply;
    std::optional<std::string> two;
    {
      py::gil_scoped_release release;
      reply = client_->Ask(starts, timeout);
      if (reply && !checked_second_) {
        two = client_->SecondService();
        checked_second_ = true;
      }
    }
    if (!reply) {
      throw std::runtime_error("no reply from a service of run " + process_.run_id +
                               " within the timeout (" + std::to_string(timeout) + " s)");
    }
    if (two) throw std::runtime_error(*two);
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    return *reply;
  }

  runtime::ProcessSetup process_;
  std::string source_;
  std::unique_ptr<runtime::ServiceClient> client_;
  std::optional<uint64_t> fingerprint_;
  int64_t sequence_ = 0;
  bool checked_second_ = false;  // whether a second service was looked for (first reply)
};

// BFS Oracle's exact distances (core's NearestStationDistances) of a
// (rows, cols) grid of cell codes: int32, -1 where no station is reachable.
py::array BfsDistances(CodesArg codes) {
  const Grid grid = GridOfCodes(codes);
  std::vector<int32_t> distance, queue;
  NearestStationDistances(grid, distance, queue);
  py::array_t<int32_t> out({grid.rows(), grid.cols()});
  std::copy(distance.begin(), distance.end(), out.mutable_data());
  return out;
}

// Seconds per policy evaluation of `actions` on `grid` (what scoring a Python
// approach's step costs in C++), the mean of `repeats`: for
// bench/python_approach_bench.py.
double EvaluationSeconds(const Maze& maze,
                         py::array_t<int8_t, py::array::c_style | py::array::forcecast> actions,
                         int repeats) {
  const Grid& grid = maze.scenario.grid;
  if (actions.size() != grid.size()) throw std::invalid_argument("one action per cell");
  PolicyEvaluator evaluator;
  PolicyDepths depths;
  PolicyScore score;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < repeats; ++i) {
    evaluator.Evaluate(grid, actions.data(), depths);
    score = ScoreGrid(grid, depths);
  }
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  return score.starts < 0 ? 0.0 : elapsed.count() / std::max(1, repeats);
}

}  // namespace
}  // namespace dynapath::python

PYBIND11_MODULE(_dynapath, m) {
  using namespace dynapath;
  using namespace dynapath::python;
  m.doc() = "C++ core of the dynapath package; use the package `dynapath`, not this module.";

  m.attr("NUM_ACTIONS") = kNumActions;
  m.attr("ACTION_ROW_OFFSETS") = std::vector<int>(kActionRowOffset.begin(), kActionRowOffset.end());
  m.attr("ACTION_COL_OFFSETS") = std::vector<int>(kActionColOffset.begin(), kActionColOffset.end());
  m.attr("STATION_REWARD") = static_cast<double>(kStationReward);
  m.attr("BUMP_REWARD") = static_cast<double>(kBumpReward);
  m.attr("STEP_REWARD") = static_cast<double>(kStepReward);

  py::class_<Maze>(m, "Maze")
      .def_static("_generate", &Generate, py::arg("size"), py::arg("difficulty"), py::arg("seed"),
                  py::arg("cols"), py::arg("steps"))
      .def_static("_load", &Load, py::arg("path"), py::arg("stations"), py::arg("movers"),
                  py::arg("stations_file"), py::arg("changes"), py::arg("seed"), py::arg("steps"),
                  py::arg("allow_unreachable"), py::arg("force_changes"))
      .def_static("_from_array", &FromArray, py::arg("grid"), py::arg("changes"))
      .def_property_readonly("_grid", &GridView)
      .def_property_readonly("rows", [](const Maze& maze) { return maze.scenario.grid.rows(); })
      .def_property_readonly("cols", [](const Maze& maze) { return maze.scenario.grid.cols(); })
      .def_property_readonly("num_steps",
                             [](const Maze& maze) { return maze.scenario.changes.steps.size(); })
      .def_property_readonly("seed", [](const Maze& maze) { return maze.seed; })
      .def_property_readonly("source", [](const Maze& maze) { return maze.source; })
      .def_property_readonly(
          "fingerprint",
          [](const Maze& maze) { return FingerprintText(MazeFingerprint(maze.scenario.grid)); })
      .def_property_readonly("requested_moves",
                             [](const Maze& maze) {
                               std::vector<int> moves;
                               for (const ChangeStep& step : maze.scenario.changes.steps) {
                                 moves.push_back(step.requested_moves);
                               }
                               return py::array_t<int32_t>(moves.size(), moves.data());
                             })
      .def("_changes", &Changes, py::arg("steps"))
      .def("_grid_at", &GridAt, py::arg("step"))
      .def("_text", [](const Maze& maze) { return GridToText(maze.scenario.grid); })
      .def("_save", [](const Maze& maze,
                       const std::string& path) { Check(SaveGrid(maze.scenario.grid, path)); })
      .def("_save_changes", [](const Maze& maze, const std::string& path) {
        Check(SaveChanges(maze.scenario.changes, maze.scenario.grid, path));
      });

  py::class_<GridEnvCore>(m, "GridEnvCore", py::dynamic_attr())
      .def(py::init<const Maze&, std::optional<int>, std::optional<int>>(), py::arg("maze"),
           py::arg("steps_per_change"), py::arg("max_steps"))
      .def("_reset", &GridEnvCore::Reset, py::arg("seed"), py::arg("options"))
      .def("step", &GridEnvCore::Step, py::arg("action"), R"doc(Move the walker once.

Parameters
----------
action : int
    0..7 = N, NE, E, SE, S, SW, W, NW.

Returns
-------
observation : numpy.ndarray of int64, shape (2,)
    The walker's (row, col).
reward : float
    +100 ending on a station, else -10 for a bump (it stayed), else -1.
terminated : bool
    It ended on a station.
truncated : bool
    max_steps steps were taken without reaching one.
info : dict
    {"time_step": the maze's time step for the next move}.

Raises
------
ValueError
    For an action outside 0..7.
RuntimeError
    When the episode is over and reset() was not called.
)doc")
      .def_property_readonly(
          "max_steps", [](const GridEnvCore& env) { return env.world().max_steps(); },
          "int: steps after which an episode is truncated.")
      .def_property_readonly(
          "steps_per_change", [](const GridEnvCore& env) { return env.world().steps_per_change(); },
          "int: environment steps per time step of the maze's changes; 0, a static maze.")
      .def_property_readonly("elapsed_steps", &GridEnvCore::steps,
                             "int: steps taken since the last reset.");

  py::class_<VectorEnvCore>(m, "VectorEnvCore", py::dynamic_attr())
      .def(py::init<const Maze&, int, std::optional<int>, std::optional<int>>(), py::arg("maze"),
           py::arg("num_envs"), py::arg("steps_per_change"), py::arg("max_steps"))
      .def("_reset", &VectorEnvCore::Reset, py::arg("seed"), py::arg("options"))
      .def("step", &VectorEnvCore::Step, py::arg("actions"),
           R"doc(Move every walker once, in one C++ call.

Parameters
----------
actions : numpy.ndarray of int, shape (num_envs,)
    One action 0..7 per walker.

Returns
-------
observations : numpy.ndarray of int64, shape (num_envs, 2)
    After the move, or the new start of a walker whose episode ended.
rewards : numpy.ndarray of float64, shape (num_envs,)
terminated, truncated : numpy.ndarray of bool, shape (num_envs,)
infos : dict
    "final_observation" (num_envs, 2): the cell an ended episode finished
    on, valid where the bool mask "_final_observation" is True.
)doc")
      .def_property_readonly("num_envs", &VectorEnvCore::num_envs, "int: number of walkers.")
      .def_property_readonly(
          "max_steps", [](const VectorEnvCore& env) { return env.world().max_steps(); },
          "int: steps after which a walker's episode is truncated.")
      .def_property_readonly(
          "steps_per_change",
          [](const VectorEnvCore& env) { return env.world().steps_per_change(); },
          "int: steps of an episode per time step of the maze's changes; 0, a static maze.");

  py::class_<World, std::shared_ptr<World>>(m, "World")
      .def(py::init([](const Maze& maze, std::optional<int> steps_per_change,
                       std::optional<int> max_steps) {
             return std::const_pointer_cast<World>(MakeWorld(maze, steps_per_change, max_steps));
           }),
           py::arg("maze"), py::arg("steps_per_change"), py::arg("max_steps"))
      .def_property_readonly("max_steps", &World::max_steps)
      .def_property_readonly("steps_per_change", &World::steps_per_change)
      .def("time_after", &World::TimeAfter, py::arg("steps"))
      .def("free_cells",
           [](const World& world) {
             return py::array_t<int32_t>(world.free_cells().size(), world.free_cells().data());
           })
      .def("step_robots", &StepRobots, py::arg("steps"), py::arg("positions"), py::arg("actions"));

  py::class_<PolicyState>(m, "Policy",
                          R"doc(One section of a policy file: one learning approach's policy.

Attributes
----------
approach : str
    The approach's result-file name ("singleAgent", "fedAsynQ_EqAvg", ...).
rows, cols : int
    The maze's shape.
leaf_limit, node_count : int
    The quadtree's shape.
semantics : str
    "ours" or "report".
precision : str
    "float" or "double": the dtype of q.
step : int
    The time step after which it was saved.
run_seed : int
fingerprint, initial_fingerprint : str
    Maze fingerprints at `step` and at time step 0.
q : numpy.ndarray, shape (rows, cols, 8)
    The root Q-table (writable view).
training_counts : numpy.ndarray of int64, shape (node_count,)
    Trainings so far per quadtree node (writable view).
baselines : numpy.ndarray of float64
    Per node, the tree strategy's stored success rate, -1 never trained;
    empty for other strategies (writable view).
)doc")
      .def_property_readonly(
          "approach", [](const PolicyState& s) { return ApproachName(s.approach); },
          "str: the approach's result-file name.")
      .def_readonly("rows", &PolicyState::rows, "int: the maze's rows.")
      .def_readonly("cols", &PolicyState::cols, "int: the maze's columns.")
      .def_readonly("leaf_limit", &PolicyState::leaf_limit,
                    "int: the quadtree's largest leaf side.")
      .def_readonly("node_count", &PolicyState::node_count, "int: the quadtree's nodes.")
      .def_readonly("step", &PolicyState::step,
                    "int: the time step after which the policy was saved.")
      .def_readonly("run_seed", &PolicyState::run_seed,
                    "int: the seed the learners' job seeds derive from.")
      .def_property_readonly(
          "semantics",
          [](const PolicyState& s) { return runtime::SemanticsWords().Name(s.semantics); },
          "str: \"ours\" or \"report\".")
      .def_property_readonly(
          "precision", [](const PolicyState& s) { return PrecisionName(s.precision); },
          "str: \"float\" or \"double\", the dtype of q.")
      .def_property_readonly(
          "fingerprint", [](const PolicyState& s) { return FingerprintText(s.fingerprint); },
          "str: the maze fingerprint at `step`.")
      .def_property_readonly(
          "initial_fingerprint",
          [](const PolicyState& s) { return FingerprintText(s.initial_fingerprint); },
          "str: the maze fingerprint at time step 0.")
      .def_property_readonly("q", &QView,
                             "numpy.ndarray (rows, cols, 8), float32 or float64: the root "
                             "Q-table, a writable view")
      .def_property_readonly(
          "training_counts",
          [](py::object self) { return FieldView(self, &PolicyState::training_counts); },
          "numpy.ndarray of int64 (node_count,): trainings per quadtree "
          "node, a writable view")
      .def_property_readonly(
          "baselines", [](py::object self) { return FieldView(self, &PolicyState::baselines); },
          "numpy.ndarray of float64: per node the stored success rate (-1 never trained), "
          "empty without the tree strategy; a writable view");

  m.def(
      "read_policy_sections",
      [](const std::string& path) { return Take(runtime::ReadPolicyFile(path)); }, py::arg("path"));
  m.def(
      "write_policy_sections",
      [](const std::string& path, const std::vector<PolicyState>& sections) {
        for (const PolicyState& s : sections) Check(CheckPolicyConsistent(s));
        Check(runtime::WritePolicyFile(path, sections));
      },
      py::arg("path"), py::arg("sections"));
  m.def("run", &Run, py::arg("maze"), py::arg("args"), py::arg("builtin"), py::arg("external"));
  m.def("cli_run", &CliRun, py::arg("args"), py::arg("builtin"), py::arg("external"));
  m.def("experiment", &Experiment, py::arg("args"), py::arg("builtin"), py::arg("external"));
  m.def("bfs_distances", &BfsDistances, py::arg("grid"));
  py::class_<PythonServiceClient>(m, "ServiceClientCore")
      .def(py::init<const std::string&, const std::string&, std::optional<std::string>, bool,
                    std::optional<std::string>>(),
           py::arg("run_id"), py::arg("lcm_url"), py::arg("secret_file"), py::arg("insecure"),
           py::arg("client"))
      .def("query", &PythonServiceClient::Query, py::arg("starts"), py::arg("timeout"))
      .def("probe", &PythonServiceClient::Probe, py::arg("timeout"))
      .def("update", &PythonServiceClient::Update, py::arg("blocked"), py::arg("freed"),
           py::arg("timeout"))
      .def("update_xy", &PythonServiceClient::UpdateXy, py::arg("blocked"), py::arg("freed"),
           py::arg("timeout"))
      .def("wait_for_step", &PythonServiceClient::WaitForStep, py::arg("step"), py::arg("timeout"));
  m.def("_evaluation_seconds", &EvaluationSeconds, py::arg("maze"), py::arg("actions"),
        py::arg("repeats"));
  m.def(
      "set_log_level",
      [](const std::string& level) {
        const spdlog::level::level_enum parsed = spdlog::level::from_str(level);
        if (parsed == spdlog::level::off && level != "off") {
          throw std::invalid_argument(
              "log_level must be trace, debug, info, warn, error or off, "
              "got '" +
              level + "'");
        }
        spdlog::set_level(parsed);
      },
      py::arg("level"));
}
