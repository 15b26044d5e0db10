"""ParallelGridEnv: robots are obstacles to each other."""

import numpy as np
import pytest

import dynapath

#  . . . .
#  . . . C
OPEN = [[1, 1, 1, 1], [1, 1, 1, 2]]
N, E, S, W = 0, 2, 4, 6


def make(starts, **kwargs):
    env = dynapath.ParallelGridEnv(dynapath.Maze.from_array(OPEN), num_robots=len(starts),
                                   **kwargs)
    obs, infos = env.reset(seed=0, options={"starts": {f"robot_{i}": s
                                                       for i, s in enumerate(starts)}})
    return env, obs


def test_api_shape():
    env, obs = make([(0, 0), (0, 2)])
    assert env.possible_agents == ["robot_0", "robot_1"] == env.agents
    assert env.action_space("robot_0") == dynapath.Discrete(8)
    assert env.observation_space("robot_1") == dynapath.MultiDiscrete([2, 4])
    np.testing.assert_array_equal(obs["robot_1"], (0, 2))


def test_moving_onto_a_robot_or_swapping_bumps():
    env, _ = make([(0, 0), (0, 1)])
    obs, rew, term, trunc, _ = env.step({"robot_0": E, "robot_1": W})  # a swap
    assert rew == {"robot_0": -10.0, "robot_1": -10.0}
    np.testing.assert_array_equal(env.state(), [(0, 0), (0, 1)])
    # robot_1 leaves (0, 1) but robot_0 may not enter it in the same step.
    obs, rew, *_ = env.step({"robot_0": E, "robot_1": E})
    assert rew == {"robot_0": -10.0, "robot_1": -1.0}
    np.testing.assert_array_equal(env.state(), [(0, 0), (0, 2)])


def test_two_robots_heading_for_one_cell_the_first_wins():
    env, _ = make([(0, 0), (0, 2)])
    _, rew, *_ = env.step({"robot_0": E, "robot_1": W})
    assert rew == {"robot_0": -1.0, "robot_1": -10.0}
    np.testing.assert_array_equal(env.state(), [(0, 1), (0, 2)])


def test_a_docked_robot_leaves_the_maze():
    env, _ = make([(0, 3), (1, 2)], max_steps=3)
    obs, rew, term, trunc, _ = env.step({"robot_0": S, "robot_1": N})
    assert rew["robot_0"] == 100.0 and term["robot_0"] and not term["robot_1"]
    assert env.agents == ["robot_1"]
    np.testing.assert_array_equal(env.state()[0], (-1, -1))
    with pytest.raises(ValueError, match="robot_1"):
        env.step({})
    env.step({"robot_1": S})
    _, rew, term, trunc, _ = env.step({"robot_1": W})
    assert trunc == {"robot_1": True} and env.agents == []


def test_random_starts_are_distinct_free_cells():
    env = dynapath.ParallelGridEnv(dynapath.Maze.from_array(OPEN), num_robots=7)
    for seed in range(20):
        obs, _ = env.reset(seed=seed)
        cells = {tuple(o) for o in obs.values()}
        assert len(cells) == 7 and (1, 3) not in cells
    with pytest.raises(ValueError, match="free cells"):
        dynapath.ParallelGridEnv(dynapath.Maze.from_array(OPEN), num_robots=8)
