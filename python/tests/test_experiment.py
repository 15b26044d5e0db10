"""dynapath.experiment against `dynapath experiment --local` (and its
embedded mode against its local one), and the CLI's py:MODULE:CLASS
approaches (handed over to python3 -m dynapath)."""

import os
import pathlib
import shutil
import subprocess
import sys

import pandas as pd
import pytest

import dynapath

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"
sys.path.insert(0, str(EXAMPLES))
from nearest_station import NearestStation  # noqa: E402  (the approach under test)
TIME_COLUMNS = ["InitialTime", "AdaptTimePerStep", "AdaptTime"]
TIME_METRICS = ["InitialTime", "AdaptTimePerStep"]
# A tiny study: one maze, two repeats, a few steps, two approaches (one learning).
STUDY = dict(sizes=[20], difficulties=["easy"], repeats=2, steps=4, edge_case=False,
             max_episodes=40, threads=1)
STUDY_ARGS = ["--local", "--sizes", 20, "--difficulties", "easy", "--repeats", 2, "--steps", 4,
              "--no-edge-case", "--max-episodes", 40, "--threads", 1, "--log-level", "warn"]


def without_times(frame):
    frame = frame.drop(columns=[c for c in TIME_COLUMNS if c in frame.columns])
    if "Metric" in frame.columns:  # summary.csv: the time metrics' rows
        frame = frame[~frame["Metric"].isin(TIME_METRICS)].reset_index(drop=True)
    return frame


def test_study_files_equal_the_cli(cli, tmp_path):
    approaches = "BFS Oracle,singleAgent"
    cli("experiment", *STUDY_ARGS, "--approaches", approaches, "--out", tmp_path / "cli")
    result = dynapath.experiment(approaches=approaches.split(","), out=str(tmp_path / "py"),
                                 **STUDY)
    assert result.out == str(tmp_path / "py")
    for frame, name in ((result.results, "results.csv"), (result.detailed, "results_detailed.csv"),
                        (result.repeats, "repeats.csv"), (result.summary, "summary.csv")):
        theirs = pd.read_csv(tmp_path / "cli" / name)
        assert list(frame.columns) == list(theirs.columns), name
        pd.testing.assert_frame_equal(without_times(frame), without_times(theirs))
    assert set(result.summary["Size"].astype(str)) == {"20"}  # one configuration: no pooled rows
    assert (result.summary["MeanCILow"] <= result.summary["MeanCIHigh"]).all()
    # Each configuration's own files, as the CLI writes them.
    runs = sorted(p.name for p in (tmp_path / "cli" / "runs").iterdir())
    assert runs == sorted(p.name for p in (tmp_path / "py" / "runs").iterdir()) == \
        ["20_easy_50", "20_easy_50_r2"]
    for run in runs:
        pd.testing.assert_frame_equal(
            without_times(pd.read_csv(tmp_path / "py" / "runs" / run / "results_detailed.csv")),
            without_times(pd.read_csv(tmp_path / "cli" / "runs" / run / "results_detailed.csv")))
    assert result.edge_results is None and result.edge_summary is None


def test_embedded_study_files_equal_local(tmp_path):
    # Two configurations, a learning approach trained by two embedded agents.
    tiny = dict(sizes=[20], difficulties=["easy", "medium"], steps=3, edge_case=False,
                max_episodes=40, threads=2, approaches=["BFS Oracle", "singleAgent"])
    local = dynapath.experiment(out=str(tmp_path / "local"), **tiny)
    embedded = dynapath.experiment(mode="embedded", agents=2, out=str(tmp_path / "embedded"),
                                   **tiny)
    assert len(local.results) == 4
    for mine, theirs in ((embedded.results, local.results),
                         (embedded.detailed, local.detailed)):
        pd.testing.assert_frame_equal(without_times(mine), without_times(theirs))
    runs = sorted(p.name for p in (tmp_path / "local" / "runs").iterdir())
    assert len(runs) == 2
    assert runs == sorted(p.name for p in (tmp_path / "embedded" / "runs").iterdir())
    for run in runs:  # each configuration's own files, written by the coordinator
        mine, theirs = (pd.read_csv(tmp_path / mode / "runs" / run / "results_detailed.csv")
                        for mode in ("embedded", "local"))
        pd.testing.assert_frame_equal(without_times(mine), without_times(theirs))


def test_embedded_refuses_what_it_cannot_run():
    with pytest.raises(ValueError, match="mode must be 'local' or 'embedded'"):
        dynapath.experiment(sizes=[20], mode="agents")
    with pytest.raises(ValueError, match="--agents and --embedded are not available"):
        dynapath.experiment(sizes=[20], mode="embedded", approaches=[NearestStation])


class Distances(NearestStation):
    """BFS distances' actions (python/examples/nearest_station.py), counted."""

    name = None
    made = 0

    def __init__(self):
        Distances.made += 1


def test_python_approach_in_a_study_scores_as_bfs_oracle():
    Distances.made = 0
    result = dynapath.experiment(approaches=[Distances, "BFS Oracle"], **STUDY)
    assert Distances.made == 2  # a new one for each repeat
    assert list(result.results["Approach"]) == ["Distances", "BFS Oracle"]
    repeats = without_times(result.repeats).set_index(["Repeat", "Approach"])
    for repeat in (1, 2):
        pd.testing.assert_series_equal(repeats.loc[(repeat, "Distances")],
                                       repeats.loc[(repeat, "BFS Oracle")], check_names=False)
    summary = without_times(result.summary).set_index(["Approach", "Size", "Metric"])
    pd.testing.assert_frame_equal(summary.loc["Distances"], summary.loc["BFS Oracle"])


def test_bad_options_are_one_error():
    with pytest.raises(ValueError, match="--sizes"):
        dynapath.experiment(sizes=[1], difficulties=["easy"], edge_case=False)
    with pytest.raises(ValueError, match="nonsense"):
        dynapath.experiment(sizes=[20], nonsense=3)
    with pytest.raises(ValueError, match="--agents"):
        dynapath.experiment(sizes=[20], agents=2)


def run_cli(cli_path, *args, cwd=EXAMPLES):
    return subprocess.run([cli_path, *map(str, args)], capture_output=True, text=True, cwd=cwd,
                          env=dict(os.environ), timeout=120)


@pytest.fixture(scope="module")
def cli_path():
    return os.environ.get("DYNAPATH_CLI", str(pathlib.Path(__file__).resolve().parents[2] /
                                              "build" / "tools" / "dynapath"))


def test_cli_runs_a_python_approach_as_bfs_oracle(cli_path, tmp_path):
    done = run_cli(cli_path, "run", "--local", "--size", 20, "--difficulty", "hard", "--steps", 6,
                   "--approach", "BFS Oracle,py:nearest_station:NearestStation",
                   "--log-level", "warn", "--out", tmp_path)
    assert done.returncode == 0, done.stderr
    assert "python BFS" in done.stdout  # the results table
    detailed = pd.read_csv(tmp_path / "results_detailed.csv").set_index(["Approach", "TimeStep"])
    columns = ["SuccessRate", "AvgPathLength", "NumChanges"]
    assert len(detailed.loc["python BFS"]) == 7
    pd.testing.assert_frame_equal(detailed.loc["python BFS"][columns],
                                  detailed.loc["BFS Oracle"][columns])
    # A file path works as MODULE too, in a study.
    done = run_cli(cli_path, "experiment", "--sizes", 20, "--difficulties", "easy", "--steps", 3,
                   "--no-edge-case", "--log-level", "warn", "--out", tmp_path / "study",
                   "--approaches", f"py:{EXAMPLES / 'nearest_station.py'}:NearestStation")
    assert done.returncode == 0, done.stderr
    assert list(pd.read_csv(tmp_path / "study" / "results.csv")["Approach"]) == ["python BFS"]


@pytest.mark.parametrize("approach, message", [
    ("py:no_such_module:X", "cannot import no_such_module"),
    ("py:nearest_station:NoSuchClass", "has no class NoSuchClass"),
    ("py:nearest_station", "py:MODULE:CLASS"),
])
def test_cli_python_approach_errors(cli_path, tmp_path, approach, message):
    done = run_cli(cli_path, "run", "--size", 20, "--steps", 2, "--approach", approach,
                   "--out", tmp_path)
    assert done.returncode == 2
    assert message in done.stderr and done.stderr.count("\n") == 1, done.stderr


def test_cli_without_the_module_says_so(cli_path, tmp_path):
    (tmp_path / "tools").mkdir()
    alone = tmp_path / "tools" / "dynapath"  # no python/ beside it
    shutil.copy(cli_path, alone)
    done = run_cli(str(alone), "run", "--size", 20, "--approach", "py:m:C", "--out", tmp_path)
    assert done.returncode == 2
    assert "needs the Python module dynapath, which was not built" in done.stderr


def test_a_cli_study_directory_is_not_overwritten(cli, tmp_path):
    cli("experiment", *STUDY_ARGS, "--approaches", "BFS Oracle", "--out", tmp_path)
    before = (tmp_path / "results.csv").read_text()
    with pytest.raises(ValueError, match="manifest.json"):
        dynapath.experiment(approaches=["BFS Oracle"], out=str(tmp_path), **STUDY)
    assert (tmp_path / "results.csv").read_text() == before


def test_cli_options_that_need_their_own_process_are_refused(cli_path, tmp_path):
    for extra, message in ((["--repeats", 2], "--repeats: not available with a py: approach"),
                           (["--agents", 2], "--agents and --embedded are not available")):
        done = run_cli(cli_path, "run", "--size", 20, "--steps", 2, *extra, "--approach",
                       "py:nearest_station:NearestStation", "--out", tmp_path)
        assert done.returncode == 2 and message in done.stderr, done.stderr
