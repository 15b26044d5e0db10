"""Runs of approaches on a maze, in this process: ``dynapath run --local``.

:func:`run` runs built-in approaches (by the CLI's names) and approaches
written in Python side by side, through the same C++ run driver as the
CLI, and returns the result files' tables as pandas DataFrames.

A Python approach is any object with

* ``initialize(grid)``: the plan at time step 0;
* ``adapt(grid, changed_cells)``: the plan after a step's changes
  (``changed_cells``: int32 flat indices of the cells that changed);

each returning the policy: one action per cell, an int8 array of the maze's
shape (or flat), 0..7 (N, NE, E, SE, S, SW, W, NW) or -1 for none; or None
to have the object's ``actions`` attribute read. ``grid`` is a read-only
int8 (rows, cols) array of cell codes (0 obstacle, 1 free, 2 station), one
array for the whole run updated in place before every call. An int8
C-contiguous result is scored as it is, without a copy. The rows' label is
the object's ``name`` attribute, else its class's name. Its time in
``initialize`` and ``adapt`` are the InitialTime and AdaptTime columns.

The policy is scored as every approach's (the specification's section 4):
from every non-obstacle cell, the path that follows the cells' actions
succeeds when it reaches a station in fewer than rows + cols moves; a move
into an obstacle or off the grid, or no action, ends it as a failure.
"""

import io
import tempfile

from . import _dynapath

__all__ = ["RunResult", "bfs_distances", "run"]


class RunResult:
    """The result files of a run as pandas DataFrames.

    Attributes
    ----------
    results : pandas.DataFrame
        results.csv: one row per approach (Approach, Size, Difficulty,
        InitialTime, AdaptTimePerStep, AvgSuccessRate, AvgPathLength).
    detailed : pandas.DataFrame
        results_detailed.csv: one row per approach and time step.
    """

    def __init__(self, results_csv, detailed_csv):
        import pandas  # only runs need pandas

        self.results = pandas.read_csv(io.StringIO(results_csv))
        self.detailed = pandas.read_csv(io.StringIO(detailed_csv))

    def __repr__(self):
        return f"<dynapath.RunResult {', '.join(map(str, self.results['Approach']))}>"


def _label(approach):
    """The rows' label: the object's (or class's) ``name``, else its class's name."""
    name = getattr(approach, "name", None)
    if isinstance(name, str) and name:
        return name
    return approach.__name__ if isinstance(approach, type) else type(approach).__name__


def _split_approaches(approaches):
    """The built-in names and the Python approaches (as the binding takes
    them: the names before each, its label, the object) of `approaches`."""
    if isinstance(approaches, str):
        approaches = [approaches]
    names, external = [], []
    for approach in approaches:
        if isinstance(approach, str):
            names.append(approach)
        else:
            for method in ("initialize", "adapt"):
                if not callable(getattr(approach, method, None)):
                    raise TypeError(f"approach {approach!r} has no method {method}(...)")
            external.append((",".join(names), _label(approach), approach))
    return names, external


def _option_value(name, value):
    if isinstance(value, bool):
        raise ValueError(f"option --{name} takes a value, not {value!r}")
    if isinstance(value, (list, tuple)):
        return ",".join(map(str, value))
    return str(value)


def run(maze, approaches=("all",), out=None, threads=None, log_level="warn", **parameters):
    """Run approaches on a maze as ``dynapath run --local`` does.

    Parameters
    ----------
    maze : Maze
        The maze and its change sequence.
    approaches : sequence of str or objects
        Built-in approaches by the CLI's names (``"bfsOracle"``,
        ``"singleAgent"``, ``"all"``, ...) and Python approaches (see the
        module's docstring), run in the order given.
    out : str, optional
        A directory to write results.csv, results_detailed.csv and
        params.toml to as the CLI does (default: none kept).
    threads : int, optional
        The CLI's --threads (default: as the CLI).
    log_level : str
        The run's log lines on stderr: "info" shows the CLI's progress
        lines; default "warn".
    **parameters
        Every option of ``dynapath run``'s run plan by its name with
        underscores: the learner and strategy parameters (``max_episodes=``,
        ``epsilon_start=``, ...), ``leaf_limit``, ``semantics``,
        ``bootstrap``, ``learner_seed``, ``save_policy``, ...

    Returns
    -------
    RunResult

    Raises
    ------
    ValueError
        An unknown parameter or a bad value, with the CLI's message; a
        Python approach's result that is no policy.
    KeyboardInterrupt
        Ctrl-C: the run stops within a step (what was written to ``out``
        stays).
    """
    from .maze import Maze

    if not isinstance(maze, Maze):
        raise TypeError(f"maze must be a dynapath.Maze, got {type(maze).__name__}")
    names, external = _split_approaches(approaches)
    args = []
    for name, value in parameters.items():
        args += [f"--{name.replace('_', '-')}", _option_value(name, value)]
    if names:
        args += ["--approach", ",".join(names)]
    if threads is not None:
        args += ["--threads", str(threads)]
    _dynapath.set_log_level(log_level)
    with tempfile.TemporaryDirectory(prefix="dynapath-run-") as scratch:
        args += ["--out", out if out is not None else scratch]
        results_csv, detailed_csv = _dynapath.run(maze._core, args, bool(names), external)
    return RunResult(results_csv, detailed_csv)


def bfs_distances(grid):
    """BFS Oracle's exact distances to the nearest station.

    Parameters
    ----------
    grid : array_like (rows, cols)
        Cell codes: 0 obstacle, 1 free, 2 station.

    Returns
    -------
    numpy.ndarray of int32 (rows, cols)
        Moves to the nearest station over free 8-connected moves, 0 on
        stations, -1 for obstacles and cells without a path.
    """
    return _dynapath.bfs_distances(grid)
