"""dynapath.Maze against what `dynapath maze` writes."""

import numpy as np
import pytest

import dynapath

CODES = {"#": 0, ".": 1, "C": 2}


def parse_grid(path):
    rows = [line for line in path.read_text().splitlines() if line and not line.startswith(";")]
    return np.array([[CODES[ch] for ch in row] for row in rows], dtype=np.int8)


def parse_changes(path):
    """(header fields, [(cells, codes)], [requested moves]) of a version 2 change file."""
    lines = path.read_text().split("\n")
    header = lines[0].split()
    steps, moves = [], []
    for line in lines[1:1 + int(header[4])]:
        fields = [int(f) for f in line.split()]
        moves.append(fields[0])
        pairs = np.array(fields[2:], dtype=np.int64).reshape(fields[1], 2)
        steps.append((pairs[:, 0], pairs[:, 1]))
    return header, steps, moves


def test_hard_50_equals_the_cli(cli, tmp_path):
    cli("maze", "--size", 50, "--difficulty", "hard", "--save", tmp_path / "m.txt",
        "--save-changes", tmp_path / "m.changes", "--no-grid")
    maze = dynapath.Maze.generate(size=50, difficulty="hard")
    assert maze.grid.dtype == np.int8 and maze.grid.shape == (50, 50)
    np.testing.assert_array_equal(maze.grid, parse_grid(tmp_path / "m.txt"))
    header, steps, moves = parse_changes(tmp_path / "m.changes")
    assert header[:5] == ["dynapath-changes", "2", "50", "50", "100"]
    assert maze.fingerprint == header[5]
    ours = maze.changes()
    assert len(ours) == maze.num_steps == 100
    for (cells, codes), (want_cells, want_codes) in zip(ours, steps):
        np.testing.assert_array_equal(cells, want_cells)
        np.testing.assert_array_equal(codes, want_codes)
    np.testing.assert_array_equal(maze.requested_moves, moves)
    assert len(maze.changes(steps=3)) == 3


def test_defaults_are_the_reports(cli):
    # seed 50 + difficulty index, 2 x rows steps
    assert dynapath.Maze.generate().seed == 52
    easy = dynapath.Maze.generate(size=20, difficulty="Easy")
    assert easy.seed == 50 and easy.num_steps == 40
    again = dynapath.Maze.generate(size=20, difficulty="easy", seed=50, steps=40)
    np.testing.assert_array_equal(easy.grid, again.grid)
    rect = dynapath.Maze.generate(size=10, cols=30, steps=5)
    assert rect.shape == (10, 30) and rect.num_steps == 5


def test_grid_is_a_read_only_view():
    maze = dynapath.Maze.generate(size=20, difficulty="easy")
    grid = maze.grid
    assert not grid.flags.writeable and not grid.flags.owndata
    with pytest.raises(ValueError):
        grid[0, 0] = 1
    del maze
    assert grid.sum() > 0  # the view keeps the maze alive


def test_save_round_trips_through_load(tmp_path):
    maze = dynapath.Maze.generate(size=30, difficulty="medium")
    maze.save(tmp_path / "m.txt")
    maze.save_changes(tmp_path / "m.changes")
    loaded = dynapath.Maze.load(tmp_path / "m.txt", changes=tmp_path / "m.changes")
    np.testing.assert_array_equal(loaded.grid, maze.grid)
    assert loaded.fingerprint == maze.fingerprint
    for (a, b), (c, d) in zip(loaded.changes(), maze.changes()):
        np.testing.assert_array_equal(a, c)
        np.testing.assert_array_equal(b, d)
    final = maze.grid.copy().reshape(-1)
    for cells, codes in maze.changes():
        final[cells] = codes
    np.testing.assert_array_equal(maze.grid_at(maze.num_steps).reshape(-1), final)


def test_every_map_format_loads(cli, tmp_path):
    (tmp_path / "room.map").write_text("type octile\nheight 3\nwidth 4\nmap\n....\n.@@.\n....\n")
    movingai = dynapath.Maze.load(tmp_path / "room.map", stations=1, movers=1, seed=7)
    assert movingai.shape == (3, 4)
    assert (movingai.grid == dynapath.STATION).sum() == 1
    # Only the mover moves: the walls (cells 5 and 6) never change.
    changed = np.concatenate([cells for cells, _ in movingai.changes()])
    assert changed.size > 0 and not np.isin(changed, [5, 6]).any()
    cli("maze", "--maze", tmp_path / "room.map", "--stations", 1, "--movers", 1, "--seed", 7,
        "--save", tmp_path / "room.txt", "--no-grid")
    np.testing.assert_array_equal(movingai.grid, parse_grid(tmp_path / "room.txt"))

    (tmp_path / "room.pgm").write_bytes(b"P2\n3 2\n255\n255 0 255\n255 255 255\n")
    (tmp_path / "room.yaml").write_text(
        "image: room.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    ros = dynapath.Maze.load(tmp_path / "room.yaml", stations="20%")
    assert ros.shape == (2, 3) and ros.grid[0, 1] == dynapath.OBSTACLE
    cli("maze", "--maze", tmp_path / "room.yaml", "--stations", "20%", "--save",
        tmp_path / "ros.txt", "--save-changes", tmp_path / "ros.changes", "--no-grid")
    np.testing.assert_array_equal(ros.grid, parse_grid(tmp_path / "ros.txt"))
    assert parse_changes(tmp_path / "ros.changes")[0][5] == ros.fingerprint

    (tmp_path / "t.txt").write_text("..C\n.#.\n")
    text = dynapath.Maze.load(tmp_path / "t.txt", steps=4)
    np.testing.assert_array_equal(text.grid, [[1, 1, 2], [1, 0, 1]])


def test_bad_input_raises_the_clis_message(tmp_path):
    with pytest.raises(FileNotFoundError, match="nowhere.txt"):
        dynapath.Maze.load(tmp_path / "nowhere.txt")
    with pytest.raises(ValueError, match="difficulty"):
        dynapath.Maze.generate(difficulty="impossible")
    (tmp_path / "room.map").write_text("type octile\nheight 1\nwidth 2\nmap\n..\n")
    with pytest.raises(ValueError, match="stations"):
        dynapath.Maze.load(tmp_path / "room.map")
    with pytest.raises(ValueError, match="code"):
        dynapath.Maze.from_array([[1, 5]])
    with pytest.raises(ValueError):  # a station may not move
        dynapath.Maze.from_array([[2, 1]], changes=[([0, 1], [1, 2])])
