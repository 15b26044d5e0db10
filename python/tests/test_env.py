"""GridEnv and VectorGridEnv: SPEC section 2's transitions and rewards."""

import numpy as np
import pytest

import dynapath

# #.C      every action from the centre (1, 1): N free, NE station, E wall,
# .a#      SE free, S free, SW station, W free, NW wall.
# C..
HAND = [[0, 1, 2], [1, 1, 0], [2, 1, 1]]
FROM_CENTRE = {  # action: (cell after, reward, terminated)
    0: ((0, 1), -1.0, False),
    1: ((0, 2), 100.0, True),
    2: ((1, 1), -10.0, False),
    3: ((2, 2), -1.0, False),
    4: ((2, 1), -1.0, False),
    5: ((2, 0), 100.0, True),
    6: ((1, 0), -1.0, False),
    7: ((1, 1), -10.0, False),
}


@pytest.fixture
def hand():
    return dynapath.Maze.from_array(HAND)


def test_every_action_from_the_centre(hand):
    env = dynapath.GridEnv(hand)
    assert env.action_space == dynapath.Discrete(8)
    assert env.observation_space == dynapath.MultiDiscrete([3, 3])
    for action, (cell, reward, terminated) in FROM_CENTRE.items():
        obs, info = env.reset(options={"start": (1, 1)})
        np.testing.assert_array_equal(obs, (1, 1))
        assert info == {"time_step": 0}
        obs, r, term, trunc, info = env.step(action)
        assert obs.dtype == np.int64 and env.observation_space.contains(obs)
        assert (tuple(obs), r, term, trunc) == (cell, reward, terminated, False), \
            dynapath.ACTION_NAMES[action]


def test_offsets_are_the_specs():
    np.testing.assert_array_equal(
        dynapath.ACTION_OFFSETS,
        [(-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1)])


def test_the_edge_is_a_bump_and_truncation_comes_after_max_steps(hand):
    env = dynapath.GridEnv(hand, max_steps=3)
    env.reset(options={"start": (0, 1)})
    for step in range(1, 4):
        obs, r, term, trunc, _ = env.step(0)  # N, out of the grid
        assert (tuple(obs), r, term, trunc) == ((0, 1), -10.0, False, step == 3)
    with pytest.raises(RuntimeError, match="reset"):
        env.step(0)
    env.reset()
    with pytest.raises(ValueError, match="0..7"):
        env.step(8)
    with pytest.raises(ValueError, match="free cell"):
        env.reset(options={"start": (0, 0)})


def test_starts_are_free_cells_and_seeded(hand):
    env = dynapath.GridEnv(hand)
    starts = {tuple(env.reset(seed=s)[0]) for s in range(50)}
    assert starts == {(0, 1), (1, 0), (1, 1), (2, 1), (2, 2)}
    a = [tuple(env.reset(seed=9)[0])] + [tuple(env.reset()[0]) for _ in range(5)]
    b = [tuple(env.reset(seed=9)[0])] + [tuple(env.reset()[0]) for _ in range(5)]
    assert a == b


def test_the_maze_changes_every_steps_per_change_steps():
    # . . .   the obstacle at (1, 0) moves to (1, 1) at time step 1, back at 2.
    # # . C
    maze = dynapath.Maze.from_array([[1, 1, 1], [0, 1, 2]],
                                    changes=[([3, 4], [1, 0]), ([4, 3], [1, 0])])
    env = dynapath.GridEnv(maze, steps_per_change=2)
    env.reset(options={"start": (0, 0)})
    assert env.step(4)[1] == -10.0     # move 1, time step 0: (1, 0) is an obstacle
    obs, r, _, _, info = env.step(4)   # move 2, time step 0 still
    assert r == -10.0 and info["time_step"] == 1
    obs, r, _, _, _ = env.step(4)      # move 3, time step 1: (1, 0) is free
    assert tuple(obs) == (1, 0) and r == -1.0
    # A static env (default) ignores the changes.
    static = dynapath.GridEnv(maze)
    static.reset(options={"start": (0, 0)})
    for _ in range(4):
        assert static.step(4)[1] == -10.0  # (1, 0) stays an obstacle


def test_an_obstacle_moving_onto_the_walker_leaves_it_there():
    # The obstacle at (0, 0) moves onto (0, 1) at time step 1.
    maze = dynapath.Maze.from_array([[0, 1, 1], [1, 1, 2]], changes=[([0, 1], [1, 0])])
    env = dynapath.GridEnv(maze, steps_per_change=1)
    env.reset(options={"start": (0, 1)})
    obs, r, *_ = env.step(0)           # N bumps; now covered by the obstacle
    assert tuple(obs) == (0, 1) and r == -10.0
    obs, r, *_ = env.step(6)           # W: (0, 0) is free now
    assert tuple(obs) == (0, 0) and r == -1.0


def test_vector_env_equals_grid_envs_and_auto_resets(hand):
    n = 64
    vec = dynapath.VectorGridEnv(hand, n, max_steps=5)
    with pytest.raises(RuntimeError, match="reset"):
        vec.step(np.zeros(n, dtype=np.int64))
    obs, _ = vec.reset(seed=100)
    assert obs.shape == (n, 2) and obs.dtype == np.int64
    singles = [dynapath.GridEnv(hand, max_steps=5) for _ in range(n)]
    for i, env in enumerate(singles):
        np.testing.assert_array_equal(env.reset(seed=100 + i)[0], obs[i])
    rng = np.random.default_rng(0)
    ended = 0
    for _ in range(30):
        actions = rng.integers(0, 8, n)
        obs, rewards, term, trunc, infos = vec.step(actions)
        for i, env in enumerate(singles):
            o, r, te, tr, _ = env.step(int(actions[i]))
            assert (rewards[i], term[i], trunc[i]) == (r, te, tr)
            if te or tr:
                ended += 1
                assert infos["_final_observation"][i]
                np.testing.assert_array_equal(infos["final_observation"][i], o)
                o, _ = env.reset()
            np.testing.assert_array_equal(obs[i], o)
    assert ended > n
    with pytest.raises(ValueError, match="actions"):
        vec.step(np.zeros(n + 1, dtype=np.int64))
    with pytest.raises(ValueError, match="0..7"):
        vec.step(np.full(n, 9))


def test_spaces_sample_and_contain():
    d = dynapath.Discrete(8, seed=1)
    assert all(d.contains(d.sample()) for _ in range(100))
    assert not d.contains(8) and not d.contains(1.5)
    m = dynapath.MultiDiscrete([3, 4], seed=1)
    assert all(m.contains(m.sample()) for _ in range(100))
    assert not m.contains(np.array([3, 0])) and not m.contains(np.array([0]))
