"""A tabular Q-learner in numpy as an approach of dynapath.run, beside BFS Oracle.

Synchronous Q-learning on SPEC section 2's MDP: every sweep updates every
(cell, action) at once from its deterministic outcome (+100 on a station,
-10 for a bump, -1 otherwise; gamma 0.9, alpha 0.5). Time step 0 trains
from zeros; each later step continues from the table it has, a few sweeps
on the changed grid. Run:
PYTHONPATH=build/python python3 python/examples/q_learning_approach.py
"""

import numpy as np

import dynapath


class QLearner:
    name = "numpy Q-learning"

    def __init__(self, sweeps=60, adapt_sweeps=8, gamma=0.9, alpha=0.5):
        self.sweeps, self.adapt_sweeps, self.gamma, self.alpha = sweeps, adapt_sweeps, gamma, alpha

    def initialize(self, grid):
        self.q = np.zeros(grid.shape + (8,))
        return self.learn(grid, self.sweeps)

    def adapt(self, grid, changed_cells):
        return self.learn(grid, self.adapt_sweeps)

    def learn(self, grid, sweeps):
        rows, cols = grid.shape
        r, c = np.indices(grid.shape)
        targets, rewards = [], []
        for dr, dc in dynapath.ACTION_OFFSETS:  # each action's next cell and reward
            tr, tc = r + dr, c + dc
            inside = (tr >= 0) & (tr < rows) & (tc >= 0) & (tc < cols)
            tr, tc = np.where(inside, tr, r), np.where(inside, tc, c)
            bump = ~inside | (grid[tr, tc] == dynapath.OBSTACLE)
            tr, tc = np.where(bump, r, tr), np.where(bump, c, tc)
            targets.append(tr * cols + tc)
            station = grid[tr, tc] == dynapath.STATION
            rewards.append(np.where(bump, -10.0, np.where(station, 100.0, -1.0)))
        targets, rewards = np.stack(targets, -1), np.stack(rewards, -1)
        # A station ends the episode: no value after it.
        goes_on = ~(grid.ravel() == dynapath.STATION)[targets].reshape(rows, cols, 8)
        q = self.q.reshape(-1, 8)
        for _ in range(sweeps):
            best = q.max(axis=1)[targets].reshape(rows, cols, 8)
            self.q += self.alpha * (rewards + goes_on * self.gamma * best - self.q)
        actions = self.q.argmax(axis=2).astype(np.int8)
        actions[grid != dynapath.FREE] = -1
        return actions


if __name__ == "__main__":
    maze = dynapath.Maze.generate(size=20, difficulty="hard", steps=20)
    result = dynapath.run(maze, ["BFS Oracle", QLearner()])
    columns = ["Approach", "AvgSuccessRate", "AvgPathLength", "AdaptTimePerStep"]
    print(result.results[columns].to_string(index=False))
