"""dynapath.run against `dynapath run --local`, and approaches written in Python."""

import os
import pathlib
import signal
import sys
import threading
import time

import numpy as np
import pandas as pd
import pytest

import dynapath

TIME_COLUMNS = ["InitialTime", "AdaptTimePerStep", "AdaptTime"]
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "examples"))
from nearest_station import NearestStation  # noqa: E402  (the approach under test)


def without_times(frame):
    return frame.drop(columns=[c for c in TIME_COLUMNS if c in frame.columns])


class BfsActions(NearestStation):
    """Exact distances' actions, recomputed on every step, labelled by the class."""

    name = None


def test_built_in_rows_equal_the_cli(cli, tmp_path):
    cli("run", "--local", "--size", 20, "--difficulty", "hard", "--approach",
        "A* Static,BFS Oracle,singleAgent", "--max-episodes", 60, "--threads", 1,
        "--out", tmp_path, "--log-level", "warn")
    maze = dynapath.Maze.generate(size=20, difficulty="hard")
    result = dynapath.run(maze, ["A* Static", "BFS Oracle", "singleAgent"], max_episodes=60,
                          threads=1)
    for ours, name in ((result.results, "results.csv"),
                       (result.detailed, "results_detailed.csv")):
        theirs = pd.read_csv(tmp_path / name)
        assert list(ours.columns) == list(theirs.columns)
        pd.testing.assert_frame_equal(without_times(ours), without_times(theirs))


def test_python_bfs_approach_scores_as_bfs_oracle():
    maze = dynapath.Maze.generate(size=20, difficulty="easy")
    result = dynapath.run(maze, ["BFS Oracle", BfsActions()])
    assert list(result.results["Approach"]) == ["BFS Oracle", "BfsActions"]
    detailed = result.detailed.set_index(["Approach", "TimeStep"])
    oracle, ours = detailed.loc["BFS Oracle"], detailed.loc["BfsActions"]
    assert len(ours) == maze.num_steps + 1
    pd.testing.assert_frame_equal(ours[["SuccessRate", "AvgPathLength", "NumChanges"]],
                                  oracle[["SuccessRate", "AvgPathLength", "NumChanges"]])


def test_rows_follow_the_given_order_and_names():
    class Fixed:
        name = "fixed"

        def initialize(self, grid):
            self.actions = np.zeros(grid.shape, dtype=np.int8)  # read as the attribute

        def adapt(self, grid, changed_cells):
            assert changed_cells.dtype == np.int32 and not grid.flags.writeable
            return None

    maze = dynapath.Maze.generate(size=12, difficulty="easy", steps=3)
    result = dynapath.run(maze, [Fixed(), "BFS Oracle", BfsActions(), "A* Static"])
    assert list(result.results["Approach"]) == ["fixed", "BFS Oracle", "BfsActions", "A* Static"]
    assert (result.detailed["Size"] == 12).all()


def test_unknown_parameters_and_bad_values_raise_the_cli_message():
    maze = dynapath.Maze.generate(size=12, difficulty="easy", steps=2)
    with pytest.raises(ValueError, match=r"^unknown option --max-episode \(see --help\)$"):
        dynapath.run(maze, ["BFS Oracle"], max_episode=3)
    with pytest.raises(ValueError, match="epsilon-start"):
        dynapath.run(maze, ["BFS Oracle"], epsilon_start=2)
    with pytest.raises(ValueError, match="unknown approach 'nope'"):
        dynapath.run(maze, ["nope"])


def test_a_bad_policy_or_a_raising_approach_ends_the_run():
    class Wrong:
        def initialize(self, grid):
            return np.full(grid.shape, 9, dtype=np.int8)

        def adapt(self, grid, changed_cells):
            raise AssertionError("not reached")

    class Raises(BfsActions):
        def adapt(self, grid, changed_cells):
            raise RuntimeError("my approach failed")

    maze = dynapath.Maze.generate(size=12, difficulty="easy", steps=3)
    with pytest.raises(ValueError, match="has action 9"):
        dynapath.run(maze, [Wrong()])
    with pytest.raises(ValueError, match=r"maze's shape \(12, 12\)"):
        dynapath.run(maze, [type("Small", (BfsActions,), {"initialize": lambda s, g: [1, 2]})()])
    with pytest.raises(RuntimeError, match="my approach failed"):
        dynapath.run(maze, [Raises()])


def test_ctrl_c_stops_a_long_run():
    class Slow(BfsActions):
        def adapt(self, grid, changed_cells):
            time.sleep(0.05)
            return super().adapt(grid, changed_cells)

    maze = dynapath.Maze.generate(size=20, difficulty="easy", steps=400)  # 20 s unstopped
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        dynapath.run(maze, [Slow()])
    assert time.monotonic() - start < 3


def test_bfs_distances_are_the_oracles():
    grid = np.array([[1, 1, 2], [1, 0, 1], [0, 1, 1]], dtype=np.int8)
    np.testing.assert_array_equal(dynapath.bfs_distances(grid),
                                  [[2, 1, 0], [2, -1, 1], [-1, 2, 2]])
