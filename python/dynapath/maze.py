"""Mazes: the report's generator, the CLI's map formats, hand-made grids."""

import numpy as np

from . import _dynapath

__all__ = ["Maze", "OBSTACLE", "FREE", "STATION"]

#: Cell codes of ``Maze.grid`` (SPEC section 1; the file formats' values).
OBSTACLE, FREE, STATION = 0, 1, 2


def _forward(name, doc):
    """A read-only property reading the C++ maze's attribute `name`."""
    return property(lambda self: getattr(self._core, name), doc=doc)


class Maze:
    """A maze at time step 0 and its change sequence (moving obstacles).

    Make one with :meth:`generate`, :meth:`load` or :meth:`from_array`; the
    constructor is not for users.
    """

    def __init__(self, core):
        self._core = core

    @classmethod
    def generate(cls, size=50, difficulty="hard", seed=None, cols=None, steps=None):
        """Generate a maze exactly as ``dynapath maze`` does.

        Parameters
        ----------
        size : int, default 50
            Rows (and columns unless `cols` is given).
        difficulty : {"easy", "medium", "hard"}, default "hard"
            Cell probabilities of SPEC section 1 (any case).
        seed : int, optional
            Seed of the C-library stream; default the report's, 50 plus the
            difficulty's index (easy 50, medium 51, hard 52).
        cols : int, optional
            Columns, for rectangular mazes; default `size`.
        steps : int, optional
            Time steps of the change sequence; default the report's 2 x rows.

        Returns
        -------
        Maze

        Raises
        ------
        ValueError
            For a value the CLI refuses, with the CLI's message.
        """
        return cls(_dynapath.Maze._generate(size, difficulty, seed, cols, steps))

    @classmethod
    def load(cls, path, stations=None, movers=None, stations_file=None, changes=None,
             seed=None, steps=None, allow_unreachable=False, force_changes=False):
        """Load a maze file as ``dynapath maze --maze PATH`` does.

        Every format the CLI reads: the text format (``#``, ``.``, ``C``;
        every obstacle may move), a MovingAI ``.map`` and a ROS map_server
        ``.yaml``/``.yml`` naming a PGM image (walls of a map never move).

        Parameters
        ----------
        path : str or os.PathLike
            The maze file.
        stations : int or str, optional
            On a map: place this many stations, or ``"P%"`` of the free
            cells, drawn from `seed` (``--stations``).
        movers : int or str, optional
            On a map: this many moving obstacles, or ``"P%"``; only they
            move (``--movers``).
        stations_file : str, optional
            Stations from a file, ``row col`` per line (``--stations-file``).
        changes : str, optional
            The change sequence from a change file (``--changes``).
        seed : int, optional
            Seed of stations, movers and moves; default the CLI's.
        steps : int, optional
            Time steps; default 2 x rows.
        allow_unreachable : bool, default False
            Accept a maze where no free cell reaches a station.
        force_changes : bool, default False
            Accept a change file made for another maze (``--force-changes``).

        Returns
        -------
        Maze

        Raises
        ------
        FileNotFoundError
            When a file does not exist.
        ValueError
            For a malformed file or a refused value, with the CLI's message.
        """
        as_str = lambda p: None if p is None else str(p)  # noqa: E731
        return cls(_dynapath.Maze._load(str(path), stations, movers, as_str(stations_file),
                                        as_str(changes), seed, steps, allow_unreachable,
                                        force_changes))

    @classmethod
    def from_array(cls, grid, changes=None):
        """A maze from cell codes, e.g. a hand-made grid for a test.

        Parameters
        ----------
        grid : array_like of int, shape (rows, cols)
            Codes 0 (obstacle), 1 (free), 2 (station).
        changes : list of (cells, codes), optional
            Per time step, the row-major cells that change and their new
            codes, in order (the shape :meth:`changes` returns). Checked as a
            change file is: no station created or removed, no obstacle put
            on an obstacle or freed from a cell without one.

        Returns
        -------
        Maze
        """
        if changes is not None:
            changes = [(np.asarray(c), np.asarray(k)) for c, k in changes]
        return cls(_dynapath.Maze._from_array(np.asarray(grid), changes))

    @property
    def grid(self):
        """numpy.ndarray of int8, shape (rows, cols): the maze at time step 0.

        A read-only view of the C++ grid (no copy): 0 obstacle, 1 free,
        2 station.
        """
        return self._core._grid

    @property
    def shape(self):
        """tuple of int: ``(rows, cols)``."""
        return (self._core.rows, self._core.cols)

    rows = _forward("rows", "int: number of rows.")

    cols = _forward("cols", "int: number of columns.")

    num_steps = _forward("num_steps", "int: time steps of the change sequence (T).")

    seed = _forward("seed", "int: the seed the maze (and its stations, movers, moves) came from.")

    source = _forward("source", "str: how the maze was made, as ``dynapath maze`` prints it.")

    @property
    def fingerprint(self):
        """str: 16 hex digits identifying the grid at time step 0.

        The maze fingerprint of a change file's header (``dynapath maze
        --save-changes``): FNV-1a over the shape and the cell codes.
        """
        return self._core.fingerprint

    @property
    def requested_moves(self):
        """numpy.ndarray of int32, shape (T,): obstacle moves asked per step."""
        return self._core.requested_moves

    def changes(self, steps=None):
        """The change sequence.

        Parameters
        ----------
        steps : int, optional
            Only the first `steps` time steps; default all.

        Returns
        -------
        list of tuple (cells, codes)
            Entry ``t`` is time step ``t + 1``: ``cells`` (int32, row-major
            indices) and ``codes`` (int8, the new codes), in the order the
            changes happen.
        """
        return self._core._changes(steps)

    def grid_at(self, step):
        """The grid at time step `step` (0..T) as a new int8 array (rows, cols)."""
        return self._core._grid_at(step)

    def save(self, path):
        """Write the grid (time step 0) in the text format, as ``--save`` does."""
        self._core._save(str(path))

    def save_changes(self, path):
        """Write the change sequence as a change file, as ``--save-changes`` does."""
        self._core._save_changes(str(path))

    def __str__(self):
        return self._core._text()

    def __repr__(self):
        return f"<dynapath.Maze {self.rows}x{self.cols}, {self.num_steps} steps, {self.source}>"
