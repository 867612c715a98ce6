"""What a drawing of a mechanism shows, decided before anything is drawn.

:class:`Layout` reads a sweep's construction and says which points are
ground pivots, which are joints and which only help the construction, which
bars and sliders to draw, which crank the input turns, how large a symbol is
and what the view must hold. :func:`input_text` and :func:`shown_text` give
the texts a figure shows. Nothing here imports matplotlib: the drawing
modules (:mod:`~geokin.plotting.mechanism`, :mod:`~geokin.plotting.animation`,
:mod:`~geokin.plotting.charts`) turn this into artists.

Examples
--------
>>> import numpy as np
>>> from geokin import Construction, sweep
>>> c = Construction("crank and rocker")
>>> c.input("theta")
>>> c.fixed("O2", 0, 0)
>>> c.fixed("O4", 40, 0)
>>> c.polar("A", "O2", 10, "theta")
>>> c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
>>> layout = Layout(sweep(c, np.linspace(0, 2 * np.pi, 73)))
>>> layout.pivots, layout.traces
(['O2', 'O4'], ['A', 'B'])
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Iterable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..analysis import Crank, cranks
from ..errors import AssemblyError, ConstructionError, show
from ..kinematics import slider_positions
from ..results import Sweep
from ..terminal import escape, shorten

__all__ = ["Layout", "distance_to_segment", "input_text", "length_unit", "pose_drawn",
           "shown_text", "signed_turn", "symbol_covers", "symbol_outline"]

_GREEK = {"theta": "θ", "phi": "φ", "psi": "ψ", "alpha": "α", "beta": "β", "gamma": "γ",
          "omega": "ω"}


class Layout:
    """The drawable parts of a sweep's construction, and their sizes.

    Parameters
    ----------
    sweep : Sweep
    traces : list of str, optional
        The points whose paths are drawn; by default the construction's
        traced points, or else every point that moves.

    Raises
    ------
    ConstructionError
        For a traced point the construction does not have, with the
        closest name.

    Attributes
    ----------
    sweep : Sweep
        The motion drawn.
    nodes : dict of str to Node
        Every point, in evaluation order.
    ground : list of str
        The points that never move, in evaluation order: the construction's
        :attr:`~geokin.construction.Compiled.ground`. A fixed point whose
        coordinates use an input moves, and is drawn as a joint.
    pivots : list of str
        The ground points drawn as ground pivots.
    references : list of str
        The points marked as construction aids, not joints.
    shown : list of str
        The points drawn and labelled.
    moving : list of str
        The points that are not ground.
    links : list of tuple of str
        The bars and plates: the declared links, or else a bar from each
        point to each point it is built on.
    neighbours : dict of str to set of str
        For every point, the points sharing a bar or plate with it.
    sliders : list of Slider
    guide_spans : dict of str to (float, float)
        For every slider, by name, the stretch of its guide drawn: from and
        to this far along the guide from its first point (as
        :func:`geokin.kinematics.slider_positions` measures). It holds the
        block's travel over the sweep and a margin; a fixed guide also
        reaches its first point, and a moving one stays on the link that
        carries it (the lever of a slotted lever), unless the block goes
        further.
    fixed_guides : dict of str to (ndarray, ndarray)
        For every slider on a fixed guide of two distinct points, by name,
        the guide's first point and its unit direction.
    guide_sides : dict of str to int
        For every slider on a fixed guide, by name, the side of the guide
        its block rides on the hatched ground of: -1 to the right of the
        guide's direction (from its first point to its second), +1 to the
        left: the side the bars cross less often over the sweep, and as
        often, the side away from the mechanism's other moving points and
        its pivots.
    traces : list of str
    crank : Crank or None
        The crank the input turns: the first of :func:`geokin.analysis.cranks`.
    driven : list of Crank
        The cranks an arc arrow is drawn on: for each input that turns one,
        the first crank it turns (:attr:`crank` first).
    pushed : list of (str, str)
        The points an input places directly (a ``fixed`` point whose
        coordinates use it, as a piston pushed by a length input), with that
        input, where it turns no crank: a straight arrow beside the point
        marks its sense.
    size : float
        The size of a symbol (pivot, block) in data units.
    ground_sizes : dict of str to float
        For every pivot, the size of its ground symbol: :attr:`size`, or
        down to 0.6 of it where another ground point is closer than the
        symbol would reach.
    ground_directions : dict of str to float
        For every pivot, the direction (radians, counter-clockwise from the
        x axis) from the pivot to its ground symbol's hatched base: straight
        down where that is clear, otherwise the side clear of the other
        pivots and their symbols, of the ground's frame and fixed guides,
        and of a bar that stays on that side about the pivot, outwards
        rather than into the mechanism (see :func:`symbol_outline`).
    valid_indices : ndarray of int
        The samples that can be assembled.
    unassembled : str or None
        Why no sample can be assembled (the message of
        :meth:`~geokin.results.Sweep.require_assembled`), or None if one can.
        Such a sweep is drawn as what is known at each sample: the ground
        pivots, and the points found before the node that fails.
    """

    def __init__(self, sweep: Sweep, traces: Iterable[str] | None = None) -> None:
        compiled = sweep.construction
        self.sweep = sweep
        self.nodes = {step.node.name: step.node for step in compiled.steps}
        self.ground = [name for name in self.nodes if name in compiled.ground]
        if compiled.links:
            self.links = [tuple(link.points) for link in compiled.links]
        else:
            self.links = _bars_from_construction(compiled)
        self.sliders = list(compiled.sliders)
        linked = {p for points in self.links for p in points}
        linked |= {s.point for s in self.sliders}
        # a ground point only giving a fixed guide its direction is shown by the guide,
        # also where the frame is declared as a link through it (a guide through a moving
        # point turns about its ground point: a pivot)
        guides = {p for s in self.sliders for p in s.along}
        fixed_guides = {p for s in self.sliders if set(s.along) <= compiled.ground
                        for p in s.along}
        jointed = {p for points in self.links if not set(points) <= compiled.ground
                   for p in points} | {s.point for s in self.sliders}
        # whatever the links say, a guide through a moving point turns about its
        # ground point
        turning = {p for s in self.sliders if not set(s.along) <= compiled.ground
                   for p in s.along if p in compiled.ground}
        if compiled.links:
            self.pivots = [p for p in self.ground if p in turning or (
                p in linked and (p in jointed or p not in fixed_guides))]
        else:
            self.pivots = list(self.ground)
        self.references = [p for p in self.ground if p not in self.pivots
                           and (p in jointed or p not in guides)]
        self.shown = [p for p in self.nodes if p in self.pivots or p in self.references
                      or p not in self.ground]
        self.moving = [p for p in self.nodes if p not in self.ground]
        self.traces = self._traces(traces)
        if compiled.links:
            # a moving point on no link, no slider and no trace only helps the
            # construction: mark it like a reference, not like a joint
            self.references += [p for p in self.moving
                                if p not in linked and p not in self.traces]
        found = cranks(compiled)
        self.crank: Crank | None = found[0] if found else None
        self.driven = [crank for i, crank in enumerate(found)
                       if all(crank.input_name != other.input_name for other in found[:i])]
        turning = {crank.input_name for crank in self.driven}
        self.pushed = []
        for name, node in self.nodes.items():
            if node.ground_kind and name not in compiled.ground:
                used = sorted(set().union(*(expr.names() for expr in node.value_fields().values()))
                              & compiled.inputs.keys() - turning)
                if used:
                    self.pushed.append((name, used[0]))
        self.neighbours: dict[str, set[str]] = {p: set() for p in self.nodes}
        for points in self.links:
            for p in points:
                self.neighbours[p].update(q for q in points if q != p)
        valid = np.flatnonzero(sweep.valid)
        self.valid_indices = valid
        self.unassembled: str | None = None
        try:
            sweep.require_assembled()
        except AssemblyError as err:
            self.unassembled = str(err)
        if valid.size:
            xy = np.concatenate([sweep.points[p] for p in self.shown] or [np.empty((0, 2))])
        else:  # the view holds what is known: the pivots, the points found before a failure
            xy = np.concatenate([np.column_stack(sweep.points.xy(p)) for p in self.shown]
                                or [np.empty((0, 2))])
        xy = xy[np.isfinite(xy).all(axis=1)]
        if xy.size:
            lo, hi = xy.min(axis=0), xy.max(axis=0)
        else:
            lo, hi = np.zeros(2), np.ones(2)
        self.lower, self.upper = lo, hi
        extent = float(np.max(hi - lo))
        self.size = 0.035 * extent if extent > 0 else 1.0
        self.guide_spans = self._guide_spans()
        self.fixed_guides = self._fixed_guides()
        self.guide_sides = self._guide_sides()
        self.ground_sizes = self._ground_sizes()
        self.ground_directions = self._ground_directions()

    def bar_ends(self, points: Sequence[str]) -> tuple[str, ...]:
        """Return a link's points, or just its two ends if they all lie on one line.

        A rigid link keeps its shape, so one assembled sample decides.
        """
        if len(points) <= 2 or not self.valid_indices.size:
            return tuple(points)
        xy = np.array([self.sweep.points[p][self.valid_indices[0]] for p in points])
        direction = xy[np.argmax(np.hypot(*(xy - xy[0]).T))] - xy[0]
        length = float(np.hypot(*direction))
        if length == 0:
            return tuple(points)
        offsets = (xy - xy[0]) @ (np.array([-direction[1], direction[0]]) / length)
        if np.max(np.abs(offsets)) > 1e-6 * length:
            return tuple(points)
        along = (xy - xy[0]) @ (direction / length)
        return points[int(np.argmin(along))], points[int(np.argmax(along))]

    def _traces(self, traces):
        compiled = self.sweep.construction
        if traces is None:
            return list(compiled.traced or self.moving)
        names = []
        for name in traces:
            if not isinstance(name, str):
                raise ConstructionError(f"cannot trace {show(name)}: name a point with a string")
            try:
                names.append(compiled.step_named(name).node.name)
            except KeyError as err:
                raise ConstructionError(f"cannot trace: {err.args[0]}") from None
        return names

    def _fixed_guides(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Return the first point and the direction of every fixed guide, by slider.

        Only guides of two distinct ground points: one of no length has no
        direction.
        """
        guides = {}
        for slider in self.sliders:
            first, second = slider.along
            if first in self.ground and second in self.ground:
                p = self.ground_at(first)
                u = self.ground_at(second) - p
                length = float(np.hypot(*u))
                if length > 0:
                    guides[slider.name] = (p, u / length)
        return guides

    def _guide_sides(self) -> dict[str, int]:
        """Choose the side of each fixed guide its hatched ground is drawn on."""
        sides = {slider.name: -1 for slider in self.sliders
                 if set(slider.along) <= set(self.ground)}
        sampled = self.valid_indices[:: max(1, self.valid_indices.size // 90)]
        if not sampled.size:
            return sides
        bars = [(self.sweep.points[a][sampled], self.sweep.points[b][sampled])
                for points in self.links if not set(points) <= set(self.ground)
                for a, b in zip(points, points[1:], strict=False)]
        for slider in self.sliders:
            name = slider.name
            if name not in self.fixed_guides:
                continue
            p, u = self.fixed_guides[name]
            n = np.array([-u[1], u[0]])
            # the bars at the sampled poses, in the guide's frame: along it, and off it
            start = np.concatenate([np.c_[(a - p) @ u, (a - p) @ n] for a, _ in bars]
                                   or [np.empty((0, 2))])
            end = np.concatenate([np.c_[(b - p) @ u, (b - p) @ n] for _, b in bars]
                                 or [np.empty((0, 2))])
            lo, hi = self.guide_spans[name]
            crossed = [int(_crossing(side * start, side * end, (side * lo, side * hi),
                                     (1.0 * self.size, 1.7 * self.size)).sum())
                       for side in (-1, 1)]
            if crossed[0] != crossed[1]:
                sides[name] = -1 if crossed[0] < crossed[1] else 1
                continue
            # as often crossed either way: away from the other moving points and the pivots
            left = sum(float(np.nansum((self.sweep.points[m][sampled] - p) @ n))
                       for m in self.moving + self.pivots if m != slider.point)
            sides[name] = -1 if left >= 0 else 1
        return sides

    def _guide_spans(self) -> dict[str, tuple[float, float]]:
        sweep, margin = self.sweep, 2.5 * self.size
        travel = slider_positions(sweep)
        spans = {}
        for slider in self.sliders:
            first, second = slider.along
            t = travel[slider.name][self.valid_indices]
            t = t[np.isfinite(t)]
            if not t.size:
                spans[slider.name] = (-margin, margin)
                continue
            lo, hi = float(t.min()) - margin, float(t.max()) + margin
            if first in self.ground and second in self.ground:
                lo = min(lo, -margin)  # the guide reaches back to its first point
            else:
                # no further than the link the guide is on, unless the block goes further
                carrier = next((points for points in self.links
                                if first in points and second in points), (first, second))
                d = sweep.points[second] - sweep.points[first]
                with np.errstate(all="ignore"):
                    u = d / np.hypot(d[:, :1], d[:, 1:])
                    along = np.array([np.einsum("ij,ij->i", sweep.points[q] - sweep.points[first],
                                                u)[self.valid_indices] for q in carrier])
                ok = along[np.isfinite(along)]
                if ok.size:
                    lo = max(lo, min(float(ok.min()), float(t.min())))
                    hi = min(hi, max(float(ok.max()), float(t.max())))
            spans[slider.name] = (lo, hi)
        return spans

    def symbol_lines(self, name: str, at: np.ndarray) -> tuple[tuple[np.ndarray, np.ndarray],
                                                               tuple[np.ndarray, np.ndarray]]:
        """Return the two lines a pivot's ground symbol is made of, each as its two ends.

        The triangle's middle line, from near the pivot (at ``at``) to its
        base, and the middle line of the hatched strip across it (the
        corners are :func:`symbol_outline`), both along
        :attr:`ground_directions`.
        """
        s, angle = self.ground_sizes[name], self.ground_directions[name]
        d = np.array([math.cos(angle), math.sin(angle)])
        e = np.array([-d[1], d[0]])
        strip = at + 1.85 * s * d
        return (at + 0.35 * s * d, at + 1.5 * s * d), (strip - 1.6 * s * e, strip + 1.6 * s * e)

    def _ground_sizes(self) -> dict[str, float]:
        """Size each pivot's ground symbol: smaller where another ground point is near."""
        sizes = {p: self.size for p in self.pivots}
        for name in self.pivots:
            here = self.ground_at(name)
            gaps = [float(np.hypot(*(self.ground_at(p) - here)))
                    for p in self.ground if p != name and p in self.shown]
            gaps = [g for g in gaps if g > 0]  # and not NaN: a ground node that fails
            if gaps:
                sizes[name] = self.size * min(max(min(gaps) / (2.2 * self.size), 0.6), 1.0)
        return sizes

    def _ground_directions(self) -> dict[str, float]:
        """Choose the side of each pivot its ground symbol is drawn on."""
        down = _SYMBOL_SIDES[0]
        directions = {p: down for p in self.pivots}
        s = self.size
        at = {p: self.ground_at(p) for p in self.ground}
        # the lines of the ground: its frame, and each fixed guide with the hatching under it
        lines = []
        grounds = []  # each fixed guide's line, and the edge of its hatched ground
        for points in self.links:
            if all(p in self.ground for p in points):
                closed = (*points, points[0]) if len(points) > 2 else points
                lines += [(at[a], at[b]) for a, b in zip(closed, closed[1:], strict=False)]
        for name, (p, u) in self.fixed_guides.items():
            out = self.guide_sides[name] * np.array([-u[1], u[0]])
            lo, hi = self.guide_spans[name]
            start, end = p + lo * u, p + hi * u
            lines.append((start, end))
            grounds.append(((start, end), (start + 1.7 * s * out, end + 1.7 * s * out)))
        # the directions of the moving bars about each pivot, over (some of) the motion
        sampled = self.valid_indices[:: max(1, self.valid_indices.size // 90)]
        placed: dict[str, float] = {}
        middle = 0.5 * (self.lower + self.upper)
        for name in self.pivots:
            here, size = at[name], self.ground_sizes[name]
            inward = math.atan2(*(middle - here)[::-1])
            ends = [self.sweep.points[q][sampled] - here
                    for q in self.neighbours[name] if q not in self.ground]
            swing = np.concatenate(ends) if ends else np.empty((0, 2))
            swing = np.arctan2(swing[:, 1], swing[:, 0])
            through, apart = [], []  # lines through the pivot (their directions), and others
            # a guide's hatched ground is the pivot's own where the guide runs through it:
            # only the grounds of other guides are in the way
            elsewhere = [edge for guide, edge in grounds
                         if distance_to_segment(here, *guide) >= 1e-6 * s]
            for line in lines + elsewhere:
                if distance_to_segment(here, *line) < 1e-6 * s:
                    through += [math.atan2(*(end - here)[::-1]) for end in line
                                if np.hypot(*(end - here)) > 0.1 * s]
                else:
                    length = float(np.hypot(*(line[1] - line[0])))
                    steps = np.linspace(0, 1, min(400, 2 + int(4 * length / s)))[:, None]
                    apart.append(line[0] + steps * (line[1] - line[0]))
            best, best_cost = down, math.inf
            for rank, angle in enumerate(_SYMBOL_SIDES):
                # below where that is clear; else outwards rather than into the mechanism
                outward = 1 + math.cos(angle - inward)  # 0 straight out, 2 straight in
                cost = 0.0 if rank == 0 else 0.05 + 0.03 * rank + 0.1 * outward
                others = np.array([point for other, point in at.items()
                                   if other != name and other in self.shown])
                if others.size and symbol_covers(here, angle, size, others, 0.5 * s).any():
                    cost += 2.0  # it would cover another ground point
                outline = symbol_outline(here, angle, size)
                for other, side in placed.items():
                    theirs = self.ground_sizes[other]
                    overlap = max(symbol_covers(at[other], side, theirs, outline, 0.2 * s).mean(),
                                  symbol_covers(here, angle, size,
                                                symbol_outline(at[other], side, theirs),
                                                0.2 * s).mean())
                    cost += 2.0 * float(overlap)
                for direction in through:  # keep off the lines through the pivot
                    cost += 1.0 if abs(signed_turn(direction, angle)) < math.radians(50) else 0.0
                for points in apart:
                    cost += 1.0 if symbol_covers(here, angle, size, points, 0.2 * s).any() else 0.0
                if swing.size:  # a bar that is there most of the time, not a crank passing
                    there = np.mean(np.abs(signed_turn(swing, angle)) < math.radians(40))
                    cost += max(0.0, float(there) - 0.4)
                if cost < best_cost - 1e-12:
                    best, best_cost = angle, cost
            directions[name] = placed[name] = best
        return directions

    def ground_at(self, name: str) -> np.ndarray:
        """Return where a ground point is: the same at every sample, assembled or not."""
        x, y = self.sweep.points.xy(name)
        return np.array([x[0], y[0]]) if len(x) else np.full(2, np.nan)

    def pose_index(self, index: int) -> int | None:
        """Return the sample whose pose is drawn for ``index``: itself or the nearest valid.

        None if no sample can be assembled.
        """
        if self.sweep.valid[index]:
            return index
        return _assembled_near(self.valid_indices, index)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the lower-left and upper-right corners of the whole motion with symbols."""
        s = self.size
        return self.lower - 3.0 * s, self.upper + np.array([3.0 * s, 3.0 * s])


# the sides a ground symbol may take, the most usual first: below, beside, above
_SYMBOL_SIDES = tuple(math.radians(a) for a in (270, 180, 0, 90, 225, 315, 135, 45))


def symbol_outline(at: np.ndarray, angle: float, size: float) -> np.ndarray:
    """Return the corners of a ground symbol: its triangle's tip and base, its hatching.

    The tip is on the pivot ``at``; the base lies 1.5 ``size`` away towards
    ``angle``, 2 ``size`` wide, and the hatching 0.7 ``size`` beyond it,
    3.2 ``size`` wide.
    """
    d = np.array([math.cos(angle), math.sin(angle)])
    e = np.array([-d[1], d[0]])
    base = at + 1.5 * size * d
    far = base + 0.7 * size * d
    return np.array([at, base - size * e, base + size * e, base - 1.6 * size * e,
                     base + 1.6 * size * e, far + 1.6 * size * e, far - 1.6 * size * e,
                     base, at + size * d])


def symbol_covers(at: np.ndarray, angle: float, size: float, points: np.ndarray,
                  pad: float = 0.0) -> np.ndarray:
    """Return which of the points (k, 2) lie on a ground symbol (see :func:`symbol_outline`).

    ``pad`` widens the symbol by that much all round.

    Examples
    --------
    >>> symbol_covers(np.zeros(2), -np.pi / 2, 1.0, np.array([[0, -1.0], [0, 1.0], [1.5, -2]]))
    array([ True, False,  True])
    """
    d = np.array([math.cos(angle), math.sin(angle)])
    e = np.array([-d[1], d[0]])
    rel = np.asarray(points, dtype=float).reshape(-1, 2) - at
    along, across = rel @ d, np.abs(rel @ e)
    triangle = (along >= -pad) & (along <= 1.5 * size) & (across <= along / 1.5 + pad)
    hatching = (along >= 1.5 * size) & (along <= 2.2 * size + pad) & (across <= 1.6 * size + pad)
    return triangle | hatching


def signed_turn(a, b):
    """Return the signed angle from ``b`` to ``a`` (radians), in [-pi, pi).

    Examples
    --------
    >>> round(float(np.degrees(signed_turn(np.radians(350), np.radians(10)))), 9)
    -20.0
    """
    return (np.asarray(a) - b + np.pi) % (2 * np.pi) - np.pi


def distance_to_segment(point: ArrayLike, a: ArrayLike, b: ArrayLike) -> np.ndarray:
    """Return the distance from a point to the segment a-b, elementwise.

    Parameters
    ----------
    point, a, b : array_like, shape (..., 2)
        Broadcast against each other.

    Returns
    -------
    ndarray, shape (...)

    Examples
    --------
    >>> float(distance_to_segment([3.0, 4.0], [0.0, 0.0], [1.0, 0.0]))
    4.47213595499958
    >>> distance_to_segment([[0.5, 1.0], [-1.0, 0.0]], [0.0, 0.0], [1.0, 0.0]).tolist()
    [1.0, 1.0]
    """
    point, a, b = (np.asarray(v, dtype=float) for v in (point, a, b))
    ab, ap = b - a, point - a
    length2 = np.sum(ab * ab, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(length2 > 0, np.sum(ap * ab, axis=-1) / length2, 0.0)
    t = np.clip(t, 0.0, 1.0)
    return np.hypot(*np.moveaxis(ap - t[..., None] * ab, -1, 0))


def _bars_from_construction(compiled):
    """Bars from each point to the points it is built on, without repeats."""
    bars, seen = [], set()
    for step in compiled.steps:
        for dep in step.node.depends_on():
            key = frozenset((step.node.name, dep))
            if dep != step.node.name and key not in seen:
                seen.add(key)
                bars.append((dep, step.node.name))
    return bars


def pose_drawn(sweep: Sweep, index: int) -> int | None:
    """Return the sample whose pose a drawing of sample ``index`` shows.

    The sample itself if it can be assembled; otherwise the last one before
    it that can be, or the first one after it if none before can be; None if
    no sample can be.

    Examples
    --------
    >>> import numpy as np
    >>> from geokin import Construction, sweep
    >>> c = Construction()
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.fixed("Q", 5, 0)
    >>> c.polar("A", "O", 2, "theta")
    >>> c.circle_circle("B", ("A", "Q"), (2, 2), branch="left")  # only while A is near Q
    >>> s = sweep(c, np.radians([180, 90, 0, -90]))
    >>> s.valid.tolist(), pose_drawn(s, 0), pose_drawn(s, 3)
    ([False, False, True, False], 2, 2)
    """
    if sweep.valid[index]:
        return index
    return _assembled_near(np.flatnonzero(sweep.valid), index)


def _assembled_near(valid: np.ndarray, index: int) -> int | None:
    """Return the last of the ``valid`` samples before ``index``, else the first; or None."""
    if valid.size == 0:
        return None
    before = valid[valid < index]
    return int(before[-1]) if before.size else int(valid[0])


def _crossing(start: np.ndarray, end: np.ndarray, along: tuple[float, float],
              off: tuple[float, float]) -> np.ndarray:
    """Whether each segment meets the rectangle ``along`` x ``off`` (Liang-Barsky).

    ``start`` and ``end`` are (K, 2) arrays of the segments' ends; a bound
    pair may come in either order. NaN ends meet nothing.

    Examples
    --------
    >>> _crossing(np.array([[0.0, -1.0], [5.0, -1.0], [np.nan, 0.0]]),
    ...           np.array([[0.0, 1.0], [5.0, 1.0], [0.0, 0.0]]), (-1.0, 1.0), (-0.5, 0.5)).tolist()
    [True, False, False]
    """
    enter = np.zeros(len(start))
    leave = np.ones(len(start))
    with np.errstate(divide="ignore", invalid="ignore"):
        for axis, bounds in enumerate((along, off)):
            low, high = min(bounds), max(bounds)
            a, step = start[:, axis], end[:, axis] - start[:, axis]
            to_low, to_high = (low - a) / step, (high - a) / step
            still = step == 0
            inside = (low <= a) & (a <= high)
            enter = np.where(still, np.where(inside, enter, np.inf),
                             np.fmax(enter, np.fmin(to_low, to_high)))
            leave = np.where(still, leave, np.fmin(leave, np.fmax(to_low, to_high)))
    finite = np.isfinite(start).all(axis=1) & np.isfinite(end).all(axis=1)
    return finite & (enter <= leave)


def input_text(sweep: Sweep, index: int) -> str:
    """Return the input values at sample ``index`` as a figure shows them.

    An angle is in degrees, a length in the construction's units, and an
    input named like a Greek letter is written as that letter.

    Examples
    --------
    >>> import numpy as np
    >>> from geokin import Construction, sweep
    >>> c = Construction()
    >>> c.input("theta")
    >>> c.input("s", kind="length", range=(0, 5))
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", "10 + s", "theta")
    >>> input_text(sweep(c, {"theta": np.radians([0, 45]), "s": [0, 2.5]}), 1)
    'θ = 45.0°, s = 2.5'
    >>> c.units = "mm"
    >>> input_text(sweep(c, {"theta": np.radians([0, 45]), "s": [0, 2.5]}), 1)
    'θ = 45.0°, s = 2.5 mm'
    """
    parts = []
    units = shown_text(sweep.construction.units)
    for name, values in sweep.inputs.items():
        label = _GREEK.get(name, name)
        value = values[index]
        if sweep.construction.inputs[name].kind == "angle":
            parts.append(f"{label} = {math.degrees(value):.1f}°")
        else:
            parts.append(f"{label} = {value:.4g}{' ' + units if units else ''}")
    return ", ".join(parts) if parts else f"sample {index}"


def shown_text(text: object) -> str:
    r"""Return text from a script as a figure shows it: escaped, at most 200 characters.

    Examples
    --------
    >>> shown_text("four-bar\x1b[2J")
    'four-bar\\x1b[2J'
    """
    return escape(shorten(str(text), 200))


TITLE_WIDTH = 80
"""The most characters on a line of a figure's title: a longer one is broken."""

CHARACTERS_PER_INCH = 9.5
"""About how many characters of a 12-point title fit in an inch (wide ones among them)."""


def title_text(text: object, width: int = TITLE_WIDTH) -> str:
    """Return a title from a script as a figure shows it, on lines of ``width`` at most.

    Examples
    --------
    >>> print(title_text("a four-bar " * 10))
    a four-bar a four-bar a four-bar a four-bar a four-bar a four-bar a four-bar
    a four-bar a four-bar a four-bar
    """
    return broken_title(shown_text(text), width)


def broken_title(shown: str, width: int = TITLE_WIDTH) -> str:
    """Return a title already shown as text (:func:`shown_text`) on lines of ``width`` at most.

    Lines break at spaces only, never at a hyphen inside a name.
    """
    return textwrap.fill(shown, width, break_on_hyphens=False)


def title_width(ax) -> int:
    """Return how many characters of a title fit over an axes, :data:`TITLE_WIDTH` at most."""
    inches = ax.get_position().width * ax.figure.get_figwidth()
    return max(12, min(TITLE_WIDTH, int(inches * CHARACTERS_PER_INCH)))


def length_unit(sweep: Sweep) -> str:
    """Return the construction's length unit as a figure shows it, or ``""`` without one.

    Examples
    --------
    >>> import numpy as np
    >>> from geokin import Construction, sweep
    >>> c = Construction(units="mm")
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta")
    >>> length_unit(sweep(c, np.zeros(1)))
    'mm'
    """
    return shown_text(sweep.construction.units.strip()) if sweep.construction.units else ""
