"""A client of a running `dynapath serve`: its maze, paths from a few cells,
and the maze's changes fed in lock step, all from Python.

Run (with a service started as docs/howto/SERVICE.md shows, on the maze
`--size 20 --difficulty easy`):
PYTHONPATH=build/python python3 python/examples/service_client.py RUN_ID LCM_URL SECRET_FILE
Prints one line per path: start, status, moves, and whether the moves
equal the exact distance (dynapath.bfs_distances) on the service's map.
"""

import sys

import numpy as np

import dynapath


def show(client, grid, starts):
    exact = dynapath.bfs_distances(grid)
    for path in client.query(starts):
        start = path["start"]
        print(f"step {path['step']} {start}: {path['status']}, {path['length']} moves "
              f"(exact {exact[start]}), by {path['answered_by']}")


def main(run_id, lcm_url, secret_file):
    maze = dynapath.Maze.generate(size=20, difficulty="easy")
    client = dynapath.ServiceClient(run_id=run_id, lcm_url=lcm_url, secret_file=secret_file,
                                    timeout=30)
    info = client.probe()  # waits for the service's first policy
    print(f"service: {info['approach']} on maze {info['maze_fingerprint']}, step {info['step']}")
    free = np.argwhere(maze.grid == dynapath.FREE)
    starts = [tuple(int(v) for v in free[i]) for i in range(0, len(free), len(free) // 5)][:5]
    show(client, maze.grid, starts)
    step = client.feed(maze, steps=2)  # two time steps of changes, in lock step
    show(client, maze.grid_at(step), starts)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit("usage: service_client.py RUN_ID LCM_URL SECRET_FILE")
    main(*sys.argv[1:])
