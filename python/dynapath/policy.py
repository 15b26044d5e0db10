"""Policy files (docs/reference/POLICY_FORMAT.md) as numpy arrays.

A policy file holds one section per learning approach of the run that saved
it (``dynapath run --save-policy``). Each section is a :class:`Policy`: its
metadata (approach, maze shape, quadtree leaf limit, semantics, precision,
the time step it was saved after and the maze fingerprints) and three
writable numpy views: the root Q-table ``q`` (rows, cols, 8), float32 or
float64 by its precision; ``training_counts`` (int64, one per quadtree
node); ``baselines`` (float64, one per node for the tree strategy, -1 for a
node never trained; empty otherwise). Change the arrays in place and write
the file back with :func:`write_policy`; ``dynapath run --load-policy``
then starts from it.
"""

from . import _dynapath

__all__ = ["Policy", "PolicyFile", "read_policy", "write_policy"]

Policy = _dynapath.Policy


class PolicyFile:
    """The sections of one policy file.

    Parameters
    ----------
    sections : list of Policy

    Attributes
    ----------
    sections : list of Policy
        In the file's order.
    """

    def __init__(self, sections):
        self.sections = list(sections)

    @property
    def approaches(self):
        """list of str: the sections' approach names."""
        return [s.approach for s in self.sections]

    def __getitem__(self, key):
        """A section by index or by approach name (any case)."""
        if isinstance(key, str):
            for section in self.sections:
                if section.approach.lower() == key.lower():
                    return section
            raise KeyError(f"no section for {key!r}; the file has {', '.join(self.approaches)}")
        return self.sections[key]

    def __len__(self):
        return len(self.sections)

    def __iter__(self):
        return iter(self.sections)

    def __repr__(self):
        return f"<dynapath.PolicyFile {', '.join(self.approaches)}>"


def read_policy(path):
    """Read a policy file.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    PolicyFile

    Raises
    ------
    FileNotFoundError
        When the file does not exist.
    ValueError
        When it is not a policy file this build reads (the message says why:
        "not a policy file", a checksum mismatch, a truncated block, ...).
    """
    return PolicyFile(_dynapath.read_policy_sections(str(path)))


def write_policy(path, policy):
    """Write a policy file atomically (the codec ``dynapath run`` uses).

    Parameters
    ----------
    path : str or os.PathLike
    policy : PolicyFile, Policy or list of Policy
        At most one section per approach, at most four.

    Raises
    ------
    ValueError
        When a section is not consistent (e.g. a negative training count, a
        baseline outside [0, 1] other than -1) or two share an approach.
    OSError
        When the file cannot be written.
    """
    if isinstance(policy, Policy):
        sections = [policy]
    else:
        sections = list(policy.sections if isinstance(policy, PolicyFile) else policy)
    _dynapath.write_policy_sections(str(path), sections)
