#!/usr/bin/env python3
"""convQ's settling as dense torch operations against the C++ kernel.

Computes the values convQ computes (core/plan/convq_values.h: the shifted
values U = V - c of the model's recurrent 8-tap convolution with a max,
settled) for a whole maze with dense CPU torch operations, iterated from
each cell's neighbourhood-only value until no value changes, two ways:

  shifts   the 8 shifted views of the padded grid and a running maximum
  maxpool  one 3x3 max_pool2d per iteration (the discount is positive, so
           the best neighbour's discounted value is the discounted maximum;
           the cell itself is in the window but cannot win)

in float64 and float32, at 1 and 2 torch threads; checks the values against
the C++ kernel's (bench/convq_kernel, the same code `dynapath run
--approach convQ` settles with) and times both: the whole-map settle, and
one time step's adaptation (the C++ repairs the changed area; the dense
form settles the whole map again, as a dense iteration cannot lower values
locally from a warm start).

Usage (the maze from the Python module, Debian's python3-torch):
  PYTHONPATH=build/python /usr/bin/python3 bench/convq_torch_bench.py \
      build/bench/convq_kernel SIZE SEED [--steps N] [--repeats R]
  ... build/bench/convq_kernel 0 SEED --map MAP --stations 0.5% --movers 2%
"""

import argparse
import os
import statistics
import struct
import subprocess
import sys
import tempfile
import time

import numpy as np
import torch
import torch.nn.functional as F

import dynapath

HERE = os.path.dirname(os.path.abspath(__file__))
MODEL = os.path.join(HERE, "..", "docs", "examples", "models", "convq.model")
# The 8 actions' offsets, in SPEC's order (core/include/dynapath/mdp.h).
OFFSETS = [(-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1)]


def read_model(path):
    """The five weights of a model file (docs/reference/MODEL_FORMAT.md)."""
    data = open(path, "rb").read()
    if data[:8] != b"DYNAMOD\n":
        sys.exit(f"{path}: not a model file")
    version, kind = struct.unpack_from("<II", data, 8)
    if kind != 1 or version not in (1, 2):
        sys.exit(f"{path}: version {version} kind {kind}, this reads 1 and 2 of kind 1")
    at = 16 + 8 + 5 * 4 + (8 if version == 2 else 0)
    (count,) = struct.unpack_from("<I", data, at)
    if count != 5:
        sys.exit(f"{path}: {count} weights, expected 5")
    names = ["station_reward", "free_reward", "blocked_reward", "move_discount", "bump_discount"]
    return dict(zip(names, struct.unpack_from("<5d", data, at + 4)))


class DenseConvQ:
    """The settle on one grid as dense torch operations."""

    def __init__(self, w, dtype, variant):
        self.dtype, self.variant = dtype, variant
        shift = w["free_reward"] / (1.0 - w["move_discount"])
        self.station = w["station_reward"] - shift
        blocked_base = w["blocked_reward"] - shift + w["bump_discount"] * shift
        self.blocked_fixed = blocked_base / (1.0 - w["bump_discount"])
        self.move = w["move_discount"]

    def settle(self, grid):
        """(U, iterations): the settled shifted values, 0 off free cells."""
        g = torch.from_numpy(grid.astype(np.int64))
        rows, cols = g.shape
        free = g == 1
        # Each neighbour's term of the neighbourhood-only value: a station
        # is entered, an obstacle or the outside bumps (its settled
        # self-loop), a free neighbour is worth 0 (wandering).
        kind = F.pad(g, (1, 1, 1, 1), value=0)
        term = torch.full(kind.shape, self.blocked_fixed, dtype=self.dtype)
        term[kind == 2] = self.station
        term[kind == 1] = 0.0
        init = None
        for dr, dc in OFFSETS:
            view = term[1 + dr : 1 + dr + rows, 1 + dc : 1 + dc + cols]
            init = view.clone() if init is None else torch.maximum(init, view)
        zero = torch.zeros((), dtype=self.dtype)
        ninf = torch.tensor(float("-inf"), dtype=self.dtype)
        init = torch.where(free, init, zero)
        u = init
        give = torch.empty((rows + 2, cols + 2), dtype=self.dtype)
        iterations = 0
        while True:
            iterations += 1
            # Only a free cell's positive value can raise a neighbour.
            offer = torch.where(free & (u > 0), u, ninf)
            if self.variant == "maxpool":
                best = F.max_pool2d(offer[None, None], 3, stride=1, padding=1)[0, 0]
            else:
                give.fill_(float("-inf"))
                give[1:-1, 1:-1] = offer
                best = None
                for dr, dc in OFFSETS:
                    view = give[1 + dr : 1 + dr + rows, 1 + dc : 1 + dc + cols]
                    best = view.clone() if best is None else torch.maximum(best, view)
            new = torch.where(free, torch.maximum(init, self.move * best), zero)
            if torch.equal(new, u):
                return u, iterations
            u = new


def greedy(grid, u, w):
    """Each free cell's first best action under the shifted values `u` (in
    u's dtype), as ConvQValues::ActionValues ranks them; -1 off free cells."""
    dt = u.dtype.type
    shift = w["free_reward"] / (1.0 - w["move_discount"])
    station = dt(w["station_reward"] - shift)
    base = dt(w["blocked_reward"] - shift + w["bump_discount"] * shift)
    rows, cols = grid.shape
    kind = np.pad(grid, 1, constant_values=0)
    up = np.pad(u, 1)
    stay = base + dt(w["bump_discount"]) * u
    q = np.empty((8, rows, cols), dtype=u.dtype)
    for a, (dr, dc) in enumerate(OFFSETS):
        k = kind[1 + dr : 1 + dr + rows, 1 + dc : 1 + dc + cols]
        v = up[1 + dr : 1 + dr + rows, 1 + dc : 1 + dc + cols]
        q[a] = np.where(k == 1, dt(w["move_discount"]) * v, np.where(k == 2, station, stay))
    return np.where(grid == 1, np.argmax(q, axis=0), -1)


def c_kernel(kernel, grids, repeats):
    """The C++ kernel's (solve seconds, repair (changed, seconds), U0, U_last)."""
    rows, cols = grids[0].shape
    with tempfile.TemporaryDirectory() as tmp:
        src, dst = os.path.join(tmp, "in"), os.path.join(tmp, "out")
        with open(src, "wb") as f:
            f.write(f"{rows} {cols} {len(grids) - 1}\n".encode())
            for g in grids:
                f.write(np.ascontiguousarray(g, dtype=np.uint8).tobytes())
        out = subprocess.run([kernel, src, dst, str(repeats)], check=True, capture_output=True,
                             text=True).stdout.split("\n")
        values = np.fromfile(dst, dtype=np.float64).reshape(2, rows, cols)
    solve = [float(line.split()[1]) for line in out if line.startswith("solve ")]
    repair = [(int(line.split()[1]), float(line.split()[2])) for line in out
              if line.startswith("repair ")]
    return solve, repair, values[0], values[1]


def span(xs, scale=1e3, unit="ms"):
    return (f"median {statistics.median(xs) * scale:.3f} {unit} "
            f"(range {min(xs) * scale:.3f}-{max(xs) * scale:.3f}, n={len(xs)})")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("kernel", help="build/bench/convq_kernel")
    p.add_argument("size", type=int)
    p.add_argument("seed", type=int)
    p.add_argument("--difficulty", default="hard")
    p.add_argument("--map", help="a map file instead of a generated maze (size 0)")
    p.add_argument("--stations", default="0.5%", help="with --map, as `--stations`")
    p.add_argument("--movers", default="2%", help="with --map, as `--movers`")
    p.add_argument("--steps", type=int, default=10, help="time steps of adaptation timed")
    p.add_argument("--repeats", type=int, default=5, help="whole-map settles timed")
    a = p.parse_args()
    if (a.size < 2 and not a.map) or a.steps < 1 or a.repeats < 1:
        print("size >= 2 (or --map), steps >= 1, repeats >= 1", file=sys.stderr)
        return 2

    w = read_model(MODEL)
    if a.map:
        maze = dynapath.Maze.load(a.map, stations=a.stations, movers=a.movers, seed=a.seed,
                                  steps=a.steps)
        name = f"{os.path.basename(a.map)} (stations {a.stations}, movers {a.movers})"
    else:
        maze = dynapath.Maze.generate(size=a.size, difficulty=a.difficulty, seed=a.seed,
                                      steps=a.steps)
        name = f"{a.difficulty} {a.size}x{a.size}"
    grids = [np.array(maze.grid_at(k)) for k in range(a.steps + 1)]
    print(f"# {name} seed {a.seed}, {a.steps} steps, torch "
          f"{torch.__version__}, model {dict((k, float(v)) for k, v in w.items())}")

    solve, repair, c_u0, c_ul = c_kernel(a.kernel, grids, a.repeats)
    changed = [n for n, _ in repair]
    print(f"C++ kernel solve (whole map): {span(solve)}")
    print(f"C++ kernel repair per step ({min(changed)}-{max(changed)} cells changed): "
          f"{span([s for _, s in repair], 1e6, 'us')}")

    free0 = grids[0] == 1
    c_greedy = greedy(grids[0], c_u0, w)
    for dtype in (torch.float64, torch.float32):
        for variant in ("maxpool", "shifts"):
            dense = DenseConvQ(w, dtype, variant)
            u0, iters = dense.settle(grids[0])
            flips = int(np.sum(greedy(grids[0], u0.numpy(), w) != c_greedy))
            u0 = u0.double().numpy()
            diff = np.abs(u0 - c_u0)
            rel = float(np.max(diff[free0] / np.maximum(np.abs(c_u0[free0]), 1e-300)))
            lost = int(np.sum(free0 & (c_u0 > 0) & (u0 == 0)))
            ul, _ = dense.settle(grids[-1])
            same_last = bool(np.array_equal(ul.double().numpy(), c_ul))
            print(f"{variant:>7} {str(dtype)[6:]}: {iters} iterations; values vs C++: "
                  f"{'bit-identical' if np.array_equal(u0, c_u0) else 'differ'} "
                  f"(max rel. error {rel:.3g}, {int(np.sum(diff > 0))} cells differ, "
                  f"{lost} positive values lost to 0, {flips} greedy actions differ); after step {a.steps}: "
                  f"{'bit-identical' if same_last else 'differ'}")
            for threads in (1, 2):
                torch.set_num_threads(threads)
                times = []
                for _ in range(a.repeats):
                    start = time.perf_counter()
                    dense.settle(grids[0])
                    times.append(time.perf_counter() - start)
                steps = []
                for k in range(1, min(a.steps, a.repeats) + 1):
                    start = time.perf_counter()
                    dense.settle(grids[k])
                    steps.append(time.perf_counter() - start)
                print(f"    {threads} thread(s): whole-map settle {span(times)}; "
                      f"a step (settle again) {span(steps)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
