"""Measures of a motion: stroke and time ratio of an output, coupler curves.

The stroke of an output over one turn of its input (:func:`stroke`), the
time ratio of its working and return strokes (:func:`time_ratio`), and
measures of a traced curve (:func:`curve_measures`). Angles are radians.
"""

from __future__ import annotations

import math
from collections.abc import Container, Mapping
from dataclasses import dataclass, field

import numpy as np
import shapely
from numpy.typing import ArrayLike

from ..compat import renamed_keywords
from ..errors import AnalysisError

__all__ = ["Curve", "Stroke", "closing_turns", "curve_measures", "refine_extreme", "stroke",
           "time_ratio"]

# -- stroke and time ratio ----------------------------------------------------------


@dataclass(frozen=True)
class Stroke:
    """Extremes of an output over one turn of a constant-speed input.

    Attributes
    ----------
    minimum, maximum : float
        The output's extremes (refined between samples).
    input_at_min, input_at_max : float
        Where they occur, within the input's first turn.
    stroke : float
        ``maximum - minimum``.
    forward, back : float
        The input travelled (the way it turns) from the minimum to the
        maximum, and from the maximum back to the minimum; they add up to
        one turn.
    time_ratio : float
        ``forward / back``: for a constant input speed, the time of the
        forward stroke (minimum to maximum) over that of the return.
    """

    minimum: float
    maximum: float
    input_at_min: float
    input_at_max: float
    stroke: float
    forward: float
    back: float
    time_ratio: float

    @property
    def quick_return_ratio(self) -> float:
        """Return the slower stroke's time over the faster one's (at least 1)."""
        return max(self.forward, self.back) / min(self.forward, self.back)


def refine_extreme(x: ArrayLike, y: ArrayLike) -> tuple[float, float]:
    """Return an extreme placed between samples: the turning point of their polynomial.

    The polynomial of degree ``len(x) - 1`` through the samples (a parabola
    through three, a quartic through five) is taken about the middle
    sample; its turning point nearest that sample, within one step of it,
    is the extreme. Where there is none (samples that do not turn, or turn
    too far away), the middle sample itself is returned.

    Parameters
    ----------
    x, y : array_like, shape (K,)
        An odd number K >= 3 of samples, the extreme sample in the middle.
        ``x`` need not be evenly spaced; it may be a sample's index.

    Returns
    -------
    (float, float)
        Where the extreme lies, and its value.

    See Also
    --------
    stroke : which places an output's extremes over a turn with it.

    Examples
    --------
    The top of ``1 - (x - 0.3)**2`` from three samples, and of a sine from five
    samples 5 degrees apart:

    >>> x, y = refine_extreme([-1, 0, 1], [-0.69, 0.91, 0.51])
    >>> round(x, 12), round(y, 12)
    (0.3, 1.0)
    >>> x = np.radians([80, 85, 90, 95, 100]) + 0.01
    >>> top, value = refine_extreme(x, np.sin(x))
    >>> abs(top - np.pi / 2) < 1e-7, abs(value - 1) < 1e-9
    (True, True)
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    mid = len(x) // 2
    x0 = x[mid]
    h = max(np.max(np.abs(np.diff(x))), np.finfo(float).tiny)
    poly = np.polynomial.Polynomial.fit((x - x0) / h, y, len(x) - 1, domain=[-1, 1],
                                        window=[-1, 1])
    roots = poly.deriv().roots()
    roots = roots[np.isreal(roots)].real
    roots = roots[np.abs(roots) <= 1.0]
    if roots.size == 0:
        return float(x0), float(y[mid])
    t = roots[np.argmin(np.abs(roots))]
    return float(x0 + t * h), float(poly(t))


def closing_turns(inputs: Mapping[str, np.ndarray], angles: Container[str]
                  ) -> dict[str, int] | None:
    """Return how many whole turns each angle input ends on from its start, if all close.

    A sweep's inputs close when every one ends where it began: an angle
    input (named in ``angles``) any whole number of turns on, to rounding,
    any other exactly. None where one does not, or over one sample.

    Examples
    --------
    >>> closing_turns({"t": np.linspace(0, 4 * np.pi, 9)}, {"t"})
    {'t': 2}
    >>> closing_turns({"t": np.linspace(0, 1, 3), "s": np.ones(3)}, {"t"}) is None
    True
    """
    turns = {}
    for name, values in inputs.items():
        if np.ndim(values) != 1 or len(values) < 2:
            return None
        travel = float(values[-1] - values[0])
        if not math.isfinite(travel):
            return None
        if name in angles:
            turned = travel / (2 * math.pi)
            if abs(turned - round(turned)) > 1e-9 * max(1.0, abs(turned)):
                return None
            turns[name] = round(turned)
        elif travel != 0:
            return None
    return turns


@renamed_keywords(input="input_values")
def stroke(output: ArrayLike, input_values: ArrayLike, *, period: float = 2 * np.pi) -> Stroke:
    """Return the extremes, stroke and time ratio of an output over one input turn.

    Parameters
    ----------
    output : array_like, shape (N,)
        The output at each sample: a point coordinate, a link angle. The
        extremes are refined between samples by a quartic through the five
        samples around each (:func:`refine_extreme`).
    input_values : array_like, shape (N,)
        The input, increasing or decreasing over at least one full ``period``
        (the last sample may repeat the first one turn later): time runs
        along the samples. NaN outputs are left out.
    period : float
        One turn of the input.

    Returns
    -------
    Stroke

    Examples
    --------
    The sine of a crank angle: equal forward and return times.

    >>> t = np.linspace(0, 2 * np.pi, 361)
    >>> s = stroke(np.sin(t), t)
    >>> round(s.stroke, 9), round(s.time_ratio, 9)
    (2.0, 1.0)
    """
    y = np.asarray(output, dtype=float)
    x = np.asarray(input_values, dtype=float)
    if x.shape != y.shape or x.ndim != 1:
        raise AnalysisError("output and input must be one-dimensional arrays of one length")
    steps = np.diff(x)
    backwards = x.size > 1 and bool(np.all(steps < 0))
    if backwards:  # turning the other way: time runs with -x
        x = -x
    elif np.any(steps <= 0):
        raise AnalysisError("the input must increase or decrease from sample to sample")
    keep = x < x[0] + period - 1e-12 * period
    span = x[-1] - x[0]
    step = np.max(np.diff(x)) if len(x) > 1 else np.inf
    if span < period - 1.5 * step:
        raise AnalysisError(f"the input covers {span:g}, less than one turn ({period:g})")
    x, y = x[keep], y[keep]
    ok = np.isfinite(y)
    if ok.sum() < 3:
        raise AnalysisError("fewer than three finite output values")
    n = len(x)

    def extreme(index):
        around = np.arange(index - 2, index + 3)
        wrapped = around % n
        if not ok[wrapped].all():
            return x[index], y[index]
        return refine_extreme(x[wrapped] + period * np.floor_divide(around, n), y[wrapped])

    x_min, y_min = extreme(int(np.nanargmin(y)))
    x_max, y_max = extreme(int(np.nanargmax(y)))
    forward = float((x_max - x_min) % period)
    back = period - forward
    if backwards:
        x_min, x_max = -x_min, -x_max
    return Stroke(float(y_min), float(y_max), float(x_min), float(x_max),
                  float(y_max - y_min), forward, float(back), forward / back)


@renamed_keywords(input="input_values")
def time_ratio(output: ArrayLike, input_values: ArrayLike, *, period: float = 2 * np.pi) -> float:
    """Return the forward over return time of an output over one input turn.

    The forward stroke runs from the output's minimum to its maximum; see
    :func:`stroke`.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 721)
    >>> round(time_ratio(np.sin(t) + 0.2 * np.sin(2 * t), t), 4)
    0.6577
    """
    return stroke(output, input_values, period=period).time_ratio


# -- curve measures -----------------------------------------------------------------------


@dataclass(frozen=True)
class Curve:
    """Measures of a traced curve (see :func:`curve_measures`).

    Attributes
    ----------
    length : float
        Total length of the polyline.
    closed : bool
        Whether it ends where it starts (within the tolerance).
    signed_area : float
        For a closed curve, the shoelace area: positive counter-clockwise;
        lobes traced in opposite senses cancel. NaN for an open curve.
    area : float
        For a closed curve, the area of the regions it encloses, each region
        once (a figure-eight: both lobes). NaN for an open curve.
    bounds : (float, float, float, float)
        ``(xmin, ymin, xmax, ymax)``.
    double_points : ndarray, shape (K, 2)
        Where the curve crosses or touches itself.
    area_tolerance : float
        For a closed curve (NaN for an open one), how far ``area`` may be
        from the area of the smooth curve the
        polyline samples: the areas between each segment and the arc it
        cuts off, about ``turn * length**2 / 12`` a segment, where ``turn``
        is the angle the path turns through across the segment (its turns
        at both ends, halved). A closed path whose area is within it
        encloses nothing the sampling can tell apart from a path run back
        over itself, as a rocker's joint is.
    """

    length: float
    closed: bool
    signed_area: float
    area: float
    bounds: tuple[float, float, float, float]
    double_points: np.ndarray = field(repr=False)
    area_tolerance: float = 0.0

    @property
    def simple(self) -> bool:
        """Return whether the curve has no double point."""
        return len(self.double_points) == 0


def _runs(points):
    ok = np.all(np.isfinite(points), axis=1)
    runs, start = [], None
    for i, good in enumerate(ok):
        if good and start is None:
            start = i
        if not good and start is not None:
            runs.append(points[start:i])
            start = None
    if start is not None:
        runs.append(points[start:])
    return runs


def curve_measures(points: ArrayLike, *, tol: float | None = None) -> Curve:
    """Measure a curve given as a polyline: length, area, bounds, double points.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        The curve's points in order, for example a coupler trace. Rows with
        NaN (invalid samples) split it into pieces; a split curve is open.
    tol : float, optional
        Distance below which the ends count as one point (a closed curve);
        by default ``1e-8`` times the diagonal of the bounding box.

    Returns
    -------
    Curve

    Examples
    --------
    A square, and a figure-eight with its double point at the origin:

    >>> square = [(0, 0), (2, 0), (2, 2), (0, 2), (0, 0)]
    >>> m = curve_measures(square)
    >>> m.length, m.signed_area, m.closed, m.simple
    (8.0, 4.0, True, True)
    >>> t = np.linspace(0, 2 * np.pi, 201)
    >>> eight = np.c_[np.sin(t), np.sin(t) * np.cos(t)]
    >>> m = curve_measures(eight)
    >>> np.round(m.double_points, 9) + 0.0, round(m.signed_area, 9) + 0.0
    (array([[0., 0.]]), 0.0)
    """
    xy = np.asarray(points, dtype=float)
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise AnalysisError(f"points must have shape (N, 2), got {xy.shape}")
    runs = [r for r in _runs(xy) if len(r) >= 2]
    if not runs:
        raise AnalysisError("a curve needs at least two finite points in a row")
    everything = np.concatenate(runs)
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    bounds = (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))
    # measured on the curve brought to about unit size by a power of two, which is
    # exact: lengths and areas of a tiny or huge curve would underflow or overflow
    size = float(np.max(np.abs(everything)))
    unit = 2.0 ** -math.frexp(size)[1] if 0 < size < np.inf else 1.0
    runs = [r * unit for r in runs]
    if tol is None:
        tol = 1e-8 * float(np.hypot(*(hi - lo))) * unit
    else:
        tol = tol * unit
    closed = len(runs) == 1 and len(runs[0]) >= 4 and \
        float(np.hypot(*(runs[0][-1] - runs[0][0]))) <= tol
    if closed:
        runs[0] = runs[0].copy()
        runs[0][-1] = runs[0][0]
    lines = [shapely.LineString(r) for r in runs]
    length = float(sum(line.length for line in lines))
    signed = area = np.nan
    if closed:
        ring = runs[0]
        x, y = ring[:, 0], ring[:, 1]
        signed = 0.5 * float(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))
    noded = shapely.unary_union(shapely.MultiLineString(lines))
    if closed:
        faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(noded)))
        area = float(sum(f.area for f in faces))
    segments = [_segments(run, closed) for run in runs]
    least_angle = min(max(GRAZING_ANGLE, 3 * _turn_per_sample(segments)), MOST_ANGLE)
    return Curve(length / unit, closed, _unscaled_area(signed, unit),
                 _unscaled_area(area, unit), bounds,
                 _double_points(noded, segments, least_angle) / unit,
                 _unscaled_area(_chord_areas(segments), unit) if closed else np.nan)


def _chord_areas(segments) -> float:
    """Return the sum of the areas between each segment and the arc it stands for.

    ``segments`` are each run's :func:`_segments`.

    An arc of curvature k cut off by a chord of length c encloses about
    k c**3 / 12 with it; k is taken as the path's turn across the segment
    (half its turns at both ends) over c. Over a circle sampled evenly this
    is the area the inscribed polygon misses, to leading order.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 101)
    >>> ring = np.c_[np.cos(t), np.sin(t)]
    >>> missed = np.pi - 50 * np.sin(2 * np.pi / 100)  # by the inscribed 100-gon
    >>> round(float(_chord_areas([_segments(ring, True)]) / missed), 3)
    1.0
    """
    total = 0.0
    for _, steps, turns in segments:
        chords = np.hypot(steps[:, 0], steps[:, 1])
        total += float(np.sum(0.5 * turns.sum(axis=1) * chords * chords)) / 12
    return total


def _segments(run: np.ndarray, closed: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return a run's segments of nonzero length: starts, steps and the turns at their ends.

    The turn at an end is the angle between the segment and the next one
    there (radians, 0 to pi); none at an open run's ends.
    """
    steps = np.diff(run, axis=0)
    moving = np.hypot(steps[:, 0], steps[:, 1]) > 0
    starts, steps = run[:-1][moving], steps[moving]
    turns = np.zeros((len(steps), 2))
    if len(steps) < 2:
        return starts, steps, turns
    ahead = np.roll(steps, -1, axis=0) if closed else steps[1:]
    a = steps[:len(ahead)]
    at_end = np.abs(np.arctan2(a[:, 0] * ahead[:, 1] - a[:, 1] * ahead[:, 0],
                               a[:, 0] * ahead[:, 0] + a[:, 1] * ahead[:, 1]))
    turns[:len(at_end), 1] = at_end
    turns[1:, 0] = at_end[:len(steps) - 1]
    if closed:  # the path turns at its joined ends too
        turns[0, 0] = at_end[-1]
    return starts, steps, turns


def _unscaled_area(area: float, unit: float) -> float:
    """Return an area measured at ``unit`` times the size, at the true size.

    NaN where that lies beyond the normal range of floats (a curve of size
    1e-200 encloses some 1e-400): never a rounded zero or a subnormal value.
    """
    value = area / unit / unit
    if area != 0 and not (np.finfo(float).tiny <= abs(value) < np.inf):
        return np.nan
    return value


GRAZING_ANGLE = np.radians(2.0)
"""The least angle between pieces meeting at a node that makes a crossing.

Where a path runs back over itself, as a rocker's joint does, two polylines
of the same arc sampled differently cross each other at angles up to about
the turn of the path between samples; so the angle used is the largest of
this, three times the path's median turn per sample and 1.5 times its turn
at the ends of the segments crossing (:data:`MOST_ANGLE` at most)."""


MOST_ANGLE = np.radians(20.0)
"""The largest angle a crossing needs, however much the path turns between samples."""


def _turn_per_sample(segments) -> float:
    """Return the median angle the polyline turns through from one segment to the next.

    ``segments`` are each run's :func:`_segments`; the turn where a closed
    run's ends join is left out.
    """
    turns = [part[2][:-1, 1] for part in segments if len(part[1]) >= 2]
    return float(np.median(np.concatenate(turns))) if turns else 0.0


def _segments_near(points: np.ndarray, starts: np.ndarray, steps: np.ndarray,
                   reach: float) -> tuple[np.ndarray, np.ndarray]:
    """Return every pair of a point and a segment within ``reach`` of it, by the point.

    Each segment is tried against the points its span along x, widened by
    ``reach``, holds (found in the points sorted by x); no geometry is made
    of the segments.

    Examples
    --------
    >>> at, through = _segments_near(np.array([[1.0, 0.0], [5.0, 5.0]]),
    ...                              np.array([[0.0, 0.0], [1.0, -1.0]]),
    ...                              np.array([[2.0, 0.0], [0.0, 2.0]]), 1e-9)
    >>> at.tolist(), through.tolist()
    ([0, 0], [0, 1])
    """
    by_x = np.argsort(points[:, 0], kind="stable")
    xs = points[by_x, 0]
    ends = starts + steps
    first = np.searchsorted(xs, np.minimum(starts[:, 0], ends[:, 0]) - reach, side="left")
    count = np.searchsorted(xs, np.maximum(starts[:, 0], ends[:, 0]) + reach,
                            side="right") - first
    segment = np.repeat(np.arange(len(starts)), count)
    within = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    point = by_x[np.repeat(first, count) + within]
    # the distance from each point to the nearest point of its segment
    offset = points[point] - starts[segment]
    step = steps[segment]
    along = np.clip(np.einsum("ij,ij->i", offset, step) / np.einsum("ij,ij->i", step, step),
                    0.0, 1.0)
    gap = offset - along[:, None] * step
    near = np.hypot(gap[:, 0], gap[:, 1]) <= reach
    order = np.lexsort((segment[near], point[near]))
    return point[near][order], segment[near][order]


def _double_points(noded, segments, least_angle=GRAZING_ANGLE) -> np.ndarray:
    """Nodes where three or more pieces of the noded curve end, crossing each other.

    A crossing ends four pieces; an end of an open curve ends one, the
    joined ends of a closed curve two. How steeply the curve crosses itself
    at a node is told by the segments through it, each run's :func:`_segments`
    (the pieces noding leaves there may be too short to have a direction): more than
    ``least_angle``, and more than 1.5 times the turn of the path at the
    ends of those segments, for two chords of one arc, as where a path runs
    back over itself sampled differently, cross at up to the arc's turn
    over a segment.
    """
    ends: dict[tuple[float, float], int] = {}
    for part in shapely.get_parts(noded):
        coords = shapely.get_coordinates(part)
        if len(coords) < 2:  # a path that never moves has no pieces to cross
            continue
        for end in (coords[0], coords[-1]):
            key = (float(end[0]), float(end[1]))
            ends[key] = ends.get(key, 0) + 1
    nodes = [key for key, count in ends.items() if count >= 3]
    if not nodes:
        return np.empty((0, 2))
    starts = np.concatenate([part[0] for part in segments])
    steps = np.concatenate([part[1] for part in segments])
    turns = np.concatenate([part[2] for part in segments]).max(axis=1)
    units = steps / np.hypot(steps[:, 0], steps[:, 1])[:, None]
    # a node lies on its segments to a billionth of the curve's extent (the curve is
    # scaled to about 1 here: never below the rounding of its coordinates)
    extent = float(np.ptp(starts, axis=0).max(initial=0.0))
    reach = max(1e-9 * extent, 64 * np.finfo(float).eps)
    at, through = _segments_near(np.array(nodes, dtype=float).reshape(-1, 2), starts, steps,
                                 reach)
    # every two segments through a node, and the steepest crossing at each node
    size = np.bincount(at, minlength=len(nodes))
    first = np.cumsum(size) - size
    count = size[at]  # the segments through the node of each pair, for each pair
    one = np.repeat(np.arange(len(at)), count)
    other = first[at[one]] + np.arange(len(one)) - np.repeat(np.cumsum(count) - count, count)
    u, v = units[through[one]], units[through[other]]
    steepest = np.zeros(len(nodes))
    np.maximum.at(steepest, at[one], np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]))
    turning = np.zeros(len(nodes))
    np.maximum.at(turning, at, turns[through])
    least = np.minimum(np.maximum(least_angle, 1.5 * turning), MOST_ANGLE)
    found = np.array(nodes, dtype=float).reshape(-1, 2)[steepest > np.sin(least)]
    return found[np.lexsort((found[:, 1], found[:, 0]))]
