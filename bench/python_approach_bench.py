"""What a Python approach costs dynapath.run per step beyond its own Python time.

On the hard 300x300 maze (600 time steps) a Python approach returns one
precomputed policy (BFS distances' actions of step 0, an int8 C-contiguous
array) from every call. Per step it costs: its own Python time (measured
inside its methods), the adaptor's (GIL, the grid copied into its read-only
array, the call, the policy's checks), the run loop's, and core's policy
evaluation of the array. The figure of interest is

    (run's wall time per step - own Python time per step) / evaluation per step

where "evaluation per step" is core's policy evaluation of the same array
timed alone in C++ (target: at most 1.1). Prints the figures, best of
--repeats runs.

Run: PYTHONPATH=build/python python3 bench/python_approach_bench.py
"""

import argparse
import os
import pathlib
import sys
import time

import dynapath
from dynapath import _dynapath

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "python" / "examples"))
from nearest_station import nearest_actions  # noqa: E402

class Fixed:
    """The same precomputed policy at every step."""

    name = "fixed policy"

    def __init__(self, actions):
        self.policy, self.seconds, self.calls = actions, 0.0, 0

    def initialize(self, grid):
        return self.adapt(grid, None)

    def adapt(self, grid, changed_cells):
        start = time.perf_counter()
        policy = self.policy
        self.seconds += time.perf_counter() - start
        self.calls += 1
        return policy


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=300)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    maze = dynapath.Maze.generate(size=args.size, difficulty="hard")
    actions = nearest_actions(maze.grid)
    steps = maze.num_steps + 1
    evaluation = min(_dynapath._evaluation_seconds(maze._core, actions, steps)
                     for _ in range(args.repeats))
    best = None
    for _ in range(args.repeats):
        approach = Fixed(actions)
        start = time.perf_counter()
        result = dynapath.run(maze, [approach], threads=1)
        wall = time.perf_counter() - start
        assert approach.calls == steps
        beyond = (wall - approach.seconds) / steps
        if best is None or beyond < best[0]:
            best = (beyond, approach.seconds / steps, result.results)
    beyond, own, results = best
    print(f"maze hard {args.size}x{args.size}, {steps} steps (0..{steps - 1}), "
          f"load average {os.getloadavg()[0]:.1f}")
    print(f"core's policy evaluation alone:        {evaluation * 1e3:8.3f} ms/step")
    print(f"run per step beyond own Python time:   {beyond * 1e3:8.3f} ms/step")
    print(f"own Python time:                        {own * 1e3:8.3f} ms/step")
    print(f"ratio (target <= 1.1):                  {beyond / evaluation:8.3f}")
    print(results[["Approach", "AvgSuccessRate", "AvgPathLength"]].to_string(index=False))


if __name__ == "__main__":
    main()
