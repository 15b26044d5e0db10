"""A DQN on dynapath.VectorGridEnv with PyTorch (Debian's python3-torch).

64 walkers explore the report's easy 20x20 maze in one C++ call per step;
a small MLP on the walker's one-hot cell learns Q-values from a replay
buffer (target network, Huber loss, Adam, epsilon falling from 1 to 0.05)
over --updates gradient steps. Its greedy policy is then scored by
dynapath.run as a Python approach, beside uniformly random actions: the
same C++ policy evaluation as every approach's. Prints the success rates
and the mean loss of the first and last tenth of the updates.
Run: PYTHONPATH=build/python python3 python/examples/dqn.py [--updates N]
Exits 77 (skipped) when PyTorch is not installed.
"""

import argparse
import sys

import numpy as np

import dynapath

try:
    import torch
except ImportError:
    print("dqn.py: PyTorch is not installed (apt-get install python3-torch): skipped",
          file=sys.stderr)
    sys.exit(77)


class Greedy:
    """A fixed policy as a dynapath approach: the same actions at every step."""

    def __init__(self, name, actions):
        self.name, self.actions = name, actions.astype(np.int8)

    def initialize(self, grid):
        return self.actions

    def adapt(self, grid, changed_cells):
        return self.actions


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--updates", type=int, default=300)
    args = parser.parse_args()
    torch.manual_seed(0)
    torch.set_num_threads(1)
    rng = np.random.default_rng(0)

    maze = dynapath.Maze.generate(size=20, difficulty="easy", steps=2)
    cells = maze.rows * maze.cols
    env = dynapath.VectorGridEnv(maze, num_envs=64, max_steps=40)
    net = torch.nn.Sequential(torch.nn.Linear(cells, 64), torch.nn.ReLU(),
                              torch.nn.Linear(64, 8))
    target = torch.nn.Sequential(torch.nn.Linear(cells, 64), torch.nn.ReLU(),
                                 torch.nn.Linear(64, 8))
    target.load_state_dict(net.state_dict())
    optimizer = torch.optim.Adam(net.parameters(), lr=1e-3)
    eye = torch.eye(cells)
    gamma, batch = 0.95, 128

    capacity = 50_000
    states = np.zeros(capacity, np.int64)
    actions = np.zeros(capacity, np.int64)
    rewards = np.zeros(capacity, np.float32)
    nexts = np.zeros(capacity, np.int64)
    ends = np.zeros(capacity, np.float32)
    size = 0

    obs, _ = env.reset(seed=0)
    losses = []
    for update in range(args.updates):
        epsilon = max(0.05, 1.0 - update / (0.6 * args.updates))
        cell = obs[:, 0] * maze.cols + obs[:, 1]
        with torch.no_grad():
            greedy = net(eye[cell]).argmax(1).numpy()
        explore = rng.random(env.num_envs) < epsilon
        action = np.where(explore, rng.integers(0, 8, env.num_envs), greedy)
        obs, reward, terminated, truncated, infos = env.step(action)
        # The next cell of an episode that ended is its last one, not the new start.
        after = obs.copy()
        if "_final_observation" in infos:
            ended = infos["_final_observation"]
            after[ended] = infos["final_observation"][ended]
        at = (size + np.arange(env.num_envs)) % capacity
        states[at], actions[at], rewards[at] = cell, action, reward / 100.0
        nexts[at], ends[at] = after[:, 0] * maze.cols + after[:, 1], terminated
        size = min(size + env.num_envs, capacity)

        pick = rng.integers(0, size, batch)
        s, a = eye[states[pick]], torch.from_numpy(actions[pick])
        with torch.no_grad():
            best = target(eye[nexts[pick]]).max(1).values
        y = torch.from_numpy(rewards[pick]) + gamma * (1 - torch.from_numpy(ends[pick])) * best
        q = net(s).gather(1, a[:, None])[:, 0]
        loss = torch.nn.functional.smooth_l1_loss(q, y)
        optimizer.zero_grad()
        loss.backward()
        optimizer.step()
        losses.append(loss.item())
        if update % 50 == 49:
            target.load_state_dict(net.state_dict())

    with torch.no_grad():
        policy = net(eye).argmax(1).numpy().reshape(maze.shape)
    random_policy = rng.integers(0, 8, maze.shape)
    result = dynapath.run(maze, [Greedy("DQN", policy), Greedy("random", random_policy)])
    rates = dict(zip(result.results["Approach"], result.results["AvgSuccessRate"]))
    tenth = max(1, len(losses) // 10)
    print(f"success rate DQN {rates['DQN']:.4f} random {rates['random']:.4f}")
    print(f"loss first {np.mean(losses[:tenth]):.5f} last {np.mean(losses[-tenth:]):.5f}")


if __name__ == "__main__":
    main()
