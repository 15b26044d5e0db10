#!/usr/bin/env python3
"""Walker-steps per second of the Python module's environments.

VectorGridEnv on the report's hard 100x100 maze with 4,096 walkers (random
actions, drawn up front), and single GridEnv.step calls from a Python loop
(the loop and the tuple unpacking included: what an agent written in Python
pays). One core: the module never starts threads.

Usage: PYTHONPATH=build/python python3 bench/python_env_bench.py [--seconds S]
"""

import argparse
import time

import numpy as np

import dynapath


def timed(run, seconds):
    """Calls run() until `seconds` have passed; returns (calls, elapsed)."""
    calls, start = 0, time.perf_counter()
    while True:
        run()
        calls += 1
        elapsed = time.perf_counter() - start
        if elapsed >= seconds:
            return calls, elapsed


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=3.0, help="time per measurement")
    parser.add_argument("--walkers", type=int, default=4096)
    parser.add_argument("--size", type=int, default=100)
    args = parser.parse_args()
    maze = dynapath.Maze.generate(size=args.size, difficulty="hard")

    for steps_per_change in (None, 1):
        vec = dynapath.VectorGridEnv(maze, args.walkers, steps_per_change=steps_per_change)
        vec.reset(seed=0)
        pool = np.random.default_rng(0).integers(0, 8, (64, args.walkers))
        state = {"i": 0}

        def vector_step():
            vec.step(pool[state["i"] & 63])
            state["i"] += 1

        calls, elapsed = timed(vector_step, args.seconds)
        clock = "static maze" if steps_per_change is None else "maze changing every step"
        print(f"VectorGridEnv hard {args.size}, {args.walkers} walkers, {clock}: "
              f"{calls * args.walkers / elapsed / 1e6:.1f} million walker-steps/s "
              f"({elapsed / calls * 1e6:.0f} us per step call)")

    env = dynapath.GridEnv(maze)
    env.reset(seed=0)
    actions = np.random.default_rng(1).integers(0, 8, 100_000).tolist()
    step, reset = env.step, env.reset

    def python_loop():
        for action in actions:
            obs, reward, terminated, truncated, info = step(action)
            if terminated or truncated:
                reset()

    calls, elapsed = timed(python_loop, args.seconds)
    print(f"GridEnv.step from a Python loop: {calls * len(actions) / elapsed / 1e3:.0f} thousand "
          f"calls/s ({elapsed / calls / len(actions) * 1e9:.0f} ns per call)")

    def empty_loop():
        for action in actions:
            pass

    calls, elapsed = timed(empty_loop, args.seconds / 3)
    print(f"  (the empty Python loop alone: {elapsed / calls / len(actions) * 1e9:.0f} ns "
          "per iteration)")


if __name__ == "__main__":
    main()
