"""Studies in this process: ``dynapath experiment --local`` (or
``--embedded``) from Python.

:func:`experiment` runs every approach (built-in ones by the CLI's names and
Python approaches, as :func:`dynapath.run` takes them) on every maze of a
study, with repeats, through the study code of ``dynapath experiment``
itself: the same plan of configurations, the same maze and run options per
configuration, the same merged files and the same repeats' statistics
(means, IQMs and 95% bootstrap intervals, computed in C++). Its result
files equal the CLI's for the same options, the time columns aside.
"""

import io
import os
import tempfile

from . import _dynapath
from .run import _option_value, _split_approaches

__all__ = ["StudyResult", "experiment"]


def _read_csv(path):
    import pandas  # only studies need pandas

    if not os.path.exists(path):
        return None
    with open(path, encoding="utf-8") as file:
        return pandas.read_csv(io.StringIO(file.read()))


class StudyResult:
    """The result files of a study as pandas DataFrames.

    Attributes
    ----------
    results : pandas.DataFrame
        results.csv: one row per configuration (size x difficulty, first
        repeat) and approach.
    detailed : pandas.DataFrame
        results_detailed.csv: the same per time step.
    repeats : pandas.DataFrame or None
        repeats.csv: every repeat's rows after its Repeat, Seed and
        LearnerSeed (None with one repeat, as the CLI writes none).
    summary : pandas.DataFrame or None
        summary.csv: per configuration, approach and metric the number of
        repeats, mean, standard deviation, median, IQM and the 95%
        bootstrap intervals of the mean and of the IQM; then each
        approach over every configuration ("all"). None with one repeat.
    edge_results, edge_detailed, edge_repeats, edge_summary : pandas.DataFrame or None
        The same of the report's edge case (None without it).
    out : str or None
        The study directory when one was given.
    """

    def __init__(self, directory, out):
        self.out = out
        for attribute, name in (("results", "results"), ("detailed", "results_detailed"),
                                ("repeats", "repeats"), ("summary", "summary")):
            setattr(self, attribute, _read_csv(os.path.join(directory, name + ".csv")))
            setattr(self, "edge_" + attribute,
                    _read_csv(os.path.join(directory, "edge_" + name + ".csv")))

    def __repr__(self):
        rows = 0 if self.results is None else len(self.results)
        return f"<dynapath.StudyResult {rows} result rows>"


def experiment(sizes=None, difficulties=None, approaches=("all",), repeats=None, edge_case=None,
               out=None, config=None, threads=None, log_level="warn", mode="local", agents=None,
               **parameters):
    """Run a study as ``dynapath experiment --local`` (or ``--embedded``) does.

    Parameters
    ----------
    sizes : sequence of int, optional
        Maze sizes (the CLI's --sizes; default the CLI's).
    difficulties : sequence of str, optional
        "easy", "medium", "hard" (--difficulties; default the CLI's).
    approaches : sequence of str, objects or classes
        Built-in approaches by the CLI's names and Python approaches (see
        :mod:`dynapath.run`), in the order of the result rows. An object
        serves every configuration (its ``initialize`` starts each); a
        class is instantiated for every configuration and repeat.
    repeats : int, optional
        Runs of each configuration (--repeats); with two or more the
        result has ``repeats`` and ``summary``.
    edge_case : bool, optional
        Whether the report's edge case (hard 50x50, seed 102) runs too
        (default the CLI's: yes).
    out : str, optional
        The study directory to write the result files to, runs/<name>/ per
        configuration included (default: a temporary one, removed). No
        manifest or log is written and nothing is resumed: every call runs
        the whole study. A directory holding a study of ``dynapath
        experiment`` (its manifest.json) is refused.
    config : str, optional
        A study file (TOML) as the CLI's --config; the keywords override it.
    threads : int, optional
        The CLI's --threads.
    log_level : str
        "info" shows a line per configuration on stderr; default "warn".
    mode : str
        "local" (default): every approach in this process on a thread
        pool, as ``--local``. "embedded": envsim, the coordinator and
        ``agents`` agents as threads of this process over memq://, as
        ``dynapath experiment --embedded``; built-in approaches only. The
        result files are the same in both modes, the time columns aside.
        Agent processes (``--agents N``) need a private network of their
        own, which a Python process cannot enter: run the CLI for them,
        ``subprocess.run(["dynapath", "experiment", "--agents", "2",
        "--out", DIR, ...])`` (it starts its processes in a private network
        namespace), and read its files with ``dynapath.StudyResult(DIR,
        DIR)``.
    agents : int, optional
        With mode="embedded": the number of agents (the CLI's --agents;
        default 1).
    **parameters
        Every other option of ``dynapath experiment`` by its name with
        underscores: ``steps``, ``seed``, ``maze_seeds``, ``maps``,
        ``stations``, ``movers``, ``learner_seed``, ``leaf_limit``,
        ``semantics``, ``bootstrap`` and every learner and strategy
        parameter (``max_episodes=``, ...).

    Returns
    -------
    StudyResult

    Raises
    ------
    ValueError
        An unknown option or a bad value, with the CLI's message; a mode
        other than "local" and "embedded", ``agents`` without
        mode="embedded", a Python approach with it; a Python approach's
        result that is no policy.
    KeyboardInterrupt
        Ctrl-C: the study stops within a step.
    """
    if mode not in ("local", "embedded"):
        raise ValueError(f"mode must be 'local' or 'embedded', got {mode!r} (agent processes: "
                         "run `dynapath experiment --agents N`; see help(dynapath.experiment))")
    names, external = _split_approaches(approaches)
    args = ["--embedded"] if mode == "embedded" else []
    if agents is not None:
        args += ["--agents", _option_value("agents", agents)]
    for name, value in (("sizes", sizes), ("difficulties", difficulties), ("repeats", repeats),
                        ("config", config), ("threads", threads)):
        if value is not None:
            args += [f"--{name}", _option_value(name, value)]
    if edge_case is not None:
        args.append("--edge-case" if edge_case else "--no-edge-case")
    for name, value in parameters.items():
        args += [f"--{name.replace('_', '-')}", _option_value(name, value)]
    if names:
        args += ["--approaches", ",".join(names)]
    args += ["--log-level", log_level]
    if out is not None:
        _dynapath.experiment(args + ["--out", out], bool(names), external)
        return StudyResult(out, out)
    with tempfile.TemporaryDirectory(prefix="dynapath-study-") as scratch:
        _dynapath.experiment(args + ["--out", scratch], bool(names), external)
        return StudyResult(scratch, None)
