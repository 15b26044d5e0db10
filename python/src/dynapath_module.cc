// _dynapath: the C++ side of the Python package dynapath (python/dynapath).
// Mazes (generated exactly as `dynapath maze` does, or loaded from every
// format the CLI reads), the MDP of SPEC section 2 for one walker, many
// walkers and several robots, and policy files. The package's Python files
// add the spaces, the dict-shaped multi-robot API and the docs users read.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/change_sequence.h"
#include "dynapath/grid.h"
#include "dynapath/limits.h"
#include "dynapath/mdp.h"
#include "dynapath/policy_state.h"
#include "dynapath/rng.h"
#include "python/src/walker_world.h"
#include "runtime/policy_file.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"

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
};

Maze FromSetup(runtime::ScenarioSetup setup) {
  return Maze{std::move(setup.scenario), std::move(setup.source), setup.seed};
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

// A maze from a (rows, cols) array of cell codes and optional changes.
Maze FromArray(py::array_t<int64_t, py::array::c_style | py::array::forcecast> codes,
               std::optional<std::vector<std::pair<py::array_t<int64_t, py::array::forcecast>,
                                                   py::array_t<int64_t, py::array::forcecast>>>>
                   changes) {
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
  Maze maze;
  maze.scenario.grid = grid;
  maze.source = "from an array";
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
}
