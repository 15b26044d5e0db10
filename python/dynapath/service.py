"""A client of a running ``dynapath serve``: paths, probes and obstacle updates (cells or metres).

:class:`ServiceClient` is the C++ client the CLI's ``query`` and ``feed``
use (runtime/service_client.h), bound here: LCM (liblcm, linked into the
extension: Debian 12 has no Python LCM binding), the run's bus with its
authentication trailer from the run's secret file, large messages in
fragments. See docs/howto/SERVICE.md for the service itself.
"""

import numpy as np

from . import _dynapath

__all__ = ["ServiceClient"]


def _cells(cells, what):
    pairs = [tuple(int(v) for v in cell) for cell in cells]
    for pair in pairs:
        if len(pair) != 2:
            raise ValueError(f"{what}: each cell is (row, col), got {pair}")
    return pairs


def _points(points, what):
    pairs = [tuple(float(v) for v in point) for point in points]
    for pair in pairs:
        if len(pair) != 2:
            raise ValueError(f"{what}: each point is (x, y) in metres, got {pair}")
    return pairs


class ServiceClient:
    """A client of ``dynapath serve`` over LCM, authenticated in C++.

    Parameters
    ----------
    run_id : str
        The service's --run-id.
    lcm_url : str
        The service's --lcm-url (``"udpm://239.255.76.67:7667?ttl=0"``
        on one host).
    secret_file : str, optional
        The run's secret (``dynapath secret FILE``), as the service's
        --secret-file; messages are signed and checked with it.
    insecure : bool
        No secret, as the service's --insecure.
    client : str, optional
        This client's name in requests and updates (1-64 characters;
        default ``python-<pid>``).
    timeout : float
        Seconds to wait for a reply (or a step) unless a call says
        otherwise; default 10.

    Raises
    ------
    ValueError
        Bad options (no secret and not insecure, a missing secret file, a
        bad URL), with the CLI's message.
    """

    def __init__(self, run_id, lcm_url, secret_file=None, insecure=False, client=None,
                 timeout=10.0):
        self.timeout = float(timeout)
        self._core = _dynapath.ServiceClientCore(str(run_id), str(lcm_url), secret_file,
                                                 bool(insecure), client)

    def _timeout(self, timeout):
        return self.timeout if timeout is None else float(timeout)

    def query(self, starts, timeout=None):
        """Paths from `starts` to a station, from the service's current policy.

        Parameters
        ----------
        starts : sequence of (row, col)
            At most the service's --max-starts (64 by default).
        timeout : float, optional

        Returns
        -------
        list of dict
            One per start, as ``dynapath query --json`` prints them:
            ``start`` (row, col), ``status`` ("reached", "loops",
            "hits_obstacle", "too_long", "start_obstacle", "outside_grid",
            "unreachable", "over_budget"), ``length`` (moves, -1 unless
            reached), ``path`` (int32 array (cells, 2) of (row, col), start
            and station included), ``version``, ``step`` and
            ``answered_by`` ("learned", "exact", "none").

        Raises
        ------
        RuntimeError
            No reply within the timeout, a service without a policy yet,
            or two services of one run id answering differently.
        """
        return self._core.query(_cells(starts, "starts"), self._timeout(timeout))

    def probe(self, timeout=None):
        """The service's maze and policy: a request without starts.

        Returns
        -------
        dict
            ``maze_fingerprint`` (16 hex digits, as ``Maze.fingerprint``),
            ``approach``, ``version`` (policy commits) and ``step`` (the
            time step of its policy).
        """
        return self._core.probe(self._timeout(timeout))

    def update(self, blocked=(), freed=(), timeout=None):
        """Publish one obstacle update: cells that became obstacles or free.

        The update is made for the service's maze (its fingerprint, from a
        probe the first time). The service makes a time step of the
        updates that arrived since its last one.

        Parameters
        ----------
        blocked, freed : sequence of (row, col)

        Returns
        -------
        int
            The update's sequence number (1, 2, ... of this client).
        """
        return self._core.update(_cells(blocked, "blocked"), _cells(freed, "freed"),
                                 self._timeout(timeout))

    def update_xy(self, blocked=(), freed=(), timeout=None):
        """Publish one obstacle update in metres: positions that became obstacles or free.

        Positions are (x, y) in the map's frame (a ROS map's resolution and
        origin, else the service's --resolution and --origin); the service
        turns each into the cell holding it and refuses the whole update
        when one lies outside the map. Sequence numbers are shared with
        :meth:`update`.

        Parameters
        ----------
        blocked, freed : sequence of (x, y) in metres

        Returns
        -------
        int
            The update's sequence number.
        """
        return self._core.update_xy(_points(blocked, "blocked"), _points(freed, "freed"),
                                    self._timeout(timeout))

    def wait_for_step(self, step, timeout=None):
        """Wait until the service's policy is of time step `step` or later; returns its step."""
        return self._core.wait_for_step(int(step), self._timeout(timeout))

    def feed(self, maze, steps=None, timeout=None):
        """Send a maze's change sequence in lock step, as ``dynapath feed`` does.

        From the service's current step on: each time step's changes as
        one update, then wait until the service has made that step.

        Parameters
        ----------
        maze : Maze
            The service's maze (checked by fingerprint) and its changes.
        steps : int, optional
            At most this many time steps (default: the rest).

        Returns
        -------
        int
            The service's time step at the end.
        """
        info = self.probe(timeout)
        if info["maze_fingerprint"] != maze.fingerprint:
            raise ValueError(f"the service's maze has fingerprint {info['maze_fingerprint']}, "
                             f"not this maze's {maze.fingerprint}")
        step = info["step"]
        changes = maze.changes()
        last = len(changes) if steps is None else min(len(changes), step + int(steps))
        cols = maze.cols
        for cells, codes in changes[step:last]:
            if len(cells) == 0:
                continue
            cells = np.asarray(cells)
            codes = np.asarray(codes)
            as_pairs = lambda chosen: [(int(c) // cols, int(c) % cols) for c in chosen]
            self.update(as_pairs(cells[codes == 0]), as_pairs(cells[codes != 0]), timeout)
            step = self.wait_for_step(step + 1, timeout)
        return step
