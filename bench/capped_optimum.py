#!/usr/bin/env python3
"""The best success rate any policy can have on a map under the report's
policy evaluation (docs/concepts/SPEC.md section 4), against the oracles'.

SPEC section 4 counts a start as a success only when its path reaches a
station at breadth-first depth < rows + cols, and a path follows real moves
(8 neighbours, the target in the grid and not an obstacle; SPEC section 2).
So no policy's path from a cell is shorter than the cell's true distance to
the nearest station, and no policy can succeed from a cell whose true
distance is rows + cols or more: the fraction of non-obstacle cells at
distance < rows + cols (the "capped optimum") bounds every approach's
success rate, convQ's and the learners' alike. The oracles (BFS Oracle,
Incremental Oracle) report the fraction of cells that reach a station at
all (the "uncapped" figure), which can be higher on maps with long
corridors.

For each map this prints both, each averaged over time steps 0..T as the
result files' AvgSuccessRate is, for the maze and change sequence that
`dynapath run --maze MAP` makes with the same --stations, --movers, --seed
and --steps. With --results FILE (a results.csv of `dynapath experiment
--maps ...` with the same options) it prints each approach's success rate
beside them and says where one is below the capped optimum.

Usage (the Python module built: cmake --build build --target dynapath_python):
  PYTHONPATH=build/python python3 bench/capped_optimum.py MAP [MAP ...]
      [--stations 0.5%] [--movers 2%] [--seed 50] [--steps 100] [--results FILE]
"""
import argparse
import collections
import csv
import os
import sys

import numpy as np

import dynapath

# SPEC section 2: actions N, NE, E, SE, S, SW, W, NW as (row, col) offsets.
MOVES = [(-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1)]


def station_distances(grid):
    """Each cell's number of moves to the nearest station (-1: none), by a
    breadth-first search backwards from every station: a cell c is one move
    farther than a cell t when a move of c lands on t."""
    rows, cols = grid.shape
    dist = np.full(grid.shape, -1, dtype=np.int64)
    queue = collections.deque()
    for r, c in zip(*np.nonzero(grid == 2)):
        dist[r, c] = 0
        queue.append((r, c))
    while queue:
        r, c = queue.popleft()
        for dr, dc in MOVES:
            pr, pc = r - dr, c - dc  # moving by (dr, dc) from (pr, pc) lands on (r, c)
            if 0 <= pr < rows and 0 <= pc < cols and grid[pr, pc] != 0 and dist[pr, pc] < 0:
                dist[pr, pc] = dist[r, c] + 1
                queue.append((pr, pc))
    return dist


def rates(grid):
    """(uncapped, capped) success rates of one grid: non-obstacle cells that
    reach a station at all, and within depth < rows + cols."""
    rows, cols = grid.shape
    dist = station_distances(grid)[grid != 0]
    if dist.size == 0:
        return 0.0, 0.0
    return float(np.mean(dist >= 0)), float(np.mean((dist >= 0) & (dist < rows + cols)))


def map_rates(path, stations, movers, seed, steps):
    maze = dynapath.Maze.load(path, stations=stations, movers=movers, seed=seed, steps=steps)
    uncapped, capped = [], []
    for step in range(len(maze.changes()) + 1):
        u, c = rates(np.asarray(maze.grid_at(step)))
        uncapped.append(u)
        capped.append(c)
    return len(uncapped), float(np.mean(uncapped)), float(np.mean(capped))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("maps", nargs="+", help="maze files (MovingAI .map, text, ROS .yaml)")
    parser.add_argument("--stations", default="0.5%")
    parser.add_argument("--movers", default="2%")
    parser.add_argument("--seed", type=int, default=50)
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--results", help="a results.csv of dynapath experiment --maps")
    args = parser.parse_args()
    results = {}
    if args.results:
        with open(args.results, newline="") as f:
            for row in csv.DictReader(f):
                results.setdefault(row["Difficulty"], []).append(
                    (row["Approach"], float(row["AvgSuccessRate"])))
    print(f"{'map':<24} {'steps':>5} {'uncapped':>9} {'capped':>9}")
    below = []
    for path in args.maps:
        name = os.path.splitext(os.path.basename(path))[0]
        steps, uncapped, capped = map_rates(path, args.stations, args.movers, args.seed,
                                            args.steps)
        print(f"{name:<24} {steps:>5} {uncapped:9.4f} {capped:9.4f}")
        for approach, success in results.get(name, []):
            # Printed to 4 places; compared with a margin for the averaging's rounding.
            verdict = "below the capped optimum" if success < capped - 1e-6 else "at the capped optimum"
            if success > capped + 1e-6:
                verdict = "above the capped optimum (an uncapped figure)"
            print(f"{'':<24} {approach:>20} {success:9.4f}  {verdict}")
            if success < capped - 1e-6:
                below.append((name, approach, success, capped))
    for name, approach, success, capped in below:
        print(f"{approach} on {name}: {success:.4f}, {capped - success:.4f} below the capped "
              f"optimum {capped:.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
