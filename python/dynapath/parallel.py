"""Several robots on one maze in PettingZoo's parallel API shape.

Every robot is the walker of :class:`dynapath.GridEnv` (same actions,
rewards, ``max_steps`` and maze clock; one clock for all robots, counted in
``step`` calls since ``reset``), and the robots are obstacles to each other.
A step's moves are decided as if simultaneous, robot by robot in the order
of ``possible_agents``: a robot's move is a bump (it stays, -10) when its
target is outside the grid, an obstacle, a cell any robot still on the maze
held before this step (so a swap, or a move into a cell another robot is
leaving, bumps), or a cell an earlier robot moved to in this step (so of two
robots heading for one cell the earlier one gets it). A robot that ends on a
station terminates and leaves the maze (it docks): it no longer blocks
anyone, and later robots may end on the same station.
"""

import numpy as np

from . import _dynapath
from .spaces import Discrete, MultiDiscrete

__all__ = ["ParallelGridEnv"]


class ParallelGridEnv:
    """Robots on one maze: PettingZoo's ``ParallelEnv`` API, without PettingZoo.

    Parameters
    ----------
    maze : Maze
    num_robots : int, default 2
        Agents ``"robot_0"``, ``"robot_1"``, ...
    max_steps : int, optional
        Steps after which every robot still on the maze is truncated;
        default 4 x max(rows, cols).
    steps_per_change : int, optional
        ``step`` calls per time step of the change sequence; default None,
        a maze that does not change.

    Attributes
    ----------
    possible_agents : list of str
    agents : list of str
        The robots still on the maze (empty before ``reset``).
    """

    metadata = {"render_modes": [], "name": "dynapath_parallel_v0"}
    render_mode = None

    def __init__(self, maze, num_robots=2, max_steps=None, steps_per_change=None):
        if num_robots < 1:
            raise ValueError(f"num_robots must be >= 1, got {num_robots}")
        self.maze = maze
        self._world = _dynapath.World(maze._core, steps_per_change, max_steps)
        self._free = self._world.free_cells()
        if len(self._free) < num_robots:
            raise ValueError(f"{num_robots} robots need as many free cells; the maze has "
                             f"{len(self._free)}")
        self.possible_agents = [f"robot_{i}" for i in range(num_robots)]
        self.agents = []
        self._positions = {}
        self._steps = 0
        self._rng = np.random.default_rng()
        self._action_space = Discrete(_dynapath.NUM_ACTIONS)
        self._observation_space = MultiDiscrete([maze.rows, maze.cols])

    @property
    def max_steps(self):
        """int: steps after which an episode is truncated."""
        return self._world.max_steps

    def observation_space(self, agent):
        """``MultiDiscrete([rows, cols])``: a robot's own ``(row, col)``."""
        return self._observation_space

    def action_space(self, agent):
        """``Discrete(8)``: N, NE, E, SE, S, SW, W, NW."""
        return self._action_space

    def reset(self, seed=None, options=None):
        """Put every robot on its own free cell.

        Parameters
        ----------
        seed : int, optional
            Seeds the draw of the start cells (distinct, uniform over the
            free cells of time step 0).
        options : dict, optional
            ``{"starts": {agent: (row, col)}}`` places robots by hand (free,
            distinct cells); the others are drawn.

        Returns
        -------
        observations : dict of str to numpy.ndarray of int64, shape (2,)
        infos : dict of str to dict
        """
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        given = dict((options or {}).get("starts", {}))
        cols = self.maze.cols
        taken = set()
        for agent, (row, col) in given.items():
            if agent not in self.possible_agents:
                raise ValueError(f"options['starts'] names {agent!r}, not one of possible_agents")
            cell = int(row) * cols + int(col)
            if not (0 <= row < self.maze.rows and 0 <= col < cols) or cell not in set(
                    self._free.tolist()) or cell in taken:
                raise ValueError(f"options['starts'][{agent!r}] = ({row}, {col}) is not a free "
                                 "cell of its own")
            taken.add(cell)
        drawn = [c for c in self._rng.permutation(self._free).tolist() if c not in taken]
        self._positions = {}
        for agent in self.possible_agents:
            if agent in given:
                row, col = given[agent]
                self._positions[agent] = (int(row), int(col))
            else:
                cell = drawn.pop()
                self._positions[agent] = divmod(cell, cols)
        self.agents = list(self.possible_agents)
        self._steps = 0
        observations = {a: np.array(self._positions[a], dtype=np.int64) for a in self.agents}
        return observations, {a: {"time_step": 0} for a in self.agents}

    def step(self, actions):
        """Move every robot on the maze once.

        Parameters
        ----------
        actions : dict of str to int
            One action per robot in ``agents``.

        Returns
        -------
        observations, rewards, terminations, truncations, infos : dict
            Keyed by the robots that were on the maze before the step; the
            robots that terminated or were truncated leave ``agents``.
        """
        if not self.agents:
            raise RuntimeError("no robot is on the maze: call reset()")
        missing = [a for a in self.agents if a not in actions]
        if missing:
            raise ValueError(f"no action for {', '.join(missing)}")
        positions = np.array([self._positions[a] for a in self.agents], dtype=np.int64)
        chosen = np.array([int(actions[a]) for a in self.agents], dtype=np.int64)
        moved, rewards, terminated = self._world.step_robots(self._steps, positions, chosen)
        self._steps += 1
        time_step = self._world.time_after(self._steps)
        cut = self._steps >= self._world.max_steps
        obs, rew, term, trunc, infos = {}, {}, {}, {}, {}
        for i, agent in enumerate(self.agents):
            self._positions[agent] = (int(moved[i, 0]), int(moved[i, 1]))
            obs[agent] = moved[i].copy()
            rew[agent] = float(rewards[i])
            term[agent] = bool(terminated[i])
            trunc[agent] = cut and not term[agent]
            infos[agent] = {"time_step": time_step}
        self.agents = [a for a in self.agents if not (term[a] or trunc[a])]
        for agent in list(self._positions):
            if agent not in self.agents:
                del self._positions[agent]
        return obs, rew, term, trunc, infos

    def state(self):
        """numpy.ndarray of int64, shape (num_robots, 2): every robot's cell, -1 when gone."""
        return np.array([self._positions.get(a, (-1, -1)) for a in self.possible_agents],
                        dtype=np.int64)

    def close(self):
        """Nothing to release; for PettingZoo's API."""
