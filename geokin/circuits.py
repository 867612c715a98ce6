"""Motion limits of an input, and sweeps around a whole circuit.

:func:`limits` finds where a construction stops being assemblable as one
input moves: it samples the input, brackets every change between assemblable
and not, and narrows each bracket by bisection on the failing node's margin
(or on assemblability where the node leaves a ray or segment) to
:data:`LIMIT_TOLERANCE`. Each limit records the node that reaches it and
whether it is a tangency (a toggle the mechanism can pass through by changing
branch) or an end (of a ray, a segment, or the input's range). A gap bounded
by tangent limits where inputs evenly spaced across it all assemble, roots
missing by less than the primitives' tangency tolerance (a change point, once
a mechanism written in decimals is rounded), is no gap: a sweep passes it as
a meeting.

:func:`circuit` is the second sweep mode. In a plain sweep (:func:`~geokin.sweep`)
unreachable samples are invalid. In circuit mode the input runs from
a start to one limit of its interval, reverses, and the node that became
tangent changes branch, as the physical mechanism does when it passes the
toggle, and so on until the configuration returns to the start: the sweep
holds the whole closed coupler curve of that circuit with its input history.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .closure import NEAR_SINGULAR
from .compat import renamed_attribute, renamed_keywords
from .construction import Compiled, Construction, as_compiled
from .engine import assembly_guesses, evaluate, start_labels, variant_values
from .errors import (
    AssemblyError,
    ConstructionError,
    degrees_hint,
    looks_like_degrees,
    range_looks_like_degrees,
    warn_of_degrees,
    warn_outside,
)
from .frozen import Frozen
from .nodes import NO_INTERSECTION, OFF_LINE, REASONS, SINGULAR
from .results import BranchEvent, Sweep, short_name

__all__ = ["LIMIT_TOLERANCE", "Limit", "Limits", "circuit", "limits", "placed_in"]

LIMIT_TOLERANCE = 1e-12
"""Width (radians or length units) to which every limit's bracket is narrowed."""

SEARCH_SAMPLES = 7201
"""Samples of the input used to find brackets (every 0.05 degrees for a turn)."""


@dataclass(frozen=True)
class Limit:
    """One end of an assemblable interval.

    Attributes
    ----------
    value : float
        The input value (radians or length units) at the limit, on the
        assemblable side within :data:`LIMIT_TOLERANCE`.
    node : str or None
        The node that cannot be assembled beyond it; None at the end of the
        searched range.
    kind : {"tangent", "end", "range"}
        "tangent": the node's two roots meet there (a toggle or dead centre);
        "end": the chosen root leaves its ray or segment, or the node degenerates;
        "range": the end of the searched range, not a limit of the mechanism.
    """

    value: float
    node: str | None
    kind: str
    nodes: tuple[str, ...] = ()
    """Every node whose roots meet at this limit, ``node`` first (a mechanism may
    have several dyads reaching their toggles together); empty for other kinds."""
    reason: str = ""
    """For an "end": what stops the node there, in words ("its root leaves its
    segment", or one of :data:`~geokin.nodes.REASONS`); empty for other kinds."""


@dataclass(frozen=True)
class Limits(Frozen):
    """The assemblable intervals of one input.

    Attributes
    ----------
    input_name : str
        The input that moves.
    intervals : tuple of (Limit, Limit)
        Each assemblable interval as its lower and upper limit, in order.
    full_turn : bool
        For an angle input: the input turns fully without any limit.
    held_branches : mapping of str to int
        The branches the search held (those of the construction's first
        assemblable sample).
    """

    input_name: str
    intervals: tuple[tuple[Limit, Limit], ...]
    full_turn: bool
    held_branches: Mapping[str, int]

    input = renamed_attribute("input", "input_name")
    branches = renamed_attribute("branches", "held_branches")
    _read_only = ("held_branches",)

    def as_values(self) -> list[tuple[float, float]]:
        """Return the intervals as (low, high) pairs of input values."""
        return [(lo.value, hi.value) for lo, hi in self.intervals]

    def __repr__(self) -> str:
        start = f"<Limits of {short_name(self.input_name)}: "
        if self.full_turn:
            return start + "turns fully>"
        if not self.intervals:
            return start + "no interval>"
        low, high = self.intervals[0][0], self.intervals[-1][1]
        count = len(self.intervals)
        ends = f"{low.value:.6g} to {high.value:.6g}"
        if count == 1:
            stops = [f"{end.kind} at {short_name(end.node)}" for end in (low, high)
                     if end.node is not None]
            return start + ends + (f" ({', '.join(stops)})" if stops else "") + ">"
        return start + f"{count} intervals from {ends}>"


def _held(compiled, name, at):
    """Return the values the inputs other than ``name`` are held at."""
    return {k: float((at or {}).get(k, v.range[0])) for k, v in compiled.inputs.items()
            if k != name}


def _evaluate_at(compiled, name, values, held, branches, parameters=None):
    """Evaluate at input values with fixed branches; other inputs held at ``held``.

    ``parameters`` gives some parameters' values at each input value (variants).
    """
    values = np.asarray(values, dtype=float)
    inputs = {k: np.full(values.shape, v) for k, v in held.items()}
    inputs[name] = values
    return evaluate(compiled, inputs, len(values), branches, track=False,
                    parameters=parameters)


def _steps_by_name(compiled):
    return {step.node.name: step for step in compiled.steps}


def _strictly_valid(result: Sweep) -> np.ndarray:
    """Assemblable without the tangency and end tolerances of the primitives.

    Limits are narrowed on this, so that a limit lies where the roots truly
    meet or the root truly reaches the end of its ray or segment.
    """
    ok = result.valid.copy()
    n = len(ok)
    with np.errstate(invalid="ignore"):
        for margin in result.margins.values():
            ok &= np.broadcast_to(margin >= 0, (n,))
        steps = _steps_by_name(result.construction)
        for node, t in result.line_parameters.items():
            kind = steps[node].node
            ok &= np.broadcast_to((t >= kind.low) & (t <= kind.high), (n,))
    return ok


def _what_stops(result: Sweep, i: int) -> tuple[str, str, tuple[str, ...], str]:
    """Return the first node not strictly assembled at sample i, how, and why.

    The third item lists every node whose roots no longer exist there: those
    tangent at the limit, the first node first; the fourth says what stops
    a node that is not tangent (:attr:`Limit.reason`).
    """
    n = result.valid.shape
    tangent = tuple(node for node, margin in result.margins.items()
                    if np.broadcast_to(margin, n)[i] < 0)
    for step in result.construction.steps:
        node = step.node.name
        if not result.valid[i] and result.failed_step[i] == step.index:
            # two roots that meet, or a closure group at a singular position: a toggle
            code = int(result.reason_code[i])
            if code in (NO_INTERSECTION, SINGULAR):
                return node, "tangent", _first(node, tangent), ""
            return node, "end", (), _leaves(step.node) if code == OFF_LINE else REASONS[code]
        margin = result.margins.get(node)
        if margin is not None and np.broadcast_to(margin, n)[i] < 0:
            return node, "tangent", _first(node, tangent), ""
        t = result.line_parameters.get(node)
        if t is not None:
            t = np.broadcast_to(t, n)[i]
            if not step.node.low <= t <= step.node.high:
                return node, "end", (), _leaves(step.node)
    # a closure group a rounding past its fold: Newton there converges to within the
    # residual's tolerance of the fold itself, all but singular
    for step in result.construction.steps:
        margin = result.margins.get(step.node.name)
        if step.node.continued and margin is not None and (
                np.broadcast_to(margin, n)[i] < NEAR_SINGULAR):
            return step.node.name, "tangent", (step.node.name,), ""
    return "", "end", (), ""


def _leaves(node) -> str:
    """Say that a node's root leaves its ray or its segment."""
    return f"its root leaves its {'ray' if node.high == np.inf else 'segment'}"


def _first(node: str, nodes: tuple[str, ...]) -> tuple[str, ...]:
    return (node, *(other for other in nodes if other != node))


def _refine(compiled, name, held, branches, inside, outside, guesses=None, parameters=None):
    """Bisect brackets [inside, outside] (arrays) down to LIMIT_TOLERANCE.

    ``guesses`` holds each continued node's solution at the inside ends
    (:func:`~geokin.engine.assembly_guesses` of the sweep that found the
    brackets): every middle is solved from the solution at its inside end,
    as a two-root node keeps its branch, so a closure group stays on its
    assembly and its fold is found where Newton from that assembly stops.
    ``branches`` and ``parameters`` may be given per bracket (design variants).

    Returns the refined inside ends and the sweep at the outside ends.
    """
    inside = np.array(inside, dtype=float)
    outside = np.array(outside, dtype=float)
    guesses = {k: np.array(v, dtype=float) for k, v in (guesses or {}).items()}
    while True:
        middle = 0.5 * (inside + outside)
        # stop at the tolerance, or where no float lies between the ends
        open_ = (np.abs(outside - inside) > LIMIT_TOLERANCE) & (middle != inside) & (
            middle != outside)
        if not open_.any():
            break
        result = _evaluate_at(compiled, name, middle, held, {**branches, **guesses},
                              parameters)
        ok = _strictly_valid(result)
        inside = np.where(ok, middle, inside)
        outside = np.where(ok, outside, middle)
        for node, found in assembly_guesses(result).items():
            guesses[node] = np.where(ok[:, None], found, guesses[node])
    return inside, _evaluate_at(compiled, name, outside, held, {**branches, **guesses},
                                parameters)


@renamed_keywords(input="input_name", range="search_range", branches="start_branches")
def limits(construction: Construction | Compiled | Sweep, input_name: str | None = None, *,
           search_range: tuple[float, float] | None = None,
           samples: int = SEARCH_SAMPLES,
           start_branches: Mapping[str, int] | None = None,
           at: Mapping[str, float] | None = None,
           parameters: Mapping[str, ArrayLike] | None = None) -> Any:
    """Find every limit of an input's motion and the assemblable intervals.

    Parameters
    ----------
    construction : Construction, Compiled or Sweep
        What to search; a sweep of design variants gives its construction
        and its variants' parameters.
    input_name : str, optional
        The input to move; the only input by default. Other inputs are held
        at ``at`` or at the start of their range.
    search_range : (float, float), optional
        Where to search, radians for an angle. By default one whole turn
        centred on the middle of the declared range for an angle input, and
        the declared range for a length input. A range of one whole turn
        is searched as a turn, wherever it starts: an input that nothing
        stops there turns fully.
    samples : int
        Samples used to bracket the limits; a stretch shorter than the
        spacing can be missed.
    start_branches : mapping of str to str or int, optional
        The branches to start from, by name (``{"C": "right"}``) or root
        index, as :func:`geokin.sweep` takes them; by default the
        construction's own choice. The search holds the branches of the first assemblable
        sample in the searched range.
    at : mapping of str to float, optional
        Values of the other inputs.
    parameters : mapping of str to array_like, optional
        Design variants, as :func:`geokin.sweep` takes them: every
        variant's limits are searched at once, its branches held from its
        own first assemblable sample, its brackets bisected together with
        all the others'.

    Returns
    -------
    Limits, or tuple of Limits
        One per variant for design variants; a variant that cannot be
        assembled anywhere in the searched range has no interval.

    Raises
    ------
    AssemblyError
        For one design that cannot be assembled anywhere in the searched range.

    Examples
    --------
    A triple rocker (ground 7, crank 5, coupler 6, follower 5):
    the crank rocks between -132.1774 and 132.1774 degrees.

    >>> import numpy as np
    >>> from geokin import Construction
    >>> c = Construction()
    >>> c.input("theta2", range=(-np.pi, np.pi))
    >>> c.fixed("A", 0, 0)
    >>> c.fixed("D", 7, 0)
    >>> c.polar("B", "A", 5, "theta2")
    >>> c.circle_circle("C", ("B", "D"), (6, 5), branch="left")
    >>> found = limits(c)
    >>> [tuple(np.degrees(v).round(4)) for v in found.as_values()]
    [(np.float64(-132.1774), np.float64(132.1774))]
    >>> found.intervals[0][1].node, found.intervals[0][1].kind
    ('C', 'tangent')
    >>> found
    <Limits of 'theta2': -2.30693 to 2.30693 (tangent at 'C', tangent at 'C')>

    The same with a ground 7 and 8 long, at once (for 8 the crank stops where
    B is 6 + 5 from D2: cos(theta2) = (25 + 64 - 121) / 80):

    >>> c.parameter("ground", 7)
    >>> c.fixed("D2", "ground", 0)
    >>> c.circle_circle("C2", ("B", "D2"), (6, 5), branch="left")
    >>> both = limits(c, parameters={"ground": [7.0, 8.0]})
    >>> [round(float(np.degrees(v.as_values()[0][1])), 4) for v in both]
    [132.1774, 113.5782]
    """
    if isinstance(construction, Sweep):
        if parameters is None and construction.variants is not None:
            parameters = {k: v[:, 0] for k, v in construction.parameters.items()}
        construction = construction.construction
    compiled = as_compiled(construction)
    name = compiled.resolve_input(input_name)
    declared = compiled.inputs[name]
    held = _held(compiled, name, at)
    turn = declared.kind == "angle"
    if search_range is None:
        lo, hi = declared.range
        if declared.kind == "angle":
            middle = 0.5 * (lo + hi)
            lo, hi = middle - np.pi, middle + np.pi
    else:
        lo, hi = sorted(map(float, search_range))
        if declared.kind == "angle" and range_looks_like_degrees(lo, hi):
            warn_of_degrees(f"limits of {name!r}: a search range of {lo:g} to {hi:g} "
                            f"{degrees_hint(hi - lo)}")
        # a searched range of one whole turn is searched as the default one is
        turn = turn and abs(hi - lo - 2 * np.pi) <= 1e-12 * 2 * np.pi
    if samples < 3:
        raise ConstructionError(f"limits need at least 3 samples to bracket, got {samples}",
                                node=name, field="samples")
    grid = np.linspace(lo, hi, samples)
    start = start_labels(compiled, start_branches)
    if parameters is None:
        return _limits_of_variants(compiled, name, grid, held, start, turn, None, 1)[0]
    varied, count = variant_values(compiled, parameters)
    if any(step.node.continued for step in compiled.steps):
        # a closure group's bisection starts from its own solutions: each variant alone
        return tuple(_limits_of_variants(
            compiled, name, grid, held, start, turn, {k: v[i:i + 1] for k, v in varied.items()},
            1)[0] for i in range(count))
    return tuple(_limits_of_variants(compiled, name, grid, held, start, turn, varied, count))


def _limits_of_variants(compiled, name, grid, held, start, turn, varied, count):
    """Return the limits of ``count`` variants (one design without ``varied``) at once."""
    samples = grid.size
    total = count * samples
    per_sample = None if varied is None else {
        k: np.broadcast_to(v[:, None], (count, samples)).reshape(-1) for k, v in varied.items()}
    inputs = {k: np.full(samples, v) for k, v in held.items()}
    inputs[name] = grid  # every variant's path: repeated for each
    probe = evaluate(compiled, inputs, total, track=False, start=start, parameters=per_sample,
                     paths=count)
    valid = probe.valid.reshape(count, samples)
    assembles = valid.any(axis=1)
    if varied is None and not assembles[0]:
        where = "over a whole turn" if turn else "over the searched range"
        failed = probe.failed_node[samples // 2]
        raise AssemblyError(f"the construction cannot be assembled anywhere {where} of input "
                            f"{name!r}: node {failed!r}: {probe.failure_reason[samples // 2]}",
                            node=failed or None)
    # each variant holds the branches of its first assemblable sample
    first_valid = np.arange(count) * samples + np.argmax(valid, axis=1)
    held_rows = {k: np.broadcast_to(v, (total,))[first_valid].astype(int)
                 for k, v in probe.branches.items()}
    if varied is None:
        branches: dict = {k: int(v[0]) for k, v in held_rows.items()}
    else:
        branches = {k: np.broadcast_to(v[:, None], (count, samples)).reshape(-1)
                    for k, v in held_rows.items()}
    probe = _evaluate_at(compiled, name, np.tile(grid, count), held, branches, per_sample)
    ok = _strictly_valid(probe).reshape(count, samples) & assembles[:, None]
    row, change = np.nonzero(ok[:, 1:] != ok[:, :-1])
    into = ok[row, change]
    inside = np.where(into, grid[change], grid[change + 1])
    outside = np.where(into, grid[change + 1], grid[change])
    start_at = row * samples + np.where(into, change, change + 1)
    found = []
    if row.size:  # no bracket where every variant turns fully
        refined, beyond = _refine(
            compiled, name, held,
            branches if varied is None else {k: v[row] for k, v in held_rows.items()},
            inside, outside, assembly_guesses(probe, start_at),
            None if varied is None else {k: v[row] for k, v in varied.items()})
        found = [Limit(float(value), *_what_stops(beyond, i)) for i, value in enumerate(refined)]
        if not any(step.node.continued for step in compiled.steps):
            joined, ok = _join_rounding_gaps(compiled, name, held, held_rows, varied, grid,
                                             turn, ok, row, change, found)
            row, found = row[~joined], [limit for limit, gone in zip(found, joined, strict=True)
                                        if not gone]
    declared = compiled.inputs[name]
    ends = np.searchsorted(row, np.arange(count + 1))
    result = []
    for variant in range(count):
        held_branches = {k: int(v[variant]) for k, v in held_rows.items()}
        if not assembles[variant]:
            result.append(Limits(name, (), False, held_branches))
            continue
        result.append(_intervals(name, declared, grid, turn, ok[variant],
                                 found[ends[variant]:ends[variant + 1]], held_branches,
                                 _closes_round(probe, variant, samples)))
    return result


MAX_TURNS = 4
"""The most turns a circuit of an input that turns fully makes to bring the
mechanism back to the pose it began in (through a change point a two-root node
or a closure group comes round on its other branch or assembly)."""

SEAM_RTOL = 1e-6
"""How close (times the mechanism's size) the closure groups' solutions at the two
ends of a searched turn must be for the turn to close on one assembly."""


def _closes_round(probe: Sweep, variant: int, samples: int) -> bool:
    """Whether a turn's search ends on the assembly it began on, for the closure groups.

    Two-root nodes keep their branches along the search, and so come back
    round; a closure group is followed along it, and after a gap may go on
    on another assembly, which the turn's end does not join to its start.
    """
    ends = assembly_guesses(probe, np.array([variant * samples, (variant + 1) * samples - 1]))
    if not ends:
        return True
    first, last = (np.concatenate([v[i] for v in ends.values()]) for i in (0, 1))
    return _one_pose(first, last, SEAM_RTOL)


def _one_pose(first: np.ndarray, second: np.ndarray, rtol: float,
              size: float | None = None) -> bool:
    """Whether two poses' coordinates agree within ``rtol`` times the first's size.

    Or times ``size`` where given (a pose may lie all but at (0, 0)).

    Examples
    --------
    >>> _one_pose(np.array([10.0, 0.0]), np.array([10.0, 1e-8]), 1e-9)
    True
    >>> _one_pose(np.array([10.0, 0.0]), np.array([10.0, np.nan]), 1e-9)
    False
    """
    if size is None:
        size = float(np.nanmax(np.abs(first), initial=0.0))
    return bool(np.all(np.abs(first - second) <= rtol * max(size, 1e-300)))


ROUNDING_GAP_PROBES = 17
"""Inputs evenly spaced across a gap bounded by tangent limits that must all be
assembled to make it a meeting within rounding (see :func:`_join_rounding_gaps`).
A near miss is a single dip of a node's margin below zero, no deeper than the
tangency tolerance; a gap so probed holds no failure wider than 1/18 of it,
and a real gap is at least as wide as the meeting tolerance allows roots to
be told apart, far wider than rounding."""

BEYOND_PROBES = 24
"""How many inputs past an end of the searched range, at 1, 2, 4, ... times the
width of a gap that runs to that end, are tried for where the mechanism is
strictly assembled again (see :func:`_join_rounding_gaps`)."""


@dataclass(eq=False)
class _Gap:
    """A stretch of the grid not strictly assembled, bounded by tangent limits.

    ``brackets`` are its limits' places in the list of limits found,
    ``stretches`` its grid samples (a slice, or two where it runs through
    the ends of a turn), ``low`` and ``high`` the inputs it runs between.
    ``past`` is 0 for a gap between two limits; for one from a limit to an
    end of the grid, the direction (-1 or 1) in which it runs on past that end.
    """

    brackets: list[int]
    stretches: list[slice]
    low: float
    high: float
    past: int = 0


def _join_rounding_gaps(compiled: Compiled, name: str, held: Mapping[str, float],
                        held_rows: Mapping[str, np.ndarray],
                        varied: Mapping[str, np.ndarray] | None, grid: np.ndarray, turn: bool,
                        ok: np.ndarray, row: np.ndarray, change: np.ndarray,
                        found: list[Limit]) -> tuple[np.ndarray, np.ndarray]:
    """Join the gaps that a sweep passes as meetings; return their brackets and the new ``ok``.

    A parallelogram written in decimals far from (0, 0) is, once rounded, a
    near miss: its roots miss by 2e-15 of its size at its change point, a
    gap of 4e-7 rad where they do not strictly exist. The primitives find it
    assembled there, its roots met within their tangency tolerance, and so
    does a sweep, which passes the change point. A gap bounded by tangent
    limits (of one node, or of two whose near misses overlap, as in two
    parallelograms in series) where :data:`ROUNDING_GAP_PROBES` inputs
    evenly spaced across it are all so assembled is taken for such a
    meeting. Over a whole turn a gap may straddle the ends of the grid.
    A gap from a tangent limit to an end of the grid is followed past that
    end (:data:`BEYOND_PROBES`) to where the mechanism is strictly
    assembled again, and probed across all its width: a real toggle just
    inside the searched range, beyond which nothing assembles, stays a
    limit. Closure groups are not asked (their limits come from their own
    continuation).

    ``ok`` is by variant (rows) and grid sample; bracket ``i`` of the limits
    ``found`` lies between grid samples ``change[i]`` and ``change[i] + 1``
    of variant ``row[i]``. Returns the mask of the brackets joined, and
    ``ok`` with the joined gaps' samples set.
    """
    into = ok[row, change]  # the bracket leaves the assembled samples, going up
    gaps: list[_Gap] = []
    for i in range(len(found) - 1):
        if row[i] == row[i + 1] and into[i] and not into[i + 1]:
            gaps.append(_Gap([i, i + 1], [slice(change[i] + 1, change[i + 1] + 1)],
                             found[i].value, found[i + 1].value))
    for r in np.unique(row):
        first, last = np.searchsorted(row, r), np.searchsorted(row, r, side="right") - 1
        if turn and first < last and not into[first] and into[last]:
            gaps.append(_Gap([last, first], [slice(change[last] + 1, None),
                                             slice(0, change[first] + 1)],
                             found[last].value, found[first].value + 2 * np.pi))
            continue
        if not into[first]:  # not assembled from the start of the grid
            gaps.append(_Gap([first], [slice(0, change[first] + 1)], float(grid[0]),
                             found[first].value, past=-1))
        if into[last]:  # nor up to its end
            gaps.append(_Gap([last], [slice(change[last] + 1, None)], found[last].value,
                             float(grid[-1]), past=1))
    gaps = [g for g in gaps if all(found[i].kind == "tangent" for i in g.brackets)]
    joined = np.zeros(len(found), dtype=bool)
    if not gaps:
        return joined, ok

    def probe(values: np.ndarray, of_gaps: list[_Gap]) -> Sweep:
        rows = np.repeat(row[[g.brackets[0] for g in of_gaps]], len(values) // len(of_gaps))
        return _evaluate_at(compiled, name, values, held,
                            {k: v[rows] for k, v in held_rows.items()},
                            None if varied is None else {k: v[rows] for k, v in varied.items()})

    ending = [g for g in gaps if g.past]
    if ending:
        # each end gap's far edge: the first input past the end found strictly assembled
        width = [max(g.high - g.low, 1e-12 * max(1.0, abs(g.low), abs(g.high))) for g in ending]
        steps = 2.0 ** np.arange(BEYOND_PROBES)
        beyond = np.concatenate([
            (g.high if g.past > 0 else g.low) + g.past * w * steps
            for g, w in zip(ending, width, strict=True)])
        past = probe(beyond, ending)
        strict = _strictly_valid(past).reshape(len(ending), -1)
        loose = past.valid.reshape(len(ending), -1)
        for g, s, v, at in zip(ending, strict, loose, beyond.reshape(len(ending), -1),
                               strict=True):
            k = int(np.argmax(s))
            if not s[k] or not v[:k].all():
                gaps.remove(g)  # nothing strictly assembled just past the end: a limit
            elif g.past > 0:
                g.high = float(at[k])
            else:
                g.low = float(at[k])
        if not gaps:
            return joined, ok
    inside = np.linspace(0.0, 1.0, ROUNDING_GAP_PROBES + 2)[1:-1]
    across = probe(np.concatenate([g.low + (g.high - g.low) * inside for g in gaps]), gaps)
    assembled = across.valid.reshape(len(gaps), -1).all(axis=1)
    ok = ok.copy()
    for g, passed in zip(gaps, np.atleast_1d(assembled), strict=True):
        if passed:
            joined[g.brackets] = True
            for stretch in g.stretches:
                ok[row[g.brackets[0]], stretch] = True
    return joined, ok


def _intervals(name, declared, grid, turn, ok, found, held_branches,
               closes_round: bool = True) -> Limits:
    """Pair the limits found along a search into assemblable intervals.

    Over a turn, the stretches through its two ends are one interval where
    the search ``closes_round`` (:func:`_closes_round`).
    """
    lo, hi = float(grid[0]), float(grid[-1])
    if ok.all() and turn:
        # it turns fully: every value is assemblable, the declared range included (a
        # closure group may come round on another assembly, through a change point,
        # and back after more turns)
        lo, hi = min(lo, *declared.range), max(hi, *declared.range)
        ends = (Limit(lo, None, "range"), Limit(hi, None, "range"))
        return Limits(name, (ends,), True, held_branches)
    # pair the limits into intervals, with the range ends where the motion reaches them
    bounds = list(found)
    if ok[0]:
        bounds.insert(0, Limit(lo, None, "range"))
    if ok[-1]:
        bounds.append(Limit(hi, None, "range"))
    intervals = [(bounds[i], bounds[i + 1]) for i in np.arange(0, len(bounds), 2)]
    if turn and closes_round and ok[0] and ok[-1] and len(intervals) > 1:
        # the stretches through both ends of the turn are one interval
        last_lo, first_hi = intervals[-1][0], intervals[0][1]
        wrapped = (replace(last_lo, value=last_lo.value - 2 * np.pi), first_hi)
        intervals = [wrapped, *intervals[1:-1]]
    return Limits(name, tuple(intervals), False, held_branches)


@renamed_keywords(input="input_name", branches="start_branches")
def circuit(construction: Construction | Compiled, input_name: str | None = None, *,
            start: float | None = None, samples_per_pass: int = 361,
            at: Mapping[str, float] | None = None,
            start_branches: Mapping[str, int] | None = None) -> Sweep:
    """Sweep a whole circuit: to a limit, through the toggle, and back round.

    Starting at ``start``, the input runs up to the upper limit of its
    assemblable interval. At a tangent limit the tangent node changes branch
    and the input runs back down to the lower limit of the interval on the
    new branches (a root may leave its segment sooner on one branch than on
    the other), where the same happens, until the configuration returns to
    the start. At an end that is not a tangency (a slider at the end of its
    guide) the input reverses on the same branches. An input that turns
    fully makes one turn, the way its declared range runs (clockwise for a
    range such as (2 pi, 0)); more where a two-root node or a closure group
    comes round on its other branch or assembly (through a change point),
    till the mechanism is back in the pose it began in (at most
    :data:`MAX_TURNS`).

    Parameters
    ----------
    construction : Construction or Compiled
    input_name : str, optional
        The input to move; the only input by default.
    start : float, optional
        Where to start (radians or length units); by default the declared
        range's start where it can be assembled, else the middle of the
        assemblable interval that overlaps the declared range the most.
    samples_per_pass : int
        Samples on each pass from one limit to the other, spaced evenly along
        the motion of the points: in the input, closer towards the limits,
        where the points move fastest for it.
    at, start_branches : mapping, optional
        As for :func:`limits`.

    Returns
    -------
    Sweep
        Over the input's history; its ``events`` list each branch change at a
        toggle, and ``branches`` the branch of every node at every sample.

    Examples
    --------
    The triple rocker passes its toggles and traces both branches of the
    coupler curve: the follower joint C comes back to where it started.

    >>> import numpy as np
    >>> from geokin import Construction
    >>> c = Construction()
    >>> c.input("theta2", range=(-np.pi, np.pi))
    >>> c.fixed("A", 0, 0)
    >>> c.fixed("D", 7, 0)
    >>> c.polar("B", "A", 5, "theta2")
    >>> c.circle_circle("C", ("B", "D"), (6, 5), branch="left")
    >>> s = circuit(c, start=0.0)
    >>> bool(s.valid.all()), [str(e.before) + "->" + str(e.after) for e in s.events]
    (True, ['left->right', 'right->left'])
    >>> bool(np.allclose(s["C"][0], s["C"][-1]))
    True
    """
    compiled = as_compiled(construction)
    name = compiled.resolve_input(input_name)
    found = limits(compiled, name, at=at, start_branches=start_branches)
    declared = compiled.inputs[name]
    held = _held(compiled, name, at)
    if start is not None and declared.kind == "angle" and looks_like_degrees(start):
        warn_of_degrees(f"circuit of {name!r}: a start of {start:g} {degrees_hint(start)}")
    if start is None:
        start = declared.range[0]
        if not any(lo.value <= start <= hi.value for lo, hi in found.intervals):
            # the middle of the interval that overlaps the declared range the most; of
            # several that overlap as much (to rounding), the first the range meets
            a, b = sorted(declared.range)

            def overlap(interval):
                lo, hi = interval
                return min(hi.value, b) - max(lo.value, a)

            most = max(map(overlap, found.intervals))
            met = (found.intervals if declared.range[0] <= declared.range[1]
                   else found.intervals[::-1])
            lo, hi = next(i for i in met if overlap(i) >= most - 1e-9 * max(1.0, abs(most)))
            start = 0.5 * (lo.value + hi.value)
    placed = placed_in(found, start, declared.kind == "angle")
    if placed is None:
        unit = " rad" if declared.kind == "angle" else ""
        intervals = ", ".join(f"{lo:.6g} to {hi:.6g}{unit}" for lo, hi in found.as_values())
        raise AssemblyError(f"input {name!r} = {start:g}{unit} is outside every assemblable "
                            f"interval: {intervals or 'none'}")
    (lo, hi), start = placed
    labels = dict(found.held_branches)
    groups = [step.node.name for step in compiled.steps if step.node.continued]
    passes: list[tuple[np.ndarray, dict[str, np.ndarray], dict[str, np.ndarray]]] = []
    meetings: list[dict[tuple[str, int], float]] = []  # of each pass, see run

    def along(values, labels, across, sketches=None):
        """Evaluate the motion along ``values`` (tracked) from the given branches.

        With ``across`` (a pass after the first, past a fold, in a
        construction with closure groups), each group continues from the
        positions ``across(values[1])`` gives at the second sample, instead
        of its sketch; the first sample, where the last pass ended, is that
        pass's. The two-root nodes are tracked over the first step all the
        same, the groups solved near where ``across`` puts them: a change
        point there, or at the second sample itself, changes their branches.
        With ``sketches`` instead (a turn after the first), each group
        continues from these positions at the first sample.
        Returns the sweep from the sample where it starts, that index, the
        branch events before it (their indices in the pass), and the branch
        of each node whose roots meet at that sample, where it differs from
        the branch the sweep goes on with.
        """
        inputs = {k: np.full(len(values), v) for k, v in held.items()}
        inputs[name] = values
        if across is None or len(values) < 2:
            return (evaluate(compiled, inputs, len(values), start=labels, sketches=sketches),
                    0, (), {})
        first_step: tuple[BranchEvent, ...] = ()
        at_meeting: dict[str, int] = {}
        if labels:
            # the first step, and the one after it for a meeting at the second sample:
            # the sweep from there would go on on the branch it meets on
            probe = values[:3]
            ends = [across(v) for v in probe]
            step = evaluate(compiled, {k: v[:len(probe)] for k, v in inputs.items()},
                            len(probe),
                            {k: np.vstack([end[k] for end in ends]) for k in ends[0]},
                            start=labels)
            labels = {k: int(np.ravel(b)[1]) for k, b in step.branches.items()}
            first_step = tuple(e for e in step.events if e.index == 1)
            for e in step.events:
                if e.index == 2 and e.fraction == 0:
                    at_meeting[e.node] = labels[e.node]
                    labels[e.node] = 1 - labels[e.node]
                    first_step += (e,)
        inputs = {k: v[1:] for k, v in inputs.items()}
        return (evaluate(compiled, inputs, len(values) - 1, start=labels,
                         sketches=across(values[1])), 1, first_step, at_meeting)

    def onward(labels):
        """Return the branches the motion goes on with past the last pass's end.

        Those it ended on (``labels``), but for each node whose roots meet at
        that very sample: the motion goes on on its other branch, as a
        tracked sweep changes branch at the sample after such a meeting. A
        meeting within the step beyond is left to the next pass, which
        tracks it.
        """
        values, branches, solved = passes[-1]
        if not labels or len(values) < 2:
            return labels
        at = np.array([values[-2], values[-1], 2 * values[-1] - values[-2]])
        inputs = {k: np.full(3, v) for k, v in held.items()}
        inputs[name] = at
        guesses = {k: _nearest_solved(rows)[[-2, -1, -1]] for k, rows in solved.items()}
        seam = evaluate(compiled, inputs, 3, guesses or None,
                        start={k: int(b[-2]) for k, b in branches.items()})
        met = {e.node for e in seam.events if e.index == 2 and e.fraction == 0}
        return {k: 1 - label if k in met else label for k, label in labels.items()}

    def run(values, labels, across=None, sketches=None):
        """One pass from its first value to its last, tracked from the given branches.

        Returns the branches it ends on (a graze on the way changes them);
        the pass's values, branches and groups' solutions are kept in ``passes``.
        """
        part, skip, first_step, at_meeting = along(values, labels, across, sketches)
        branches = {k: np.concatenate([np.full(skip, labels[k], dtype=np.int8), b])
                    for k, b in part.branches.items()}
        for node, label in at_meeting.items():
            branches[node][skip] = label  # it changes branch after the sample it meets at
        # where within its step each change of branch lies, by node and sample of the pass
        meetings.append({**{(e.node, e.index): e.fraction for e in first_step},
                         **{(e.node, e.index + skip): e.fraction for e in part.events}})
        solved = assembly_guesses(part)
        if skip:
            solved = {k: np.vstack([passes[-1][2][k][-1:], v]) for k, v in solved.items()}
        passes.append((values, branches, solved))
        return {k: int(b[-1]) for k, b in branches.items()}

    def reach(value, upward, labels, across, known: Limit) -> Limit | None:
        """Return where the motion past a group's fold at ``value`` ends.

        On the group's other assembly, the first sample that cannot be
        assembled is bisected (``known`` where that is the limit it gives);
        None where the bisection finds that sample assembled after all (the
        continuation could not follow the assembly there). A whole turn of an
        angle is searched, or to the end of a length's declared range (a
        "range" end where nothing stops it before).
        """
        if declared.kind == "angle":
            far = value + (2 * np.pi if upward else -2 * np.pi)
        else:
            far = max(declared.range) if upward else min(declared.range)
        values = np.linspace(value, far, REACH_SAMPLES)
        probe, skip, _, _ = along(values, labels, across)  # of values[skip:]
        ok = _strictly_valid(probe)
        if ok.all():
            return Limit(float(far), None, "range")
        stop = int(np.argmin(ok))
        if stop == 0:  # nothing assembles past the fold
            return None
        inside, outside = values[skip + stop - 1], values[skip + stop]
        guesses = {k: v[stop - 1:stop] for k, v in assembly_guesses(probe).items()}
        branches = {k: int(v[stop - 1]) for k, v in probe.branches.items()}
        refined, beyond = _refine(compiled, name, held, branches, [inside], [outside],
                                  guesses)
        if _strictly_valid(beyond)[0]:
            return None  # assembled there from the side before: the probe gave up
        if abs(refined[0] - known.value) <= 1e3 * LIMIT_TOLERANCE:
            return known  # the end the search found: the same limit, as it gave it
        return Limit(float(refined[0]), *_what_stops(beyond, 0))

    sheets = dict.fromkeys(groups, 0)  # each group's assembly, 0 or 1, as its events name it
    folds: list[tuple[int, str, int]] = []  # a group passing its fold at a pass's end
    if found.full_turn:  # one turn the way the declared range runs
        turn = 2 * np.pi if declared.range[1] >= declared.range[0] else -2 * np.pi
        one_turn = np.linspace(start, start + turn, samples_per_pass)
        initial = labels
        labels = run(one_turn, labels)
        # through a change point a node or a closure group comes round on its other
        # branch or assembly: on, turn by turn, till the mechanism is back in the pose
        # it began in
        for count in range(1, MAX_TURNS + 1):
            # a group within what a turn's search joins its ends within (a start on a
            # change point is solved to about the square root of the tolerance), of the
            # group's size over the turn
            groups_back = all(
                _one_pose(_first_solved(passes[0][2][k]), _last_solved(passes[-1][2][k]),
                          SEAM_RTOL, float(np.nanmax(np.abs(passes[0][2][k]))))
                for k in groups)
            # the branches the motion goes on with: at a change point the pose alone
            # cannot tell them (both branches pass through it)
            labels = onward(labels)
            if groups_back and labels == initial:
                break
            if count == MAX_TURNS:
                warn_outside(f"circuit of {name!r}: not back where it began after "
                             f"{MAX_TURNS} turns; the motion is given as far as it went",
                             UserWarning)
                break
            # each group goes on from where the turn before ended, the same input value:
            # its continuation follows it over the first step, change points included
            labels = run(one_turn + count * turn, labels,
                         sketches={k: _last_solved(v) for k, v in passes[-1][2].items()}
                         or None)
    else:
        # samples evenly spaced along the motion: first a fine sampling evenly spaced in
        # phi, where input = centre + radius * sin(phi), which crowds towards the limits
        # where the motion runs fastest; then resampled to equal steps of the motion
        def stretch(a, b, labels, across):
            # about the interval the pass runs in, which a toggle may have changed
            centre, radius = 0.5 * (lo.value + hi.value), 0.5 * (hi.value - lo.value)
            pa, pb = (np.arcsin(np.clip((v - centre) / radius, -1, 1)) for v in (a, b))
            count = max(2, int(np.ceil(abs(pb - pa) / np.pi * samples_per_pass)) + 1)
            fine = centre + radius * np.sin(np.linspace(pa, pb, 8 * count))
            fine[[0, -1]] = a, b
            motion, skip, _, _ = along(fine, labels, across)
            steps = sum(np.nan_to_num(np.hypot(*np.diff(motion.points[p], axis=0).T))
                        for p in compiled.point_names)
            travelled = np.concatenate([np.zeros(1 + skip), np.cumsum(steps)])
            if travelled[-1] == 0:
                return np.linspace(a, b, count)
            values = np.interp(np.linspace(0, travelled[-1], count), travelled, fine)
            values[[0, -1]] = a, b
            return values

        initial = searched = dict(labels)
        position, target = start, hi
        across = None
        # every state of the branches and sheets, both ways, at either end of an interval
        # (its ends change with the branches): more passes than these cannot close
        most = 4 * 2 ** min(len(labels) + len(groups), 10) + 4
        for count in range(1, most + 1):
            upward = target is hi
            labels = run(stretch(position, target.value, labels, across), labels, across)
            if groups:
                across = _continuing(compiled, name, held, passes[-1], target)
            folded, folds_before = False, len(folds)
            if target.kind == "tangent":
                ends = {k: _last_solved(v)[None] for k, v in passes[-1][2].items()}
                labels = _through_toggle(compiled, name, held, labels, target, ends)
                for node in sorted(set(groups).intersection(target.nodes or (target.node,))):
                    sheets[node] ^= 1
                    folds.append((len(passes) - 1, node, sheets[node]))
                    across = _continuing(compiled, name, held, passes[-1], target, node)
                    folded = True
            if labels != searched and not groups:
                lo, hi = _interval_on(compiled, name, at, labels, target.value, (lo, hi))
                searched = labels
            if folded:
                # on its other assembly a group goes as far as that assembly does
                end = reach(target.value, not upward, labels, across, lo if upward else hi)
                if end is None:
                    warn_outside(f"circuit of {name!r}: past the fold at {target.value:g} "
                                 "the group's other assembly could not be followed; the "
                                 "motion is given as far as it went", UserWarning)
                    del folds[folds_before:]
                    break
                lo, hi = (end, hi) if upward else (lo, end)
            position, target = target.value, (lo if upward else hi)
            # a circuit reaches both ends: at an end that is no toggle (of the searched
            # range, or of a ray) the branches stay, and the other end is still to come;
            # it is closed once back at the start in its first pose, heading up as it set
            # out (heading down, it has yet to pass the start and reach the lower end)
            if count >= 2 and target is hi and lo.value <= start <= hi.value:
                # run on to the start, and stop there if back in the pose it began in (on
                # the way a node may pass a change point, a group past folds on any of
                # its assemblies); else go on from there
                labels = run(stretch(position, start, labels, across), labels, across)
                if _same_pose(compiled, name, held, start, labels, initial) and all(
                        _one_pose(_first_solved(passes[0][2][k]),
                                  _last_solved(passes[-1][2][k]), POSE_RTOL)
                        for k in groups):
                    break
                position = start
                if groups:
                    across = _continuing(compiled, name, held, passes[-1], target)
        else:
            warn_outside(f"circuit of {name!r}: not back where it began after {most} passes "
                         "between limits; the motion is given as far as it went", UserWarning)
    # each pass starts where the one before ended: drop the repeated sample
    values = np.concatenate([p[0] if i == 0 else p[0][1:] for i, p in enumerate(passes)])
    per_sample = {k: np.concatenate([p[1][k] if i == 0 else p[1][k][1:]
                                     for i, p in enumerate(passes)]) for k in labels}
    solved = {k: np.concatenate([_nearest_solved(p[2][k]) if i == 0
                                 else _nearest_solved(p[2][k])[1:]
                                 for i, p in enumerate(passes)]) for k in groups}
    inputs = {k: np.full(len(values), v) for k, v in held.items()}
    inputs[name] = values
    result = evaluate(compiled, inputs, len(values), {**per_sample, **solved}, track=False)
    # each pass's first sample is the one before's last
    last = np.cumsum([len(p[0]) - (i > 0) for i, p in enumerate(passes)]) - 1
    fractions = {(node, int(at) + (last[i - 1] if i else 0)): fraction
                 for i, met in enumerate(meetings) for (node, at), fraction in met.items()}
    events = []
    for node, label in per_sample.items():
        names = compiled.step_named(node).node.branch_names
        for i in np.flatnonzero(np.diff(label)) + 1:
            events.append(BranchEvent(node, int(i), names[label[i - 1]], names[label[i]],
                                      fractions.get((node, int(i)), 0.0)))
    # a closure group goes on to its other assembly at its fold, at the end of a pass
    for pass_index, node, sheet in folds:
        events.append(BranchEvent(node, int(last[pass_index]) + 1, f"assembly {sheet ^ 1}",
                                  f"assembly {sheet}"))
    events.sort(key=lambda e: e.index)
    return replace(result, events=tuple(events))


def _same_pose(compiled, name, held, value, labels, initial) -> bool:
    """Whether the mechanism at input ``value`` is in one pose on both sets of branches.

    The same branches are; others are where the roots of each node that
    differs meet there (a circuit that starts at a change point comes back
    on the other branch of it, in the same pose).
    """
    if labels == initial:
        return True
    poses = [_evaluate_at(compiled, name, [value], held, branches)
             for branches in (labels, initial)]
    points = [np.concatenate([np.asarray(pose[p]).ravel() for p in compiled.point_names])
              for pose in poses]
    return _one_pose(points[0], points[1], POSE_RTOL)


REACH_SAMPLES = 721
"""Samples of the search for where a group's other assembly ends, past its fold."""

POSE_RTOL = 1e-9
"""How close (times the mechanism's size) every point must be for two poses to be one."""


def _interval_on(compiled, name, at, labels, value, ends) -> tuple[Limit, Limit]:
    """Return the interval the input moves in on branches ``labels``, from ``value``.

    Past a toggle the branches change, and with them where the motion ends:
    on its new branch a root may leave its segment before the end the old
    branch reached. The interval's ends are moved by whole turns to the turn
    of ``value``. An interval narrower than the search's grid is looked for
    again about ``value`` (a degree, or a 360th of a length input's range,
    either way); ``ends`` where none on these branches holds it.
    """
    declared = compiled.inputs[name]
    angle = declared.kind == "angle"
    reach = math.radians(1) if angle else abs(declared.range[1] - declared.range[0]) / 360
    for search in (None, (value - reach, value + reach)):
        try:
            found = limits(compiled, name, at=at, start_branches=labels, search_range=search)
        except AssemblyError:  # assembled on a sliver the search's grid steps over
            continue
        placed = placed_in(found, value, angle, LIMIT_SLACK)
        if found.full_turn or placed is None:
            continue
        (lo, hi), near = placed
        shift = 2 * math.pi * round((value - near) / (2 * math.pi)) if angle else 0.0
        return replace(lo, value=lo.value + shift), replace(hi, value=hi.value + shift)
    return ends


LIMIT_SLACK = 1e-9
"""How far (radians or length units) a toggle may lie from the end of the
interval of the branches it leads to: both ends are bisected to
:data:`LIMIT_TOLERANCE`."""


def _continuing(compiled, name, held, last_pass, limit: Limit, folded: str | None = None):
    """Return where the closure groups start the pass after ``last_pass``, as a function.

    The function takes the pass's second input value and gives each group's
    positions to start its continuation from there: where the last pass
    ended, except for the group ``folded`` that passes its fold at
    ``limit``. Near a fold at input q_L the group's two solutions are
    z_L +- sqrt(q_L - q) w + O(q_L - q) (w along the Jacobian's null vector):
    z_L and w are read from the last two solutions the pass found, and the
    other side of the fold, z_L - sqrt(q_L - q) w, starts Newton there.
    """
    values, branches, solved = last_pass
    ends = {k: _last_solved(v) for k, v in solved.items()}
    if folded is None or len(values) < 2:
        return lambda value: ends
    rows = solved[folded]
    found = _solved(rows)
    if found.size < 2:
        return lambda value: ends
    last, before = found[-1], found[-2]
    reach = np.sqrt(np.abs(limit.value - values[[last, before]]))
    if not reach[1] > reach[0]:
        return lambda value: ends
    along = (rows[last] - rows[before]) / (reach[0] - reach[1])
    fold = rows[last] - reach[0] * along

    def across(value):
        return {**ends, folded: fold - np.sqrt(abs(limit.value - value)) * along}

    return across


def _solved(rows: np.ndarray) -> np.ndarray:
    """Return the samples of a pass where a group's solution was found."""
    return np.flatnonzero(np.isfinite(rows).all(axis=1))


def _nearest_solved(rows: np.ndarray) -> np.ndarray:
    """Return each group solution of a pass, or where unsolved the one before it in the pass.

    The continuation along a pass may stop a sample short of a fold, where
    the group's Jacobian is all but singular; the circuit's samples are
    then each solved by Newton from these, and the sample at the fold from
    the solution before it, on the same assembly, converges. Rows before
    the pass's first solution take that one.
    """
    solved = np.isfinite(rows).all(axis=1)
    if solved.all() or not solved.any():
        return rows
    before = np.maximum.accumulate(np.where(solved, np.arange(len(rows)), -1))
    return rows[np.where(before >= 0, before, np.argmax(solved))]


def _first_solved(rows: np.ndarray) -> np.ndarray:
    """Return the first solution a pass found, NaN if none."""
    found = _solved(rows)
    return rows[found[0]] if found.size else rows[0]


def _last_solved(rows: np.ndarray) -> np.ndarray:
    """Return the last solution a pass found, NaN if none.

    A pass's last sample lies at a limit within bisection's tolerance; at a
    group's fold its Jacobian is all but singular there, and the
    continuation may stop a sample short of it: the last solution found is
    then the nearest to the fold.
    """
    found = _solved(rows)
    return rows[found[-1]] if found.size else rows[-1]


def _through_toggle(compiled, name, held, labels, limit: Limit, ends=None) -> dict:
    """Return the branches that carry the motion through a toggle at ``limit``.

    Every two-root node whose roots meet there changes branch, as the
    mechanism does passing the toggle (a closure group at its fold passes
    it by continuation, :func:`_continuing`); every other two-root node then
    takes the root that continues its position at the limit, since a node
    built on nodes that changed branch may see its own roots in the other
    order. ``ends`` holds the closure groups' solutions at the limit.
    """
    ends = ends or {}
    before = _evaluate_at(compiled, name, [limit.value], held, {**labels, **ends})
    after = dict(labels)
    toggled = limit.nodes or (limit.node,)
    for node in toggled:
        if node in after:
            after[node] ^= 1
    for step in compiled.steps:
        node = step.node.name
        if step.node.roots != 2 or node in toggled or not np.isfinite(
                before[node][0]).all():
            continue
        choices = []
        for label in (after[node], after[node] ^ 1):
            trial = _evaluate_at(compiled, name, [limit.value], held,
                                 {**after, node: label, **ends})
            choices.append(np.hypot(*(trial[node][0] - before[node][0])))
        if choices[1] < choices[0]:
            after[node] ^= 1
    return after


def placed_in(found: Limits, value: float, angle: bool, slack: float = 0.0
              ) -> tuple[tuple[Limit, Limit], float] | None:
    """Return the interval of ``found`` that holds ``value``, and the value there.

    An angle (``angle``) is moved by whole turns to the interval it falls in;
    a value within ``slack`` of an interval's end (an end as printed, to a
    few decimals) is that end. None where no interval holds it, and for a
    value that is not finite.

    Examples
    --------
    >>> ends = (Limit(-1.0, "C", "tangent"), Limit(1.0, "C", "tangent"))
    >>> found = Limits("theta", (ends,), False, {})
    >>> round(placed_in(found, 0.5 + 4 * np.pi, angle=True)[1], 12)
    0.5
    >>> placed_in(found, 1.0 + 1e-9, angle=True, slack=1e-6)[1], placed_in(found, 2.0, True)
    (1.0, None)
    """
    if not math.isfinite(value):
        return None
    turn = 2 * math.pi if angle else 0.0
    for lo, hi in found.intervals:
        near = value + (turn * round((0.5 * (lo.value + hi.value) - value) / turn)
                        if turn else 0.0)
        if lo.value - slack <= near <= hi.value + slack:
            return (lo, hi), min(max(near, lo.value), hi.value)
    return None


def describe_limit(limit: Limit) -> str:
    """Say in words what stops the motion at a limit."""
    if limit.kind == "range":
        return "end of the searched range"
    if limit.kind == "tangent":
        return f"node {limit.node!r} becomes tangent (toggle)"
    reason = limit.reason or "its root leaves its ray or segment, or it degenerates"
    return f"node {limit.node!r}: {reason}"
