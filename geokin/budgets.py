"""Budgets: the documented limits on what geokin reads and what it allocates.

A script, an expression or a name larger than its limit is refused with a
clear error before any work is done on it, and so is a computation whose
arrays would not fit in memory: its size is estimated first, and the error
gives the estimate and how to reduce it.

Limits
------
``MAX_SCRIPT_BYTES``
    Size of a construction script: 16 MiB (a script of 40,000 parameters
    is about 0.6 MB).
``MAX_EXPRESSION_LENGTH``
    Characters of one expression (a value written as text): 10,000.
``MAX_EXPRESSION_DEPTH``
    Nesting of one expression: 100 levels of operations and calls, counted
    along the longest path from the whole expression to a number or a
    name. ``1 + 1 + 1`` is 2 deep, ``sqrt(-(a * b))`` 3; a sum of 102
    terms is too deep: use parameters for parts of it.
``MAX_NAME_LENGTH``
    Characters of a name (a parameter, input, point, link or slider): 200.
Memory
    A sweep may use at most :func:`memory_budget` bytes: half the physical
    memory (or of a container's memory limit, when lower).

Examples
--------
>>> sweep_bytes(5, 1000)
304000
>>> check_sweep_memory(2000, 1_000_000, budget=8 * 2**30)
Traceback (most recent call last):
...
geokin.errors.BudgetError: a sweep of 2,000 points x 1,000,000 samples needs about 96 GB, ...
"""

from __future__ import annotations

import functools
import os
import sys

from .errors import BudgetError

__all__ = [
    "BYTES_PER_POINT_SAMPLE",
    "BYTES_PER_SAMPLE",
    "MAX_EXPRESSION_DEPTH",
    "MAX_EXPRESSION_LENGTH",
    "MAX_NAME_LENGTH",
    "MAX_SCRIPT_BYTES",
    "MEMORY_FRACTION",
    "check_memory",
    "check_sweep_memory",
    "memory_budget",
    "physical_memory",
    "sweep_bytes",
]

MAX_SCRIPT_BYTES = 16 * 2**20
"""The largest construction script read, in bytes."""

MAX_EXPRESSION_LENGTH = 10_000
"""The most characters in one expression."""

MAX_EXPRESSION_DEPTH = 100
"""The deepest nesting of operations and calls in one expression."""

MAX_NAME_LENGTH = 200
"""The most characters in one name."""

MEMORY_FRACTION = 0.5
"""The share of the physical memory a computation may use."""

FALLBACK_MEMORY = 4 * 2**30
"""The physical memory assumed where it cannot be read."""

BYTES_PER_POINT_SAMPLE = 48
"""Bytes a sweep holds per point and sample at its peak (measured: 40 to 45):
the point's coordinates, the candidate roots and margin of a two-root node,
and the (N, 2) array of the point once it is read."""

BYTES_PER_SAMPLE = 64
"""Bytes a sweep holds per sample besides its points: the inputs, the
validity, failing step and reason, and the branch labels."""


@functools.cache
def physical_memory() -> int:
    """Return the memory this process can use at most, in bytes.

    The physical memory, or a container's (cgroup) memory limit when that is
    lower; :data:`FALLBACK_MEMORY` where neither can be read. Read once, so
    checking a budget before every sweep costs nothing.

    Examples
    --------
    >>> physical_memory() > 0
    True
    """
    total = None
    try:
        total = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        total = _windows_memory()
    if not total or total <= 0:
        total = FALLBACK_MEMORY
    for path in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            with open(path) as f:
                limit = int(f.read().strip())
        except (OSError, ValueError):  # absent, or "max": no limit
            continue
        if 0 < limit < total:
            total = limit
    return total


def _windows_memory() -> int | None:
    """Return the physical memory on Windows, or None elsewhere or on failure."""
    if sys.platform != "win32":
        return None
    try:
        import ctypes

        class _Status(ctypes.Structure):
            _fields_ = [("length", ctypes.c_ulong), ("load", ctypes.c_ulong),
                        ("total", ctypes.c_ulonglong), ("available", ctypes.c_ulonglong),
                        ("page_total", ctypes.c_ulonglong), ("page_free", ctypes.c_ulonglong),
                        ("virtual_total", ctypes.c_ulonglong),
                        ("virtual_free", ctypes.c_ulonglong), ("extended", ctypes.c_ulonglong)]

        status = _Status()
        status.length = ctypes.sizeof(_Status)
        if ctypes.windll.kernel32.GlobalMemoryStatusEx(ctypes.byref(status)):
            return int(status.total)
    except (ImportError, AttributeError, OSError):
        pass
    return None


def memory_budget() -> int:
    """Return the bytes a computation may use: :data:`MEMORY_FRACTION` of :func:`physical_memory`.

    Examples
    --------
    >>> memory_budget() == int(MEMORY_FRACTION * physical_memory())
    True
    """
    return int(MEMORY_FRACTION * physical_memory())


def sweep_bytes(points: int, samples: int, *, copies: float = 1.0) -> int:
    """Estimate the bytes a sweep of ``points`` points over ``samples`` samples needs.

    Parameters
    ----------
    points : int
        The number of points (steps) of the construction.
    samples : int
        The number of samples.
    copies : float
        How many such sweeps the caller holds at once (kinematics holds the
        positions and their derivatives, for example).

    Returns
    -------
    int
        ``copies * samples * (points * BYTES_PER_POINT_SAMPLE + BYTES_PER_SAMPLE)``.

    Examples
    --------
    >>> sweep_bytes(2000, 1_000_000) / 1e9
    96.064
    """
    per_sample = int(points) * BYTES_PER_POINT_SAMPLE + BYTES_PER_SAMPLE
    return int(copies * int(samples) * per_sample)


def check_memory(needed: int, *, what: str, advice: str, budget: int | None = None) -> None:
    """Refuse a computation that needs more than the memory budget.

    Parameters
    ----------
    needed : int
        The estimated bytes.
    what : str
        What needs them, for the message ("a sweep of 20 points x 10 samples").
    advice : str
        How to need less, for the message.
    budget : int, optional
        The budget in bytes; :func:`memory_budget` by default.

    Raises
    ------
    BudgetError
        If ``needed`` exceeds the budget, with a one-line message.

    Examples
    --------
    >>> check_memory(10**6, what="a frame", advice="use fewer pixels", budget=10**9)
    >>> check_memory(10**10, what="an animation of 3,000 frames", advice="stream the frames",
    ...              budget=10**9)
    Traceback (most recent call last):
    ...
    geokin.errors.BudgetError: an animation of 3,000 frames needs about 10 GB, more than the ...
    """
    source = ""
    if budget is None:
        budget = memory_budget()
        source = f" ({MEMORY_FRACTION:.0%} of this machine's memory)"
    if needed > budget:
        raise BudgetError(f"{what} needs about {_bytes(needed)}, more than the {_bytes(budget)} "
                          f"budget{source}; {advice}", needed=int(needed), budget=int(budget))


def check_sweep_memory(points: int, samples: int, *, what: str = "sweep",
                       copies: float = 1.0, budget: int | None = None) -> int:
    """Refuse a sweep whose arrays would not fit in memory, before allocating them.

    Parameters
    ----------
    points : int
        The number of points of the construction.
    samples : int
        The number of samples.
    what : str
        The name of the computation, for the message ("sweep", "trace").
    copies : float
        How many sweeps' worth of arrays are held at once (see :func:`sweep_bytes`).
    budget : int, optional
        Bytes allowed; :func:`memory_budget` by default.

    Returns
    -------
    int
        The estimate in bytes, when it fits.

    Raises
    ------
    BudgetError
        If the estimate exceeds the budget. The message gives the estimate
        and the largest block of samples that fits, for evaluation in blocks.

    Examples
    --------
    >>> check_sweep_memory(5, 361)
    109744
    >>> check_sweep_memory(2000, 1_000_000, budget=8 * 2**30)
    Traceback (most recent call last):
    ...
    geokin.errors.BudgetError: a sweep of 2,000 points x 1,000,000 samples needs about 96 GB, more
    than the 8.6 GB budget; use fewer samples, fewer points, or evaluate in blocks of at most
    89,000 samples
    """
    needed = sweep_bytes(points, samples, copies=copies)
    allowed = memory_budget() if budget is None else budget
    if needed > allowed:
        per_sample = max(sweep_bytes(points, 1, copies=copies), 1)
        block = allowed // per_sample
        block = _round_down(block) if block >= 2 else 0
        advice = "use fewer samples, fewer points"
        advice += (f", or evaluate in blocks of at most {block:,} samples" if block
                   else ": not even one sample of this many points fits")
        check_memory(needed, what=f"a {what} of {int(points):,} points x {int(samples):,} "
                     "samples", advice=advice, budget=budget)
    return needed


def _round_down(n: int) -> int:
    """Round down to two significant digits: 89,478 -> 89,000."""
    digits = len(str(n))
    unit = 10 ** max(digits - 2, 0)
    return n // unit * unit


def _bytes(n: float) -> str:
    """Format a number of bytes in decimal units: 96 GB, 8.6 GB, 512 kB."""
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= size:
            value = n / size
            return f"{value:.2g} {unit}" if value < 10 else f"{value:.0f} {unit}"
    return f"{int(n)} bytes"
