"""The one exception hierarchy of geokin.

Every error geokin raises on purpose derives from :class:`GeokinError`, so a
caller can catch them all with one ``except`` clause. An unassemblable sample
in a sweep is *not* an error: it is recorded in the sweep result.
"""

from __future__ import annotations

import difflib
import math
import sys
import warnings
from collections.abc import Iterable
from types import FrameType

from .terminal import cut_text


class GeokinError(Exception):
    """Base class of every error geokin raises on purpose."""


class ConstructionError(GeokinError, ValueError):
    """A construction is malformed: unknown name, cycle, duplicate, wrong arity.

    Parameters
    ----------
    message : str
        What is wrong.
    node : str, optional
        The name of what the error is about: a point (a node of the
        construction), a parameter, an input, a link, a slider or a group.
    field : str, optional
        The field of that node.
    kind : str
        What ``node`` names, as the error's text calls it: ``"node"`` for a
        point, else ``"parameter"``, ``"input"``, ``"link"``, ``"slider"``
        or ``"group"``.

    Attributes
    ----------
    message : str
        What is wrong, without the node and field.
    node, field : str or None
        As given, whole; the text of the error shows them shortened by
        :func:`quote`.
    kind : str
        As given.

    Examples
    --------
    >>> err = ConstructionError("unknown point 'B'", node="C", field="centers[0]")
    >>> str(err)
    "node 'C', field 'centers[0]': unknown point 'B'"
    >>> err.message
    "unknown point 'B'"
    >>> str(ConstructionError("must be positive", node="theta", field="speed", kind="input"))
    "input 'theta', field 'speed': must be positive"
    """

    def __init__(self, message: str, *, node: str | None = None, field: str | None = None,
                 kind: str = "node"):
        self.node = node
        self.field = field
        self.kind = kind
        self.message = message
        where = ""
        if node is not None:
            where = f"{kind} {quote(node)}"
            if field is not None:
                where += f", field {quote(field)}"
            where += ": "
        super().__init__(where + message)

    def naming(self, kind: str) -> ConstructionError:
        """Return this error with its node called a ``kind`` ("link", "input", ...).

        Examples
        --------
        >>> str(ConstructionError("duplicate name", node="rocker", field="name").naming("link"))
        "link 'rocker', field 'name': duplicate name"
        """
        return ConstructionError(self.message, node=self.node, field=self.field, kind=kind)


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


class DegreesWarning(UserWarning):
    """An angle given to Python looks like degrees: geokin takes radians there.

    A whole number of 10 or more (``range=(0, 360)``, an angle of 40): rare
    in radians, common in degrees. ``np.radians`` converts; scripts, which
    are in degrees, never warn.
    """


class RadiansWarning(UserWarning):
    """An input's range in a script looks like radians: scripts take degrees.

    A range as wide as a whole number of quarter turns in radians, to a
    thousandth (6.283 for a turn), with no end a whole number but zero:
    ``range = [0, 6.283]`` sweeps 6.3 degrees. ``[0, 360]`` is a full turn.
    """


class PairingWarning(UserWarning):
    """A script's later input declares samples or a speed its declared sweep cannot keep.

    A sweep of the declared ranges (``sweep(c)``, the command line) moves
    several inputs together, sample by sample: the first input's samples
    (or step) say how many there are, and its range at its speed how long
    the sweep takes; every other input covers its range over the same
    samples in the same time. (Given values of its own in Python, or made
    the driver of ``motion``, an input keeps its declarations.)
    """


def range_looks_like_radians(low: float, high: float) -> bool:
    """Whether the ends of an angle's range in degrees are more likely radians.

    >>> range_looks_like_radians(0, 6.283), range_looks_like_radians(-1.5708, 1.5708)
    (True, True)
    >>> range_looks_like_radians(0, 6), range_looks_like_radians(0, 360)
    (False, False)
    """
    quarters = abs(high - low) / (math.pi / 2)
    return (0.5 <= quarters <= 8.01 and abs(quarters - round(quarters)) <= 1e-3 * quarters
            and all(end == 0 or not float(end).is_integer() for end in (low, high)))


def looks_like_degrees(angle: float) -> bool:
    """Whether an angle in radians is more likely degrees given by mistake.

    A whole number of 10 or more: 30, 40, 90, 360 are common angles in
    degrees, and rare ones in radians.

    >>> looks_like_degrees(40), looks_like_degrees(40.5), looks_like_degrees(3)
    (True, False, False)
    """
    return abs(angle) >= 10 and float(angle).is_integer()


def range_looks_like_degrees(low: float, high: float) -> bool:
    """Whether the ends of an angle's range in radians are more likely degrees.

    Each end a whole number of 10 or more, or zero, and the range as wide
    as such a number: (0, 360), (-90, 90); but not beyond a hundred
    thousand, which no one sweeps in degrees (and every float that large is
    whole).

    >>> range_looks_like_degrees(0, 360), range_looks_like_degrees(0, 6.283185307179586)
    (True, False)
    """
    # the width first: it settles the commonest call, a range in radians, at once
    return (looks_like_degrees(high - low)
            and all((looks_like_degrees(end) or end == 0) and abs(end) <= 1e5
                    for end in (low, high)))


def degrees_hint(angle: float, converts: str = "np.radians converts degrees") -> str:
    """Say how many turns an angle (or a range's width) that looks like degrees is in radians.

    ``converts`` says how to give degrees instead.

    >>> degrees_hint(360)
    'is 57.3 turns in radians, which angles are here (np.radians converts degrees)'
    """
    return f"is {angle / (2 * math.pi):.3g} turns in radians, which angles are here ({converts})"


def warn_of_degrees(message: str) -> None:
    """Warn with a :class:`DegreesWarning`, pointing at the first caller outside geokin."""
    warn_outside(message, DegreesWarning)


def warn_outside(message: str, category: type[Warning]) -> None:
    """Warn, pointing at the first caller outside geokin: the user's line."""
    frame: FrameType | None = sys._getframe(1)
    level = 2
    while frame is not None and str(frame.f_globals.get("__name__", "")).startswith("geokin."):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, category, stacklevel=level)


class BudgetError(GeokinError):
    """A script, an expression or a computation is larger than its budget.

    Raised before the work starts (see :mod:`geokin.budgets`); the message
    gives the size, the budget and how to reduce the size.

    Parameters
    ----------
    message : str
        What is too large and what to do about it.
    needed, budget : int, optional
        The estimated size and the budget, in the message's unit (bytes for memory).
    """

    def __init__(self, message: str, *, needed: int | None = None, budget: int | None = None):
        self.needed = needed
        self.budget = budget
        super().__init__(message)


SHOWN_CHARACTERS = 40
"""The most characters of a name or value that an error message shows."""

_MAX_COMPARED = 1000
"""Names longer than this get no "did you mean": none is that close to a short name."""


def quote(text, limit: int = SHOWN_CHARACTERS) -> str:
    r"""Return ``repr(text)`` for a message, cut short if it is long.

    Control characters come out escaped, as ``repr`` writes them; a text of
    more than ``limit`` characters shows its start and end around an
    ellipsis (:func:`geokin.terminal.cut_text`) and its length. Anything that
    is not a string is shown by :func:`show`.

    Examples
    --------
    >>> quote("l3")
    "'l3'"
    >>> quote("x" * 10_000_000)
    "'xxxxxxxxxxxxxxxxxxxxxxxxxx…xxxxxxxxxxxxx' [10,000,000 characters]"
    >>> print(quote("a\x1b]0;title\x07"))
    'a\x1b]0;title\x07'
    """
    if not isinstance(text, str):
        return show(text, limit)
    cut = cut_text(text, limit)
    return repr(text) if cut is text else f"{cut!r} [{len(text):,} characters]"


def show(value, limit: int = SHOWN_CHARACTERS) -> str:
    """Return the repr of any value for a message, short and safe to compute.

    Integers too large to print in full (Python refuses over 4,300 digits),
    long sequences and long reprs are summarised instead of raising or
    flooding the message.

    Examples
    --------
    >>> show(2.5)
    '2.5'
    >>> show(16 ** 5000)
    'an integer of 6,021 digits'
    >>> show([0, 10 ** 5000])
    '[0, an integer of 5,001 digits]'
    >>> show(list(range(100)))
    'a list of 100 items'
    """
    if isinstance(value, str):
        return quote(value, limit)
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 3 * limit:
        return _big_integer(value)
    if isinstance(value, list | tuple):
        items = [show(v, limit) for v in value[:9]]
        if len(items) > 8 or sum(map(len, items)) > 2 * limit:
            return f"a {type(value).__name__} of {len(value):,} items"
        text = ", ".join(items)
        return f"[{text}]" if isinstance(value, list) else f"({text}{',' * (len(items) == 1)})"
    try:
        text = repr(value)
    except Exception:  # noqa: BLE001 - a message must not fail on a strange value
        return f"a {type(value).__name__}"
    return text if len(text) <= 2 * limit else f"{text[:2 * limit]}... (a {type(value).__name__})"


def _big_integer(value: int) -> str:
    """Describe a large integer by its number of digits, without printing it."""
    bits = value.bit_length()
    digits = int(bits * 0.3010299956639812) + 1  # or one more than there are
    if bits > 100_000:  # counting exactly would take longer than a message should
        return f"an integer of about {digits:,} digits"
    if abs(value) < 10 ** (digits - 1):
        digits -= 1
    return f"an integer of {digits:,} digits"


def closest_name(name: str, candidates: Iterable[str]) -> str | None:
    """Return the candidate closest to ``name``, or None if none is close.

    Examples
    --------
    >>> closest_name("B00", ["A0", "B0", "C"])
    'B0'
    >>> closest_name("zzz", ["A0", "B0"]) is None
    True
    >>> closest_name("B" * 10_000_000, ["B0"]) is None
    True
    """
    if not isinstance(name, str) or len(name) > _MAX_COMPARED:
        return None
    candidates = [c for c in candidates if isinstance(c, str) and len(c) <= _MAX_COMPARED]
    matches = difflib.get_close_matches(name, candidates, n=1, cutoff=0.5)
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
    return f"; did you mean {quote(best)}?" if best is not None else ""
