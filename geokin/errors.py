"""The one exception hierarchy of geokin.

Every error geokin raises on purpose derives from :class:`GeokinError`, so a
caller can catch them all with one ``except`` clause. An unassemblable sample
in a sweep is *not* an error: it is recorded in the sweep result.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable


class GeokinError(Exception):
    """Base class of every error geokin raises on purpose."""


class ConstructionError(GeokinError, ValueError):
    """A construction is malformed: unknown name, cycle, duplicate, wrong arity.

    Parameters
    ----------
    message : str
        What is wrong.
    node : str, optional
        The node (point, parameter, input, link) the error is about.
    field : str, optional
        The field of that node.
    """

    def __init__(self, message: str, *, node: str | None = None, field: str | None = None):
        self.node = node
        self.field = field
        where = ""
        if node is not None:
            where = f"node {node!r}"
            if field is not None:
                where += f", field {field!r}"
            where += ": "
        super().__init__(where + message)


class ScriptError(ConstructionError):
    """A construction script cannot be read: the message names file, table and key."""


class AnalysisError(GeokinError, ValueError):
    """An analysis cannot be made of what it was given (lengths, arrays, curves)."""


class AssemblyError(GeokinError):
    """A construction cannot be assembled where the caller required it.

    Parameters
    ----------
    message : str
        What failed.
    node : str, optional
        The node that could not be assembled.
    """

    def __init__(self, message: str, *, node: str | None = None):
        self.node = node
        super().__init__(message)


def closest_name(name: str, candidates: Iterable[str]) -> str | None:
    """Return the candidate closest to ``name``, or None if none is close.

    Examples
    --------
    >>> closest_name("B00", ["A0", "B0", "C"])
    'B0'
    >>> closest_name("zzz", ["A0", "B0"]) is None
    True
    """
    matches = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.5)
    if matches:
        return matches[0]
    lowered = {c.lower(): c for c in candidates}
    return lowered.get(name.lower())


def did_you_mean(name: str, candidates: Iterable[str]) -> str:
    """Return ``"; did you mean 'X'?"`` for the closest candidate, or ``""``.

    Examples
    --------
    >>> did_you_mean("l33", ["l3", "l4"])
    "; did you mean 'l3'?"
    """
    best = closest_name(name, candidates)
    return f"; did you mean {best!r}?" if best is not None else ""
