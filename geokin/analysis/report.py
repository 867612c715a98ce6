"""One report of everything geokin can say about a construction.

:func:`analyze` gathers the degrees of freedom, the motion limits of each
input, the Grashof class of every four-bar loop it recognises, the
transmission angle at every circle-circle node, strokes and time ratios of
the traced points and the declared links, and measures of the traced
curves, in a :class:`Report`. ``geokin analyze`` prints it;
:meth:`Report.to_dict` gives it as the plain data of ``geokin analyze --json``,
:meth:`Report.to_text` as the text of ``geokin analyze``.
"""

from __future__ import annotations

import html
import math
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from functools import partial
from itertools import combinations
from typing import Any

import numpy as np

from ..circuits import Limits, circuit, describe_limit, limits, placed_in
from ..closure import NEAR_SINGULAR, RESIDUAL_RTOL
from ..construction import Compiled, Construction, Slider, as_compiled
from ..engine import meeting_rtol, sweep
from ..errors import AnalysisError, degrees_hint, looks_like_degrees, quote, warn_of_degrees
from ..kinematics import link_angles, slider_positions, sliders_off_guide
from ..nodes import CircleCircle
from ..results import Sweep, short_name
from ..terminal import one_line
from .fourbar import ROLES, grashof, transmission_angles
from .measures import closing_turns, curve_measures, refine_extreme, stroke
from .mobility import Mobility, cranks, degrees_of_freedom

__all__ = [
    "EQUAL_STROKES",
    "CurveReport",
    "FourBarReport",
    "InputReport",
    "LimitReport",
    "Report",
    "StrokeReport",
    "TransmissionReport",
    "analyze",
]

def off_guide_text(slider: Slider, offset: float, units: str, where: str) -> str:
    """Say how far a slider's point is off its guide's line, and where it is farthest.

    ``where`` names that sample (its input values, in the caller's units).

    Examples
    --------
    >>> from geokin.construction import Slider
    >>> print(off_guide_text(Slider("ram", "B", ("C", "G")), -0.5, "mm", "theta = 90 deg"))
    its point 'B' is 0.5 mm off its guide, the line through 'C' and 'G' (farthest at
    theta = 90 deg); a slider's point must lie on the line of its guide
    """
    unit = f" {one_line(units, 100)}" if units else ""
    first, second = slider.along
    return (f"its point {quote(slider.point)} is {abs(offset):.4g}{unit} off its guide, the "
            f"line through {quote(first)} and {quote(second)} (farthest at {where}); a "
            "slider's point must lie on the line of its guide")


# -- the report ---------------------------------------------------------------------

EQUAL_STROKES = 1e-6
"""How far above 1 a time ratio may be and its two strokes still be taken as
equal (:attr:`StrokeReport.slower_stroke`): the extremes are placed between
samples to about this accuracy."""
# Angles are in the report's unit (Report.angle_unit); lengths and input values
# of length inputs in the construction's length unit.


@dataclass(frozen=True)
class LimitReport:
    """One end of an input's assemblable interval, set by a node.

    Attributes
    ----------
    value : float
        The input's value there.
    node : str or None
        The node that cannot be assembled beyond it (None only at the end
        of a searched range, which is not reported as a limit).
    kind : {"tangent", "end"}
        ``"tangent"`` where the node's two roots meet (a toggle or dead
        centre), ``"end"`` where its root leaves its ray or segment (see
        :class:`geokin.circuits.Limit`).
    meaning : str
        The same in words.
    """

    value: float
    node: str | None
    kind: str
    meaning: str

    def __repr__(self) -> str:
        return f"<LimitReport: {self.kind} at {self.value:.6g}, node {short_name(self.node)}>"

    def to_dict(self) -> dict[str, Any]:
        """Return the limit as plain data: ``value``, ``node``, ``kind``, ``meaning``."""
        return {"value": self.value, "node": self.node, "kind": self.kind,
                "meaning": self.meaning}


@dataclass(frozen=True)
class InputReport:
    """Where one input can go.

    Attributes
    ----------
    kind : {"angle", "length"}
        The input's kind.
    full_turn : bool
        Whether an angle input turns fully, without any limit.
    intervals : tuple of (float, float)
        Each assemblable interval as ``(low, high)``, within the declared
        range, in order.
    limits : tuple of LimitReport
        The ends of the intervals that a node sets, in order (an end of the
        declared range is not one).
    circuit_turns : int or None
        Where the input turns fully and its circuit is analysed, after how
        many turns the mechanism's motion repeats: 1, or more where a node
        comes round on its other branch through a change point (see
        :func:`geokin.circuit`; started on the change point itself, it is
        back in the same pose after one turn, yet goes on on the other
        branch). None otherwise, and where the mechanism is not back after
        the circuit's turns (the report warns).
    """

    kind: str
    full_turn: bool
    intervals: tuple[tuple[float, float], ...]
    limits: tuple[LimitReport, ...]
    circuit_turns: int | None = None

    def __repr__(self) -> str:
        if self.full_turn:
            where = "turns fully" + self._back_after()
        elif not self.intervals:
            where = "no interval"
        else:
            where = (f"{len(self.intervals)} interval(s) from {self.intervals[0][0]:.6g} to "
                     f"{self.intervals[-1][1]:.6g}, {len(self.limits)} limit(s)")
        return f"<InputReport ({self.kind}): {where}>"

    def _back_after(self) -> str:
        """Say after how many turns the motion repeats, where it takes more than one."""
        if self.circuit_turns is None or self.circuit_turns == 1:
            return ""
        return f", its motion repeating after {self.circuit_turns} turns"

    def to_dict(self) -> dict[str, Any]:
        """Return the input as plain data.

        The keys are ``kind``, ``full_turn``, ``intervals``, ``limits`` and
        ``circuit_turns``.
        """
        return {"kind": self.kind, "full_turn": self.full_turn,
                "intervals": [[low, high] for low, high in self.intervals],
                "limits": [limit.to_dict() for limit in self.limits],
                "circuit_turns": self.circuit_turns}


@dataclass(frozen=True)
class FourBarReport:
    """A four-bar loop closed at a circle-circle node, and its Grashof class.

    Attributes
    ----------
    node : str
        The circle-circle node that closes the loop.
    points : (str, str, str, str)
        The crank's ground pivot, the crank pin, ``node`` and the output's
        ground pivot.
    lengths : mapping of str to float
        The lengths of the ``"ground"``, ``"input"``, ``"coupler"`` and
        ``"output"`` links, in that order.
    kind : str
        The Grashof class (``"class"`` in :meth:`to_dict`), one of
        :data:`geokin.analysis.KINDS`.
    code : str
        Its short code (``"GCRR"``, ``"RRR1"``), ``""`` for none.
    grashof : bool
        Whether the shortest link turns fully relative to the others.
    turning : tuple of str
        The links (``"input"``, ``"coupler"``, ``"output"``) that turn fully
        relative to the ground.
    """

    node: str
    points: tuple[str, str, str, str]
    lengths: Mapping[str, float]
    kind: str
    code: str
    grashof: bool
    turning: tuple[str, ...]

    def __repr__(self) -> str:
        sides = ", ".join(f"{role} {self.lengths[role]:.6g}" for role in ROLES)
        return f"<FourBarReport at {short_name(self.node)}: {self.named}; {sides}>"

    @property
    def named(self) -> str:
        """The class with its code, once: ``crank-rocker (GCRR)``, ``triple-rocker RRR1``."""
        if not self.code or self.code in self.kind:
            return self.kind
        return f"{self.kind} ({self.code})"

    def to_dict(self) -> dict[str, Any]:
        """Return the four-bar as plain data, each length under its role's name."""
        return {"node": self.node, "points": list(self.points),
                **{role: self.lengths[role] for role in ROLES},
                "class": self.kind, "code": self.code, "grashof": self.grashof,
                "turning": list(self.turning)}


@dataclass(frozen=True)
class TransmissionReport:
    """The extremes of the transmission angle at a circle-circle node.

    Attributes
    ----------
    minimum, maximum : float
        The extremes of the angle between the node's two links, in
        ``[0, 180]`` degrees or ``[0, pi]`` radians (``min`` and ``max``
        in :meth:`to_dict`).
    at_minimum, at_maximum : mapping of str to float
        The input values where they occur (``at_min`` and ``at_max``).
    """

    minimum: float
    maximum: float
    at_minimum: Mapping[str, float]
    at_maximum: Mapping[str, float]

    def __repr__(self) -> str:
        return f"<TransmissionReport: {self.minimum:.6g} to {self.maximum:.6g}>"

    def to_dict(self) -> dict[str, Any]:
        """Return the extremes as plain data: ``min``, ``max``, ``at_min``, ``at_max``."""
        return {"min": self.minimum, "max": self.maximum, "at_min": dict(self.at_minimum),
                "at_max": dict(self.at_maximum)}


@dataclass(frozen=True)
class StrokeReport:
    """The extremes of one output: a traced coordinate, a slider's position, a link's angle.

    Attributes
    ----------
    turns : bool
        Whether the output is a link angle that turns fully; the other
        fields are then None.
    minimum, maximum : float or None
        The output's extremes, placed between samples (``min`` and ``max``
        in :meth:`to_dict`).
    stroke : float or None
        ``maximum - minimum``.
    time_ratio : float or None
        Where the input turns fully and the output goes out and back once
        a turn: the input travelled from the minimum to the maximum over
        that from the maximum back (forward over return time at a constant
        input speed); None otherwise. The usual figure, at least 1, is
        :attr:`quick_return_ratio`, with :attr:`slower_stroke`.
    strokes_per_turn : int or None
        Where the input turns fully, how many times a turn the output goes
        out and back; None where it does not (and :meth:`to_dict` leaves
        it out).

    Examples
    --------
    >>> s = StrokeReport(False, 0.0, 1.0, 1.0, time_ratio=0.8)
    >>> s.quick_return_ratio, s.slower_stroke
    (1.25, 'max->min')
    """

    turns: bool
    minimum: float | None = None
    maximum: float | None = None
    stroke: float | None = None
    time_ratio: float | None = None
    strokes_per_turn: int | None = None

    @property
    def quick_return_ratio(self) -> float | None:
        """Return the slower stroke's time over the faster one's: the time ratio, at least 1.

        None where there is no time ratio. At a constant input speed, the
        input travelled during the slower stroke over that during the faster.
        """
        if self.time_ratio is None:
            return None
        return max(self.time_ratio, 1 / self.time_ratio)

    @property
    def slower_stroke(self) -> str | None:
        """Return which stroke takes longer: ``"min->max"`` or ``"max->min"``.

        None where there is no time ratio, or where the two take the same
        time to :data:`EQUAL_STROKES` (the extremes are placed between
        samples to about that accuracy).
        """
        ratio = self.quick_return_ratio
        if ratio is None or ratio - 1 <= EQUAL_STROKES:
            return None
        assert self.time_ratio is not None
        return "min->max" if self.time_ratio > 1 else "max->min"

    def __repr__(self) -> str:
        if self.turns:
            return "<StrokeReport: turns fully>"
        ratio = "" if self.time_ratio is None else f", time ratio {self.time_ratio:.6g}"
        return (f"<StrokeReport: {self.minimum:.6g} to {self.maximum:.6g}, "
                f"stroke {self.stroke:.6g}{ratio}>")

    def to_dict(self) -> dict[str, Any]:
        """Return the output's extremes as plain data: ``{"turns": True}`` for a turning link.

        The keys are ``turns``, ``min``, ``max``, ``stroke``, ``time_ratio``
        (forward over return: minimum to maximum over maximum to minimum),
        ``quick_return_ratio`` (at least 1) and ``slower_stroke``, then
        ``strokes_per_turn`` where the input turns fully.
        """
        if self.turns:
            return {"turns": True}
        entry: dict[str, Any] = {"turns": False, "min": self.minimum, "max": self.maximum,
                                 "stroke": self.stroke, "time_ratio": self.time_ratio,
                                 "quick_return_ratio": self.quick_return_ratio,
                                 "slower_stroke": self.slower_stroke}
        if self.strokes_per_turn is not None:
            entry["strokes_per_turn"] = self.strokes_per_turn
        return entry


@dataclass(frozen=True)
class CurveReport:
    """Measures of a traced point's path (see :func:`~geokin.analysis.curve_measures`).

    Attributes
    ----------
    length : float
        The path's length.
    closed : bool
        Whether it ends where it starts.
    area : float or None
        The area it encloses, each region once; zero where that is within
        what sampling the path can make of none (:attr:`Curve.area_tolerance
        <geokin.analysis.measures.Curve.area_tolerance>`), as for a joint
        that swings out and back; None where it is open, or where the area
        lies beyond the range of floats.
    bounds : (float, float, float, float)
        ``(xmin, ymin, xmax, ymax)``.
    double_points : tuple of (float, float)
        Where it crosses itself.
    """

    length: float
    closed: bool
    area: float | None
    bounds: tuple[float, float, float, float]
    double_points: tuple[tuple[float, float], ...]

    def __repr__(self) -> str:
        area = "" if self.area is None else f", area {self.area:.6g}"
        return (f"<CurveReport: length {self.length:.6g}, "
                f"{'closed' if self.closed else 'open'}{area}, "
                f"{len(self.double_points)} double point(s)>")

    def to_dict(self) -> dict[str, Any]:
        """Return the measures as plain data, with ``bounds`` and ``double_points`` as lists."""
        return {"length": self.length, "closed": self.closed, "area": self.area,
                "bounds": list(self.bounds),
                "double_points": [list(point) for point in self.double_points]}


@dataclass(frozen=True)
class Report:
    """What :func:`analyze` finds about a construction; immutable.

    Angles (values of angle inputs, transmission angles, link angles) are in
    :attr:`angle_unit`; lengths, and values of length inputs, in the
    construction's length unit.

    Attributes
    ----------
    construction : str
        The construction's name.
    angle_unit : {"rad", "deg"}
        The unit of every angle in the report.
    mobility : Mobility
        The Gruebler-Kutzbach count of the declared links (:attr:`dof` is
        its ``dof``).
    inputs : mapping of str to InputReport
        Where each input can go, by input name, in declaration order.
    warnings : tuple of str
        What the figures below leave out: samples of the motion that cannot
        be assembled.
    assembled : bool
        Whether any sample of the motion can be assembled. Where none can,
        the fields below are empty and :meth:`to_dict` leaves them out.
    four_bars : tuple of FourBarReport
        Every four-bar loop on a driven crank and a ground pivot.
    transmission_angles : mapping of str to TransmissionReport
        By circle-circle node whose two links are declared (every such node
        where no link is declared).
    strokes : mapping of str to StrokeReport
        By output (``"<point>.x"``, ``"<point>.y"``, ``"<slider>.position"``,
        ``"<link>.angle"``), for a construction of one input; outputs that do
        not move are left out.
    curves : mapping of str to CurveReport
        By traced point.
    """

    construction: str
    angle_unit: str
    mobility: Mobility
    inputs: Mapping[str, InputReport]
    warnings: tuple[str, ...]
    assembled: bool
    four_bars: tuple[FourBarReport, ...]
    transmission_angles: Mapping[str, TransmissionReport]
    strokes: Mapping[str, StrokeReport]
    curves: Mapping[str, CurveReport]

    @property
    def dof(self) -> int:
        """Return the degrees of freedom of the declared links (Gruebler-Kutzbach)."""
        return self.mobility.dof

    def __getitem__(self, key: str) -> Any:
        """Return ``to_dict()[key]``: the dict :func:`analyze` used to return (deprecated)."""
        warnings.warn("analyze() returns a Report: read its fields (report.inputs), or "
                      "report.to_dict() for the old dict; indexing it will be removed",
                      DeprecationWarning, stacklevel=2)
        return self.to_dict()[key]

    def __repr__(self) -> str:
        kinds = sorted({bar.kind for bar in self.four_bars})
        bars = f", four-bars: {', '.join(kinds)}" if kinds else ""
        return (f"<Report of {short_name(self.construction)}: DOF {self.dof}, "
                f"{len(self.inputs)} input(s){bars}, {len(self.strokes)} stroke(s), "
                f"{len(self.curves)} curve(s), angles in {self.angle_unit}>")

    def _repr_html_(self) -> str:
        """Return the report as ``geokin analyze`` prints it, for a notebook."""
        return f"<pre>{html.escape(self.to_text())}</pre>"

    def to_dict(self) -> dict[str, Any]:
        """Return the report as plain data, ready for JSON: what ``geokin analyze --json`` prints.

        The keys are those of the fields, in their order, with ``dof`` after
        ``angle_unit``; ``mobility`` holds the counts of :class:`Mobility`,
        ``matches_inputs`` and the ``formula`` as text. Where no sample can
        be assembled, ``four_bars``, ``transmission_angles``, ``strokes``
        and ``curves`` are left out.

        Examples
        --------
        >>> from geokin import Construction
        >>> c = Construction("crank")
        >>> c.input("theta")
        >>> c.fixed("O", 0, 0)
        >>> c.polar("A", "O", 2, "theta")
        >>> c.link("crank", "O", "A")
        >>> c.trace("A")
        >>> data = analyze(c, degrees=True).to_dict()
        >>> list(data)  # doctest: +NORMALIZE_WHITESPACE
        ['construction', 'angle_unit', 'dof', 'mobility', 'inputs', 'warnings',
         'four_bars', 'transmission_angles', 'strokes', 'curves']
        >>> data["strokes"]["crank.angle"], data["curves"]["A"]["closed"]
        ({'turns': True}, True)
        """
        m = self.mobility
        report: dict[str, Any] = {
            "construction": self.construction,
            "angle_unit": self.angle_unit,
            "dof": self.dof,
            "mobility": {
                "moving_links": m.moving_links, "revolute_joints": m.revolute_joints,
                "prismatic_pairs": m.prismatic_pairs, "lower_pairs": m.lower_pairs,
                "higher_pairs": m.higher_pairs, "inputs": m.inputs,
                "matches_inputs": m.matches_inputs, "formula": str(m),
            },
            "inputs": {name: entry.to_dict() for name, entry in self.inputs.items()},
            "warnings": list(self.warnings),
        }
        if not self.assembled:
            return report
        report["four_bars"] = [bar.to_dict() for bar in self.four_bars]
        report["transmission_angles"] = {
            node: mu.to_dict() for node, mu in self.transmission_angles.items()}
        report["strokes"] = {label: s.to_dict() for label, s in self.strokes.items()}
        report["curves"] = {point: curve.to_dict() for point, curve in self.curves.items()}
        return report

    def _inputs_text(self, values: Mapping[str, float], angles: str, lengths: str) -> str:
        """Say input values, each in its unit: ``theta = 12.3456 deg``."""
        return ", ".join(f"{name} = {round(value, 4) + 0.0:.4f}"  # never -0.0000
                         f"{angles if self.inputs[name].kind == 'angle' else lengths}"
                         for name, value in values.items())

    def to_text(self, units: str = "") -> str:
        """Return the report as ``geokin analyze`` prints it, one finding a line.

        Parameters
        ----------
        units : str
            The unit written after lengths (a construction's ``units``);
            none by default. Angles are followed by ``deg`` or ``rad``, the
            report's :attr:`angle_unit`.

        Returns
        -------
        str
            Lines, each ending in a newline. What came from a script (the
            construction's name, ``units``, the warnings) is escaped and cut
            to 1000 characters (:func:`geokin.terminal.one_line`), so that
            each stays on its line.

        Examples
        --------
        >>> from geokin import Construction
        >>> c = Construction("crank-rocker")
        >>> c.input("theta")
        >>> c.fixed("O2", 0, 0)
        >>> c.fixed("O4", 4, 0)
        >>> c.polar("A", "O2", 1, "theta")
        >>> c.circle_circle("B", ("A", "O4"), (4, 3), branch="left")
        >>> c.link("crank", "O2", "A")
        >>> c.link("coupler", "A", "B")
        >>> c.link("rocker", "O4", "B")
        >>> print(analyze(c, degrees=True).to_text(), end="")
        crank-rocker
        degrees of freedom: DOF = 3(3) - 2(4) - 0 = 1; 1 input
        input theta: turns fully
        four-bar O2-A-B-O4 (ground 4, input 1, coupler 4, output 3): crank-rocker (GCRR);
        input turns fully
        transmission angle at B: 48.19 to 90.00 deg (at theta = 0.0000 deg and
        theta = 180.0000 deg)
        crank.angle: turns fully
        coupler.angle: 28.9550 to 60.0000 deg, stroke 31.0450 deg, time ratio 1.1887
        (min->max slower)
        rocker.angle: 90.0000 to 131.8103 deg, stroke 41.8103 deg, time ratio 1.1342
        (min->max slower)
        """
        lengths = f" {one_line(units, 1000)}" if units else ""
        areas = f" {_squared(one_line(units, 1000))}" if units else ""
        angles = " deg" if self.angle_unit == "deg" else " rad"
        lines = [one_line(self.construction, 1000),
                 f"degrees of freedom: {self.mobility}"]
        lines += [f"warning: {one_line(warning, 1000)}" for warning in self.warnings]
        for name, entry in self.inputs.items():
            unit = angles if entry.kind == "angle" else lengths
            if entry.full_turn:
                lines.append(f"input {name}: turns fully{entry._back_after()}")
                continue
            spans = ", ".join(f"{lo:.6f}{_range_end(entry, lo)} to {hi:.6f}{unit}"
                              f"{_range_end(entry, hi)}" for lo, hi in entry.intervals)
            lines.append(f"input {name}: assemblable from {spans}")
            for limit in entry.limits:
                lines.append(f"  limit at {limit.value:.6f}{unit}: {limit.meaning}")
        # a loop's input may turn fully where the mechanism's, held back by other nodes,
        # cannot: the loop's classes are its own
        held_back = len(self.inputs) == 1 and not next(iter(self.inputs.values())).full_turn
        for bar in self.four_bars:
            sides = ", ".join(f"{role} {bar.lengths[role]:g}" for role in ROLES)
            turning = ", ".join(bar.turning) or "no link"
            verb = "turn" if len(bar.turning) > 1 else "turns"
            alone = " in this loop alone" if held_back and "input" in bar.turning else ""
            lines.append(f"four-bar {'-'.join(bar.points)} ({sides}): {bar.named}; "
                         f"{turning} {verb} fully{alone}")
        for node, mu in self.transmission_angles.items():
            # several inputs' values are a list of their own: the two apart by more than "and"
            where = ("; and at " if len(mu.at_minimum) > 1 else " and ").join(
                self._inputs_text(at, angles, lengths) for at in (mu.at_minimum, mu.at_maximum))
            lines.append(f"transmission angle at {node}: {mu.minimum:.2f} to "
                         f"{mu.maximum:.2f}{angles} (at {where})")
        for label, s in self.strokes.items():
            if s.turns:
                lines.append(f"{label}: turns fully")
                continue
            unit = angles if label.endswith(".angle") else lengths
            ratio = ""
            if s.quick_return_ratio is not None:
                slower = (f"{s.slower_stroke} slower" if s.slower_stroke is not None
                          else "strokes equal")
                ratio = f", time ratio {s.quick_return_ratio:.4f} ({slower})"
            if s.strokes_per_turn is not None and s.strokes_per_turn > 1:
                ratio = f", {s.strokes_per_turn} strokes per turn"
            lines.append(f"{label}: {_figure(s.minimum)} to {_figure(s.maximum)}{unit}, stroke "
                         f"{_figure(s.stroke)}{unit}{ratio}")
        for point, curve in self.curves.items():
            area = ("" if curve.area is None else ", encloses no area" if curve.area == 0
                    else f", encloses {_figure(curve.area)}{areas}")
            lines.append(f"path of {point}: length {_figure(curve.length)}{lengths}"
                         f"{', closed' if curve.closed else ', open'}{area}, "
                         f"{len(curve.double_points)} double point(s)")
        return "\n".join(lines) + "\n"


def _squared(unit: str) -> str:
    """Return the square of a length unit as the terminal text writes it, in ASCII.

    >>> _squared("mm"), _squared("length units")
    ('mm^2', '(length units)^2')
    """
    return f"{unit}^2" if unit.isalnum() else f"({unit})^2"


def _range_end(entry: InputReport, value: float) -> str:
    """Mark an interval's end that is the end of the searched range, not a limit."""
    if any(abs(limit.value - value) <= 1e-9 * max(1.0, abs(value)) for limit in entry.limits):
        return ""
    return " (end of the declared range)"


def _figure(value: float | None) -> str:
    """Four decimals for a figure of everyday size, six significant digits otherwise.

    >>> _figure(52.95454), _figure(5.2954e-159), _figure(0.0)
    ('52.9545', '5.2954e-159', '0.0000')
    """
    assert value is not None  # a stroke's figures are given wherever it does not turn
    if value == 0 or 1e-3 <= abs(value) < 1e9:
        return f"{value:.4f}"
    return f"{value:.6g}"


# -- analysis -------------------------------------------------------------------------


def _four_bars(compiled: Compiled, motion: Sweep):
    """Find circle-circle nodes closing a four-bar on a driven crank and a fixed pivot.

    The crank is one of :func:`~geokin.analysis.mobility.cranks` turning
    about a ground pivot. Where links are declared, the crank, the coupler
    and the output must be among them; a helper point of the construction
    is not a crank.
    """
    driven = {crank.tip: crank for crank in cranks(compiled) if crank.grounded and crank.on_link}
    found = []
    for step in compiled.steps:
        node = step.node
        if not isinstance(node, CircleCircle):
            continue
        for crank_pin, pivot in (node.centers, node.centers[::-1]):
            crank = driven.get(crank_pin)
            if crank is None or pivot not in compiled.ground:
                continue
            # with declared links, coupler and output must be among them too
            bars = [(crank_pin, node.name), (node.name, pivot)]
            if compiled.links and not all(
                    any({a, b} <= set(link.points) for link in compiled.links) for a, b in bars):
                continue
            i = int(np.flatnonzero(motion.valid)[0])
            p = {name: motion[name][i] for name in (crank.origin, crank_pin, node.name, pivot)}
            lengths = {
                "ground": float(np.hypot(*(p[pivot] - p[crank.origin]))),
                "input": float(np.hypot(*(p[crank_pin] - p[crank.origin]))),
                "coupler": float(np.hypot(*(p[node.name] - p[crank_pin]))),
                "output": float(np.hypot(*(p[node.name] - p[pivot]))),
            }
            found.append((node.name, (crank.origin, crank_pin, node.name, pivot), lengths))
            break
    return found


def analyze(construction: Construction | Compiled, *, degrees: bool = False,
            start: float | None = None) -> Report:
    """Analyse a construction: mobility, limits, four-bars, transmission, strokes, curves.

    The motion analysed is the whole circuit of the input (one turn if it
    turns fully, the way its declared range runs, which sets which stroke
    of an output is slower; otherwise from limit to limit on both sides of each
    toggle, see :func:`geokin.circuit`); with several inputs, the sweep of
    them all together over their declared ranges, sample by sample, which
    is one path through their combinations (the report says so). An input
    that can be assembled in several intervals has a circuit in each: the
    report names the one it analyses.

    Parameters
    ----------
    construction : Construction or Compiled
    degrees : bool
        Give angles (input values of angle inputs, transmission angles, link
        angles) in degrees instead of radians.
    start : float, optional
        For a construction with one input, the value (radians or length
        units, whatever ``degrees`` says) to start its circuit at: the
        circuit through it is analysed. By default that of
        :func:`geokin.circuit`.

    Returns
    -------
    Report
        :meth:`Report.to_dict` gives it as plain data (JSON-ready).

    Examples
    --------
    >>> import numpy as np
    >>> from geokin import Construction
    >>> c = Construction("triple rocker")
    >>> c.input("theta2", range=(-np.pi, np.pi))
    >>> c.fixed("A", 0, 0)
    >>> c.fixed("D", 7, 0)
    >>> c.polar("B", "A", 5, "theta2")
    >>> c.circle_circle("C", ("B", "D"), (6, 5), branch="left")
    >>> report = analyze(c, degrees=True)
    >>> [round(v, 4) for v in report.inputs["theta2"].intervals[0]]
    [-132.1774, 132.1774]
    >>> [limit.kind for limit in report.inputs["theta2"].limits]
    ['tangent', 'tangent']
    >>> report.four_bars[0].kind
    'triple-rocker RRR1'
    """
    compiled = as_compiled(construction)
    mobility = degrees_of_freedom(compiled)

    def angle(value) -> float:
        return float(np.degrees(value) if degrees else value)

    def value_of(name: str) -> Callable[[Any], float]:
        return angle if compiled.inputs[name].kind == "angle" else float

    inputs = {}
    found_limits = {}
    for name, declared in compiled.inputs.items():
        convert = value_of(name)
        found = found_limits[name] = limits(compiled, name)
        inputs[name] = InputReport(
            kind=declared.kind,
            full_turn=found.full_turn,
            intervals=tuple((convert(lo), convert(hi)) for lo, hi in found.as_values()),
            limits=tuple(LimitReport(convert(end.value), end.node, end.kind, describe_limit(end))
                         for pair in found.intervals for end in pair if end.kind != "range"))
    warnings = []
    if len(compiled.inputs) == 1:
        name = next(iter(compiled.inputs))
        if start is not None:
            start = _circuit_start(compiled, found_limits[name], inputs[name], start, degrees)
        motion = circuit(compiled, start=start)
        low, high = compiled.inputs[name].range
        if found_limits[name].full_turn and abs(high - low) < 2 * np.pi * (1 - 1e-9):
            unit = _input_unit(compiled, name, degrees)
            span = round(float(np.ptp(motion.inputs[name])) / (2 * np.pi))
            whole = "one whole turn" if span == 1 else f"{span} whole turns, its circuit"
            warnings.append(f"input {quote(name)} turns fully: the figures below are of "
                            f"{whole}, not of its declared range ({angle(low):g} to "
                            f"{angle(high):g}{unit})")
        if len(inputs[name].intervals) > 1:
            warnings.append(_which_circuit(compiled, name, len(inputs[name].intervals),
                                           motion.inputs[name], value_of(name), degrees))
    else:
        if start is not None:
            raise AnalysisError(
                "start= picks the circuit of an input; this construction has "
                + (f"{len(compiled.inputs)} inputs, swept together" if compiled.inputs
                   else "no input"))
        motion = sweep(compiled)
        if compiled.inputs:
            warnings.append(_swept_together(compiled, motion, value_of, degrees))
    if not motion.valid.all():
        i = int(np.flatnonzero(~motion.valid)[0])
        warnings.append(
            f"{int((~motion.valid).sum())} of {len(motion)} samples of the "
            f"{'circuit' if len(compiled.inputs) == 1 else 'sweep'} cannot be assembled "
            f"(first at sample {i}: node {motion.failed_node[i]!r}: "
            f"{motion.failure_reason[i]}); the figures below come from the others")
    for block, (i, offset) in sliders_off_guide(motion).items():
        slider = next(each for each in compiled.sliders if each.name == block)
        at = ", ".join(f"{k} = {value_of(k)(v[i]):g}"
                       + (f" {'deg' if degrees else 'rad'}"
                          if compiled.inputs[k].kind == "angle" else "")
                       for k, v in motion.inputs.items())
        warnings.append(f"slider {quote(block)}: "
                        f"{off_guide_text(slider, offset, compiled.units, at)}")
    off = _known_to(compiled, motion)
    back = _returning(compiled, motion, off)
    if _whole_turns(compiled, motion) and motion.valid[[0, -1]].all():
        name = next(iter(compiled.inputs))
        turns = abs(round((motion.inputs[name][-1] - motion.inputs[name][0]) / (2 * np.pi)))
        away = [p for p, returns in back.items() if not returns]
        if not away and inputs[name].full_turn:
            inputs[name] = replace(inputs[name], circuit_turns=turns)
        elif away:
            warnings.append(
                f"after {turns} turn{'s' if turns > 1 else ''} of {name!r} the mechanism is "
                f"not back where it began ({', '.join(map(repr, away[:4]))}"
                f"{', ...' if len(away) > 4 else ''} {'end' if len(away) > 1 else 'ends'} "
                "elsewhere): what moves with these points is given over this motion, without "
                "time ratios")
    unit = "deg" if degrees else "rad"
    if not motion.valid.any():
        return Report(compiled.name, unit, mobility, inputs, tuple(warnings), assembled=False,
                      four_bars=(), transmission_angles={}, strokes={}, curves={})
    four_bars = []
    for node, points, lengths in _four_bars(compiled, motion):
        try:
            g = grashof(*(lengths[role] for role in ROLES))
        except AnalysisError:  # a link of zero length: no four-bar to classify
            continue
        four_bars.append(FourBarReport(node, points, lengths, g.kind, g.code, g.grashof,
                                       g.turning))

    def inputs_at(values: Mapping[str, float]) -> dict[str, float]:
        return {k: value_of(k)(v) for k, v in values.items()}

    def between_links(t) -> bool:
        # with declared links, the angle must be between two of them, not a helper line
        return not compiled.links or all(
            any({t.node, centre} <= set(link.points) for link in compiled.links)
            for centre in t.centers)

    # extremes placed on the mechanism evaluated again between samples, as strokes' are
    steps = (None if any(step.node.continued for step in compiled.steps)
             else _Steps(compiled, motion))
    transmission = {}
    for node, t in transmission_angles(motion).items():
        if not between_links(t):
            continue
        ends = [(t.at_minimum, t.minimum), (t.at_maximum, t.maximum)]
        if steps is not None and np.isfinite(t.angle).any():
            of = partial(_transmission_angle, node=node)
            ends = [(steps.inputs_at(where), value) for where, value in (
                _placed_extreme(t.angle, sign, steps, of, False) for sign in (-1, 1))]
        (at_low, low), (at_high, high) = ends
        transmission[node] = TransmissionReport(
            angle(low), angle(high), inputs_at(_in_declared_turn(compiled, inputs, at_low)),
            inputs_at(_in_declared_turn(compiled, inputs, at_high)))
    curves = {}
    for point in compiled.traced:
        try:
            curve = curve_measures(motion[point])
        except AnalysisError:  # fewer than two assembled samples in a row
            continue
        area: float | None = curve.area
        if not np.isfinite(curve.area):
            area = None  # the curve is open, or its area is beyond the range of floats
        elif curve.area <= curve.area_tolerance:
            area = 0.0  # slivers between the samples of a path run out and back
        curves[point] = CurveReport(
            curve.length, curve.closed, area,
            curve.bounds, tuple((x, y) for x, y in curve.double_points.tolist()))
    return Report(compiled.name, unit, mobility, inputs, tuple(warnings), assembled=True,
                  four_bars=tuple(four_bars), transmission_angles=transmission,
                  strokes=_strokes(compiled, motion, angle, off, back, steps),
                  curves=curves)


def _peaks(values, span) -> int:
    """Count the maxima of a periodic output over one turn.

    Steps smaller than 1e-9 of the output's span (rounding) do not count.
    """
    step = np.diff(np.concatenate([values, values[:1]]))
    step = step[np.isfinite(step) & (np.abs(step) > 1e-9 * span)]
    if step.size == 0:
        return 1
    rising = step > 0
    # a maximum wherever a rise is followed by a fall, the last step wrapping to the first
    return max(int(np.count_nonzero(rising & ~np.roll(rising, -1))), 1)


_AROUND = np.array([-1.0, 0.0, 1.0])
"""A sample and its neighbours, by index."""


EDGE_ROUNDS = 5
"""How many times :meth:`_Steps.edge` evaluates the stretch about a limit again,
each :data:`REFINE_SAMPLES` samples: a 128**5-th of a step, 3e-11 of a
degree in a degree's step."""

REFINE_SAMPLES = 129
"""How many samples of the mechanism :func:`_strokes` evaluates again along a
step next to an extreme sample, to place the extreme inside it."""


def _told_turn(low: float, high: float, values: np.ndarray,
               driving: np.ndarray | None) -> tuple[float, float]:
    """Return an angle's extremes turned by whole turns to read as people expect.

    A crank's as :func:`~geokin.kinematics.link_angles` gives them, in the
    turn of the input that drives it (``driving``, at the samples of
    ``values``), when it keeps a constant angle from it; any other angle's
    centred on zero (:func:`_about_zero`).
    """
    if driving is None:
        return _about_zero(low, high)
    at = np.flatnonzero(np.isfinite(values) & np.isfinite(driving))
    if not at.size:
        return _about_zero(low, high)
    # a crank turned otherwise (-theta, 2 theta) is told as any other link
    between = values[at] - driving[at]
    if np.ptp(between) > ROUNDING * max(1.0, float(np.max(np.abs(between)))):
        return _about_zero(low, high)
    return low, high


def _about_zero(low: float, high: float) -> tuple[float, float]:
    """Return the extremes of an angle, turned by whole turns to centre in (-pi, pi].

    An angle's extremes are known up to whole turns: so the same swing reads
    the same whichever way the sweep unwound it. A swing centred on a half
    turn, to rounding, is centred on +pi.

    >>> [round(float(np.degrees(v)), 4) for v in _about_zero(*np.radians([-312.0, -48.0]))]
    [48.0, 312.0]
    """
    middle = 0.5 * (low + high)
    turns = math.floor((middle + math.pi - ROUNDING) / (2 * math.pi))
    return low - 2 * math.pi * turns, high - 2 * math.pi * turns


def _running_on(motion: Sweep) -> np.ndarray:
    """Whether the path runs on evenly through each sample, on the same branches.

    One input runs on through a sample where it keeps its direction. Several
    inputs do where each takes the same step on both sides of the sample (to
    rounding), so that the samples lie evenly along a straight stretch of
    the path and a parabola through three of them may place an extreme.
    """
    smooth = np.zeros(len(motion), dtype=bool)
    steps = [np.diff(values) for values in motion.inputs.values()]
    if len(steps) == 1:
        smooth[1:-1] = steps[0][:-1] * steps[0][1:] > 0
    elif steps and len(motion) > 2:
        even = np.ones(len(motion) - 2, dtype=bool)
        moving = np.zeros(len(motion) - 2, dtype=bool)
        for step in steps:
            size = np.fmax(np.abs(step[:-1]), np.abs(step[1:]))
            even &= np.abs(step[1:] - step[:-1]) <= 1e-9 * size
            moving |= size > 0
        smooth[1:-1] = even & moving
    for event in motion.events:
        smooth[max(event.index - 1, 0):event.index + 1] = False
    return smooth


def _extreme(values, sign, smooth) -> float:
    """Return the largest (sign 1) or smallest (sign -1) value, refined between samples.

    :func:`~geokin.analysis.measures.refine_extreme` places the extreme
    between samples through the extreme sample and its neighbours, where
    the motion runs smoothly through that sample (``smooth``); at the ends
    of a run, where the neighbours are missing, and where the input turns
    back or a branch changes (a limit, where the output may have a corner),
    the sample itself is taken.
    """
    finite = np.where(np.isfinite(values), sign * values, -np.inf)
    i = int(np.argmax(finite))
    if (0 < i < len(values) - 1 and smooth[i] and np.isfinite(finite[i - 1])
            and np.isfinite(finite[i + 1])):
        return refine_extreme(_AROUND, values[i - 1:i + 2])[1]
    return float(values[i])


def _coordinate(s: Sweep, point: str, axis: int) -> np.ndarray:
    return np.asarray(s[point])[:, axis]


def _slider(s: Sweep, name: str) -> np.ndarray:
    return slider_positions(s)[name]


def _transmission_angle(s: Sweep, node: str) -> np.ndarray:
    return transmission_angles(s)[node].angle


def _angle(s: Sweep, name: str) -> np.ndarray:
    return link_angles(s)[name]


class _Steps:
    """The steps of a motion, each evaluated again densely when first asked.

    Step ``a`` runs from sample a to a + 1 along the straight segment of
    the inputs, parametrized by the input (one input) or by the sample
    index (several). Over a closed circuit (it ends where it began, on the
    same branches) the step before the first sample is the last step.
    """

    def __init__(self, compiled: Compiled, motion: Sweep):
        self.compiled = compiled
        self.inputs = motion.inputs
        n = self.n = len(motion)
        # the parameter along the steps: the input, or the sample's index
        self.along = (next(iter(motion.inputs.values())) if len(motion.inputs) == 1
                      else np.arange(n, dtype=float))
        self.labels = {k: np.broadcast_to(b, (n,)) for k, b in motion.branches.items()}
        self.changes = {event.index for event in motion.events}  # in the step ending there
        self.closed = (n > 2 and closing_turns(self.inputs, compiled.angle_inputs) is not None
                       and all(b[0] == b[-1] for b in self.labels.values()))
        self.dense: dict[int, tuple[np.ndarray, Sweep]] = {}

    def about(self, i: int, across: bool = False) -> list[int]:
        """Return the steps that sample ``i`` ends or begins (not those of no length).

        With ``across``, over a closed circuit, the first sample also ends
        the last step and the last sample begins the first: what is asked
        of them comes back with the mechanism.
        """
        across = across and self.closed
        found = [i - 1] if i >= 1 else [self.n - 2] if across else []
        found += [i] if i <= self.n - 2 else [0] if across else []
        return [a for a in found if any(v[a] != v[a + 1] for v in self.inputs.values())]

    def evaluated(self, a: int) -> tuple[np.ndarray, Sweep]:
        """Return step ``a``'s parameter at :data:`REFINE_SAMPLES` samples, and its sweep.

        Swept from its end after a change of branch in it, if there is one:
        that end's branches hold back to the change, which the sweep follows
        where it lies inside the step.
        """
        if a not in self.dense:
            start, end = (a + 1, a) if a + 1 in self.changes else (a, a + 1)
            values = {k: np.linspace(v[start], v[end], REFINE_SAMPLES)
                      for k, v in self.inputs.items()}
            branches = {k: int(v[start]) for k, v in self.labels.items()}
            self.dense[a] = (np.linspace(self.along[start], self.along[end], REFINE_SAMPLES),
                             sweep(self.compiled, values, start_branches=branches))
        return self.dense[a]

    def edge(self, a: int, inside: float, outside: float, value: float,
             branches: Mapping[str, int], of: Callable[[Sweep], np.ndarray]
             ) -> tuple[float, float]:
        """Return where the assembled part of step ``a`` ends, and the output ``of`` there.

        Between the parameters ``inside`` (assembled on ``branches``, the
        output ``value`` there) and ``outside`` (not assembled), evaluated
        again at :data:`REFINE_SAMPLES` samples :data:`EDGE_ROUNDS` times,
        each time about the last assembled sample: an output near a limit
        changes as the square root of the distance to it, and is only
        placed there closely.
        """
        for _ in range(EDGE_ROUNDS):
            x = np.linspace(inside, outside, REFINE_SAMPLES)
            local = sweep(self.compiled, self._on_step(a, x), start_branches=branches)
            found = np.asarray(of(local), dtype=float)
            j = len(x) - 1 if np.isfinite(found).all() else int(np.argmin(np.isfinite(found))) - 1
            if j < 0:  # not even the inside end, to rounding: as found before
                break
            inside, value = float(x[j]), float(found[j])
            if j == len(x) - 1:
                break
            outside = float(x[j + 1])
            branches = {k: int(np.broadcast_to(b, x.shape)[j]) for k, b in local.branches.items()}
        return inside, value

    def inputs_at(self, where: float) -> dict[str, float]:
        """Return the inputs where the steps' parameter is ``where``."""
        return {name: float(value) for name, value in
                self._on_step(min(int(where), self.n - 2), where).items()}

    def _on_step(self, a: int, where):
        """Return the inputs on step ``a`` where the steps' parameter is ``where`` (numbers)."""
        if len(self.inputs) == 1:
            return {name: where for name in self.inputs}
        # the parameter is the sample's index
        return {name: v[a] + (where - a) * (v[a + 1] - v[a]) for name, v in self.inputs.items()}


def _placed_extreme(values, sign, steps: _Steps, of: Callable[[Sweep], np.ndarray],
                    is_angle: bool) -> tuple[float, float]:
    """Return where the largest (sign 1) or smallest (sign -1) value lies, and the value.

    The extreme sample's two steps are evaluated again densely
    (:meth:`_Steps.evaluated`); an extreme strictly inside one, further out
    than the sample, is placed by a parabola through the dense samples about
    it. A link angle is moved by whole turns to agree with the sample. Where
    is told as the steps' parameter (:meth:`_Steps.inputs_at` gives the
    inputs there).
    """
    finite = np.where(np.isfinite(values), sign * values, -np.inf)
    i = int(np.argmax(finite))
    where, best = float(steps.along[i]), float(values[i])
    # the ends of a closed circuit are neighbours if the output comes back too (not one
    # read off a part that turns at another rate)
    back = values[-1] - values[0]
    if is_angle:
        back -= 2 * np.pi * np.round(back / (2 * np.pi))
    across = bool(abs(back) <= ROUNDING * max(1.0, float(np.nanmax(np.abs(values)))))
    for a in steps.about(i, across):
        x, local = steps.evaluated(a)
        dense = np.asarray(of(local), dtype=float)
        assembled = np.isfinite(dense)
        if is_angle:
            # on the sample's own turn, told by the dense sample nearest to it
            if not assembled.any():
                continue
            near = np.where(assembled, np.abs(x - steps.along[i]), np.inf)
            dense = dense + 2 * np.pi * np.round((best - dense[np.argmin(near)]) / (2 * np.pi))
        # where part of the step cannot be assembled, the extreme of the part that can
        k = int(np.argmax(np.where(assembled, sign * dense, -np.inf)))
        if not assembled[k]:
            continue
        gap = next((g for g in (k - 1, k + 1) if 0 <= g < len(dense) and not assembled[g]),
                   None)
        if gap is not None:  # next to a part of the step that cannot be assembled: a limit
            labels = {name: int(np.broadcast_to(b, x.shape)[k])
                      for name, b in local.branches.items()}
            place, found = steps.edge(a, float(x[k]), float(x[gap]), float(dense[k]), labels, of)
            if is_angle:
                found += 2 * np.pi * round((dense[k] - found) / (2 * np.pi))
        elif 0 < k < len(dense) - 1:
            place, found = refine_extreme(x[k - 1:k + 2], dense[k - 1:k + 2])
        else:  # at an end of the step
            place, found = float(x[k]), float(dense[k])
        if sign * found > sign * best:
            where, best = place, found
    return where, best


MEETING_SPREAD = 4.0
"""How many times the meeting tolerance of a node whose roots meet the points found
from it may be off (:func:`_known_to`): the chosen root lies within that
tolerance of the meeting, and the nodes found from it carry the error on."""

ROUNDING = 1e-9
"""How far an output may be off by rounding alone, relative to its size (of at
least 1 rad for an angle, of the mechanism's coordinates for a point's
position): an output that moves less does not move."""


def _positions(motion: Sweep, point: str) -> np.ndarray:
    """Return a point's positions at the assembled samples of a motion, shape (M, 2)."""
    return np.asarray(motion[point])[np.asarray(motion.valid)]


def _known_to(compiled: Compiled, motion: Sweep) -> dict[str, float]:
    """Return how far each point may be off, through the meetings of the motion.

    Where a node's roots meet (a branch event of the motion), the branch
    rules know them only to :func:`~geokin.engine.meeting_rtol` of the
    node's scale s (taken as its largest distance from the points it is
    found from), for points R from (0, 0): near a meeting the roots are the
    square root of a difference of squares. Such a node's points are known
    to :data:`MEETING_SPREAD` times that. Every point carries on the errors
    of the points it is found from, times its lever: 1 + 2 L / b, L its
    largest distance from them and b their widest spread (a point
    of a rigid body far out on its frame turns with the frame's error).
    A closure group that comes to a singular position (its margin below
    :data:`~geokin.closure.NEAR_SINGULAR`, as at a change point it passes)
    is known to MEETING_SPREAD times the square root of its residual's
    tolerance there. A point found from no meeting is known to rounding (0
    here).

    Examples
    --------
    >>> from geokin import Construction, circuit
    >>> c = Construction("parallelogram")
    >>> c.input("theta")
    >>> c.fixed("O2", 0, 0)
    >>> c.fixed("O4", 10, 0)
    >>> c.polar("A", "O2", 4, "theta")
    >>> c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
    >>> c.local("P", "A", "B", (100, 0))
    >>> off = _known_to(c.compile(), circuit(c))
    >>> off["A"], bool(0 < off["B"] < 1e-5), bool(off["P"] > 10 * off["B"])
    (0.0, True, True)
    """
    met = {event.node for event in motion.events}
    off: dict[str, float] = {}
    if not np.any(motion.valid):
        return dict.fromkeys(motion.points, 0.0)
    for step in compiled.steps:
        node = step.node
        built_on = {p: _positions(motion, p) for p in node.depends_on()}
        found = [_positions(motion, p) for p in node.defines]
        reach = max((float(np.nanmax(np.hypot(*(a - b).T))) for a in found
                     for b in built_on.values()), default=0.0)
        carried = max((off[p] for p in built_on), default=0.0)
        if carried > 0:
            # the frame the node is built on: its points' widest spread, never a
            # passing near-coincidence of points that do not fix it together
            spread = max((float(np.nanmax(np.hypot(*(a - b).T)))
                          for a, b in combinations(built_on.values(), 2)), default=0.0)
            carried *= 1 + 2 * reach / spread if spread > 0 else 1.0
        if node.name in met and reach > 0:
            moving = [a for p, a in built_on.items() if p not in compiled.ground] + found
            far = max(float(np.nanmax(np.abs(a))) for a in moving)
            rtol = float(meeting_rtol(far / reach))
            carried = max(carried, MEETING_SPREAD * rtol * reach)
        margin = motion.margins.get(node.name)
        if node.continued and margin is not None and reach > 0 and np.nanmin(
                np.where(motion.valid, margin, np.inf), initial=np.inf) < NEAR_SINGULAR:
            # a closure group at a singular position (a change point it passes) is found
            # there to about the square root of its residual's tolerance
            carried = max(carried, MEETING_SPREAD * math.sqrt(RESIDUAL_RTOL) * reach)
        for point in node.defines:
            off[point] = carried
    return off


def _in_declared_turn(compiled: Compiled, inputs: Mapping[str, InputReport],
                      values: Mapping[str, float]) -> dict[str, float]:
    """Return input values (radians) with each input that turns fully told in its first turn.

    The turn from the start of its declared range, the way the range runs:
    a circuit started elsewhere gives a crank's angles some turns on.
    """
    told = dict(values)
    for name, value in values.items():
        if inputs[name].full_turn and compiled.inputs[name].kind == "angle":
            start, end = compiled.inputs[name].range
            sense = 1.0 if end >= start else -1.0
            turned = (sense * (value - start)) % (2 * math.pi)
            # a turn short of the start by rounding is the start
            told[name] = start + sense * (0.0 if 2 * math.pi - turned <= ROUNDING else turned)
    return told


def _input_unit(compiled: Compiled, name: str, degrees: bool) -> str:
    """Return the unit an input's values are told in, with its leading space."""
    if compiled.inputs[name].kind == "angle":
        return " deg" if degrees else " rad"
    return f" {one_line(compiled.units, 100)}" if compiled.units else ""


START_SLACK = 1e-6
"""How far (in the report's units) a start may lie outside an interval and still be
taken at its end: the report gives the ends to six decimals."""


def _circuit_start(compiled: Compiled, found: Limits, entry: InputReport, start: float,
                   degrees: bool) -> float:
    """Return a circuit's start in radians (or length units), refused outside every interval.

    ``start`` is in the report's units; an angle is taken any whole number of
    turns away, and a start within :data:`START_SLACK` of an interval's end
    (as the report prints it) at that end.
    """
    name = found.input_name
    angle = compiled.inputs[name].kind == "angle"
    unit = _input_unit(compiled, name, degrees)
    if not math.isfinite(start):
        raise AnalysisError(f"a start must be a finite number, got {start!r}")
    in_degrees = angle and not degrees and looks_like_degrees(start)
    if in_degrees:
        warn_of_degrees(f"analyze: a start of {start:g} "
                        f"{degrees_hint(start, 'degrees=True takes degrees')}")
    to_radians = math.radians if angle and degrees else float
    placed = placed_in(found, to_radians(start), angle, to_radians(START_SLACK))
    if placed is not None:
        return placed[1]
    spans = ", ".join(f"{lo:.6f} to {hi:.6f}{unit}" for lo, hi in entry.intervals)
    hint = "; angles are in radians here (degrees=True takes degrees)" if in_degrees else ""
    raise AnalysisError(f"a start of {start:.12g}{unit}: input {quote(name)} cannot be "
                        f"assembled there (it can from {spans or 'nowhere'}){hint}")


def _which_circuit(compiled: Compiled, name: str, count: int, path: np.ndarray,
                   convert: Callable[[Any], float], degrees: bool) -> str:
    """Say where the analysed circuit runs, of an input assembled in ``count`` intervals.

    The intervals are those of the branches the circuit starts on; past a
    toggle it may run on in an interval of other branches.
    """
    unit = _input_unit(compiled, name, degrees)
    low, high = convert(np.min(path)), convert(np.max(path))
    return (f"input {quote(name)} can be assembled in {count} intervals on the branches it "
            f"starts on: the figures below are of the circuit from {low:.6f} to "
            f"{high:.6f}{unit} (start= in Python or --start on the command line picks "
            "another)")


def _swept_together(compiled: Compiled, motion: Sweep, value_of: Callable[[str], Callable],
                    degrees: bool) -> str:
    """Say that several inputs were swept together along one path, and how."""
    spans = []
    for name, values in motion.inputs.items():
        convert = value_of(name)
        spans.append(f"{quote(name)} from {convert(values[0]):g} to {convert(values[-1]):g}"
                     f"{_input_unit(compiled, name, degrees)}")
    return (f"{len(spans)} inputs swept together over {len(motion)} samples "
            f"({', '.join(spans)}): the figures below are over this path, not over every "
            "combination of their values")


def _whole_turns(compiled: Compiled, motion: Sweep) -> bool:
    """Whether the motion's one input is an angle that ends whole turns (not 0) on."""
    turns = closing_turns(motion.inputs, compiled.angle_inputs)
    return len(compiled.inputs) == 1 and turns is not None and any(turns.values())


def _returning(compiled: Compiled, motion: Sweep, off: Mapping[str, float]) -> dict[str, bool]:
    """Whether each point, and every point it is found from, ends where it began.

    To what each is known to (``off``, see :func:`_known_to`) and the
    rounding of the mechanism's coordinates. Over whole turns of the input,
    what is read off such points only is periodic in it: the part of the
    mechanism it depends on is back in its first configuration.

    Examples
    --------
    >>> from geokin import Construction, sweep
    >>> c = Construction("crank and a pointer at half its speed")
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 3, "theta")
    >>> c.polar("P", "A", 1, "theta / 2")
    >>> c.polar("Q", "P", 1, 0.0)
    >>> _returning(c.compile(), sweep(c, np.linspace(0, 2 * np.pi, 9)), {})
    {'O': True, 'A': True, 'P': False, 'Q': False}
    """
    first, last = np.asarray(motion.valid)[[0, -1]]
    size = max((float(np.nanmax(np.abs(motion[p]))) for p in motion.points), default=0.0)
    back: dict[str, bool] = {}
    for step in compiled.steps:
        node = step.node
        ends = [np.asarray(motion[p])[[0, -1]] for p in node.defines]
        here = bool(first and last) and all(
            np.hypot(*(b - a)) <= off.get(p, 0.0) + ROUNDING * size
            for p, (a, b) in zip(node.defines, ends, strict=True))
        here = here and all(back[p] for p in node.depends_on())
        for point in node.defines:
            back[point] = here
    return back


def _strokes(compiled: Compiled, motion: Sweep, angle: Callable[[Any], float],
             off: Mapping[str, float], back: Mapping[str, bool],
             steps: _Steps | None) -> dict[str, StrokeReport]:
    """Extremes and time ratios of traced coordinates and link angles.

    ``steps`` evaluates the motion again between samples (None for a
    construction with a closure group), shared with the transmission angles.

    Over one turn of an input that turns fully the time ratio is given too.
    Constant outputs (a ground link's angle) are left out, and a link that
    turns fully is reported as turning rather than with extremes. With
    several inputs, over the path of the sweep: extremes only.
    """
    if not compiled.inputs:  # one configuration: nothing moves
        return {}
    name, declared = next(iter(compiled.inputs.items()))
    single = len(compiled.inputs) == 1
    # one turn of the input, either way: through change points too, where the branches
    # swap as the mechanism runs on smoothly
    x = motion.inputs[name]
    turns = bool(single and declared.kind == "angle" and motion.valid.all() and len(x) > 2
                 and abs(abs(x[-1] - x[0]) / (2 * np.pi) - 1) <= ROUNDING
                 and (np.all(np.diff(x) > 0) or np.all(np.diff(x) < 0)))
    # each output's values, whether it is an angle, how to read it off another sweep,
    # and the points it is read from
    outputs: dict[str, tuple[np.ndarray, bool, Callable[[Sweep], np.ndarray],
                             tuple[str, ...]]] = {}
    for point in compiled.traced:
        for axis, coordinate in enumerate("xy"):
            outputs[f"{point}.{coordinate}"] = (motion[point][:, axis], False,
                                                partial(_coordinate, point=point, axis=axis),
                                                (point,))
    positions = slider_positions(motion)
    for block in compiled.sliders:
        outputs[f"{block.name}.position"] = (positions[block.name], False,
                                             partial(_slider, name=block.name),
                                             (block.point, *block.along))
    angles = link_angles(motion)
    # a crank's angle is told in the turn of the input that drives it
    driven: dict[str, np.ndarray] = {}
    for link in compiled.links:
        if set(link.points[:2]) <= compiled.ground:
            continue
        outputs[f"{link.name}.angle"] = (angles[link.name], True, partial(_angle, name=link.name),
                                         link.points[:2])
        for crank in cranks(compiled):
            if {crank.origin, crank.tip} == set(link.points[:2]):
                driven[f"{link.name}.angle"] = motion.inputs[crank.input_name]
                break
    # the extremes of a motion that does not turn fully are placed on the mechanism
    # evaluated again along the steps about an extreme sample (a circuit's samples
    # are too far apart near its limits for a parabola through three), and so are those
    # of a turn through change points, where an output may have a corner
    if turns and not motion.events:
        steps = None  # a smooth turn: the samples about each extreme place it
    smooth = _running_on(motion)
    strokes: dict[str, StrokeReport] = {}
    whole_turns = _whole_turns(compiled, motion)
    for label, (values, is_angle, of, points) in outputs.items():
        if not np.isfinite(values).any():
            continue
        known = sum(off.get(p, 0.0) for p in points)
        if is_angle and known > 0:  # the points' errors across the link, as an angle
            length = np.nanmax(np.hypot(*(motion[points[1]] - motion[points[0]]).T))
            known = known / length if length > 0 else known
        low, high = np.nanmin(values), np.nanmax(values)
        if high - low <= known + ROUNDING * max(abs(high), abs(low), 1.0 if is_angle else 0.0):
            continue  # it does not move, to what it is known to
        # over whole turns of the input, an output read off points that all come back is
        # periodic in it; a link that so ends whole turns on turns fully
        periodic = whole_turns and all(back.get(p, False) for p in points)
        wound = round((values[-1] - values[0]) / (2 * np.pi)) if periodic and is_angle else 0
        if is_angle and (high - low >= 2 * np.pi - ROUNDING or wound != 0):
            strokes[label] = StrokeReport(turns=True)
            continue
        convert = angle if is_angle else float
        if steps is not None:
            low = _placed_extreme(values, -1, steps, of, is_angle)[1]
            high = _placed_extreme(values, 1, steps, of, is_angle)[1]
        else:
            low, high = _extreme(values, -1, smooth), _extreme(values, 1, smooth)
        found = None
        if turns and periodic:  # a time ratio for what goes out and back in a turn
            try:
                found = stroke(values[:-1], motion.inputs[name][:-1])
            except AnalysisError:  # too few assembled samples to locate the extremes
                pass
        if found is None:
            if is_angle:
                low, high = _told_turn(low, high, values, driven.get(label))
            strokes[label] = StrokeReport(False, convert(low), convert(high), convert(high - low))
            continue
        per_turn = _peaks(values[:-1], high - low)
        if steps is None:
            low, high = found.minimum, found.maximum
        if is_angle:
            low, high = _told_turn(low, high, values, driven.get(label))
        strokes[label] = StrokeReport(
            False, convert(low), convert(high), convert(high - low),
            # out and back more than once a turn: no one forward and return stroke
            float(found.time_ratio) if per_turn == 1 else None, per_turn)
    return strokes
