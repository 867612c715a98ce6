"""Vectorized intersection primitives: both roots and a validity mask.

Every function here is pure and elementwise. Points are arrays whose last
axis has length 2 (x, y); every other argument broadcasts against the
leading axes of the points. An element that has no solution, or whose input
is degenerate (coincident centres, zero-length direction, parallel lines,
negative or NaN radius), gives NaN and ``valid=False`` for that element; no
element ever raises.

Root order
----------
``circle_circle``
    ``points[..., 0, :]`` lies to the *left* of the directed line from the
    first centre to the second, ``points[..., 1, :]`` to the *right*.
``line_circle``, ``segment_circle``, ``ray_circle``
    Roots are ordered along the direction of the line, from ``start`` to
    ``through``: ``points[..., 0, :]`` comes *first*, ``points[..., 1, :]``
    *second*. The parameter ``t`` of a point ``start + t * (through - start)``
    decides validity: any ``t`` for a line, ``t >= 0`` for a ray, and
    ``0 <= t <= 1`` for a segment (with a relative tolerance of 1e-9).

Tangency
--------
A pair of curves counts as tangent, giving one double root (both roots
equal), when they miss each other by no more than ``TANGENCY_RTOL`` times
the scale of the inputs (the largest of the distances and radii involved):
two circles when ``d <= r1 + r2 + tol`` and ``d >= |r1 - r2| - tol`` for
centres ``d`` apart, a line and a circle when the line passes within
``r + tol`` of the centre. The miss is measured as a distance, not through
the squared half-chord, so the tolerance means the same for a small circle
as for a large one. Exactly tangent inputs in floating point therefore give
the double root rather than NaN, and every double root lies within
``TANGENCY_RTOL`` of the scale of both curves.

Scale
-----
Every function works relative to the size of each configuration, so a
mechanism 1e200 or 1e-200 times larger gives the same roots, as many times
larger, and the same validity: squares that would overflow or go subnormal
are taken on coordinates divided by a power of two near the configuration's
size. Sizes within :data:`SCALE_RANGE` are answered right to rounding.

Plain Python floats behave as arrays of one element: a degenerate
configuration of fixed points gives NaN as an array does, never
``ZeroDivisionError``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

import numpy as np

__all__ = [
    "SCALE_RANGE",
    "TANGENCY_RTOL",
    "circle_circle",
    "cos_sin",
    "line_circle",
    "line_line",
    "local_point",
    "nearby_rows",
    "point_along",
    "polar_point",
    "ray_circle",
    "relative_point",
    "segment_circle",
]

TANGENCY_RTOL = 1e-12
"""Curves that miss each other by at most this times the scale touch."""

PARAMETER_RTOL = 1e-9
"""Tolerance on the line parameter ``t`` at the ends of rays and segments."""

PARALLEL_RTOL = 1e-12
"""Lines whose directions' cross product is below this (relative) are parallel."""

DEGENERATE_RTOL = 1e-12
"""Centres closer than this times the scale count as coincident, and a line
through two points closer than this times the scale has no direction."""


def _xy(points):
    points = np.asarray(points, dtype=float)
    return points[..., 0], points[..., 1]


def _stack_roots(x0, y0, x1, y1):
    """Stack two roots into an array of shape (..., 2, 2)."""
    first = np.stack(np.broadcast_arrays(x0, y0), axis=-1)
    second = np.stack(np.broadcast_arrays(x1, y1), axis=-1)
    return np.stack([first, second], axis=-2)


# -- cosine and sine of angles that come in rows of nearby values --------------
#
# NumPy's cosine and sine of float64 cost some fifty multiplications each. The
# finite differences of kinematics evaluate a construction at a few nearby
# inputs of every sample, stacked as rows: there the first row's cosine and
# sine are computed, and the other rows' follow from them by the angle-addition
# formulas with series for the small differences, to a few units in the last
# place.

_NEARBY_ROWS: ContextVar[tuple[int, int]] = ContextVar("nearby_rows", default=(1, 0))

NEARBY = 1e-3
"""The largest difference from the first row's angles (radians) for which the
other rows are found by angle addition: the series are then exact to rounding
(the perturbations of kinematics are a few times 2e-4 apart)."""


@contextmanager
def nearby_rows(rows: int, length: int) -> Iterator[None]:
    """Let :func:`cos_sin` take arrays of ``rows * length`` angles as rows of nearby values.

    Only arrays of exactly that size are taken so: an evaluation cut into
    other pieces computes every angle in full, and a sample's cosine never
    depends on how the samples were cut.

    Examples
    --------
    >>> angles = np.concatenate([np.linspace(0, 6, 100) + k * 2e-4 for k in range(3)])
    >>> with nearby_rows(3, 100):
    ...     c, s = cos_sin(angles)
    >>> bool(np.allclose(c, np.cos(angles), rtol=0, atol=4e-16))
    True
    """
    token = _NEARBY_ROWS.set((rows, length))
    try:
        yield
    finally:
        _NEARBY_ROWS.reset(token)


def cos_sin(angle):
    """Return the cosine and the sine of ``angle`` (an array or a number).

    Inside :func:`nearby_rows` an array whose rows differ from the first by
    at most :data:`NEARBY` has only its first row's computed in full.

    Examples
    --------
    >>> [float(v) for v in cos_sin(0.0)]
    [1.0, 0.0]
    """
    if type(angle) is float and math.isfinite(angle):
        return math.cos(angle), math.sin(angle)  # numpy's are slow on one number
    rows, length = _NEARBY_ROWS.get()
    if rows > 1 and type(angle) is np.ndarray and angle.shape == (rows * length,):
        table = angle.reshape(rows, -1)
        first, delta = table[0], table[1:] - table[0]
        # NaN fails the test, and takes the full way
        if np.maximum.reduce(np.abs(delta), axis=None) <= NEARBY:
            c0, s0 = np.cos(first), np.sin(first)
            square = delta * delta
            # their first neglected terms, delta**7 / 7! and delta**6 / 6!, are below
            # rounding for |delta| <= NEARBY
            sin_delta = 1.0 - square / 20.0
            sin_delta *= square / -6.0
            sin_delta += 1.0
            sin_delta *= delta
            cos_delta = 1.0 - square / 12.0
            cos_delta *= square / -2.0
            cos_delta += 1.0
            c, s = np.empty_like(table), np.empty_like(table)
            c[0], s[0] = c0, s0
            np.multiply(c0, cos_delta, out=c[1:])
            c[1:] -= s0 * sin_delta
            np.multiply(s0, cos_delta, out=s[1:])
            s[1:] += c0 * sin_delta
            return c.reshape(-1), s.reshape(-1)
    return np.cos(angle), np.sin(angle)


# -- kernels on separate coordinate arrays: the sweep calls these directly ----
#
# Each kernel first computes in plain floating point, then checks on one
# quantity it computed anyway (a scale of the configuration) whether some
# element lies outside the window where no square overflows or goes subnormal.
# Such elements, and only they, are computed again on their coordinates
# relative to the first point, divided by a power of two near their own size:
# exact scaling, so the answer is the one the same formulas give to a
# configuration of size about 1. The kernels thus work relative to each
# configuration's own size, whatever it is (see ``SCALE_RANGE``), at the cost
# of two reductions on the usual path.
#
# A first difference of coordinates that is a Python number becomes a numpy
# scalar, and with it every quantity a kernel divides by, so a degenerate
# element divides by zero the numpy way (inf or NaN) rather than raising
# ZeroDivisionError: a scalar behaves as an array of one element. Arithmetic
# on the other Python floats (radii, distances) stays as it is, being faster.

SCALE_RANGE = (1e-290, 1e290)
"""Sizes of a configuration (its largest distance or radius) that the kernels
answer right to rounding, working relative to that size. Beyond, coordinates
are subnormal or their differences overflow; where a difference overflows,
the answer is NaN, never a wrong number."""

_CC_WINDOW = (1e-130, 1e130)  # circle_circle: scale, whose square must be normal
_LC_WINDOW = (1e-140, 1e140)  # line_circle: squared length, and squared scale below
_LL_WINDOW = (1e-140, 1e140)  # line_line: squared lengths, whose product must be normal
_RP_WINDOW = (1e-280, 1e280)  # relative_point, local_point: squared length


_PLAIN = (float, int)
"""Python number types, turned into numpy scalars where a kernel divides them."""


ARGS_BELOW = 8192
"""Arrays up to this size have their extremes found by ``argmin`` and ``argmax``
(:func:`least_element`, :func:`largest_element`)."""


def least_element(array: np.ndarray) -> float:
    """Return the least element of a non-empty array, NaN if it holds one.

    For a float array, the value ``np.minimum.reduce`` gives over the whole
    array (but for the sign of a zero), as a Python number. On short arrays
    it is found by ``argmin``, which takes the first NaN as the least, in a
    third of the time of a reduction on a few hundred elements; on long
    ones, where ``argmin`` is slower per element, by the reduction.

    Examples
    --------
    >>> least_element(np.array([[3.0, -1.0], [2.0, 5.0]]))
    -1.0
    >>> least_element(np.array([3.0, np.nan, 5.0]))
    nan
    """
    if array.size <= ARGS_BELOW:
        return array.item(array.argmin())
    return float(np.minimum.reduce(array, axis=None))


def largest_element(array: np.ndarray) -> float:
    """Return the largest element of a non-empty array, NaN if it holds one.

    See :func:`least_element`.

    Examples
    --------
    >>> largest_element(np.array([[3.0, -1.0], [2.0, 5.0]]))
    5.0
    >>> largest_element(np.array([3.0, np.nan, 5.0]))
    nan
    """
    if array.size <= ARGS_BELOW:
        return array.item(array.argmax())
    return float(np.maximum.reduce(array, axis=None))


def extremes(array: np.ndarray) -> tuple[float, float]:
    """Return :func:`least_element` and :func:`largest_element` of an array.

    Examples
    --------
    >>> extremes(np.array([3.0, np.nan, 5.0]))
    (nan, nan)
    """
    return least_element(array), largest_element(array)


def _within(quantity, window) -> bool:
    """Whether every non-NaN element of ``quantity`` lies inside ``window``.

    A window ``(None, high)`` has no lower end.
    """
    if type(quantity) is np.ndarray and quantity.ndim:
        if quantity.size == 0:
            return True
        low, high = extremes(quantity)
        if high != high:  # a NaN: the other elements decide
            low, high = np.fmin.reduce(quantity, axis=None), np.fmax.reduce(quantity, axis=None)
    else:
        low = high = quantity
    return not ((window[0] is not None and low < window[0]) or high > window[1])


def _outside(quantity, window, shape):
    """Return the mask, broadcast to ``shape``, of elements outside ``window``."""
    if window[0] is None:
        return np.broadcast_to(quantity > window[1], shape)
    return np.broadcast_to((quantity < window[0]) | (quantity > window[1]), shape)


def _power_of_two(*magnitudes):
    """Return a power of two within a factor 2 below the largest magnitude, elementwise.

    Dividing by it is exact and brings the largest magnitude into [1, 2);
    it is 0.5 where every magnitude is zero, finite for the largest floats.
    """
    largest = np.abs(magnitudes[0])
    for m in magnitudes[1:]:
        largest = np.maximum(largest, np.abs(m))
    return np.ldexp(1.0, np.frexp(largest)[1] - 1)


def _patch(outputs, mask, shape, redo, *args):
    """Replace the masked elements of ``outputs`` with ``redo`` of the masked ``args``."""
    if not shape:
        return redo(*args)
    picked = [np.broadcast_to(a, shape)[mask] for a in args]
    fresh = redo(*picked)
    patched = []
    for out, new in zip(outputs, fresh, strict=True):
        out = np.array(np.broadcast_to(out, shape))
        out[mask] = new
        patched.append(out)
    return tuple(patched)


def _guarded(kernel, rescaled, windows, *args):
    """Run ``kernel``, and redo with ``rescaled`` the elements it cannot be trusted on.

    The kernel returns its outputs and the quantities to check, one per
    window, in the order given (``None`` for one it has found within its
    window already): the elements where one leaves its window are computed
    again by ``rescaled`` (the same computation on inputs scaled by a power
    of two). The common case, everything within, costs a reduction or two.
    """
    outputs, *checked = kernel(*args)
    if len(checked) == 1:  # the commonest: one quantity, unrolled
        if checked[0] is None or _within(checked[0], windows[0]):
            return outputs
    else:
        # a loop, not all() of a generator: this runs for most nodes of every sweep
        for q, w in zip(checked, windows, strict=True):
            if q is not None and not _within(q, w):
                break
        else:
            return outputs
    shape = np.shape(outputs[0])
    mask = np.zeros(shape, dtype=bool)
    for q, w in zip(checked, windows, strict=True):
        if q is not None:
            mask |= _outside(q, w, shape)
    return _patch(outputs, mask, shape, rescaled, *args)


def _circle_circle(x1, y1, dx, dy, r1, r2):
    """Compute :func:`circle_circle_xy`; also return the scale to check the result on.

    Where the circles meet at every element and none is degenerate (the
    common case), the masks are skipped: each test is monotone in the
    distance of the centres, so its least and largest value decide it for
    all, exactly as elementwise; so do the scale's, which is then found
    within its window here and given as None.
    """
    d2 = dx * dx
    d2 += dy * dy
    # the foot of the chord is c1 + k * (c2 - c1); coincident centres give inf or NaN
    k = 0.5 * (r1 - r2) * (r1 + r2) / d2
    k += 0.5
    # in the memory of the squares: a fresh array of many samples costs more to fault
    # in than to compute
    d = np.sqrt(d2, out=d2) if type(d2) is np.ndarray else np.sqrt(d2)
    m = k * d
    half_chord_sq = r1 - m
    m += r1
    half_chord_sq *= m
    # radii given as numbers (NaN excepted, which np.maximum spreads): no numpy call
    plain = type(r1) is float and type(r2) is float and r1 == r1 and r2 == r2
    largest = max(abs(r1), abs(r2)) if plain else np.maximum(np.abs(r1), np.abs(r2))
    # NaN in a reduction fails every test below, and takes the masked way
    fits = False
    if (type(d) is np.ndarray and d.ndim
            and (r1 >= 0 and r2 >= 0 if plain else _nonnegative(r1) and _nonnegative(r2))):
        if plain or np.ndim(largest) == 0:
            low, high = extremes(d)
            least, most = max(low, largest), max(high, largest)  # of the scale
            fits = bool(_apart(low, largest) and _meet(low, high, r1, r2, least, most))
        elif np.ndim(largest) == np.ndim(d) and np.shape(largest)[-1] == 1:
            # radii constant along each row (design variants): row by row
            low = np.minimum.reduce(d, axis=-1, keepdims=True)
            high = np.maximum.reduce(d, axis=-1, keepdims=True)
            least, most = np.maximum(low, largest), np.maximum(high, largest)
            fits = bool(np.all(_apart(low, largest) & _meet(low, high, r1, r2, least, most)))
            least, most = np.minimum.reduce(least, axis=None), np.maximum.reduce(most, axis=None)
    if fits and _CC_WINDOW[0] <= least and most <= _CC_WINDOW[1]:
        scale = np.maximum(d, largest, out=m) if m.shape == d.shape else np.maximum(d, largest)
        margin = np.divide(half_chord_sq, np.multiply(scale, scale, out=scale))
        h_over_d = np.sqrt(np.maximum(half_chord_sq, 0.0, out=half_chord_sq), out=half_chord_sq)
        h_over_d /= d
        return (*_roots(x1, y1, dx, dy, k, h_over_d), margin), None
    scale = np.maximum(d, largest)
    margin = np.where(_apart(d, scale), half_chord_sq / (scale * scale), np.nan)
    if not (_nonnegative(r1) and _nonnegative(r2)):
        margin = np.where((r1 >= 0) & (r2 >= 0), margin, np.nan)
    # decide whether the circles meet on the distances themselves: accurate to
    # rounding of the scale, however small one circle is
    meet = _meet(d, d, r1, r2, scale, scale) & ~np.isnan(margin)
    h_over_d = np.sqrt(np.where(meet, np.maximum(half_chord_sq, 0.0), np.nan)) / d
    return (*_roots(x1, y1, dx, dy, k, h_over_d), margin), scale


def _apart(d, scale):
    """Whether centres at a distance ``d`` are apart (not coincident) at this scale."""
    return d > DEGENERATE_RTOL * scale


def _meet(low, high, r1, r2, least, most):
    """Whether circles of radii ``r1``, ``r2`` meet with centres ``low`` to ``high`` apart.

    To the tolerance of the scale ``max(d, largest)`` at each distance ``d``,
    which is ``least`` at ``low`` and ``most`` at ``high``; elementwise.
    """
    return ((high <= r1 + r2 + TANGENCY_RTOL * most)
            & (low >= abs(r1 - r2) - TANGENCY_RTOL * least))


def _roots(x1, y1, dx, dy, k, h_over_d):
    """Return the left and right roots from the foot of the chord and its half length.

    ``k`` and ``h_over_d`` are the caller's own temporaries: where they are
    arrays of the roots' shape, the roots are computed in their memory.
    """
    fy = k * dy
    fy += y1
    # the left normal of (dx, dy) is (-dy, dx)
    ex = h_over_d * dy
    if not (type(k) is np.ndarray and type(h_over_d) is np.ndarray
            and k.shape == h_over_d.shape == fy.shape):
        fx = k * dx
        fx += x1
        ey = h_over_d * dx
        return fx - ex, fy + ey, fx + ex, fy - ey
    fx = np.multiply(k, dx, out=k)
    fx += x1
    ey = np.multiply(h_over_d, dx, out=h_over_d)
    left_x = fx - ex
    fx += ex  # the right root's x
    left_y = np.add(fy, ey, out=ex)
    fy -= ey  # the right root's y
    return left_x, left_y, fx, fy


def _circle_circle_rescaled(x1, y1, dx, dy, r1, r2):
    s = _power_of_two(dx, dy, r1, r2)
    (xl, yl, xr, yr, margin), _ = _circle_circle(0.0, 0.0, dx / s, dy / s, r1 / s, r2 / s)
    return x1 + xl * s, y1 + yl * s, x1 + xr * s, y1 + yr * s, margin


def circle_circle_xy(x1, y1, r1, x2, y2, r2):
    """Kernel of :func:`circle_circle` on coordinate arrays.

    Kernels leave floating-point warnings to the caller (wrap calls in
    ``np.errstate``): degenerate elements give NaN or inf on the way.
    Python floats behave as arrays of one element: nothing raises.

    Returns
    -------
    xl, yl, xr, yr : ndarray
        The left and right roots (NaN where there are none).
    margin : ndarray
        The squared half-chord divided by the squared scale: positive for two
        roots, zero at tangency, negative where the circles miss. NaN for
        degenerate input. Smooth in the inputs, so a root finder can locate
        the limits of motion on it.

    Examples
    --------
    >>> xl, yl, xr, yr, margin = circle_circle_xy(0.0, 0.0, 5.0, 8.0, 0.0, 5.0)
    >>> float(xl), float(yl), float(xr), float(yr), float(margin)
    (4.0, 3.0, 4.0, -3.0, 0.140625)

    Coincident centres are degenerate, not an error, for plain floats too:

    >>> with np.errstate(all="ignore"):
    ...     [float(v) for v in circle_circle_xy(1.0, 1.0, 2.0, 1.0, 1.0, 2.0)]
    [nan, nan, nan, nan, nan]

    A configuration 1e200 times larger has the same roots, 1e200 times larger:

    >>> with np.errstate(all="ignore"):  # the squares overflow on the first try
    ...     big = circle_circle_xy(0.0, 0.0, 5e200, 8e200, 0.0, 5e200)
    >>> [float(v) for v in big[:4]]
    [4e+200, 3e+200, 4e+200, -3e+200]
    """
    dx = x2 - x1
    dy = y2 - y1
    if type(dx) in _PLAIN:
        dx = np.float64(dx)
    return _guarded(_circle_circle, _circle_circle_rescaled, (_CC_WINDOW,),
                    x1, y1, dx, dy, r1, r2)


def circle_circle_scale(x1, y1, r1, x2, y2, r2):
    """Return the scale :func:`circle_circle_xy` measures its margin against.

    That is the larger of the centres' distance and the radii.

    Parameters
    ----------
    x1, y1, r1, x2, y2, r2 : float or ndarray
        As for :func:`circle_circle_xy`.

    Returns
    -------
    ndarray
        The scale, broadcast over the inputs.

    Examples
    --------
    >>> float(circle_circle_scale(0.0, 0.0, 5.0, 8.0, 0.0, 3.0))
    8.0
    """
    return np.maximum(np.hypot(x2 - x1, y2 - y1), np.maximum(np.abs(r1), np.abs(r2)))


def _nonnegative(r) -> bool:
    """Whether every element of ``r`` is a number >= 0 (fast for Python floats)."""
    if type(r) is float or isinstance(r, (float, int)):
        return r >= 0
    return bool(np.all(np.asarray(r) >= 0))


def _line_circle(x1, y1, dx, dy, wx, wy, r):
    """Compute :func:`line_circle_xy`; also return the squared length and scale to check."""
    length_sq = dx * dx + dy * dy
    # t of the foot of the perpendicular from the centre, and the centre's offset
    t_foot = (wx * dx + wy * dy) / length_sq
    offset_sq = (wy * dx - wx * dy) ** 2 / length_sq
    r_sq = r * r
    half_chord_sq = r_sq - offset_sq
    scale_sq = np.maximum(np.maximum(r_sq, offset_sq), np.maximum(t_foot * t_foot, 1.0) * length_sq)
    margin = np.where(length_sq > DEGENERATE_RTOL**2 * scale_sq, half_chord_sq / scale_sq, np.nan)
    if not _nonnegative(r):
        margin = np.where(r >= 0, margin, np.nan)
    # a zero-length line gives NaN through t_foot
    meet = (np.sqrt(offset_sq) <= r + TANGENCY_RTOL * np.sqrt(scale_sq)) & ~np.isnan(margin)
    dt = np.sqrt(np.where(meet, np.maximum(half_chord_sq, 0.0), np.nan) / length_sq)
    ta = t_foot - dt
    tb = t_foot + dt
    outputs = (x1 + ta * dx, y1 + ta * dy, x1 + tb * dx, y1 + tb * dy, ta, tb, margin)
    return outputs, length_sq, scale_sq


def _line_circle_rescaled(x1, y1, dx, dy, wx, wy, r):
    s = _power_of_two(dx, dy, wx, wy, r)
    (xa, ya, xb, yb, ta, tb, margin), _, _ = _line_circle(0.0, 0.0, dx / s, dy / s, wx / s,
                                                          wy / s, r / s)
    return x1 + xa * s, y1 + ya * s, x1 + xb * s, y1 + yb * s, ta, tb, margin


def line_circle_xy(x1, y1, x2, y2, cx, cy, r):
    """Kernel of :func:`line_circle` on coordinate arrays.

    Returns
    -------
    xa, ya, xb, yb : ndarray
        The first and second roots along the line (NaN where there are none).
    ta, tb : ndarray
        Their parameters along ``start + t * (through - start)``.
    margin : ndarray
        Squared half-chord over squared scale, as in :func:`circle_circle_xy`.

    Examples
    --------
    >>> roots = line_circle_xy(-10.0, 0.0, 10.0, 0.0, 0.0, 0.0, 5.0)
    >>> [float(v) for v in roots]
    [-5.0, 0.0, 5.0, 0.0, 0.25, 0.75, 0.0625]
    >>> with np.errstate(all="ignore"):  # a zero-length line
    ...     bool(np.isnan(line_circle_xy(1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 5.0)[-1]))
    True
    """
    dx = x2 - x1
    dy = y2 - y1
    if type(dx) in _PLAIN:
        dx = np.float64(dx)
    wx = cx - x1
    wy = cy - y1
    # the scale is at least the length: within the window, nothing underflows; a
    # length that overflows or vanishes can make the scale NaN, so it is checked first
    return _guarded(_line_circle, _line_circle_rescaled, (_LC_WINDOW, (None, _LC_WINDOW[1])),
                    x1, y1, dx, dy, wx, wy, r)


def line_circle_scale(x1, y1, x2, y2, cx, cy, r):
    """Return the scale :func:`line_circle_xy` measures its margin against.

    That is the largest of the radius, the centre's offset from the line,
    the line's length and the distance along it from its first point to the
    foot of the centre.

    Parameters
    ----------
    x1, y1, x2, y2, cx, cy, r : float or ndarray
        As for :func:`line_circle_xy`.

    Returns
    -------
    ndarray
        The scale, broadcast over the inputs (NaN for a line of no length).

    Examples
    --------
    >>> float(line_circle_scale(-10.0, 0.0, 10.0, 0.0, 0.0, 0.0, 5.0))
    20.0
    """
    dx = np.float64(x2 - x1) if type(x2 - x1) in _PLAIN else x2 - x1  # 0 / 0 is NaN
    scale_sq = _line_circle(x1, y1, dx, y2 - y1, cx - x1, cy - y1, r)[2]
    return np.sqrt(scale_sq)


def _line_line(x1, y1, ax, ay, bx, by, wx, wy):
    """Compute :func:`line_line_xy`; also return the squared lengths to check it on."""
    cross = ax * by - ay * bx
    a_sq = ax * ax + ay * ay
    b_sq = bx * bx + by * by
    norms = np.sqrt(a_sq * b_sq)
    sine = cross / norms
    ok = np.abs(sine) > PARALLEL_RTOL  # False for NaN: zero-length lines
    t = np.where(ok, (wx * by - wy * bx) / cross, np.nan)
    u = np.where(ok, (wx * ay - wy * ax) / cross, np.nan)
    return (x1 + t * ax, y1 + t * ay, t, u, sine), a_sq, b_sq


def _line_line_rescaled(x1, y1, ax, ay, bx, by, wx, wy):
    # each line's direction is divided by its own power of two and the offset
    # between the lines by the first's: t and the sine do not change, u does
    sa = _power_of_two(ax, ay)
    sb = _power_of_two(bx, by)
    (_, _, t, u, sine), _, _ = _line_line(0.0, 0.0, ax / sa, ay / sa, bx / sb, by / sb,
                                          wx / sa, wy / sa)
    return x1 + t * ax, y1 + t * ay, t, u * (sa / sb), sine


def line_line_xy(x1, y1, x2, y2, x3, y3, x4, y4):
    """Kernel of :func:`line_line` on coordinate arrays.

    Returns
    -------
    x, y : ndarray
        The intersection (NaN where the lines are parallel or degenerate).
    t, u : ndarray
        Its parameters along the first and the second line.
    margin : ndarray
        The sine of the angle between the lines (signed); zero when parallel.

    Examples
    --------
    >>> [float(v) for v in line_line_xy(0.0, 0.0, 2.0, 2.0, 0.0, 2.0, 2.0, 0.0)]
    [1.0, 1.0, 0.5, 0.5, -1.0]
    >>> with np.errstate(all="ignore"):  # parallel lines
    ...     [float(v) for v in line_line_xy(0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0)[:2]]
    [nan, nan]
    """
    ax = x2 - x1
    ay = y2 - y1
    bx = x4 - x3
    by = y4 - y3
    if type(ax) in _PLAIN:
        ax = np.float64(ax)
    return _guarded(_line_line, _line_line_rescaled, (_LL_WINDOW, _LL_WINDOW),
                    x1, y1, ax, ay, bx, by, x3 - x1, y3 - y1)


# -- public primitives --------------------------------------------------------


def circle_circle(c1, r1, c2, r2):
    """Intersect two circles elementwise.

    Parameters
    ----------
    c1, c2 : array_like, shape (..., 2)
        Centres.
    r1, r2 : float or array_like
        Radii, broadcasting against the leading axes of the centres.

    Returns
    -------
    points : ndarray, shape (..., 2, 2)
        ``points[..., 0, :]`` left of the directed line c1 -> c2,
        ``points[..., 1, :]`` right of it; NaN where invalid.
    valid : ndarray of bool, shape (..., 2)
        Whether each root exists. Both roots exist or neither does.

    See Also
    --------
    line_circle : a line and a circle.

    Examples
    --------
    >>> points, valid = circle_circle([0, 0], 5, [8, 0], 5)
    >>> points
    array([[ 4.,  3.],
           [ 4., -3.]])
    >>> valid
    array([ True,  True])

    A point 20 and 15 from the ends of a 35-long bar is a double root:

    >>> points, valid = circle_circle([1, 2], 20, [1 + 35 * 0.6, 2 + 35 * 0.8], 15)
    >>> bool(valid.all()), np.allclose(points[0], points[1])
    (True, True)
    """
    x1, y1 = _xy(c1)
    x2, y2 = _xy(c2)
    r1 = np.asarray(r1, dtype=float)
    r2 = np.asarray(r2, dtype=float)
    with np.errstate(all="ignore"):
        xl, yl, xr, yr, _ = circle_circle_xy(x1, y1, r1, x2, y2, r2)
    points = _stack_roots(xl, yl, xr, yr)
    valid = ~np.isnan(points[..., 0])
    return points, valid


def _line_based_circle(start, through, center, radius, low, high):
    x1, y1 = _xy(start)
    x2, y2 = _xy(through)
    cx, cy = _xy(center)
    r = np.asarray(radius, dtype=float)
    with np.errstate(all="ignore"):
        xa, ya, xb, yb, ta, tb, _ = line_circle_xy(x1, y1, x2, y2, cx, cy, r)
    points = _stack_roots(xa, ya, xb, yb)
    t = np.stack(np.broadcast_arrays(ta, tb), axis=-1)
    with np.errstate(invalid="ignore"):
        valid = (t >= low - PARAMETER_RTOL) & (t <= high + PARAMETER_RTOL)
    points = np.where(valid[..., None], points, np.nan)
    return points, valid


def line_circle(start, through, center, radius):
    """Intersect the line through two points with a circle, elementwise.

    Parameters
    ----------
    start, through : array_like, shape (..., 2)
        Two points of the line; its direction is from ``start`` to ``through``.
    center : array_like, shape (..., 2)
        Centre of the circle.
    radius : float or array_like
        Radius of the circle.

    Returns
    -------
    points : ndarray, shape (..., 2, 2)
        The first and second root along the line's direction; NaN where invalid.
    valid : ndarray of bool, shape (..., 2)
        Whether each root exists.

    See Also
    --------
    ray_circle, segment_circle : the same with the line cut short.

    Examples
    --------
    >>> points, valid = line_circle([-10, 0], [10, 0], [0, 0], 5)
    >>> points
    array([[-5.,  0.],
           [ 5.,  0.]])
    >>> line_circle([10, 0], [-10, 0], [0, 0], 5)[0]
    array([[ 5.,  0.],
           [-5.,  0.]])
    """
    return _line_based_circle(start, through, center, radius, -np.inf, np.inf)


def ray_circle(start, through, center, radius):
    """Intersect the ray from ``start`` through ``through`` with a circle.

    Same as :func:`line_circle`, but a root is valid only if it lies on the
    ray: ``t >= 0`` in ``start + t * (through - start)``.

    Examples
    --------
    >>> points, valid = ray_circle([0, 0], [1, 0], [0, 0], 140)
    >>> valid
    array([False,  True])
    >>> points[1]
    array([140.,   0.])
    """
    return _line_based_circle(start, through, center, radius, 0.0, np.inf)


def segment_circle(start, through, center, radius):
    """Intersect the segment from ``start`` to ``through`` with a circle.

    Same as :func:`line_circle`, but a root is valid only if it lies on the
    segment: ``0 <= t <= 1`` in ``start + t * (through - start)``.

    Examples
    --------
    >>> points, valid = segment_circle([0, 30], [20, 30], [20, 30], 5)
    >>> valid
    array([ True, False])
    >>> points[0]
    array([15., 30.])
    """
    return _line_based_circle(start, through, center, radius, 0.0, 1.0)


def line_line(start1, through1, start2, through2):
    """Intersect two lines, each through two points, elementwise.

    Parameters
    ----------
    start1, through1, start2, through2 : array_like, shape (..., 2)
        Two points on each line.

    Returns
    -------
    point : ndarray, shape (..., 2)
        The intersection; NaN where the lines are parallel, coincident or
        degenerate (two equal points).
    valid : ndarray of bool, shape (...)

    Examples
    --------
    >>> point, valid = line_line([0, 0], [2, 2], [0, 2], [2, 0])
    >>> point, bool(valid)
    (array([1., 1.]), True)
    >>> bool(line_line([0, 0], [1, 0], [0, 1], [1, 1])[1])
    False
    """
    x1, y1 = _xy(start1)
    x2, y2 = _xy(through1)
    x3, y3 = _xy(start2)
    x4, y4 = _xy(through2)
    with np.errstate(all="ignore"):
        x, y, _, _, _ = line_line_xy(x1, y1, x2, y2, x3, y3, x4, y4)
    point = np.stack(np.broadcast_arrays(x, y), axis=-1)
    return point, np.asarray(~np.isnan(x + y))


def polar_point(origin, distance, angle):
    """Return the point at ``distance`` from ``origin`` at an absolute ``angle``.

    Parameters
    ----------
    origin : array_like, shape (..., 2)
    distance : float or array_like
    angle : float or array_like
        Radians, counter-clockwise from the x axis.

    Examples
    --------
    >>> polar_point([0, 30], 20, np.pi / 3).round(6)
    array([10.      , 47.320508])
    """
    x, y = _xy(origin)
    distance = np.asarray(distance, dtype=float)
    angle = np.asarray(angle, dtype=float)
    return np.stack(np.broadcast_arrays(x + distance * np.cos(angle),
                                        y + distance * np.sin(angle)), axis=-1)


def relative_point(origin, start, through, distance, angle):
    """Return the point at ``distance`` from ``origin``, ``angle`` off a line's direction.

    The angle is measured counter-clockwise from the direction of the line
    from ``start`` to ``through``; a coupler point is usually
    ``relative_point(A, A, B, distance, angle)``. NaN where the line has zero
    length.

    Examples
    --------
    >>> relative_point([0, 0], [0, 0], [0, 10], 2, np.pi / 2)
    array([-2.,  0.])
    """
    ox, oy = _xy(origin)
    x1, y1 = _xy(start)
    x2, y2 = _xy(through)
    with np.errstate(all="ignore"):
        x, y = relative_point_xy(ox, oy, x1, y1, x2, y2, np.asarray(distance, dtype=float),
                                 np.asarray(angle, dtype=float))
    return np.stack(np.broadcast_arrays(x, y), axis=-1)


def _relative_point(ox, oy, dx, dy, distance, angle):
    """Compute :func:`relative_point_xy`; also return the squared length to check it on."""
    length_sq = dx * dx + dy * dy
    c, s = cos_sin(angle)
    k = distance / np.sqrt(length_sq)  # inf or NaN for a zero-length line, NaN in the result
    # rotate the direction (dx, dy) by the angle, scaled to the distance
    return (ox + k * (c * dx - s * dy), oy + k * (s * dx + c * dy)), length_sq


def _relative_point_rescaled(ox, oy, dx, dy, distance, angle):
    # the answer depends on the direction only: divide it by a power of two
    s = _power_of_two(dx, dy)
    return _relative_point(ox, oy, dx / s, dy / s, distance, angle)[0]


def relative_point_xy(ox, oy, x1, y1, x2, y2, distance, angle, length=None):
    """Kernel of :func:`relative_point` on coordinate arrays.

    ``length``, where given, is the distance from (x1, y1) to (x2, y2),
    known without measuring it (a point on a circle about the other is as
    far from it as the radius): the direction is then scaled by it, which
    spares the square root and the check of the squares. A length that is
    not positive somewhere, or a ratio to it that overflows, takes the
    measured way.

    Examples
    --------
    >>> [round(float(v), 12) for v in relative_point_xy(0.0, 0.0, 0.0, 0.0, 0.0, 10.0, 2.0,
    ...                                                 np.pi / 2)]
    [-2.0, 0.0]
    >>> [round(float(v), 12) for v in relative_point_xy(0.0, 0.0, 0.0, 0.0, 0.0, 10.0, 2.0,
    ...                                                 np.pi / 2, length=10.0)]
    [-2.0, 0.0]
    >>> with np.errstate(all="ignore"):  # a zero-length line has no direction
    ...     [float(v) for v in relative_point_xy(0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0, 0.0)]
    [nan, nan]
    """
    dx = x2 - x1
    dy = y2 - y1
    if length is not None:
        k = _ratio(distance, length)
        if k is not None:
            c, s = cos_sin(angle)
            kc, ks = k * c, k * s  # numbers, for a constant distance and angle
            return ox + (kc * dx - ks * dy), oy + (ks * dx + kc * dy)
    if type(dx) in _PLAIN:
        dx = np.float64(dx)
    return _guarded(_relative_point, _relative_point_rescaled, (_RP_WINDOW,),
                    ox, oy, dx, dy, distance, angle)


def _ratio(value, length):
    """Return ``value / length``, or None where a length is not positive or it is not finite.

    Examples
    --------
    >>> _ratio(3.0, 2.0), _ratio(3.0, 0.0), _ratio(1e300, 1e-300)
    (1.5, None, None)
    """
    if type(value) is float and type(length) is float:  # the commonest: numbers
        if not length > 0:
            return None
        ratio = value / length
        return ratio if math.isfinite(ratio) else None
    with np.errstate(all="ignore"):
        ratio = np.divide(value, length)
        ok = np.all(np.asarray(length) > 0) and np.all(np.isfinite(ratio))
    return ratio if ok else None


def local_point(origin, toward, u, v):
    """Return the point at coordinates ``(u, v)`` in a frame on two points.

    The frame has its origin at ``origin`` and its x axis pointing from
    ``origin`` towards ``toward``; its y axis is that turned a quarter turn
    counter-clockwise. A point of a rigid link is so given once by its
    coordinates in the link's own frame, wherever the link moves. NaN where
    ``origin`` and ``toward`` coincide: the frame has no direction.

    Parameters
    ----------
    origin, toward : array_like, shape (..., 2)
    u, v : float or array_like
        Coordinates along the frame's x and y axes (lengths).

    Returns
    -------
    ndarray, shape (..., 2)

    See Also
    --------
    relative_point : the same point by a distance and an angle.

    Examples
    --------
    >>> local_point([1, 1], [1, 3], 2, 1)  # x axis straight up, y axis to the left
    array([0., 3.])
    >>> local_point([0, 0], [0, 0], 2, 1)
    array([nan, nan])
    """
    ox, oy = _xy(origin)
    tx, ty = _xy(toward)
    with np.errstate(all="ignore"):
        x, y = local_point_xy(ox, oy, tx, ty, np.asarray(u, dtype=float),
                              np.asarray(v, dtype=float))
    return np.stack(np.broadcast_arrays(x, y), axis=-1)


def _local_point(ox, oy, dx, dy, u, v):
    """Compute :func:`local_point_xy`; also return the squared length to check it on."""
    length_sq = dx * dx + dy * dy
    k = 1.0 / np.sqrt(length_sq)  # inf for a zero-length direction, NaN in the result
    # the frame's unit axes (ex, ey) and (-ey, ex): dimensionless, so u and v set the scale
    ex = dx * k
    ey = dy * k
    return (ox + (u * ex - v * ey), oy + (u * ey + v * ex)), length_sq


def _local_point_rescaled(ox, oy, dx, dy, u, v):
    # the axes depend on the direction only: divide it by a power of two
    s = _power_of_two(dx, dy)
    return _local_point(ox, oy, dx / s, dy / s, u, v)[0]


def local_point_xy(ox, oy, tx, ty, u, v, length=None):
    """Kernel of :func:`local_point` on coordinate arrays.

    ``length``, where given, is the distance from origin to toward, known
    without measuring it, as for :func:`relative_point_xy`.

    Examples
    --------
    >>> [float(c) for c in local_point_xy(1.0, 1.0, 4.0, 5.0, 10.0, 5.0)]
    [3.0, 12.0]
    >>> [float(c) for c in local_point_xy(1.0, 1.0, 4.0, 5.0, 10.0, 5.0, length=5.0)]
    [3.0, 12.0]
    >>> with np.errstate(all="ignore"):  # origin and toward coincide: no frame
    ...     [float(c) for c in local_point_xy(1.0, 1.0, 1.0, 1.0, 2.0, 0.0)]
    [nan, nan]
    """
    dx = tx - ox
    dy = ty - oy
    if length is not None:
        k = _ratio(1.0, length)
        if k is not None:
            ku, kv = u * k, v * k  # numbers, for coordinates that are
            return ox + (ku * dx - kv * dy), oy + (ku * dy + kv * dx)
    if type(dx) in _PLAIN:
        dx = np.float64(dx)
    return _guarded(_local_point, _local_point_rescaled, (_RP_WINDOW,), ox, oy, dx, dy, u, v)


def point_along(start, through, distance):
    """Return the point at a signed ``distance`` from ``start`` towards ``through``.

    Examples
    --------
    >>> point_along([0, 0], [3, 4], 10)
    array([6., 8.])
    >>> point_along([0, 0], [3, 4], -5)
    array([-3., -4.])
    """
    zero = np.zeros(np.shape(distance))
    return relative_point(start, start, through, distance, zero)
