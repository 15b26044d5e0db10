"""The MDP of SPEC section 2 in Gymnasium's API shape (without Gymnasium).

Actions 0..7 are N, NE, E, SE, S, SW, W, NW with the row/col offsets of
``ACTION_OFFSETS``. A move whose target is inside the grid and not an
obstacle moves the walker; otherwise it stays. Reward +100 when the cell it
ends on is a station (the episode then *terminates*), else -10 when it
stayed (a bump), else -1. An episode is *truncated* after ``max_steps``
steps. Episodes start on a free cell (not a station) of time step 0, drawn
uniformly, or on ``options={"start": (row, col)}``.

The maze's clock (``steps_per_change``): None (default) keeps the maze as it
is at time step 0. With k >= 1 the maze advances one time step of its change
sequence every k steps of the episode: the move after n steps since
``reset`` is decided on the maze at time step ``min(n // k, T)``, and every
``reset`` rewinds it to time step 0, so each episode replays the sequence.
``info["time_step"]`` is the time step in force for the next move. An
obstacle that moves onto the walker leaves the walker where it is; it leaves
by any move whose target is not an obstacle (a blocked move is a bump).
"""

import numpy as np

from . import _dynapath
from .spaces import Discrete, MultiDiscrete

__all__ = ["GridEnv", "VectorGridEnv", "ACTION_NAMES", "ACTION_OFFSETS"]

#: Names of the actions 0..7.
ACTION_NAMES = ("N", "NE", "E", "SE", "S", "SW", "W", "NW")
#: (row, col) offset of each action, shape (8, 2).
ACTION_OFFSETS = np.array(list(zip(_dynapath.ACTION_ROW_OFFSETS, _dynapath.ACTION_COL_OFFSETS)),
                          dtype=np.int64)
ACTION_OFFSETS.setflags(write=False)


class GridEnv(_dynapath.GridEnvCore):
    """One walker on a maze: a Gymnasium-style environment.

    Parameters
    ----------
    maze : Maze
        The maze and its change sequence.
    max_steps : int, optional
        Steps after which an episode is truncated; default 4 x max(rows, cols).
    steps_per_change : int, optional
        Environment steps per time step of the change sequence; default
        None, a maze that does not change (see the module's docstring).

    Attributes
    ----------
    action_space : Discrete
        ``Discrete(8)``.
    observation_space : MultiDiscrete
        ``MultiDiscrete([rows, cols])``: the observation is the walker's
        ``(row, col)`` as an int64 array of shape (2,).
    maze : Maze
    metadata : dict
    """

    metadata = {"render_modes": []}
    render_mode = None

    def __init__(self, maze, max_steps=None, steps_per_change=None):
        super().__init__(maze._core, steps_per_change, max_steps)
        self.maze = maze
        self.action_space = Discrete(_dynapath.NUM_ACTIONS)
        self.observation_space = MultiDiscrete([maze.rows, maze.cols])

    def reset(self, seed=None, options=None):
        """Start an episode.

        Parameters
        ----------
        seed : int, optional
            Reseeds the start-cell stream (and the spaces' ``sample()``);
            without it the stream goes on.
        options : dict, optional
            ``{"start": (row, col)}`` starts on that free cell.

        Returns
        -------
        observation : numpy.ndarray of int64, shape (2,)
        info : dict
            ``{"time_step": 0}``.
        """
        if seed is not None:
            self.action_space.seed(seed)
            self.observation_space.seed(seed)
        return self._reset(seed, options)

    def close(self):
        """Nothing to release; for Gymnasium's API."""

    @property
    def unwrapped(self):
        """This environment (Gymnasium's API)."""
        return self


class VectorGridEnv(_dynapath.VectorEnvCore):
    """Many independent walkers on one maze, stepped in one C++ call.

    Each walker is the :class:`GridEnv` MDP with its own episode (and so its
    own maze clock). Episodes that end are reset inside ``step`` (Gymnasium
    0.29's same-step auto-reset): the returned observation is the new
    episode's start, and ``infos["final_observation"][i]`` the cell the
    ended episode finished on, valid where ``infos["_final_observation"]``.
    Walker ``i`` reset with seed ``s`` draws its starts as ``GridEnv`` reset
    with seed ``s + i`` does.

    Parameters
    ----------
    maze : Maze
    num_envs : int
        Number of walkers.
    max_steps : int, optional
        As for :class:`GridEnv`.
    steps_per_change : int, optional
        As for :class:`GridEnv`.

    Attributes
    ----------
    num_envs : int
    single_action_space : Discrete
    single_observation_space : MultiDiscrete
    action_space : MultiDiscrete
        ``[8] * num_envs``.
    observation_space : MultiDiscrete
        Shape (num_envs, 2).
    """

    metadata = {"render_modes": [], "autoreset_mode": "same-step"}

    def __init__(self, maze, num_envs, max_steps=None, steps_per_change=None):
        super().__init__(maze._core, num_envs, steps_per_change, max_steps)
        self.maze = maze
        self.single_action_space = Discrete(_dynapath.NUM_ACTIONS)
        self.single_observation_space = MultiDiscrete([maze.rows, maze.cols])
        self.action_space = MultiDiscrete([_dynapath.NUM_ACTIONS] * num_envs)
        self.observation_space = MultiDiscrete(np.tile([maze.rows, maze.cols], (num_envs, 1)))

    def reset(self, seed=None, options=None):
        """Start every walker's episode.

        Parameters
        ----------
        seed : int, optional
            Walker ``i`` gets seed ``seed + i``; without it the streams go on.
        options : dict, optional
            ``{"start": (row, col)}`` starts every walker there.

        Returns
        -------
        observations : numpy.ndarray of int64, shape (num_envs, 2)
        infos : dict
        """
        if seed is not None:
            self.action_space.seed(seed)
        return self._reset(seed, options)

    def close(self):
        """Nothing to release; for Gymnasium's API."""
