#!/usr/bin/env python3
"""Writes synthetic maps in the MovingAI format (type octile) for docs/howto/MAPS.md.

Real MovingAI maps are not available offline here, so these imitate the kinds
of the benchmark: `city` (street grid with irregular blocks), `maze`
(corridors of a given width from a randomised depth-first search), `room`
(rooms with doors), `random` (uniform obstacles), `cave` (the open, irregular
caverns of game levels such as the Dragon Age maps, by cellular automaton; `T`
trees on its walls). Deterministic for a seed.

usage: make_synthetic_maps.py OUT_DIR
"""
import os
import random
import sys


def write(path, rows):
    with open(path, "w") as out:
        out.write(f"type octile\nheight {len(rows)}\nwidth {len(rows[0])}\nmap\n")
        for row in rows:
            out.write("".join(row) + "\n")


def city(h, w, rng):
    g = [["@"] * w for _ in range(h)]
    r = 0
    while r < h:  # horizontal streets of width 2..4 every 8..20 rows
        for rr in range(r, min(h, r + rng.randint(2, 4))):
            g[rr] = ["."] * w
        r += rng.randint(8, 20)
    c = 0
    while c < w:
        width = rng.randint(2, 4)
        for rr in range(h):
            for cc in range(c, min(w, c + width)):
                g[rr][cc] = "."
        c += rng.randint(8, 20)
    for _ in range(h * w // 400):  # courtyards and parks inside blocks
        r0, c0 = rng.randrange(h), rng.randrange(w)
        for rr in range(r0, min(h, r0 + rng.randint(2, 5))):
            for cc in range(c0, min(w, c0 + rng.randint(2, 5))):
                g[rr][cc] = "."
    return g


def maze(h, w, corridor, rng):
    ch, cw = h // (corridor + 1), w // (corridor + 1)
    g = [["@"] * w for _ in range(h)]
    seen = [[False] * cw for _ in range(ch)]
    stack = [(0, 0)]
    seen[0][0] = True

    def carve(r0, c0, r1, c1):
        for rr in range(r0, r1):
            for cc in range(c0, c1):
                g[rr][cc] = "."

    carve(0, 0, corridor, corridor)
    while stack:
        r, c = stack[-1]
        options = [(r + dr, c + dc) for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1))
                   if 0 <= r + dr < ch and 0 <= c + dc < cw and not seen[r + dr][c + dc]]
        if not options:
            stack.pop()
            continue
        nr, nc = rng.choice(options)
        seen[nr][nc] = True
        s = corridor + 1
        carve(min(r, nr) * s, min(c, nc) * s, max(r, nr) * s + corridor, max(c, nc) * s + corridor)
        stack.append((nr, nc))
    return g


def room(h, w, size, rng):
    g = [["."] * w for _ in range(h)]
    for r in range(0, h, size):
        for c in range(w):
            g[r][c] = "@"
    for c in range(0, w, size):
        for r in range(h):
            g[r][c] = "@"
    for r in range(0, h, size):  # doors
        for c in range(0, w, size):
            if r + size // 2 < h and c > 0:
                g[r + size // 2][c] = "."
            if c + size // 2 < w and r > 0:
                g[r][c + size // 2] = "."
    return g


def uniform(h, w, percent, rng):
    return [["@" if rng.random() < percent / 100 else "." for _ in range(w)] for _ in range(h)]


def cave(h, w, rng):
    # 45% rock, then five rounds of "rock where at least 5 of the 9 cells
    # around are rock": the classic cave automaton.
    g = [[rng.random() < 0.45 for _ in range(w)] for _ in range(h)]
    for _ in range(5):
        n = [[False] * w for _ in range(h)]
        for r in range(h):
            for c in range(w):
                rock = 0
                for dr in (-1, 0, 1):
                    for dc in (-1, 0, 1):
                        rr, cc = r + dr, c + dc
                        rock += 1 if not (0 <= rr < h and 0 <= cc < w) or g[rr][cc] else 0
                n[r][c] = rock >= 5
        g = n
    return [["T" if g[r][c] else "." for c in range(w)] for r in range(h)]


def main():
    if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        sys.exit(0 if sys.argv[1:] in (["--help"], ["-h"]) else 2)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    rng = random.Random(11)
    write(os.path.join(out, "city-128-128.map"), city(128, 128, rng))
    write(os.path.join(out, "maze-99-199-2.map"), maze(99, 199, 2, rng))
    write(os.path.join(out, "room-101-101-10.map"), room(101, 101, 10, rng))
    write(os.path.join(out, "random-300-300-20.map"), uniform(300, 300, 20, rng))
    write(os.path.join(out, "city-1000-1000.map"), city(1000, 1000, rng))
    write(os.path.join(out, "cave-256-512.map"), cave(256, 512, rng))


if __name__ == "__main__":
    main()
