"""The examples under python/examples run and do what they say."""

import os
import pathlib
import subprocess
import sys

import pytest

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def test_q_learning_learns_most_of_the_maze():
    out = subprocess.run([sys.executable, str(EXAMPLES / "q_learning.py")], check=True,
                         capture_output=True, text=True, env=dict(os.environ)).stdout
    reached, starts = (int(w) for w in out.split() if w.isdigit())
    assert reached >= 0.9 * starts, out


def test_q_learning_approach_nearly_matches_bfs_oracle():
    out = subprocess.run([sys.executable, str(EXAMPLES / "q_learning_approach.py")], check=True,
                         capture_output=True, text=True, env=dict(os.environ)).stdout
    rates = {line.rsplit(None, 3)[0].strip(): float(line.split()[-3]) for line in out.splitlines()[1:]}
    assert set(rates) == {"BFS Oracle", "numpy Q-learning"}, out
    assert rates["numpy Q-learning"] >= 0.97 * rates["BFS Oracle"], out


def test_dqn_beats_random_actions_and_its_loss_falls():
    try:
        import torch  # noqa: F401
    except ImportError:
        pytest.skip("PyTorch is not installed (python3-torch; scripts/install-deps.sh)")
    done = subprocess.run([sys.executable, str(EXAMPLES / "dqn.py")], capture_output=True,
                          text=True, env=dict(os.environ))
    assert done.returncode == 0, done.stderr
    rates, losses = done.stdout.splitlines()  # "success rate DQN X random Y", "loss first F last L"
    dqn, random = float(rates.split()[3]), float(rates.split()[5])
    first, last = float(losses.split()[2]), float(losses.split()[4])
    assert dqn >= 0.3 and dqn >= 3 * random, done.stdout
    assert last < first, done.stdout
