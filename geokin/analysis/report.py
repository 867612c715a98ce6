"""One report of everything geokin can say about a construction.

:func:`analyze` gathers the degrees of freedom, the motion limits of each
input, the Grashof class of every four-bar loop it recognises, the
transmission angle at every circle-circle node, strokes and time ratios of
the traced points and the declared links, and measures of the traced
curves. It is what ``geokin analyze`` prints.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..circuits import circuit, describe_limit, limits
from ..construction import Compiled, Construction, as_compiled
from ..engine import sweep
from ..errors import AnalysisError
from ..kinematics import link_angles
from ..nodes import CircleCircle
from ..results import Sweep
from .fourbar import grashof, transmission_angles
from .measures import curve_measures, refine_extreme, stroke
from .mobility import cranks, degrees_of_freedom

__all__ = ["analyze"]


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


def analyze(construction: Construction | Compiled, *, degrees: bool = False) -> dict[str, Any]:
    """Analyse a construction and return a report as plain data (JSON-ready).

    The motion analysed is the whole circuit of the first input (one turn if
    it turns fully; otherwise from limit to limit on both sides of each
    toggle, see :func:`geokin.circuit`).

    Parameters
    ----------
    construction : Construction or Compiled
    degrees : bool
        Give angles (input values of angle inputs, transmission angles, link
        swings) in degrees instead of radians.

    Returns
    -------
    dict
        ``dof``, ``mobility``, ``inputs.<name>.intervals`` (each ``[low, high]``)
        with ``full_turn`` and ``limits``, ``four_bars``,
        ``transmission_angles``, ``strokes`` and ``curves``.

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
    >>> [round(v, 4) for v in report["inputs"]["theta2"]["intervals"][0]]
    [-132.1774, 132.1774]
    >>> report["four_bars"][0]["class"]
    'triple-rocker RRR1'
    """
    compiled = as_compiled(construction)
    angle = np.degrees if degrees else (lambda v: v)
    mobility = degrees_of_freedom(compiled)
    # JSON-ready: each key's value has its own shape
    report: dict[str, Any] = {
        "construction": compiled.name,
        "angle_unit": "deg" if degrees else "rad",
        "dof": mobility.dof,
        "mobility": {
            "moving_links": mobility.moving_links, "revolute_joints": mobility.revolute_joints,
            "prismatic_pairs": mobility.prismatic_pairs, "lower_pairs": mobility.lower_pairs,
            "higher_pairs": mobility.higher_pairs, "inputs": mobility.inputs,
            "matches_inputs": mobility.matches_inputs, "formula": str(mobility),
        },
        "inputs": {},
    }
    for name, declared in compiled.inputs.items():
        convert = angle if declared.kind == "angle" else (lambda v: v)
        found = limits(compiled, name)
        report["inputs"][name] = {
            "kind": declared.kind,
            "full_turn": found.full_turn,
            "intervals": [[float(convert(lo)), float(convert(hi))]
                          for lo, hi in found.as_values()],
            "limits": [{"value": float(convert(end.value)), "node": end.node, "kind": end.kind,
                        "meaning": describe_limit(end)}
                       for pair in found.intervals for end in pair if end.kind != "range"],
        }
    if len(compiled.inputs) == 1:
        motion = circuit(compiled)
    else:
        motion = sweep(compiled)
    report["warnings"] = []
    if not motion.valid.all():
        i = int(np.flatnonzero(~motion.valid)[0])
        report["warnings"].append(
            f"{int((~motion.valid).sum())} of {len(motion)} samples of the "
            f"{'circuit' if len(compiled.inputs) == 1 else 'sweep'} cannot be assembled "
            f"(first at sample {i}: node {motion.failed_node[i]!r}: "
            f"{motion.failure_reason[i]}); the figures below come from the others")
    if not motion.valid.any():
        return report
    report["four_bars"] = []
    for node, points, lengths in _four_bars(compiled, motion):
        try:
            g = grashof(lengths["ground"], lengths["input"], lengths["coupler"],
                        lengths["output"])
        except AnalysisError:  # a link of zero length: no four-bar to classify
            continue
        report["four_bars"].append({"node": node, "points": list(points), **lengths,
                                    "class": g.kind, "code": g.code, "grashof": g.grashof,
                                    "turning": list(g.turning)})
    def inputs_at(values):
        return {k: float(angle(v) if compiled.inputs[k].kind == "angle" else v)
                for k, v in values.items()}

    def between_links(t):
        # with declared links, the angle must be between two of them, not a helper line
        return not compiled.links or all(
            any({t.node, centre} <= set(link.points) for link in compiled.links)
            for centre in t.centers)

    report["transmission_angles"] = {
        node: {"min": float(angle(t.minimum)), "max": float(angle(t.maximum)),
               "at_min": inputs_at(t.at_minimum), "at_max": inputs_at(t.at_maximum)}
        for node, t in transmission_angles(motion).items() if between_links(t)}
    report["strokes"] = _strokes(compiled, motion, angle)
    report["curves"] = {}
    for point in compiled.traced:
        try:
            curve = curve_measures(motion[point])
        except AnalysisError:  # fewer than two assembled samples in a row
            continue
        report["curves"][point] = {
            "length": curve.length, "closed": curve.closed,
            # none where the curve is open, or its area is beyond the range of floats
            "area": curve.area if np.isfinite(curve.area) else None,
            "bounds": list(curve.bounds),
            "double_points": curve.double_points.tolist()}
    return report


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


def _strokes(compiled, motion: Sweep, angle) -> dict:
    """Extremes and time ratios of traced coordinates and link angles.

    Over one turn of an input that turns fully the time ratio is given too.
    Constant outputs (a ground link's angle) are left out, and a link that
    turns fully is reported as turning rather than with extremes.
    """
    if len(compiled.inputs) != 1:
        return {}
    name, declared = next(iter(compiled.inputs.items()))
    turns = declared.kind == "angle" and not motion.events and motion.valid.all()
    outputs = {}
    for point in compiled.traced:
        outputs[f"{point}.x"] = (motion[point][:, 0], False)
        outputs[f"{point}.y"] = (motion[point][:, 1], False)
    for slider in compiled.sliders:
        # the block's position along its guide, from the guide's first point
        a, b = slider.along
        guide = motion[b] - motion[a]
        with np.errstate(all="ignore"):
            unit = guide / np.hypot(*guide.T)[:, None]
        outputs[f"{slider.name}.position"] = (
            np.einsum("ij,ij->i", motion[slider.point] - motion[a], unit), False)
    angles = link_angles(motion)
    for link in compiled.links:
        if set(link.points[:2]) <= compiled.ground:
            continue
        outputs[f"{link.name}.angle"] = (angles[link.name], True)
    # where the input runs on through a sample, on the same branches
    step = np.diff(motion.inputs[name])
    smooth = np.zeros(len(motion), dtype=bool)
    smooth[1:-1] = step[:-1] * step[1:] > 0
    for event in motion.events:
        smooth[max(event.index - 1, 0):event.index + 1] = False
    strokes: dict[str, dict[str, Any]] = {}
    for label, (values, is_angle) in outputs.items():
        if not np.isfinite(values).any():
            continue
        low, high = np.nanmin(values), np.nanmax(values)
        if high - low <= 1e-9 * max(abs(high), abs(low)):
            continue  # it does not move (to rounding, at any scale)
        if is_angle and high - low >= 2 * np.pi - 1e-9:
            strokes[label] = {"turns": True}
            continue
        convert = angle if is_angle else (lambda v: v)
        low, high = _extreme(values, -1, smooth), _extreme(values, 1, smooth)
        entry: dict[str, Any] = {
            "turns": False, "min": float(convert(low)), "max": float(convert(high)),
            "stroke": float(convert(high - low)), "time_ratio": None}
        if turns:
            try:
                s = stroke(values[:-1], motion.inputs[name][:-1])
            except AnalysisError:  # too few assembled samples to locate the extremes
                strokes[label] = entry
                continue
            entry.update(min=float(convert(s.minimum)), max=float(convert(s.maximum)),
                         stroke=float(convert(s.stroke)), time_ratio=float(s.time_ratio))
            entry["strokes_per_turn"] = _peaks(values[:-1], high - low)
            if entry["strokes_per_turn"] > 1:
                # out and back more than once a turn: no one forward and return stroke
                entry["time_ratio"] = None
        strokes[label] = entry
    return strokes
