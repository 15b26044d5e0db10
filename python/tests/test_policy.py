"""read_policy / write_policy against files `dynapath run` saves and loads."""

import numpy as np
import pytest

import dynapath

RUN = ["run", "--local", "--size", 16, "--difficulty", "easy", "--steps", 3,
       "--approach", "singleAgent,fedAsynQ_EqAvg", "--log-level", "warn"]


@pytest.fixture(scope="module")
def saved(cli, tmp_path_factory):
    work = tmp_path_factory.mktemp("policy")
    cli(*RUN, "--out", work / "run", "--save-policy", work / "p.pol", "--save-at", 1)
    return work


def test_read_gives_the_sections_as_arrays(saved):
    policy = dynapath.read_policy(saved / "p.pol")
    assert policy.approaches == ["singleAgent", "fedAsynQ_EqAvg"]
    single = policy["singleagent"]
    assert (single.rows, single.cols, single.step) == (16, 16, 1)
    assert single.precision == "float" and single.semantics == "ours"
    assert single.q.shape == (16, 16, 8) and single.q.dtype == np.float32
    assert single.training_counts.shape == (single.node_count,)
    assert single.training_counts.dtype == np.int64 and single.training_counts.max() > 0
    assert np.abs(single.q).sum() > 0
    maze = dynapath.Maze.generate(size=16, difficulty="easy", steps=3)
    assert single.initial_fingerprint == maze.fingerprint
    with pytest.raises(KeyError, match="A\\* Static"):
        policy["A* Static"]


def test_round_trip_and_the_cli_loads_a_written_file(cli, saved):
    original = (saved / "p.pol").read_bytes()
    dynapath.write_policy(saved / "same.pol", dynapath.read_policy(saved / "p.pol"))
    assert (saved / "same.pol").read_bytes() == original

    policy = dynapath.read_policy(saved / "p.pol")
    policy["singleAgent"].q[:] = 0.5  # a view: changes the section
    dynapath.write_policy(saved / "edited.pol", policy)
    again = dynapath.read_policy(saved / "edited.pol")
    assert (again["singleAgent"].q == 0.5).all()
    np.testing.assert_array_equal(again["fedAsynQ_EqAvg"].q, policy["fedAsynQ_EqAvg"].q)
    cli(*RUN, "--out", saved / "continued", "--load-policy", saved / "edited.pol")
    assert (saved / "continued" / "results.csv").exists()


def test_bad_files_and_sections_raise(saved, tmp_path):
    with pytest.raises(FileNotFoundError):
        dynapath.read_policy(tmp_path / "none.pol")
    (tmp_path / "junk.pol").write_bytes(b"not a policy at all")
    with pytest.raises(ValueError, match="junk.pol"):
        dynapath.read_policy(tmp_path / "junk.pol")
    section = dynapath.read_policy(saved / "p.pol")["singleAgent"]
    section.training_counts[0] = -1
    with pytest.raises(ValueError, match="training"):
        dynapath.write_policy(tmp_path / "bad.pol", section)
