"""Property-based tests of the intersection primitives, with shapely as the oracle.

Conventions used throughout:

* ``S`` is the scale of a configuration: the largest of the distances and
  radii involved, as in the module's tangency rule.
* ``C`` is the magnitude of the coordinates; rounding a coordinate costs
  ``eps * C``, so bounds that involve absolute positions use ``max(S, C)``.
* The tangency band is where the squared half-chord is within a small
  multiple of ``TANGENCY_RTOL * S**2`` of zero, or where a distance that
  decides existence is within ``1e-6 * S`` of a radius. Inside it the answer
  depends on rounding and on the documented tolerance, so existence is only
  compared with shapely outside it.
* The documented rule bounds the *miss* between the curves, a distance, by
  ``TANGENCY_RTOL * S``: a near miss accepted as tangent is checked to be
  within it, and its double root (the foot of the chord) is off each curve by
  the clamped squared half-chord, no more.
"""

import warnings

import numpy as np
import pytest
import shapely
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from geokin.primitives import (
    NEARBY,
    PARAMETER_RTOL,
    SCALE_RANGE,
    TANGENCY_RTOL,
    circle_circle,
    circle_circle_scale,
    circle_circle_xy,
    cos_sin,
    line_circle,
    line_circle_scale,
    line_circle_xy,
    line_line,
    line_line_xy,
    local_point,
    local_point_xy,
    nearby_rows,
    point_along,
    polar_point,
    ray_circle,
    relative_point,
    relative_point_xy,
    segment_circle,
)

LINE_BASED = {"line": line_circle, "ray": ray_circle, "segment": segment_circle}
T_RANGE = {"line": (-np.inf, np.inf), "ray": (0.0, np.inf), "segment": (0.0, 1.0)}

# Inscribed polygons with this many segments per quarter stay within
# r * (pi / 8192)**2 / 2 < 1e-7 * r of the true circle.
QUAD_SEGS = 2048
BAND = 1e-6
"""Relative width of the band around tangency excluded from shapely comparisons."""

# -- strategies ---------------------------------------------------------------

# tiny coordinates are snapped to zero: scales are explored by explicit factors of
# 1e-6 .. 1e6, and lengths whose squares underflow count as zero-length lines
coord = st.floats(-100, 100, allow_nan=False, allow_infinity=False).map(
    lambda x: 0.0 if abs(x) < 1e-9 else x)
point = st.tuples(coord, coord).map(np.array)
radius = st.one_of(st.just(0.0), st.floats(1e-3, 100, allow_subnormal=False))
positive_radius = st.floats(1e-2, 100)
angle = st.floats(-np.pi, np.pi)
# axis-aligned directions make one component exactly zero (0 * inf and 0 / 0 cases)
grid_angle = st.one_of(st.sampled_from([0.0, -np.pi / 2]), angle)
exponent = st.floats(-6, 6)
unit = st.floats(0.05, 1.0)


def _direction(theta):
    return np.array([np.cos(theta), np.sin(theta)])


def _transform(points, lam, theta, shift):
    """Scale by ``lam``, rotate by ``theta`` about the origin, then shift."""
    p = np.asarray(points, dtype=float)
    c, s = np.cos(theta), np.sin(theta)
    x, y = lam * p[..., 0], lam * p[..., 1]
    return np.stack([c * x - s * y + shift[0], s * x + c * y + shift[1]], axis=-1)


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _norm(a):
    return np.hypot(a[..., 0], a[..., 1])


def _boundary(center, r):
    """Shapely geometry of a circle's boundary (a point when the radius is zero)."""
    centre = shapely.Point(*center)
    if r == 0:
        return centre
    return centre.buffer(r, quad_segs=QUAD_SEGS).exterior


def _count_points(geometry):
    return len(shapely.get_coordinates(geometry))


def _circle_margin(c1, r1, c2, r2):
    """The kernel's margin (squared half-chord over squared scale) for two circles."""
    with np.errstate(all="ignore"):
        return circle_circle_xy(c1[0], c1[1], r1, c2[0], c2[1], r2)[-1]


def _line_kernel(start, through, center, r):
    """The line-circle kernel's outputs: roots, their parameters and the margin."""
    with np.errstate(all="ignore"):
        return line_circle_xy(*start, *through, *center, r)


def _heron_half_chord_sq(d, r1, r2):
    """Squared half-chord of two circles from the triangle (d, r1, r2), by Heron."""
    return (d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (-d + r1 + r2) / (4 * d * d)


@st.composite
def circle_pairs(draw):
    """Two circles: anywhere, or deliberately close to (not on) a tangency."""
    c1 = draw(point)
    r1 = draw(radius)
    r2 = draw(radius)
    if draw(st.booleans()):
        c2 = draw(point)
    else:
        scale = max(r1, r2, 1e-3)
        internal = draw(st.booleans())
        gap = draw(st.sampled_from([-1.0, 1.0])) * 10 ** draw(st.floats(-6, -1)) * scale
        d = (abs(r1 - r2) if internal else r1 + r2) + gap
        assume(d > 0)
        c2 = c1 + d * _direction(draw(angle))
    return c1, r1, c2, r2


# -- every valid root lies on both curves -------------------------------------


@given(circle_pairs(), exponent)
def test_circle_circle_roots_lie_on_both_circles(pair, k):
    """Each valid circle_circle root satisfies |p - c|**2 = r**2 for both circles."""
    lam = 10.0**k
    c1, r1, c2, r2 = (lam * np.asarray(v) for v in pair)
    points, valid = circle_circle(c1, r1, c2, r2)
    assert valid[0] == valid[1]
    d = _norm(c2 - c1)
    S = max(d, r1, r2)
    C = max(_norm(c1), _norm(c2), S)
    margin = _circle_margin(c1, r1, c2, r2)
    if valid[0] and margin < 0:
        # an accepted near-miss: the circles miss by no more than the tolerance
        miss = max(d - (r1 + r2), abs(r1 - r2) - d)
        assert miss <= TANGENCY_RTOL * S + 1e-15 * C
    # its double root sits at the foot of the chord, off each circle by the
    # (negative) squared half-chord that was clamped to zero
    bound = 1e-12 * S * C + (1.01 * abs(margin) * S * S if margin < 0 else 0.0)
    for p in points[valid]:
        assert abs(np.sum((p - c1) ** 2) - r1 * r1) <= bound
        assert abs(np.sum((p - c2) ** 2) - r2 * r2) <= bound
    assert np.isnan(points[~valid]).all()


@pytest.mark.parametrize("kind", sorted(LINE_BASED))
@given(start=point, through=point, center=point, r=radius, k=exponent)
def test_line_based_roots_lie_on_line_and_circle(kind, start, through, center, r, k):
    """Each valid line/ray/segment root is on the circle, on the line, and in its t range."""
    lam = 10.0**k
    start, through, center, r = lam * start, lam * through, lam * center, lam * r
    direction = through - start
    length = _norm(direction)
    assume(length > 0)
    points, valid = LINE_BASED[kind](start, through, center, r)
    S = max(r, _norm(center - start), _norm(center - through), length)
    C = max(_norm(start), _norm(through), _norm(center), S)
    margin = _line_kernel(start, through, center, r)[-1]
    bound = 1e-12 * S * C + (1.01 * abs(margin) * S * S if margin < 0 else 0.0)
    low, high = T_RANGE[kind]
    t_slack = PARAMETER_RTOL + 1e-12 * C / length
    for p in points[valid]:
        assert abs(np.sum((p - center) ** 2) - r * r) <= bound
        assert abs(_cross(p - start, direction)) / length <= 1e-12 * C
        t = np.dot(p - start, direction) / length**2
        assert low - t_slack <= t <= high + t_slack
    assert np.isnan(points[~valid]).all()


@st.composite
def two_lines(draw):
    """Two lines through two points each: anywhere, or turned by a tiny angle."""
    s1, t1, s2 = draw(point), draw(point), draw(point)
    if draw(st.booleans()):
        return s1, t1, s2, draw(point)
    turn = draw(st.sampled_from([-1.0, 1.0])) * 10 ** draw(st.floats(-11, -1))
    c, s = np.cos(turn), np.sin(turn)
    a = (t1 - s1) * draw(st.floats(0.1, 10))
    return s1, t1, s2, s2 + np.array([c * a[0] - s * a[1], s * a[0] + c * a[1]])


@given(two_lines(), exponent)
def test_line_line_root_lies_on_both_lines(lines, k):
    """A valid line_line point is on both lines, and it is valid unless nearly parallel."""
    lam = 10.0**k
    s1, t1, s2, t2 = (lam * v for v in lines)
    a, b = t1 - s1, t2 - s2
    assume(_norm(a) > 0 and _norm(b) > 0)
    p, valid = line_line(s1, t1, s2, t2)
    sine = _cross(a, b) / (_norm(a) * _norm(b))
    if abs(sine) > 1e-9:
        assert valid
    if valid:
        C = max(_norm(s1), _norm(t1), _norm(s2), _norm(t2), _norm(p))
        assert abs(_cross(p - s1, a)) / _norm(a) <= 1e-12 * C
        assert abs(_cross(p - s2, b)) / _norm(b) <= 1e-12 * C
    else:
        assert np.isnan(p).all()


# -- the documented root order ------------------------------------------------


@st.composite
def crossing_circles(draw):
    """Two circles that cross: |r1 - r2| <= 0.9 d and r1 + r2 >= 1.1 d."""
    c1 = draw(point)
    d = draw(st.floats(1e-2, 100))
    c2 = c1 + d * _direction(draw(angle))
    return c1, d * draw(st.floats(0.55, 1.45)), c2, d * draw(st.floats(0.55, 1.45))


@st.composite
def crossing_line(draw):
    """A circle and a line crossing it, with both roots between start and through."""
    center, r, u = draw(point), draw(positive_radius), _direction(draw(angle))
    foot = center + draw(st.floats(-0.99, 0.99)) * r * np.array([-u[1], u[0]])
    start = foot - r * draw(st.floats(1.01, 3)) * u
    through = foot + r * draw(st.floats(1.01, 3)) * u
    return start, through, center, r


@given(crossing_circles())
def test_circle_circle_left_root_first(pair):
    """circle_circle gives the root left of c1 -> c2 first and the right one second."""
    c1, r1, c2, r2 = pair
    points, valid = circle_circle(c1, r1, c2, r2)
    assert valid.all()
    axis = c2 - c1
    S = max(_norm(axis), r1, r2)
    C = max(_norm(c1), _norm(c2), S)
    slack = 1e-12 * S * C
    assert _cross(axis, points[0] - c1) >= -slack
    assert _cross(axis, points[1] - c1) <= slack


@pytest.mark.parametrize("kind", sorted(LINE_BASED))
@given(config=crossing_line())
def test_line_based_roots_ordered_along_direction(kind, config):
    """Line-based roots come first then second along start -> through."""
    start, through, center, r = config
    points, valid = LINE_BASED[kind](start, through, center, r)
    assert valid.all()
    direction = through - start
    assert np.dot(points[0] - start, direction) < np.dot(points[1] - start, direction)
    reversed_points, _ = LINE_BASED[kind](through, start, center, r)
    assert np.dot(reversed_points[0] - start, direction) > np.dot(
        reversed_points[1] - start, direction)


# -- agreement with shapely away from the tangency band -----------------------


@given(circle_pairs(), exponent)
def test_circle_circle_existence_agrees_with_shapely(pair, k):
    """circle_circle has roots exactly when shapely's circle boundaries meet (off the band)."""
    lam = 10.0**k
    c1, r1, c2, r2 = (lam * np.asarray(v) for v in pair)
    d = float(shapely.distance(shapely.Point(*c1), shapely.Point(*c2)))
    assume(d > 0)
    S = max(d, r1, r2)
    assume(min(abs(d - (r1 + r2)), abs(d - abs(r1 - r2))) > BAND * S)
    assume(abs(_heron_half_chord_sq(d, r1, r2)) > 4 * TANGENCY_RTOL * S * S)
    _, valid = circle_circle(c1, r1, c2, r2)
    meet = shapely.intersects(_boundary(c1, r1), _boundary(c2, r2))
    assert bool(valid[0]) == bool(valid[1]) == bool(meet)


@st.composite
def line_and_circle(draw):
    """A line through two points and a circle, sometimes close to tangent or an end."""
    start, through, center, r = draw(point), draw(point), draw(point), draw(radius)
    near = draw(st.sampled_from(["free", "tangent", "end"]))
    if near != "free" and _norm(through - start) > 0:
        u = (through - start) / _norm(through - start)
        gap = draw(st.sampled_from([-1.0, 1.0])) * 10 ** draw(st.floats(-6, -1)) * max(r, 1)
        if near == "tangent":
            foot = start + draw(st.floats(-2, 3)) * (through - start)
            center = foot + (r + gap) * np.array([-u[1], u[0]])
        else:
            end = draw(st.sampled_from([start, through]))
            center = end + (r + gap) * _direction(draw(angle))
    return start, through, center, r


@given(st.one_of(crossing_circles(), circle_pairs()))
def test_circle_circle_margin_is_the_half_chord_over_circle_circle_scale(pair):
    """The margin times the squared scale is the squared half-chord (Heron's)."""
    c1, r1, c2, r2 = pair
    d = _norm(c2 - c1)
    size = max(d, r1, r2)
    half_sq = _heron_half_chord_sq(d, r1, r2) if d > 0 else -1.0
    assume(half_sq > 1e-6 * size**2)
    scale = circle_circle_scale(*c1, r1, *c2, r2)
    margin = _circle_margin(c1, r1, c2, r2)
    assert abs(margin * scale**2 - half_sq) <= 1e-9 * size**2


@given(config=st.one_of(crossing_line(), line_and_circle()))
def test_line_circle_margin_is_the_half_chord_over_line_circle_scale(config):
    """The margin times the squared scale is r**2 less the centre's squared offset."""
    start, through, center, r = config
    length = _norm(through - start)
    assume(length > 1e-6)
    offset = abs(_cross(through - start, center - start)) / length
    half_sq = r * r - offset * offset
    size = max(r, length, _norm(center - start))
    assume(half_sq > 1e-6 * size**2)
    with np.errstate(all="ignore"):
        scale = line_circle_scale(*start, *through, *center, r)
    margin = _line_kernel(start, through, center, r)[-1]
    assert scale >= max(r, length) * (1 - 1e-12)
    assert abs(margin * scale**2 - half_sq) <= 1e-9 * max(size, float(scale))**2


@pytest.mark.parametrize("kind", sorted(LINE_BASED))
@given(config=line_and_circle(), k=exponent)
def test_line_based_roots_agree_with_shapely(kind, config, k):
    """Line/ray/segment roots exist, and are as many, as shapely's crossings (off the band)."""
    lam = 10.0**k
    start, through, center, r = (lam * np.asarray(v) for v in config)
    length = _norm(through - start)
    assume(length > 0)
    u = (through - start) / length
    reach = _norm(center - start) + r + length
    ends = {
        "line": (start - 2 * reach * u, start + 2 * reach * u),
        "ray": (start, start + 2 * reach * u),
        "segment": (start, through),
    }[kind]
    path = shapely.LineString(ends)
    centre = shapely.Point(*center)
    S = max(r, _norm(center - start), _norm(center - through), length)
    full_line = shapely.LineString([start - 2 * reach * u, start + 2 * reach * u])
    e = float(shapely.distance(full_line, centre))
    # away from tangency of the full line, and from an end sitting on the circle
    assume(abs(e - r) > BAND * S and abs(e * e - r * r) > 4 * TANGENCY_RTOL * S * S)
    if kind != "line":
        assume(abs(_norm(center - start) - r) > BAND * S)
    if kind == "segment":
        assume(abs(_norm(center - through) - r) > BAND * S)
    _, valid = LINE_BASED[kind](start, through, center, r)
    expected = _count_points(shapely.intersection(path, _boundary(center, r)))
    assert int(valid.sum()) == expected
    # the closed-form oracle for existence on a segment, as a cross-check
    if kind == "segment":
        far = max(_norm(center - start), _norm(center - through))
        assert bool(valid.any()) == bool(shapely.distance(path, centre) <= r <= far)


@given(point, point, point, point, exponent)
def test_line_line_agrees_with_shapely(s1, t1, s2, t2, k):
    """line_line matches shapely's intersection of long segments when not nearly parallel."""
    lam = 10.0**k
    s1, t1, s2, t2 = (lam * v for v in (s1, t1, s2, t2))
    a, b = t1 - s1, t2 - s2
    assume(_norm(a) > 1e-3 * lam and _norm(b) > 1e-3 * lam)
    sine = _cross(a, b) / (_norm(a) * _norm(b))
    assume(abs(sine) > 1e-3)
    # the intersection is within |s2 - s1| / |sine| of both starts
    reach = 1.5 * _norm(s2 - s1) / abs(sine) + lam
    ua, ub = a / _norm(a), b / _norm(b)
    first = shapely.LineString([s1 - reach * ua, s1 + reach * ua])
    second = shapely.LineString([s2 - reach * ub, s2 + reach * ub])
    expected = shapely.get_coordinates(shapely.intersection(first, second))
    p, valid = line_line(s1, t1, s2, t2)
    assert valid
    assert expected.shape == (1, 2)
    C = max(_norm(s1), _norm(s2), reach)
    np.testing.assert_allclose(p, expected[0], rtol=0, atol=1e-9 * C / abs(sine))


# -- swapping inputs ----------------------------------------------------------


@given(circle_pairs())
def test_circle_circle_swap_exchanges_left_and_right(pair):
    """circle_circle(c2, r2, c1, r1) gives the same roots with left and right exchanged."""
    c1, r1, c2, r2 = pair
    d = _norm(c2 - c1)
    S = max(d, r1, r2)
    assume(d > 1e-2 * S)
    margin = _circle_margin(c1, r1, c2, r2)
    assume(abs(margin) > 1e-9)
    forward, valid_f = circle_circle(c1, r1, c2, r2)
    backward, valid_b = circle_circle(c2, r2, c1, r1)
    np.testing.assert_array_equal(valid_f, valid_b)
    # root positions move with the square root of rounding near tangency
    C = max(_norm(c1), _norm(c2), S)
    atol = 1e-13 * C * S / d / np.sqrt(abs(margin)) + 1e-13 * C
    np.testing.assert_allclose(forward, backward[::-1], rtol=0, atol=atol)


@given(start=point, through=point, center=point, r=radius)
def test_reversing_line_reverses_root_order(start, through, center, r):
    """Reversing a line or segment reverses its roots; the two opposite rays share the line's."""
    length = _norm(through - start)
    assume(length > 0)
    S = max(r, _norm(center - start), _norm(center - through), length)
    C = max(_norm(start), _norm(through), _norm(center), S)
    _, _, _, _, ta, tb, margin = _line_kernel(start, through, center, r)
    assume(abs(margin) > 1e-9)
    # keep roots off the ends, where the parameter tolerance decides
    assume(all(np.isnan(t) or min(abs(t), abs(t - 1)) > 1e-6 for t in (ta, tb)))
    atol = 1e-12 * C / np.sqrt(abs(margin))
    for fn in (line_circle, segment_circle):
        forward, valid_f = fn(start, through, center, r)
        backward, valid_b = fn(through, start, center, r)
        np.testing.assert_array_equal(valid_f, valid_b[::-1])
        np.testing.assert_allclose(forward, backward[::-1], rtol=0, atol=atol)
    line, valid_line = line_circle(start, through, center, r)
    ahead, valid_ahead = ray_circle(start, through, center, r)
    behind, valid_behind = ray_circle(start, 2 * start - through, center, r)
    # the ray behind runs the other way: its second root is the line's first
    np.testing.assert_array_equal(valid_ahead | valid_behind[::-1], valid_line)
    assert not (valid_ahead & valid_behind[::-1]).any()
    merged = np.where(valid_ahead[:, None], ahead, behind[::-1])
    np.testing.assert_allclose(merged, line, rtol=0, atol=atol)


@given(point, point, point, point)
def test_line_line_symmetric_in_its_lines(s1, t1, s2, t2):
    """line_line gives the same point with the lines exchanged or their directions reversed."""
    a, b = t1 - s1, t2 - s2
    assume(_norm(a) > 1e-3 and _norm(b) > 1e-3)
    sine = _cross(a, b) / (_norm(a) * _norm(b))
    assume(abs(sine) > 1e-6)
    p, valid = line_line(s1, t1, s2, t2)
    assert valid
    C = max(_norm(s1), _norm(t1), _norm(s2), _norm(t2), _norm(p))
    for args in ((s2, t2, s1, t1), (t1, s1, s2, t2), (s1, t1, t2, s2)):
        q, valid_q = line_line(*args)
        assert valid_q
        np.testing.assert_allclose(q, p, rtol=0, atol=1e-12 * C / abs(sine))


# -- invariance under similarity transforms -----------------------------------

similarity = st.tuples(exponent, angle, point)
"""(log10 of the scale, rotation, shift in units of the scale)."""


@given(circle_pairs(), similarity)
def test_circle_circle_similarity_covariant(pair, transform):
    """circle_circle commutes with translation, rotation and scaling by 1e-6 .. 1e6."""
    c1, r1, c2, r2 = pair
    k, theta, shift = transform
    lam = 10.0**k
    d = _norm(c2 - c1)
    assume(d >= 1.0)
    margin = _circle_margin(c1, r1, c2, r2)
    assume(abs(margin) > 1e-8)
    points, valid = circle_circle(c1, r1, c2, r2)
    moved, valid_moved = circle_circle(_transform(c1, lam, theta, lam * shift), lam * r1,
                                       _transform(c2, lam, theta, lam * shift), lam * r2)
    np.testing.assert_array_equal(valid_moved, valid)
    C = max(_norm(c1), _norm(c2), d, r1, r2, _norm(shift))
    np.testing.assert_allclose(moved, _transform(points, lam, theta, lam * shift),
                               rtol=0, atol=1e-11 * lam * C * C / np.sqrt(abs(margin)))


@pytest.mark.parametrize("kind", sorted(LINE_BASED))
@given(start=point, through=point, center=point, r=radius, transform=similarity)
def test_line_based_similarity_covariant(kind, start, through, center, r, transform):
    """Line/ray/segment roots commute with translation, rotation and scaling by 1e-6 .. 1e6."""
    k, theta, shift = transform
    lam = 10.0**k
    assume(_norm(through - start) >= 1.0)
    _, _, _, _, ta, tb, margin = _line_kernel(start, through, center, r)
    assume(abs(margin) > 1e-8)
    assume(all(np.isnan(t) or min(abs(t), abs(t - 1)) > 1e-6 for t in (ta, tb)))
    fn = LINE_BASED[kind]
    points, valid = fn(start, through, center, r)
    moved, valid_moved = fn(*(_transform(p, lam, theta, lam * shift)
                              for p in (start, through, center)), lam * r)
    np.testing.assert_array_equal(valid_moved, valid)
    C = max(_norm(start), _norm(through), _norm(center), r, _norm(shift))
    np.testing.assert_allclose(moved, _transform(points, lam, theta, lam * shift),
                               rtol=0, atol=1e-11 * lam * C / np.sqrt(abs(margin)))


@given(point, point, point, point, similarity)
def test_line_line_similarity_covariant(s1, t1, s2, t2, transform):
    """line_line commutes with translation, rotation and scaling by 1e-6 .. 1e6."""
    k, theta, shift = transform
    lam = 10.0**k
    a, b = t1 - s1, t2 - s2
    assume(_norm(a) >= 1.0 and _norm(b) >= 1.0)
    sine = _cross(a, b) / (_norm(a) * _norm(b))
    assume(abs(sine) > 1e-3)
    p, valid = line_line(s1, t1, s2, t2)
    moved, valid_moved = line_line(*(_transform(v, lam, theta, lam * shift)
                                     for v in (s1, t1, s2, t2)))
    assert valid and valid_moved
    C = max(_norm(s1), _norm(t1), _norm(s2), _norm(t2), _norm(p), _norm(shift))
    np.testing.assert_allclose(moved, _transform(p, lam, theta, lam * shift),
                               rtol=0, atol=1e-12 * lam * C / abs(sine))


# -- exact tangency gives a double root ---------------------------------------

# Tangent configurations are only tangent up to the rounding of their
# construction (about eps * C); the root separation grows like the square
# root of that, so coincidence is checked to 1e-6 of the scale.
DOUBLE_ROOT_RTOL = 1e-6


@given(c1=st.tuples(coord, coord).map(np.array), a=positive_radius, b=positive_radius,
       theta=angle, k=exponent, internal=st.booleans())
def test_tangent_circles_give_double_root(c1, a, b, theta, k, internal):
    """Circles touching externally (d = a + b) or internally (d = a - b) give a double root."""
    lam = 10.0**k
    if internal:
        a, b = max(a, b), min(a, b)
        # internal tangency of nearly equal circles is ill-conditioned
        assume(a - b >= 0.1 * a)
    a, b, c1 = lam * a, lam * b, lam * c1
    u = _direction(theta)
    bar = a - b if internal else a + b
    c2 = c1 + bar * u
    for first, second in (((c1, a), (c2, b)), ((c2, b), (c1, a))):
        points, valid = circle_circle(*first, *second)
        assert valid.all()
        S = max(a, b, bar)
        np.testing.assert_allclose(points[0], points[1], rtol=0, atol=DOUBLE_ROOT_RTOL * S)
        np.testing.assert_allclose(points[0], c1 + a * u, rtol=0,
                                   atol=DOUBLE_ROOT_RTOL * max(S, _norm(c1)))


@pytest.mark.parametrize("kind", sorted(LINE_BASED))
@given(center=point, r=positive_radius, theta=angle, before=unit, after=unit, k=exponent)
def test_tangent_line_gives_double_root(kind, center, r, theta, before, after, k):
    """A line at distance exactly r from the centre, built by rotation, touches in a double root."""
    lam = 10.0**k
    center, r = lam * center, lam * r
    span = lam * 100
    u = _direction(theta)
    normal = np.array([-u[1], u[0]])
    foot = center + r * normal
    start = foot - before * span * u
    through = foot + after * span * u
    points, valid = LINE_BASED[kind](start, through, center, r)
    assert valid.all()
    S = max(r, _norm(center - start), _norm(center - through))
    np.testing.assert_allclose(points[0], points[1], rtol=0, atol=DOUBLE_ROOT_RTOL * S)
    np.testing.assert_allclose(points[0], foot, rtol=0,
                               atol=DOUBLE_ROOT_RTOL * max(S, _norm(center)))


@given(c1=point, r1=positive_radius, ratio=st.floats(0.1, 1.0), theta=angle,
       internal=st.booleans(), sign=st.sampled_from([-1.0, 1.0]), u=st.floats(-6, -1),
       k=exponent)
def test_near_tangency_is_classified_sharply(c1, r1, ratio, theta, internal, sign, u, k):
    """Comparable circles (or a line) off tangency by 1e-6 .. 1e-1 of the scale are hit or miss."""
    lam = 10.0**k
    c1, r1 = lam * c1, lam * r1
    r2 = ratio * r1
    gap = sign * 10**u * r1
    d = (r1 - r2 if internal else r1 + r2) + gap
    assume(d >= 0.1 * r1)
    c2 = c1 + d * _direction(theta)
    # outward gaps miss externally and hit internally; inward gaps the reverse
    hit = (gap > 0) == internal
    _, valid = circle_circle(c1, r1, c2, r2)
    assert valid.all() if hit else not valid.any()
    normal = np.array([-np.sin(theta), np.cos(theta)])
    foot = c1 + (r1 + gap) * normal
    _, valid = line_circle(foot, foot + lam * _direction(theta), c1, r1)
    assert valid.all() if gap < 0 else not valid.any()


# -- degenerate input ----------------------------------------------------------

GRID = (3, 4)
bad_mask = hnp.arrays(bool, GRID)


@st.composite
def good_circle_grid(draw):
    """Circles on a (3, 4) grid that cross robustly: |r1 - r2| < d < r1 + r2 with room."""
    c1 = draw(hnp.arrays(float, GRID + (2,), elements=coord))
    d = draw(hnp.arrays(float, GRID, elements=st.floats(1.0, 100)))
    theta = draw(hnp.arrays(float, GRID, elements=grid_angle))
    ratios = draw(hnp.arrays(float, (2,) + GRID, elements=st.floats(0.6, 1.4)))
    c2 = c1 + d[..., None] * np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    return c1, d * ratios[0], c2, d * ratios[1]


def _no_warnings(fn, *args):
    """Call fn, turning any numpy floating-point warning into a test failure."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return fn(*args)


@given(good_circle_grid(), bad_mask,
       st.sampled_from(["coincident", "negative", "nan radius", "inf radius", "nan centre"]))
def test_circle_circle_degenerate_elements_invalid(grid, bad, kind):
    """Degenerate circle pairs give invalid NaN roots without raising or warning; others stay."""
    c1, r1, c2, r2 = (np.array(v) for v in grid)
    reference, ref_valid = circle_circle(c1, r1, c2, r2)
    assert ref_valid.all()
    if kind == "coincident":
        c2[bad] = c1[bad]
    elif kind == "negative":
        r1[bad] = -r1[bad]
    elif kind == "nan radius":
        r2[bad] = np.nan
    elif kind == "inf radius":
        r1[bad] = np.inf
    else:
        c1[bad, 1] = np.nan
    points, valid = _no_warnings(circle_circle, c1, r1, c2, r2)
    assert points.shape == GRID + (2, 2) and valid.shape == GRID + (2,)
    assert not valid[bad].any()
    assert np.isnan(points[bad]).all()
    assert valid[~bad].all()
    np.testing.assert_allclose(points[~bad], reference[~bad], rtol=1e-14, atol=1e-12)


@st.composite
def good_line_grid(draw):
    """Lines through the centre of a circle on a (3, 4) grid: two roots, well inside."""
    center = draw(hnp.arrays(float, GRID + (2,), elements=coord))
    r = draw(hnp.arrays(float, GRID, elements=st.floats(1.0, 100)))
    theta = draw(hnp.arrays(float, GRID, elements=grid_angle))
    u = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    start = center - 2 * r[..., None] * u
    through = center + 2 * r[..., None] * u
    return start, through, center, r


@pytest.mark.parametrize("kind", sorted(LINE_BASED))
@given(grid=good_line_grid(), bad=bad_mask,
       degeneracy=st.sampled_from(["zero length", "negative", "nan radius", "inf radius",
                                   "nan start", "nan centre"]))
def test_line_based_degenerate_elements_invalid(kind, grid, bad, degeneracy):
    """Degenerate lines or circles give invalid NaN roots without raising; others stay."""
    start, through, center, r = (np.array(v) for v in grid)
    fn = LINE_BASED[kind]
    reference, ref_valid = fn(start, through, center, r)
    assert ref_valid.all()
    if degeneracy == "zero length":
        through[bad] = start[bad]
    elif degeneracy == "negative":
        r[bad] = -r[bad]
    elif degeneracy == "nan radius":
        r[bad] = np.nan
    elif degeneracy == "inf radius":
        r[bad] = np.inf
    elif degeneracy == "nan start":
        start[bad, 0] = np.nan
    else:
        center[bad, 1] = np.nan
    points, valid = _no_warnings(fn, start, through, center, r)
    assert points.shape == GRID + (2, 2) and valid.shape == GRID + (2,)
    assert not valid[bad].any()
    assert np.isnan(points[bad]).all()
    assert valid[~bad].all()
    np.testing.assert_allclose(points[~bad], reference[~bad], rtol=1e-14, atol=1e-12)


@given(hnp.arrays(float, GRID + (2,), elements=coord),
       hnp.arrays(float, GRID, elements=grid_angle),
       hnp.arrays(float, GRID, elements=st.floats(0.1, 1.5)),
       bad_mask,
       st.sampled_from(["parallel", "coincident", "zero length", "nan point", "inf point"]))
def test_line_line_degenerate_elements_invalid(base, theta, turn, bad, kind):
    """Parallel, coincident, zero-length or non-finite lines are invalid without raising."""
    u = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    v = np.stack([np.cos(theta + turn), np.sin(theta + turn)], axis=-1)
    s1, t1 = base, base + 10 * u
    s2, t2 = base + 3 * v, base + 13 * v
    reference, ref_valid = line_line(s1, t1, s2, t2)
    assert ref_valid.all()
    s2, t2 = s2.copy(), t2.copy()
    if kind == "parallel":
        s2[bad] = s1[bad] + 5 * np.stack([-u[bad, 1], u[bad, 0]], axis=-1)
        t2[bad] = s2[bad] + (t1[bad] - s1[bad])
    elif kind == "coincident":
        s2[bad] = s1[bad] + 0.5 * (t1[bad] - s1[bad])
        t2[bad] = t1[bad]
    elif kind == "zero length":
        t2[bad] = s2[bad]
    elif kind == "nan point":
        s2[bad, 0] = np.nan
    else:
        t2[bad, 1] = np.inf
    p, valid = _no_warnings(line_line, s1, t1, s2, t2)
    assert p.shape == GRID + (2,) and valid.shape == GRID
    assert not valid[bad].any()
    assert np.isnan(p[bad]).all()
    assert valid[~bad].all()
    np.testing.assert_array_equal(p[~bad], reference[~bad])


# -- broadcasting ----------------------------------------------------------------


def _elementwise(fn, shape, *args):
    """Call fn on each element of the broadcast leading shape, then stack the results."""
    outputs = []
    for index in np.ndindex(*shape):
        picked = []
        for arg, is_point in args:
            arr = np.asarray(arg, dtype=float)
            lead = arr.shape[:-1] if is_point else arr.shape
            arr = np.broadcast_to(arr, shape + arr.shape[len(lead):])
            picked.append(arr[index])
        outputs.append(fn(*picked))
    return [np.stack([out[i] for out in outputs]).reshape(shape + np.shape(outputs[0][i]))
            for i in range(len(outputs[0]))]


leading_shapes = st.sampled_from([(), (5,), (2, 3), (2, 1, 3)])


@st.composite
def broadcast_args(draw, kinds):
    """Arguments whose leading shapes broadcast to one drawn shape (some are scalars)."""
    shape = draw(leading_shapes)
    args = []
    for i, is_point in enumerate(kinds):
        # the first argument takes the full shape, the others a trailing part or none
        cut = 0 if i == 0 else draw(st.integers(0, len(shape)))
        lead = shape[cut:]
        if is_point:
            args.append((draw(hnp.arrays(float, lead + (2,), elements=coord)), True))
        else:
            values = draw(hnp.arrays(float, lead, elements=st.floats(0, 100)))
            args.append((values if lead else float(values), False))
    return shape, args


@given(broadcast_args([True, False, True, False]))
def test_circle_circle_broadcasts_like_elementwise(case):
    """circle_circle on broadcast arrays equals stacking its elementwise results."""
    shape, args = case
    points, valid = circle_circle(*(a for a, _ in args))
    expected_points, expected_valid = _elementwise(circle_circle, shape, *args)
    assert points.shape == shape + (2, 2)
    np.testing.assert_array_equal(valid, expected_valid)
    # equal to rounding: numpy's vector and scalar loops may round the last bit apart
    np.testing.assert_allclose(points, expected_points, rtol=1e-14, atol=1e-12)


@pytest.mark.parametrize("kind", sorted(LINE_BASED))
@given(case=broadcast_args([True, True, True, False]))
def test_line_based_broadcasts_like_elementwise(kind, case):
    """Line/ray/segment functions on broadcast arrays equal their elementwise results."""
    shape, args = case
    fn = LINE_BASED[kind]
    points, valid = fn(*(a for a, _ in args))
    expected_points, expected_valid = _elementwise(fn, shape, *args)
    assert points.shape == shape + (2, 2)
    np.testing.assert_array_equal(valid, expected_valid)
    # equal to rounding: numpy's vector and scalar loops may round the last bit apart
    np.testing.assert_allclose(points, expected_points, rtol=1e-14, atol=1e-12)


@given(broadcast_args([True, True, True, True]))
def test_line_line_broadcasts_like_elementwise(case):
    """line_line on broadcast arrays equals stacking its elementwise results."""
    shape, args = case
    p, valid = line_line(*(a for a, _ in args))
    expected_p, expected_valid = _elementwise(line_line, shape, *args)
    assert p.shape == shape + (2,)
    np.testing.assert_array_equal(valid, expected_valid)
    np.testing.assert_allclose(p, expected_p, rtol=1e-14, atol=1e-12)


@given(hnp.arrays(float, (6, 2), elements=coord), hnp.arrays(float, (6,), elements=coord),
       st.floats(1.0, 100), hnp.arrays(float, (6,), elements=st.floats(1.0, 100)))
def test_scalar_radius_matches_array_radius(centres, offsets, r, radii):
    """A scalar radius against (N, 2) centres equals the same radius repeated N times."""
    other = centres + np.stack([offsets, np.zeros_like(offsets)], axis=-1)
    for fn, args in ((circle_circle, (centres, r, other, radii)),
                     (line_circle, (centres, other, np.zeros(2), r))):
        scalar = fn(*args)
        repeated = fn(*(np.full(6, a) if np.ndim(a) == 0 else a for a in args))
        for got, want in zip(scalar, repeated, strict=True):
            np.testing.assert_allclose(got, want, rtol=1e-14, atol=1e-12)


# -- polar_point, relative_point, point_along ---------------------------------


@given(point, coord, angle, exponent)
def test_polar_point_distance_and_angle(origin, distance, theta, k):
    """polar_point lies |distance| from the origin in direction theta (or opposite if negative)."""
    lam = 10.0**k
    origin, distance = lam * origin, lam * distance
    p = polar_point(origin, distance, theta)
    C = max(_norm(origin), abs(distance))
    offset = p - origin
    assert abs(_norm(offset) - abs(distance)) <= 1e-14 * C
    # the offset is distance times the unit vector at theta
    np.testing.assert_allclose(offset, distance * _direction(theta), rtol=0, atol=1e-14 * C)
    assume(abs(distance) > 1e-6 * C)
    along = np.sign(distance) * _direction(theta)
    assert abs(_cross(along, offset)) <= 1e-13 * C
    assert np.dot(along, offset) > 0


@given(point, point, point, coord, angle, exponent)
def test_relative_point_distance_and_angle(origin, start, through, distance, theta, k):
    """relative_point is |distance| from origin at theta counter-clockwise from start -> through."""
    lam = 10.0**k
    origin, start, through, distance = (lam * v for v in (origin, start, through, distance))
    direction = through - start
    length = _norm(direction)
    assume(length > 1e-6 * lam)
    p = relative_point(origin, start, through, distance, theta)
    C = max(_norm(origin), abs(distance))
    offset = p - origin
    assert abs(_norm(offset) - abs(distance)) <= 1e-13 * C
    assume(abs(distance) > 1e-6 * C)
    # the angle from the line's direction to the offset is theta (plus pi if negative)
    turned = np.arctan2(_cross(direction, offset), np.dot(direction, offset))
    expected = theta + (np.pi if distance < 0 else 0.0)
    wrapped = np.angle(np.exp(1j * (turned - expected)))
    # rounding the offset against the origin's coordinates costs eps * C / |distance|
    assert abs(wrapped) <= 1e-13 + 1e-15 * C / abs(distance)


@given(point, point, coord, coord, exponent)
def test_local_point_lies_at_its_coordinates_in_the_frame(origin, toward, u, v, k):
    """local_point is hypot(u, v) from the origin, atan2(v, u) counter-clockwise off the x axis.

    Equivalently its offset from the origin projects to u on the frame's x
    axis (origin towards toward) and to v on the y axis to its left.
    """
    lam = 10.0**k
    origin, toward, u, v = lam * origin, lam * toward, lam * u, lam * v
    direction = toward - origin
    length = _norm(direction)
    assume(length > 1e-6 * lam)
    p = local_point(origin, toward, u, v)
    C = max(_norm(origin), abs(u), abs(v))
    offset = p - origin
    assert abs(_norm(offset) - np.hypot(u, v)) <= 1e-13 * C
    ex = direction / length
    assert abs(np.dot(offset, ex) - u) <= 1e-13 * C
    assert abs(_cross(ex, offset) - v) <= 1e-13 * C
    assume(np.hypot(u, v) > 1e-6 * C)
    turned = np.arctan2(_cross(direction, offset), np.dot(direction, offset))
    wrapped = np.angle(np.exp(1j * (turned - np.arctan2(v, u))))
    assert abs(wrapped) <= 1e-13 + 1e-15 * C / np.hypot(u, v)


@given(point, point, point, coord, angle, exponent, st.floats(-1.0, 1.0))
def test_a_known_length_gives_the_relative_point_the_measured_one_gives(origin, start, through,
                                                                          distance, theta, k,
                                                                          error):
    """Given the line's length, relative_point_xy scales the direction by it, as measured:
    the same point to rounding of the configuration's size (the length given to rounding
    too, as a radius gives it)."""
    lam = 10.0**k
    origin, start, through, distance = (lam * v for v in (origin, start, through, distance))
    length = _norm(through - start)
    assume(length > 1e-6 * lam)
    known = length * (1 + error * 2.2e-16)
    measured = relative_point_xy(*origin, *start, *through, distance, theta)
    scaled = relative_point_xy(*origin, *start, *through, distance, theta, length=known)
    C = max(_norm(origin), abs(distance), lam)
    np.testing.assert_allclose(scaled, measured, rtol=0, atol=1e-14 * C)


@given(point, point, coord, coord, exponent)
def test_a_known_length_gives_the_local_point_the_measured_one_gives(origin, toward, u, v, k):
    """local_point_xy with the frame's length given: the point it measures, to rounding."""
    lam = 10.0**k
    origin, toward, u, v = lam * origin, lam * toward, lam * u, lam * v
    length = _norm(toward - origin)
    assume(length > 1e-6 * lam)
    measured = local_point_xy(*origin, *toward, u, v)
    scaled = local_point_xy(*origin, *toward, u, v, length=length)
    C = max(_norm(origin), abs(u), abs(v), lam)
    np.testing.assert_allclose(scaled, measured, rtol=0, atol=1e-14 * C)


@pytest.mark.parametrize("length", [0.0, -1.0, np.nan, 1e-320])
def test_a_known_length_that_cannot_scale_takes_the_measured_way(length):
    """A length that is not positive, or one the distance overflows against, is measured
    instead: a zero-length line has no direction (NaN); a real one its point."""
    with np.errstate(all="ignore"):
        nowhere = relative_point_xy(0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0, 0.0, length=length)
        assert np.isnan(nowhere).all()
        # a subnormal length given for a line of length 10: the ratio overflows
        here = relative_point_xy(0.0, 0.0, 0.0, 0.0, 0.0, 10.0, 1e10, 0.0, length=length)
    np.testing.assert_allclose(here, [0.0, 1e10], rtol=1e-15)


@given(point, point, coord, coord)
def test_local_point_is_relative_point_by_distance_and_angle(origin, toward, u, v):
    """The coordinates (u, v) are the distance hypot(u, v) at the angle atan2(v, u)."""
    assume(_norm(toward - origin) > 1e-6)
    np.testing.assert_allclose(
        local_point(origin, toward, u, v),
        relative_point(origin, origin, toward, np.hypot(u, v), np.arctan2(v, u)),
        rtol=0, atol=1e-13 * max(_norm(origin), np.hypot(u, v), 1.0))


def test_local_point_on_axes_is_exact():
    """On the frame's axes no angle is rounded: a quarter turn gives exact coordinates."""
    np.testing.assert_array_equal(local_point([1, 2], [1, 7], [3, 0, -2], [0, 4, 0]),
                                  [[1, 5], [-3, 2], [1, 0]])


@settings(max_examples=30)
@given(hnp.arrays(float, (4, 2), elements=coord), hnp.arrays(float, (4, 2), elements=coord),
       hnp.arrays(float, (3, 1), elements=coord), hnp.arrays(float, (4,), elements=coord))
def test_local_point_broadcasts(origins, towards, us, vs):
    """local_point broadcasts u and v against the points' leading axes."""
    with np.errstate(all="ignore"):
        p = local_point(origins, towards, us, vs)
    assert p.shape == (3, 4, 2)
    for i, j in np.ndindex(3, 4):
        np.testing.assert_array_equal(p[i, j], local_point(origins[j], towards[j], us[i, 0],
                                                           vs[j]))


@given(point, point, coord, exponent)
def test_point_along_distance_and_side(start, through, distance, k):
    """point_along is |distance| from start on the line, towards through when positive."""
    lam = 10.0**k
    start, through, distance = lam * start, lam * through, lam * distance
    direction = through - start
    assume(_norm(direction) > 1e-6 * lam)
    p = point_along(start, through, distance)
    C = max(_norm(start), abs(distance))
    offset = p - start
    assert abs(_norm(offset) - abs(distance)) <= 1e-13 * C
    assert abs(_cross(direction, offset)) / _norm(direction) <= 1e-13 * C
    if abs(distance) > 1e-6 * C:
        assert np.sign(np.dot(direction, offset)) == np.sign(distance)


@given(point, coord)
def test_zero_length_direction_gives_nan(start, distance):
    """relative_point and point_along give NaN, without warnings, for a zero-length line."""
    assert np.isnan(_no_warnings(point_along, start, start, distance)).all()
    assert np.isnan(_no_warnings(relative_point, start, start, start, distance, 0.3)).all()
    assert np.isnan(_no_warnings(local_point, start, start, distance, 0.3)).all()


@settings(max_examples=30)
@given(hnp.arrays(float, (2, 3, 2), elements=coord), hnp.arrays(float, (3,), elements=coord),
       hnp.arrays(float, (2, 1), elements=angle))
def test_polar_point_broadcasts(origins, distances, angles):
    """polar_point broadcasts distance and angle against the origins' leading axes."""
    p = polar_point(origins, distances, angles)
    assert p.shape == (2, 3, 2)
    for i, j in np.ndindex(2, 3):
        np.testing.assert_array_equal(p[i, j],
                                      polar_point(origins[i, j], distances[j], angles[i, 0]))


@pytest.mark.parametrize("small", [1e-4, 1e-2, 1.0])
def test_a_small_circle_that_misses_is_not_taken_as_touching(small):
    """A miss of 1e-9 of the scale is invalid, however small one circle is; touching is valid."""
    for miss, expected in [(1e-9, False), (0.0, True), (-1e-9, True)]:
        _, valid = circle_circle([0.0, 0.0], small, [1.0 + small + miss, 0.0], 1.0)
        assert bool(valid[0]) is expected, (small, miss)
        _, valid = line_circle([-5.0, small + miss], [5.0, small + miss], [0.0, 0.0], small)
        assert bool(valid[0]) is expected, (small, miss)


# -- kernels on Python floats: degenerate elements are NaN, never an exception --------

KERNELS = {
    # kernel, number of arguments, the indices of the arguments that are lengths
    "circle_circle_xy": (circle_circle_xy, 6),
    "line_circle_xy": (line_circle_xy, 7),
    "line_line_xy": (line_line_xy, 8),
    "relative_point_xy": (relative_point_xy, 8),
    "local_point_xy": (local_point_xy, 6),
}

# small integers make coincident points, parallel lines and zero lengths common
grid_coord = st.one_of(st.integers(-2, 2).map(float), coord)
ARGUMENTS = {
    "circle_circle_xy": st.tuples(grid_coord, grid_coord, radius, grid_coord, grid_coord, radius),
    "line_circle_xy": st.tuples(*[grid_coord] * 6, radius),
    "line_line_xy": st.tuples(*[grid_coord] * 8),
    "relative_point_xy": st.tuples(*[grid_coord] * 6, coord, angle),
    "local_point_xy": st.tuples(*[grid_coord] * 4, coord, coord),
}


@pytest.mark.parametrize("name", sorted(KERNELS))
@given(data=st.data())
def test_kernels_treat_python_floats_as_arrays_of_one(name, data):
    """Python floats give what one-element arrays give, NaN included, and never raise."""
    kernel, _ = KERNELS[name]
    args = data.draw(ARGUMENTS[name])
    with np.errstate(all="ignore"):
        scalar = kernel(*args)
        array = kernel(*(np.array([a]) for a in args))
    for got, want in zip(scalar, array, strict=True):
        assert np.ndim(got) == 0
        np.testing.assert_allclose(np.reshape(got, 1), want, rtol=1e-14, atol=1e-12)


@pytest.mark.parametrize(("name", "args"), [
    ("circle_circle_xy", (1.0, 2.0, 3.0, 1.0, 2.0, 3.0)),  # coincident centres
    ("circle_circle_xy", (1.0, 2.0, 0.0, 1.0, 2.0, 0.0)),  # and zero radii
    ("line_circle_xy", (1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 5.0)),  # zero-length line
    ("line_line_xy", (0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0)),  # parallel
    ("line_line_xy", (0.0, 0.0, 1.0, 0.0, 2.0, 0.0, 3.0, 0.0)),  # coincident
    ("line_line_xy", (0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0)),  # zero-length line
    ("relative_point_xy", (0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0, 0.5)),  # zero-length line
    ("relative_point_xy", (0, 0, 1, 1, 1, 1, 2, 0)),  # Python ints
    ("local_point_xy", (1.0, 1.0, 1.0, 1.0, 2.0, 0.5)),  # origin and toward coincide
    ("local_point_xy", (1, 1, 1, 1, 2, 0)),  # Python ints
])
def test_degenerate_python_floats_give_nan(name, args):
    """Degenerate fixed geometry in plain Python numbers gives NaN points, not ZeroDivisionError."""
    kernel, _ = KERNELS[name]
    with np.errstate(all="ignore"):
        out = kernel(*args)
    assert np.isnan(out[0]) and np.isnan(out[1])


# -- scale: the kernels work relative to the configuration's own size ---------------

# (index of each length argument); the first point of every kernel is at the origin
LENGTHS = {
    "circle_circle_xy": (2, 3, 4, 5),
    "line_circle_xy": (2, 3, 4, 5, 6),
    "line_line_xy": (2, 3, 4, 5, 6, 7),
    "relative_point_xy": (2, 3, 4, 5, 6),
    "local_point_xy": (2, 3, 4, 5),
}
ORIGIN_FIRST = {
    "circle_circle_xy": st.tuples(st.just(0.0), st.just(0.0), radius, grid_coord, grid_coord,
                                  radius),
    "line_circle_xy": st.tuples(st.just(0.0), st.just(0.0), *[grid_coord] * 4, radius),
    "line_line_xy": st.tuples(st.just(0.0), st.just(0.0), *[grid_coord] * 6),
    # angles that are not subnormal: their sines would be, at scale 1 already
    "relative_point_xy": st.tuples(st.just(0.0), st.just(0.0), *[grid_coord] * 4, coord,
                                   angle.map(lambda a: 0.0 if abs(a) < 1e-9 else a)),
    "local_point_xy": st.tuples(st.just(0.0), st.just(0.0), *[grid_coord] * 2, coord, coord),
}


@pytest.mark.parametrize("name", sorted(KERNELS))
@given(data=st.data(), bits=st.integers(-960, 960))
def test_kernels_scale_exactly(name, data, bits):
    """Scaling every length by 2**bits scales every point by 2**bits and nothing else changes.

    Scaling by a power of two is exact in floating point, so the kernels must
    give bit for bit the same answer at 1e-289 or 1e289 as at 1: squares that
    overflow or go subnormal may not change a single root or validity.
    """
    kernel, _ = KERNELS[name]
    args = list(data.draw(ORIGIN_FIRST[name]))
    if name == "relative_point_xy":  # the origin of the point is the line's start too
        args[0], args[1] = args[2], args[3]
    factor = 2.0**bits
    scaled = [a * factor if i in LENGTHS[name] or (name == "relative_point_xy" and i < 2)
              else a for i, a in enumerate(args)]
    shape = (3,)  # arrays, so both calls take numpy's same loops
    with np.errstate(all="ignore"):
        unit = kernel(*(np.full(shape, a) for a in args))
        big = kernel(*(np.full(shape, a) for a in scaled))
    points = 2 if name in ("line_line_xy", "relative_point_xy", "local_point_xy") else 4
    for i, (u, b) in enumerate(zip(unit, big, strict=True)):
        if i < points:
            np.testing.assert_array_equal(b, u * factor)
        else:  # parameters along lines, margins, sines: dimensionless
            np.testing.assert_array_equal(b, u)


@given(st.floats(1e-280, 1e280), st.floats(0.1, 10), st.floats(0.1, 10), grid_angle,
       st.floats(-1e3, 1e3))
def test_circle_circle_is_right_at_any_scale(scale, r1, r2, theta, offset):
    """Roots at any scale lie on both circles to rounding of that scale, as at scale 1."""
    d = abs(r1 - r2) + 0.5 * (r1 + r2 - abs(r1 - r2))  # between the radii's difference and sum
    c1 = np.array([offset, -offset]) * scale
    c2 = c1 + scale * d * _direction(theta)
    points, valid = circle_circle(c1, scale * r1, c2, scale * r2)
    assert valid.all()
    size = scale * max(r1, r2, d, abs(offset))
    for p in points:
        assert abs(_norm(p - c1) - scale * r1) <= 1e-13 * size
        assert abs(_norm(p - c2) - scale * r2) <= 1e-13 * size


def test_scale_range_covers_the_documented_figures():
    """The documented range reaches the scales where squares used to fail, with room."""
    low, high = SCALE_RANGE
    assert low <= 1e-200 and high >= 1e200
    assert low > np.finfo(float).tiny  # beyond, inputs are subnormal: few digits left


@given(base=hnp.arrays(float, st.integers(1, 40), elements=st.floats(-1e3, 1e3)),
       steps=st.lists(st.floats(-NEARBY, NEARBY), min_size=1, max_size=4),
       wide=st.booleans())
def test_cos_sin_of_nearby_rows_are_those_of_numpy_to_rounding(base, steps, wide):
    """Rows found by angle addition from the first; rows too far apart computed in full."""
    rows = np.concatenate([base] + [base + (2 if wide else 1) * step for step in steps])
    with nearby_rows(1 + len(steps), len(base)):
        c, s = cos_sin(rows)
    if wide and max(abs(step) for step in steps) > 0.5000001 * NEARBY:
        np.testing.assert_array_equal(c, np.cos(rows))
        np.testing.assert_array_equal(s, np.sin(rows))
    np.testing.assert_allclose(c, np.cos(rows), rtol=0, atol=4 * np.finfo(float).eps)
    np.testing.assert_allclose(s, np.sin(rows), rtol=0, atol=4 * np.finfo(float).eps)
    # outside the context, or for an array of another size, numpy's own
    np.testing.assert_array_equal(cos_sin(rows)[0], np.cos(rows))
    with nearby_rows(1 + len(steps), len(base) + 1):
        np.testing.assert_array_equal(cos_sin(rows)[1], np.sin(rows))


def test_cos_sin_leaves_nan_to_numpy():
    angles = np.array([0.0, 1.0, np.nan, 1.0])
    with nearby_rows(2, 2):
        c, _ = cos_sin(angles)
    np.testing.assert_array_equal(c, np.cos(angles))


@given(st.floats(allow_nan=True, allow_infinity=True))
def test_cos_sin_of_one_number_never_raises(angle):
    """A Python float takes the math module's way, and gives what numpy gives."""
    with np.errstate(invalid="ignore"):
        expected = np.cos(angle), np.sin(angle)
        found = cos_sin(angle)
    np.testing.assert_allclose(found, expected, rtol=0, atol=2 * np.finfo(float).eps)


any_radius = st.one_of(st.floats(-5, 60), st.just(0.0), st.just(float("nan")),
                       st.just(float("inf")))


@given(centres=hnp.arrays(float, 7, elements=st.floats(-50, 50)), r1=any_radius, r2=any_radius)
def test_circle_circle_gives_the_same_for_radii_as_floats_or_numpy_numbers(centres, r1, r2):
    """Radii given as Python floats (checked on numbers) give what numpy scalars give."""
    x1, y1, x2 = centres[:3], centres[3:6], centres[6]
    with np.errstate(all="ignore"):
        plain = circle_circle_xy(x1, y1, float(r1), x2, 0.0, float(r2))
        scalar = circle_circle_xy(x1, y1, np.float64(r1), x2, 0.0, np.float64(r2))
    for a, b in zip(plain, scalar, strict=True):
        np.testing.assert_array_equal(a, b)
