"""Shared fixtures: the dynapath CLI the tests compare against.

ctest (python/CMakeLists.txt) sets PYTHONPATH to build/python and
DYNAPATH_CLI to build/tools/dynapath; by hand:
PYTHONPATH=build/python DYNAPATH_CLI=build/tools/dynapath python3 -m pytest python/tests
"""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli():
    """Runs the dynapath CLI; returns its completed process (checked)."""
    path = os.environ.get("DYNAPATH_CLI", str(REPO / "build" / "tools" / "dynapath"))
    if not os.access(path, os.X_OK):
        pytest.fail(f"the dynapath CLI is not at {path} (set DYNAPATH_CLI)")

    def run(*args):
        return subprocess.run([path, *map(str, args)], check=True, capture_output=True, text=True)

    return run
