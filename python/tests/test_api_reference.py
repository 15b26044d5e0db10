"""docs/reference/PYTHON_API.md is what python/api_reference.py makes of the docstrings."""

import os
import pathlib
import subprocess
import sys

REPO = pathlib.Path(__file__).resolve().parents[2]


def test_api_reference_is_current():
    done = subprocess.run([sys.executable, str(REPO / "python" / "api_reference.py"), "--check",
                           str(REPO / "docs" / "reference" / "PYTHON_API.md")],
                          capture_output=True, text=True, env=dict(os.environ))
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr


def test_a_stale_reference_is_found(tmp_path):
    stale = tmp_path / "PYTHON_API.md"
    stale.write_text((REPO / "docs" / "reference" / "PYTHON_API.md").read_text() + "\nextra\n")
    done = subprocess.run([sys.executable, str(REPO / "python" / "api_reference.py"), "--check",
                           str(stale)], capture_output=True, text=True, env=dict(os.environ))
    assert done.returncode == 1 and "+extra" not in done.stdout and "-extra" in done.stdout
