"""A Python approach of exact distances: BFS Oracle's scores, from Python.

Every step it takes core's BFS distances (dynapath.bfs_distances) and
points each free cell at its lowest-numbered neighbour one move nearer a
station. Run beside BFS Oracle, its rows have the same success rates and
path lengths. Run: PYTHONPATH=build/python python3 python/examples/nearest_station.py
"""

import numpy as np

import dynapath


def nearest_actions(grid):
    """int8 (rows, cols): an action one move nearer a station, -1 where none."""
    distance = dynapath.bfs_distances(grid)
    rows, cols = grid.shape
    padded = np.full((rows + 2, cols + 2), -1, dtype=np.int32)
    padded[1:-1, 1:-1] = distance
    wanted = np.where((grid == dynapath.FREE) & (distance > 0), distance - 1, -2)
    actions = np.full(grid.shape, -1, dtype=np.int8)
    for a in range(7, -1, -1):  # written last, the lowest action that fits wins
        dr, dc = dynapath.ACTION_OFFSETS[a]
        actions[padded[1 + dr:1 + dr + rows, 1 + dc:1 + dc + cols] == wanted] = a
    return actions


class NearestStation:
    """Recomputes the exact distances' actions on every step."""

    name = "python BFS"

    def initialize(self, grid):
        return nearest_actions(grid)

    def adapt(self, grid, changed_cells):
        return nearest_actions(grid)


if __name__ == "__main__":
    maze = dynapath.Maze.generate(size=30, difficulty="hard")
    result = dynapath.run(maze, ["BFS Oracle", NearestStation()])
    print(result.results[["Approach", "AvgSuccessRate", "AvgPathLength"]].to_string(index=False))
