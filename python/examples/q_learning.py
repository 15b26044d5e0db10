"""Tabular Q-learning on dynapath.GridEnv (SPEC section 2's MDP), in numpy.

Learns a Q-table for the report's easy maze of 12x12 (gamma 0.9,
alpha 0.4, epsilon-greedy) and prints how many free cells its greedy policy
leads to a station. Run: PYTHONPATH=build/python python3 python/examples/q_learning.py
"""

import sys

import numpy as np

import dynapath

maze = dynapath.Maze.generate(size=12, difficulty="easy")
env = dynapath.GridEnv(maze, max_steps=60)
q = np.zeros((maze.rows, maze.cols, env.action_space.n))
rng = np.random.default_rng(0)
gamma, alpha, epsilon = 0.9, 0.4, 0.2

obs, _ = env.reset(seed=0)
for episode in range(int(sys.argv[1]) if len(sys.argv) > 1 else 3000):
    obs, _ = env.reset()
    done = False
    while not done:
        r, c = obs
        a = rng.integers(8) if rng.random() < epsilon else int(q[r, c].argmax())
        obs, reward, terminated, truncated, _ = env.step(a)
        target = reward + (0.0 if terminated else gamma * q[obs[0], obs[1]].max())
        q[r, c, a] += alpha * (target - q[r, c, a])
        done = terminated or truncated

# Follow the greedy policy from every free cell.
starts = np.argwhere(maze.grid == dynapath.FREE)
reached = 0
for start in starts:
    obs, _ = env.reset(options={"start": tuple(start)})
    done = terminated = False
    while not done:
        obs, _, terminated, truncated, _ = env.step(int(q[obs[0], obs[1]].argmax()))
        done = terminated or truncated
    reached += terminated
print(f"greedy policy reaches a station from {reached} of {len(starts)} free cells")
