"""Action and observation spaces in Gymnasium's shape, without Gymnasium.

Only the attributes and methods Gymnasium code usually reads are provided
(``n``, ``nvec``, ``shape``, ``dtype``, ``sample()``, ``contains()``,
``seed()``), so agents written against ``gymnasium.spaces`` run unchanged.
"""

import numpy as np

__all__ = ["Discrete", "MultiDiscrete"]


class _IntegerSpace:
    """What both spaces share: int64 elements drawn by a seedable generator."""

    dtype = np.dtype(np.int64)

    def __init__(self, shape, seed):
        self.shape = shape
        self.np_random = np.random.default_rng(seed)

    def seed(self, seed=None):
        """Reseed the generator of ``sample()``; returns ``[seed]``."""
        self.np_random = np.random.default_rng(seed)
        return [seed]

    def __contains__(self, x):
        return self.contains(x)


class Discrete(_IntegerSpace):
    """The integers ``start, ..., start + n - 1`` (Gymnasium's ``Discrete``).

    Parameters
    ----------
    n : int
        Number of elements, at least 1.
    seed : int, optional
        Seed of the generator ``sample()`` draws from.
    start : int, default 0
        The smallest element.
    """

    def __init__(self, n, seed=None, start=0):
        if int(n) < 1:
            raise ValueError(f"n must be >= 1, got {n}")
        super().__init__((), seed)
        self.n = int(n)
        self.start = int(start)

    def sample(self):
        """Return one element drawn uniformly, as ``numpy.int64``."""
        return np.int64(self.start + self.np_random.integers(self.n))

    def contains(self, x):
        """Return True when ``x`` is an integer element of the space."""
        if isinstance(x, (int, np.integer)) or (
            isinstance(x, np.ndarray) and x.shape == () and np.issubdtype(x.dtype, np.integer)
        ):
            return self.start <= int(x) < self.start + self.n
        return False

    def __eq__(self, other):
        return isinstance(other, Discrete) and (self.n, self.start) == (other.n, other.start)

    def __repr__(self):
        return f"Discrete({self.n})" if self.start == 0 else f"Discrete({self.n}, start={self.start})"


class MultiDiscrete(_IntegerSpace):
    """Integer arrays with ``0 <= x[i] < nvec[i]`` (Gymnasium's ``MultiDiscrete``).

    A walker's observation ``(row, col)`` lies in ``MultiDiscrete([rows, cols])``.

    Parameters
    ----------
    nvec : array_like of int
        Number of values of each element, every one at least 1; its shape is
        the space's shape.
    seed : int, optional
        Seed of the generator ``sample()`` draws from.
    """

    def __init__(self, nvec, seed=None):
        self.nvec = np.asarray(nvec, dtype=np.int64)
        if self.nvec.size == 0 or (self.nvec < 1).any():
            raise ValueError(f"nvec must be non-empty and >= 1, got {nvec}")
        super().__init__(self.nvec.shape, seed)

    def sample(self):
        """Return one element drawn uniformly, an int64 array of ``shape``."""
        return self.np_random.integers(self.nvec).astype(np.int64)

    def contains(self, x):
        """Return True when ``x`` has the space's shape and integer values in range."""
        x = np.asarray(x)
        return (
            x.shape == self.shape
            and np.issubdtype(x.dtype, np.integer)
            and bool(((x >= 0) & (x < self.nvec)).all())
        )

    def __eq__(self, other):
        return isinstance(other, MultiDiscrete) and np.array_equal(self.nvec, other.nvec)

    def __repr__(self):
        return f"MultiDiscrete({self.nvec.tolist()})"
