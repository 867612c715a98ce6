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
from collections.abc import Iterable, Sequence

import numpy as np

from ..analysis import Crank, cranks
from ..errors import ConstructionError, show
from ..kinematics import slider_positions
from ..results import Sweep
from ..terminal import escape, shorten

__all__ = ["Layout", "input_text", "length_unit", "shown_text"]

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
    traces : list of str
    crank : Crank or None
        The crank the input turns, where the arc arrow is drawn: the first
        of :func:`geokin.analysis.cranks`.
    size : float
        The size of a symbol (pivot, block) in data units.
    valid_indices : ndarray of int
        The samples that can be assembled.
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
        if compiled.links:
            self.pivots = [p for p in self.ground if p in linked]
        else:
            self.pivots = list(self.ground)
        # a ground point only giving a slider's guide its direction is shown by the guide
        guides = {p for s in self.sliders for p in s.along}
        self.references = [p for p in self.ground if p not in self.pivots
                           and (p in linked or p not in guides)]
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
        self.neighbours: dict[str, set[str]] = {p: set() for p in self.nodes}
        for points in self.links:
            for p in points:
                self.neighbours[p].update(q for q in points if q != p)
        valid = np.flatnonzero(sweep.valid)
        self.valid_indices = valid
        xy = np.concatenate([sweep.points[p] for p in self.shown]) if self.shown else None
        if xy is not None and valid.size:
            lo, hi = np.nanmin(xy, axis=0), np.nanmax(xy, axis=0)
        else:
            lo, hi = np.zeros(2), np.ones(2)
        self.lower, self.upper = lo, hi
        extent = float(np.max(hi - lo))
        self.size = 0.035 * extent if extent > 0 else 1.0
        self.guide_spans = self._guide_spans()

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

    def pose_index(self, index: int) -> int | None:
        """Return the sample whose pose is drawn for ``index``: itself or the nearest valid."""
        if self.sweep.valid[index]:
            return index
        valid = self.valid_indices
        if valid.size == 0:
            return None
        before = valid[valid < index]
        return int(before[-1]) if before.size else int(valid[0])

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the lower-left and upper-right corners of the whole motion with symbols."""
        s = self.size
        return self.lower - 3.0 * s, self.upper + np.array([3.0 * s, 3.0 * s])


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


def input_text(sweep: Sweep, index: int) -> str:
    """Return the input values at sample ``index`` as a figure shows them.

    An angle is in degrees, and an input named like a Greek letter is
    written as that letter.

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
    """
    parts = []
    for name, values in sweep.inputs.items():
        label = _GREEK.get(name, name)
        value = values[index]
        if sweep.construction.inputs[name].kind == "angle":
            parts.append(f"{label} = {math.degrees(value):.1f}°")
        else:
            parts.append(f"{label} = {value:.4g}")
    return ", ".join(parts) if parts else f"sample {index}"


def shown_text(text: object) -> str:
    r"""Return text from a script as a figure shows it: escaped, at most 200 characters.

    Examples
    --------
    >>> shown_text("four-bar\x1b[2J")
    'four-bar\\x1b[2J'
    """
    return escape(shorten(str(text), 200))


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
