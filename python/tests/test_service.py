"""dynapath.ServiceClient against a real `dynapath serve`, inside a private
network namespace (`dynapath netns`): paths, probes, fed changes, and the
run's authentication (a client with another secret gets no answer)."""

import json
import os
import pathlib
import subprocess
import sys
import textwrap

import pytest

import dynapath

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"
URL = "udpm://239.255.76.67:7667?ttl=0"

# Runs inside the namespace: a service of Incremental Oracle (exact paths)
# on easy 20, the example client, then checks printed as one JSON line.
SESSION = textwrap.dedent("""
    import json, os, subprocess, sys, time
    import numpy as np
    import dynapath
    cli, example, url = sys.argv[1:4]
    subprocess.run([cli, "secret", "run.key"], check=True)
    subprocess.run([cli, "secret", "other.key"], check=True)
    service = subprocess.Popen([cli, "serve", "--run-id", "py", "--secret-file", "run.key",
                                "--lcm-url", url, "--size", "20", "--difficulty", "easy",
                                "--approach", "Incremental Oracle", "--log-level", "warn"],
                               stdout=subprocess.DEVNULL)
    out = {}
    try:
        example_run = subprocess.run([sys.executable, example, "py", url, "run.key"],
                                     capture_output=True, text=True, timeout=60)
        out["example"] = example_run.stdout
        out["example_status"] = example_run.returncode
        out["example_stderr"] = example_run.stderr[-2000:]
        maze = dynapath.Maze.generate(size=20, difficulty="easy")
        client = dynapath.ServiceClient(run_id="py", lcm_url=url, secret_file="run.key",
                                        timeout=30)
        info = client.probe()
        out["probe"] = info
        grid = maze.grid_at(info["step"])
        exact = dynapath.bfs_distances(grid)
        free = [tuple(int(v) for v in c) for c in np.argwhere(grid != dynapath.OBSTACLE)]
        paths = [p for i in range(0, len(free), 64) for p in client.query(free[i:i + 64])]
        bad = []
        for path in paths:
            cells = path["path"]
            ok = (path["status"] == "reached" and path["length"] == exact[path["start"]]
                  and tuple(cells[0]) == path["start"] and grid[tuple(cells[-1])] == dynapath.STATION
                  and len(cells) == path["length"] + 1
                  and all(grid[tuple(c)] != dynapath.OBSTACLE for c in cells)
                  and (len(cells) < 2 or np.abs(np.diff(cells, axis=0)).max() <= 1))
            if not ok and exact[path["start"]] >= 0:
                bad.append(str(path))
        out["paths"] = len(paths)
        out["bad"] = bad[:3]
        # An obstacle named in metres (the service's frame: 1 m cells from
        # (0, 0)): the cell holding it is blocked from the next step on.
        row, col = [tuple(int(v) for v in c) for c in np.argwhere(grid == dynapath.FREE)][0]
        sequence = client.update_xy(blocked=[(col + 0.3, grid.shape[0] - 1 - row + 0.9)])
        client.wait_for_step(info["step"] + 1)
        out["xy_sequence"] = sequence
        out["xy_status"] = client.query([(row, col)])[0]["status"]
        stranger = dynapath.ServiceClient(run_id="py", lcm_url=url, secret_file="other.key",
                                          timeout=1)
        try:
            stranger.probe()
            out["stranger"] = "answered"
        except RuntimeError as error:
            out["stranger"] = str(error)
    finally:
        service.send_signal(2)
        service.wait(timeout=30)
    print(json.dumps(out))
""")


@pytest.fixture(scope="module")
def netns(cli):
    path = os.environ.get("DYNAPATH_CLI", str(pathlib.Path(__file__).resolve().parents[2] /
                                              "build" / "tools" / "dynapath"))
    probe = subprocess.run([path, "netns", "--", "true"], capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip(f"no private network namespace here: {probe.stderr.strip()}")
    return path


def test_client_of_a_real_service(netns, tmp_path):
    done = subprocess.run([netns, "netns", "--", sys.executable, "-c", SESSION, netns,
                           str(EXAMPLES / "service_client.py"), URL],
                          capture_output=True, text=True, cwd=tmp_path, env=dict(os.environ),
                          timeout=120)
    assert done.returncode == 0, done.stderr[-3000:]
    out = json.loads(done.stdout.strip().splitlines()[-1])
    assert out["example_status"] == 0, out["example_stderr"]
    lines = out["example"].splitlines()
    assert lines[0].startswith("service: Incremental Oracle on maze "), lines
    assert lines[0].split()[5].rstrip(",") == dynapath.Maze.generate(size=20,
                                                                     difficulty="easy").fingerprint
    assert out["xy_status"] == "start_obstacle", out
    answers = lines[1:]
    assert len(answers) == 10 and {a.split()[1] for a in answers} == {"0", "2"}, answers
    for answer in answers:  # "step S (r, c): reached, N moves (exact N), by exact"
        words = answer.replace(",", "").replace("(", "").replace(")", "").split()
        assert words[4] == "reached" and words[5] == words[8], answer
    assert out["probe"]["approach"] == "Incremental Oracle" and out["probe"]["step"] == 2
    assert out["paths"] > 200 and out["bad"] == []
    assert "no reply from a service of run py" in out["stranger"]


def test_bad_client_options():
    with pytest.raises(ValueError, match="lcm_url"):
        dynapath.ServiceClient(run_id="x", lcm_url="")
    with pytest.raises(ValueError, match="secret"):
        dynapath.ServiceClient(run_id="x", lcm_url="memq://")
    with pytest.raises(FileNotFoundError):
        dynapath.ServiceClient(run_id="x", lcm_url="memq://", secret_file="/nonexistent/key")
