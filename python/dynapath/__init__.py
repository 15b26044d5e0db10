"""DynaPath from Python: the report's dynamic mazes and their MDP.

The package binds DynaPath's C++ core (through the extension
``dynapath._dynapath``): mazes generated exactly as ``dynapath maze`` does
or loaded from every format the CLI reads, the MDP of the specification's
section 2 as Gymnasium-style environments (one walker, many walkers in one
C++ call, several robots in PettingZoo's parallel shape), policy files and
runs and studies of built-in and Python approaches (``dynapath.run``,
``dynapath.experiment``), and a client of ``dynapath serve``
(``dynapath.ServiceClient``).
See docs/howto/PYTHON.md.

Examples
--------
>>> import dynapath
>>> maze = dynapath.Maze.generate(size=20, difficulty="easy")
>>> env = dynapath.GridEnv(maze)
>>> obs, info = env.reset(seed=1)
>>> obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
"""

from .experiment import StudyResult, experiment
from .env import ACTION_NAMES, ACTION_OFFSETS, GridEnv, VectorGridEnv
from .maze import FREE, OBSTACLE, STATION, Maze
from .parallel import ParallelGridEnv
from .policy import Policy, PolicyFile, read_policy, write_policy
from .run import RunResult, bfs_distances, run
from .service import ServiceClient
from .spaces import Discrete, MultiDiscrete
from . import _dynapath

#: Rewards of SPEC section 2.
STATION_REWARD = _dynapath.STATION_REWARD
BUMP_REWARD = _dynapath.BUMP_REWARD
STEP_REWARD = _dynapath.STEP_REWARD

__all__ = [
    "ACTION_NAMES", "ACTION_OFFSETS", "BUMP_REWARD", "Discrete", "FREE", "GridEnv", "Maze",
    "MultiDiscrete", "OBSTACLE", "ParallelGridEnv", "Policy", "PolicyFile", "RunResult", "STATION",
    "STATION_REWARD", "STEP_REWARD", "ServiceClient", "StudyResult", "VectorGridEnv",
    "bfs_distances", "experiment", "read_policy", "run", "write_policy",
]
