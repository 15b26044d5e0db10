"""The examples under python/examples run and do what they say."""

import os
import pathlib
import subprocess
import sys

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def test_q_learning_learns_most_of_the_maze():
    out = subprocess.run([sys.executable, str(EXAMPLES / "q_learning.py")], check=True,
                         capture_output=True, text=True, env=dict(os.environ)).stdout
    reached, starts = (int(w) for w in out.split() if w.isdigit())
    assert reached >= 0.9 * starts, out
