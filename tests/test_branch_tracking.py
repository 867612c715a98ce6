"""Branch tracking along any sample path, against answers that need no tracking.

Between two samples the inputs move along the straight segment joining them;
a two-root node changes branch exactly where its roots meet on that path.
For a four-bar whose roots never meet along the path, the closed form on
the declared branch is the exact answer at every sample; where the path
crosses a change point, a dense sweep of the same path (200 sub-samples a
step) is.
"""

import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from mechanisms import fourbar, parallelograms_in_series, sixbar

import geokin
from geokin import Construction, sweep
from geokin.circuits import circuit, limits

DEG = np.pi / 180


def closed_form_left(theta, ground, crank, coupler, rocker):
    """B of a four-bar on the root left of A -> O4, by the law of cosines; NaN if none."""
    ax, ay = crank * np.cos(theta), crank * np.sin(theta)
    dx, dy = ground - ax, -ay
    d = np.hypot(dx, dy)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        # angle at A between A -> O4 and A -> B
        cos_phi = (coupler**2 + d**2 - rocker**2) / (2 * coupler * d)
        phi = np.arccos(cos_phi)
    base = np.arctan2(dy, dx)
    return np.stack([ax + coupler * np.cos(base + phi), ay + coupler * np.sin(base + phi)], -1)


def crank_intervals(ground, crank, coupler, rocker):
    """The crank angles where the four-bar assembles, as [lo, hi] in (-2 pi, 2 pi), or None
    for a full turn: where |b - c| <= |A - O4| <= b + c."""
    # |A - O4|^2 = a^2 + g^2 - 2 a g cos(theta)
    lo_cos = (crank**2 + ground**2 - (coupler + rocker) ** 2) / (2 * crank * ground)
    hi_cos = (crank**2 + ground**2 - (coupler - rocker) ** 2) / (2 * crank * ground)
    lo_cos, hi_cos = max(lo_cos, -1.0), min(hi_cos, 1.0)
    if lo_cos > hi_cos:
        return []
    if lo_cos <= -1 and hi_cos >= 1:
        return None
    # cos(theta) in [lo_cos, hi_cos]: theta in [acos(hi), acos(lo)] and its mirror
    a, b = np.arccos(hi_cos), np.arccos(lo_cos)
    if a == 0:
        return [(-b, b)]
    if b == np.pi:
        return [(a, 2 * np.pi - a)]
    return [(a, b), (-b, -a)]


lengths = st.floats(1.0, 10.0)


def grashof_margin(g, a, b, c):
    s = sorted([g, a, b, c])
    return abs(s[0] + s[3] - s[1] - s[2])


@st.composite
def four_bars(draw):
    g, a, b, c = (draw(lengths) for _ in range(4))
    # clear of the change-point lengths, where the roots meet inside the motion
    assume(grashof_margin(g, a, b, c) > 1e-2)
    assume(crank_intervals(g, a, b, c) != [])
    return g, a, b, c


def assert_closed_form(s, theta, g, a, b, c):
    """geokin equals the closed form on the declared branch wherever it assembles."""
    exact = closed_form_left(theta, g, a, b, c)
    d = np.hypot(g - a * np.cos(theta), a * np.sin(theta))
    # samples within rounding of a toggle may be either way; all others must agree
    inside = (d < b + c - 1e-9) & (d > abs(b - c) + 1e-9)
    outside = (d > b + c + 1e-9) | (d < abs(b - c) - 1e-9)
    assert s.valid[inside].all() and not s.valid[outside].any()
    np.testing.assert_allclose(s["B"][s.valid], exact[s.valid], atol=1e-9)
    assert s.events == ()


@given(four_bars(), st.floats(-180, 180), st.floats(0.5, 170), st.integers(2, 40))
def test_uniform_steps_of_any_size_never_change_branch(bar, start, step, count):
    g, a, b, c = bar
    count = min(count, int(5 * 360 / step) + 2)  # several turns at most
    theta = (start + step * np.arange(count)) * DEG
    assert_closed_form(sweep(fourbar(g, a, b, c), theta), theta, g, a, b, c)


@given(four_bars(), st.data())
def test_back_and_forth_walks_inside_the_interval_never_change_branch(bar, data):
    g, a, b, c = bar
    intervals = crank_intervals(g, a, b, c)
    lo, hi = (-np.pi, 3 * np.pi) if intervals is None else data.draw(
        st.sampled_from(intervals))
    inset = 0.05 * DEG
    lo, hi = lo + inset, hi - inset
    assume(hi > lo)
    theta = [data.draw(st.floats(lo, hi))]
    for _ in range(data.draw(st.integers(1, 60))):
        move = data.draw(st.floats(-40 * DEG, 40 * DEG))
        theta.append(float(np.clip(theta[-1] + move, lo, hi)))
    theta = np.array(theta)
    s = sweep(fourbar(g, a, b, c), theta)
    assert s.valid.all()
    np.testing.assert_allclose(s["B"], closed_form_left(theta, g, a, b, c), atol=1e-9)
    assert s.events == ()


def change_point_fourbar(draw):
    """A four-bar with s + l = p + q: its roots meet where all four joints line up."""
    kind = draw(st.sampled_from(["parallelogram", "kite", "general"]))
    a, b = draw(lengths), draw(lengths)
    if kind == "parallelogram":
        g, c = b, a  # ground = coupler, crank = rocker
    elif kind == "kite":
        b, c = a, draw(lengths)  # crank = coupler, ground = rocker
        g = c
    else:
        g = draw(lengths)
        c = g + b - a  # ground + coupler = crank + rocker
        assume(c >= 1.0)
    # the crank pin never reaches the rocker's pivot, where the loop degenerates
    assume(abs(g - a) > 0.1)
    return g, a, b, c


def change_angles(g, a, b, c):
    """The crank angles in [0, 2 pi) where the four-bar's roots meet (joints in line)."""
    found = []
    for theta in (0.0, np.pi):
        d = abs(g - a * np.cos(theta))
        if min(abs(d - (b + c)), abs(d - abs(b - c))) < 1e-9 * (g + a + b + c):
            found.append(theta)
    return found


def dense(theta, per_step=200):
    fractions = np.arange(per_step) / per_step
    inner = theta[:-1, None] + fractions[None, :] * np.diff(theta)[:, None]
    return np.concatenate([inner.ravel(), theta[-1:]])


@given(st.data())
def test_paths_through_change_points_match_a_dense_sweep(data):
    g, a, b, c = change_point_fourbar(data.draw)
    meets = change_angles(g, a, b, c)
    assume(meets)
    start = data.draw(st.sampled_from(meets)) + data.draw(st.floats(-0.1, 0.1)) * DEG
    step = data.draw(st.floats(0.5, 170)) * DEG * data.draw(st.sampled_from([1, -1]))
    theta = start + step * np.arange(data.draw(st.integers(2, 12)))
    branch = data.draw(st.sampled_from(["left", "right"]))
    c4 = fourbar(g, a, b, c, branch=branch)
    coarse = sweep(c4, theta)
    fine = sweep(c4, dense(theta))
    # a change-point four-bar may have toggles too: the same samples assemble
    assert (coarse.valid == fine.valid[::200]).all()
    np.testing.assert_allclose(coarse["B"], fine["B"][::200], atol=1e-9 * (g + a + b + c))


@pytest.mark.parametrize("samples", [3, 7, 19, 46])
def test_the_six_bar_at_coarse_samplings_matches_its_dense_sweep(samples):
    c = sixbar()
    theta = np.linspace(0, 1800 * DEG, samples)
    coarse = sweep(c, theta)
    fine = sweep(c, dense(theta))
    assert coarse.events == () and fine.events == ()
    for point in c.nodes:
        np.testing.assert_allclose(coarse[point], fine[point][::200], atol=1e-9)
    for node, branch in coarse.branches.items():
        assert (branch == fine.branches[node][0]).all()
    np.testing.assert_allclose(coarse["M"][-1], [134.1040, 103.5815], atol=1e-4)


def test_a_coarse_sixbar_keeps_b_on_its_branch_where_its_roots_stay_far_apart():
    s = sweep(sixbar(), np.linspace(0, 1800 * DEG, 19))
    assert (s.branches["B"] == 0).all()
    half_chord = np.hypot(*(s["B"] - s["A"]).T)
    assert half_chord.min() > 32


# -- near: the root nearer the sketch point, for every two-root kind ---------------


def test_near_picks_the_nearer_root_of_a_circle_pair():
    c = Construction()
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.polar("A", "O2", 6, "theta")
    c.fixed("O4", 1, -4)
    c.circle_circle("B", ("A", "O4"), (4, 5), near=(2, 1))
    np.testing.assert_allclose(sweep(c, [0.0])["B"][0], [2.0975609756, 0.8780487805])


@pytest.mark.parametrize("kind", ["line_circle", "ray_circle", "segment_circle"])
@pytest.mark.parametrize("near, expected", [((-3, 0.5), (-4, 1)), ((3.5, 0), (4, 1))])
def test_near_picks_the_nearer_root_of_a_line_and_circle(kind, near, expected):
    # the line y = 1 from (-10, 1) to (10, 1) meets the circle of radius sqrt(17)
    # about the origin at (-4, 1) and (4, 1)
    c = Construction()
    c.input("s", kind="length", range=(0, 1))
    c.fixed("O", 0, 0)
    c.fixed("P", -10, 1)
    c.fixed("Q", 10, 1)
    getattr(c, kind)("X", ("P", "Q"), "O", "sqrt(17) + s", near=near)
    np.testing.assert_allclose(sweep(c, [0.0])["X"][0], expected, atol=1e-12)


def test_near_is_judged_at_the_first_sample_that_assembles():
    c = Construction()
    c.input("r", kind="length", range=(0, 2))
    c.fixed("O", 0, 0)
    c.fixed("Q", 2, 0)
    # the circles meet only from r = 1 on; then at (1, +-sqrt(r^2 - 1))
    c.circle_circle("X", ("O", "Q"), ("r", "r"), near=(1, -0.1))
    s = sweep(c, [0.5, 0.8, 1.5, 2.0])
    assert list(s.valid) == [False, False, True, True]
    assert (s["X"][2:, 1] < 0).all()


@pytest.mark.parametrize("x", [3e7, -1e9])
def test_near_is_judged_where_the_roots_are_far_from_the_origin(x):
    """The mechanism is found around its pivots; ``near`` stays absolute."""
    def make(x):
        c = Construction()
        c.input("theta")
        c.fixed("O2", x, x)
        c.polar("A", "O2", 6, "theta")
        c.fixed("O4", x + 1, x - 4)
        c.circle_circle("B", ("A", "O4"), (4, 5), near=(x + 2, x + 1))
        return c
    for theta in ([0.0], [0.3, 0.0]):
        far, near = sweep(make(x), theta), sweep(make(0.0), theta)
        assert far.branches["B"].tolist() == near.branches["B"].tolist()
        np.testing.assert_allclose(far["B"] - [x, x], near["B"], atol=1e-15 * abs(x))


@pytest.mark.parametrize("x", [2500.0, 1e5, 3e7, 1e9])
@pytest.mark.parametrize("start, samples", [(0.3, 721), (0.5, 721), (0.0, 40_001)])
def test_a_parallelogram_far_from_the_origin_changes_branch_as_at_the_origin(x, start, samples):
    """Its pivots x away: the same changes, about where they are, a parallelogram throughout.

    Its points are found around its pivots; its roots meet within the
    rounding of where they are, 1e-7 sqrt(R) of the scale for coordinates R
    times the scale: B may take the other root that near the change point.
    """
    theta = np.linspace(start, start + 4 * np.pi, samples)
    far, near = (sweep(fourbar(10, 4, 10, 4, ground_at=(offset, -offset)), theta)
                 for offset in (x, 0.0))
    assert len(near.events) in (3, 4)

    def angles(s):
        return np.array([theta[e.index - 1] + e.fraction * (theta[e.index] - theta[e.index - 1])
                         for e in s.events])

    assert len(far.events) == len(near.events)
    np.testing.assert_allclose(angles(far), angles(near), rtol=0, atol=1e-6 * np.sqrt(x))
    coupler = far["B"] - far["A"]
    assert np.abs(coupler[:, 1]).max() <= 1e-6 * np.sqrt(10 * x)


def test_variants_of_a_mechanism_far_from_the_origin_share_its_frame():
    """A varied pivot coordinate: the variant of the nominal value is the nominal sweep."""
    c = Construction()
    c.input("theta")
    c.parameter("x0", 3e7)
    c.fixed("O2", "x0", "-x0")
    c.fixed("O4", "x0 + 10", "-x0")
    c.polar("A", "O2", 4, "theta")
    c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
    theta = np.linspace(0.3, 0.3 + 4 * np.pi, 721)
    alone, variant = sweep(c, theta), sweep(c, theta, parameters={"x0": [3e7]})
    assert len(alone.events) == 4
    assert [(e.index, e.fraction) for e in variant.events] == [
        (e.index, e.fraction) for e in alone.events]
    np.testing.assert_array_equal(variant["B"][0], alone["B"])


@pytest.mark.parametrize("o2, o4", [((1e6, -0.5), (1e6 + 10, 0.1)),
                                     ((0.1, 1e6), (10.1, 1e6)),
                                     ((-3e7 + 0.3, 4e5 - 0.7), (-3e7 + 10.3, 4e5 - 0.7))])
def test_fixed_points_far_from_the_origin_come_back_as_written(o2, o4):
    c = Construction()
    c.input("t")
    c.fixed("O2", *o2)
    c.fixed("O4", *o4)
    c.polar("A", "O2", 4, "t")
    c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
    s = sweep(c, np.linspace(0, 1, 5))
    assert (s["O2"] == o2).all() and (s["O4"] == o4).all()


@pytest.mark.parametrize("x", [2500.3, 5000.3, 12345.6, 100000.3, 1e6 + 0.3])
def test_a_parallelogram_drawn_in_decimal_coordinates_keeps_its_change_points(x):
    """Its second pivot at x + 52.6 is 52.6 only to the rounding of x: still a parallelogram.

    Found around its pivots, the mechanism as rounded is a near miss of a
    parallelogram by up to 1e-11 of its size; its roots meet within the
    rounding of the coordinates it is written in, and it passes its change
    points as the parallelogram it was meant to be.
    """
    theta = np.linspace(0.1, 0.1 + 4 * np.pi, 25)
    s = sweep(fourbar(52.6, 30.25, 52.6, 30.25, ground_at=(x, -1800.7)), theta)
    assert len(s.events) == 4
    coupler = s["B"] - s["A"]
    assert np.abs(coupler[:, 1]).max() <= 1e-9 * x


@pytest.mark.parametrize("x, y", [(5000.3, -1800.7), (12345.6, 0.0), (100000.3, 7.1),
                                  (2500.3, -911.9)])
def test_limits_and_circuits_see_the_change_points_a_sweep_sees_far_from_the_origin(x, y):
    """The decimal parallelogram turns fully, and its circuit is the one at the origin.

    Rounded, its roots miss by 2e-15 of its size at pi (at 0 for the last):
    a gap of 4e-7 rad for a search that takes them as they are, which then
    bounced between its two sides and never closed. The primitives, and a
    sweep, find it assembled across, its roots met: it passes its change
    point. The last gap straddles the ends of the searched turn.
    """
    far, near = (fourbar(52.6, 30.25, 52.6, 30.25, ground_at=at) for at in ((x, y), (0, 0)))
    assert limits(far).full_turn and limits(near).full_turn
    far_circuit, near_circuit = circuit(far), circuit(near)
    assert len(far_circuit) == len(near_circuit)
    assert [(e.index, e.before, e.after) for e in far_circuit.events] == [
        (e.index, e.before, e.after) for e in near_circuit.events]
    # at a change point the roots are known to 1e-7 sqrt(R) of the scale
    for point in ("A", "B"):
        np.testing.assert_allclose(far_circuit[point] - [x, y], near_circuit[point],
                                   rtol=0, atol=1e-6 * np.sqrt(x))


@pytest.mark.parametrize("x, y, samples", [(0.0, 0.0, 361), (5000.3, -1800.7, 361),
                                           (2500.3, -911.9, 361), (5000.3, -1800.7, 121)])
def test_near_misses_of_two_nodes_overlapping_are_one_meeting(x, y, samples):
    """B's and C's near misses at pi overlap, neither inside the other (at the origin too).

    A sweep passes both change points together; so does the circuit, in one
    turn, both nodes changing branch at its middle sample (at pi).
    """
    c = parallelograms_in_series(x, y)
    assert limits(c).full_turn
    whole = circuit(c, start=0.0, samples_per_pass=samples)
    theta = whole.inputs["theta"]
    np.testing.assert_allclose(theta, np.linspace(0, 2 * np.pi, samples), rtol=0, atol=1e-12)
    at_pi = int(np.argmin(np.abs(theta - np.pi)))
    assert theta[at_pi] == pytest.approx(np.pi, abs=1e-12)  # the change point is a sample
    # each changes branch after the sample at the change point: in the step ending next
    assert sorted((e.node, e.index) for e in whole.events) == [("B", at_pi + 1),
                                                                ("C", at_pi + 1)]
    theta = np.linspace(np.pi - 1e-6, np.pi + 1e-6, 2001)
    assert sweep(c, theta).valid.all()


@pytest.mark.parametrize("x, y, search", [(2500.3, -911.9, (0.0, 2 * np.pi)),
                                          (5000.3, -1800.7, (0.0, np.pi)),
                                          (5000.3, -1800.7, (np.pi, 2 * np.pi))])
def test_a_near_miss_at_an_end_of_the_searched_range_is_no_limit(x, y, search):
    """The decimal parallelogram's change point at an end of ``search_range``: a range end.

    A sweep is valid there, as it is at the origin, where the search ends
    on the range's ends too.
    """
    far = fourbar(52.6, 30.25, 52.6, 30.25, ground_at=(x, y))
    near = fourbar(52.6, 30.25, 52.6, 30.25)
    for found in (limits(far, search_range=search), limits(near, search_range=search)):
        [(lo, hi)] = found.intervals
        assert (lo.kind, lo.value, hi.kind, hi.value) == ("range", search[0], "range", search[1])
    assert sweep(far, np.array(search)).valid.all()


@pytest.mark.parametrize("x, y", [(0.0, 0.0), (5000.3, -1800.7), (100000.3, 7.1)])
def test_a_narrow_gap_wider_than_the_rounding_stays_a_gap(x, y):
    """A coupler 1e-6 too long: no crank position near 0 reaches; limits closed by hand.

    At crank angle t, A to O4 is sqrt(a^2 + d^2 - 2ad cos t); B is found while
    that is at least b - c, so cos t <= (a^2 + d^2 - (b - c)^2) / 2ad.
    """
    a, b, c, d = 30.25, 52.6 + 1e-6, 30.25, 52.6
    found = limits(fourbar(d, a, b, c, ground_at=(x, y)))
    assert not found.full_turn
    edge = np.arccos((a * a + d * d - (b - c) ** 2) / (2 * a * d))
    [(lo, hi)] = found.intervals
    assert lo.kind == hi.kind == "tangent"
    np.testing.assert_allclose([lo.value, hi.value], [edge, 2 * np.pi - edge], rtol=0,
                               atol=1e-9)


# -- the defects the contract removes ------------------------------------------------


def double_rocker():
    """Grashof double-rocker: ground 10, input 8, coupler 3, output 9."""
    return fourbar(10, 8, 3, 9)


def test_a_swing_that_turns_back_short_of_the_toggle_keeps_its_branch():
    theta = np.r_[np.arange(40, 82.7, 1.0), 82.7, np.arange(81.7, 39.0, -1.0)] * DEG
    found = limits(double_rocker())
    assert any(abs(hi.value - 82.8192 * DEG) < 1e-5 for _, hi in found.intervals)
    s = sweep(double_rocker(), theta)
    assert s.valid.all() and s.events == ()
    np.testing.assert_allclose(s["B"], closed_form_left(theta, 10, 8, 3, 9), atol=1e-9)


def test_a_swing_that_turns_back_exactly_at_the_toggle_keeps_its_branch():
    # a Grashof double-rocker (ground 4, input 3, coupler 1.5, output 3.5) whose input
    # reaches its toggle at 90 degrees, where |A - O4| = 5 = coupler + output: turning
    # back there is the limit of turning back just short of it
    g, a, b, c = 4, 3, 1.5, 3.5
    for top in (90 - 1e-9, 90 - 1e-13, 90):
        theta = np.r_[np.arange(80, 90, 1.0), top, np.arange(89, 79, -1.0)] * DEG
        s = sweep(fourbar(g, a, b, c), theta)
        assert s.valid.all() and s.events == ()
        np.testing.assert_allclose(s["B"], closed_form_left(theta, g, a, b, c), atol=1e-6)


def test_a_path_through_a_graze_at_a_sample_changes_branch_there():
    # the parallelogram crossing its change point exactly at a sample, onwards
    theta = np.radians([150.0, 180.0, 210.0])
    s = sweep(parallelogram(), theta)
    assert [(e.index, e.fraction) for e in s.events] == [(2, 0.0)]
    assert on_the_parallelogram(s).all()
    # and turning back there: the parallelogram retraces its path
    back = sweep(parallelogram(), np.radians([150.0, 180.0, 150.0]))
    assert back.events == () and on_the_parallelogram(back).all()


def test_a_swing_that_turns_back_at_the_limit_found_keeps_its_branch():
    # limits lie on the assemblable side of the toggle, 1e-12 from it in the input:
    # the roots are still about 1e-6 of the scale apart there, and do not meet
    toggle = next(hi.value for _, hi in limits(double_rocker()).intervals
                  if abs(hi.value - 82.8192 * DEG) < 1e-5)
    theta = np.r_[np.arange(75, 82.8, 1.0) * DEG, toggle, np.arange(82, 74, -1.0) * DEG]
    s = sweep(double_rocker(), theta)
    assert s.valid.all() and s.events == ()


def parallelogram():
    return fourbar(10, 4, 10, 4)


def on_the_parallelogram(s):
    return np.hypot(*(s["B"] - s["A"] - [10, 0]).T) < 1e-9


def test_a_change_point_between_the_first_two_samples_is_passed():
    s = sweep(parallelogram(), (179.9 + np.arange(361.0)) * DEG)
    assert on_the_parallelogram(s).all()
    assert [e.index for e in s.events] == [1, 181]
    assert all(abs(e.fraction - 0.1) < 1e-4 for e in s.events)


@pytest.mark.parametrize("degrees", [[90, 360, 450], [90, 180, 360, 450], [90, 180, 540, 630],
                                     [0, 180, 360], [180, 180, 360, 360, 450],
                                     [90, 180, 90, 180, 270]])
def test_change_points_at_consecutive_samples_are_each_passed(degrees):
    theta = np.radians(degrees)
    s = sweep(parallelogram(), theta)
    if degrees[0] % 180:  # started off a change point, on the parallelogram
        assert on_the_parallelogram(s).all()
    fine = sweep(parallelogram(), dense(theta))
    np.testing.assert_allclose(s["B"], fine["B"][::200], atol=1e-9)


@pytest.mark.parametrize("step", [60.0, 90.0, 170.0])
def test_every_change_point_is_passed_at_coarse_steps(step):
    theta = (1.0 + step * np.arange(int(1440 / step) + 1)) * DEG
    s = sweep(parallelogram(), theta)
    assert on_the_parallelogram(s).all()
    assert len(s.events) == int((theta[-1] / DEG) // 180)


def peaucellier(turn=(-np.pi / 2, np.pi / 2)):
    """A Peaucellier-Lipkin inversor: its two dyads A, B reach their toggles together."""
    c = Construction("inversor")
    c.input("theta", range=turn)
    c.fixed("O", 0, 0)
    c.fixed("C", 2.5, 0)
    c.polar("Q", "C", 2.5, "theta")
    c.circle_circle("A", ("O", "Q"), (5, 2), branch="left")
    c.circle_circle("B", ("O", "Q"), (5, 2), branch="right")
    c.circle_circle("P", ("A", "B"), (2, 2), branch="right")
    c.link("crank", "C", "Q")
    c.link("armA", "O", "A")
    c.link("armB", "O", "B")
    c.trace("P")
    return c


def test_a_circuit_passes_a_toggle_of_two_dyads_at_once():
    c = peaucellier()
    (lo, hi), = limits(c).intervals
    assert set(hi.nodes) == {"A", "B"} and set(lo.nodes) == {"A", "B"}
    s = circuit(c)
    assert s.valid.all()
    toggles = {}
    for e in s.events:
        toggles.setdefault(e.index, set()).add(e.node)
    assert sum({"A", "B"} <= nodes for nodes in toggles.values()) == 2
    # the inversor's point P runs on a straight line: x = 5^2 - 2^2 over 2 * 2.5 * 2
    for p, q, length in (("O", "A", 5), ("O", "B", 5), ("A", "P", 2), ("B", "P", 2),
                         ("A", "Q", 2), ("B", "Q", 2)):
        np.testing.assert_allclose(np.hypot(*(s[p] - s[q]).T), length, rtol=1e-9)
    report = geokin.analyze(c)
    assert report.warnings == ()
    crank = report.strokes["crank.angle"]
    assert crank.minimum >= lo.value - 1e-9 and crank.maximum <= hi.value + 1e-9


def test_analyze_keeps_extremes_inside_the_limits_it_reports():
    c = Construction("triple rocker")
    c.input("theta2", range=(-np.pi, np.pi))
    c.fixed("A", 0, 0)
    c.fixed("D", 7, 0)
    c.polar("B", "A", 5, "theta2")
    c.circle_circle("C", ("B", "D"), (6, 5), branch="left")
    c.link("crank", "A", "B")
    c.link("coupler", "B", "C")
    c.link("follower", "D", "C")
    report = geokin.analyze(c)
    (lo, hi), = report.inputs["theta2"].intervals
    crank = report.strokes["crank.angle"]
    assert lo - 1e-12 <= crank.minimum and crank.maximum <= hi + 1e-12
    np.testing.assert_allclose([crank.minimum, crank.maximum], [lo, hi], atol=1e-9)


def test_analyze_warns_when_part_of_the_motion_cannot_be_assembled():
    # a triple rocker swept over a whole turn, with a second input that moves nothing
    c = Construction()
    c.input("theta2")
    c.input("u", kind="length", range=(0, 1))
    c.fixed("A", 0, 0)
    c.fixed("D", "7 + 0 * u", 0)
    c.polar("B", "A", 5, "theta2")
    c.circle_circle("C", ("B", "D"), (6, 5), branch="left")
    report = geokin.analyze(c)
    assert any("cannot be assembled" in w for w in report.warnings)


# -- meetings at a sample, for every kind ------------------------------------------------


def line_touching(kind, low=-1.0, high=1.0):
    """A unit circle and the line y = 1 - s^2, which touches it at s = 0."""
    c = Construction()
    c.input("s", kind="length", range=(low, high))
    c.fixed("O", 0, 0)
    c.fixed("P", -3, "1 - s ** 2")
    c.fixed("Q", 3, "1 - s ** 2")
    getattr(c, kind)("X", ("P", "Q"), "O", 1, branch="first")
    return c


@pytest.mark.parametrize("kind", ["line_circle", "ray_circle", "segment_circle"])
@pytest.mark.parametrize("samples", [200, 201, 2, 3])
def test_a_line_grazing_a_circle_passes_on_smoothly(kind, samples):
    s = sweep(line_touching(kind), samples=samples)
    assert s.valid.all()
    x = s["X"][:, 0]
    # the smooth motion comes in from the left, touches at (0, 1) and goes on right
    assert (np.diff(x) > 0).all()
    assert len(s.events) == 1


@pytest.mark.parametrize("kind", ["line_circle", "circle_circle"])
def test_roots_meeting_at_the_first_or_last_sample_change_nothing(kind):
    if kind == "line_circle":
        c = line_touching(kind, 0.0, 1.0)
        branch = "first"
    else:
        c = Construction()
        c.input("s", kind="length", range=(0, 1))
        c.fixed("O", 0, 0)
        c.polar("Q", "O", "2 - s ** 2", 0)
        c.circle_circle("X", ("O", "Q"), (1, 1), branch="left")
        branch = "left"
    forwards = sweep(c, np.linspace(0, 1, 11))
    backwards = sweep(c, np.linspace(1, 0, 11))
    assert forwards.events == () and backwards.events == ()
    assert (forwards.named_branches("X") == branch).all()
    assert (backwards.named_branches("X") == branch).all()


def test_a_meeting_within_rounding_distance_of_a_sample_but_not_at_it_counts():
    # the parallelogram (ground 6, crank 2, coupler 6, rocker 2) starting 2**-14 degrees
    # short of its change point: the roots there are 2e-7 of the scale apart, just
    # outside the tolerance, and meet 6e-5 of the step later
    c = fourbar(6.0, 2.0, 6.0, 2.0)
    theta = np.pi - 2.0**-14 * DEG + np.radians([0.0, 1.0])
    s = sweep(c, theta)
    assert len(s.events) == 1 and 0 < s.events[0].fraction < 1e-4
    # at the first sample the roots are 2e-7 of the scale apart: either is that close
    np.testing.assert_allclose(s["B"][0], s["A"][0] + [6.0, 0.0], atol=1e-6)
    np.testing.assert_allclose(s["B"][1], s["A"][1] + [6.0, 0.0], atol=1e-9)


def test_a_slider_crank_with_equal_crank_and_rod_passes_its_change_point():
    # crank = rod: the block's two roots meet where the crank stands upright; the
    # smooth motion there is the block's folding through the pivot (x = 2 r cos theta)
    r = 2.789327214550029
    c = Construction()
    c.input("theta")
    c.fixed("O", 0, 0)
    c.fixed("P", -100, 0)
    c.fixed("Q", 100, 0)
    c.polar("A", "O", r, "theta")
    c.line_circle("B", ("P", "Q"), "A", r, branch="second")
    for theta in (np.radians(np.linspace(-81.4067157741687, -91.8858056090682, 201)),
                  np.radians(np.linspace(60, 120, 3)), np.radians([60, 100, 89, 130])):
        s = sweep(c, theta)
        np.testing.assert_allclose(s["B"][:, 0], 2 * r * np.cos(theta), atol=1e-6)


@pytest.mark.parametrize("degrees", [[-1, 1, 1, -1], [-1, 1, 1, -1, -1, 1], [1, -1, -1, -1, 1]])
def test_repeated_samples_do_not_hide_where_the_path_turns_back(degrees):
    theta = np.radians(degrees)
    s = sweep(parallelogram(), theta)
    fine = sweep(parallelogram(), dense(theta))
    np.testing.assert_allclose(s["B"], fine["B"][::200], atol=1e-9)
    assert len(s.events) == len(fine.events)


def test_inputs_that_are_not_finite_are_samples_that_cannot_be_assembled():
    for values in ([0.1, np.nan, 0.3, 0.4], [0.1, 0.2, 0.3, np.nan], [0.1, np.inf, 0.3]):
        s = sweep(fourbar(), values)
        assert list(s.valid) == list(np.isfinite(values)) and s.events == ()


def test_held_branches_are_seen_between_samples_by_later_nodes():
    from geokin.engine import evaluate

    c = sixbar()
    theta = {"theta": np.linspace(0, 10 * np.pi, 7)}
    held = evaluate(c, theta, 7, held={"B": 0})
    free = sweep(c, theta["theta"])
    np.testing.assert_allclose(held["M"], free["M"], atol=1e-9)


def test_a_circuit_across_the_ends_of_the_turn_passes_both_dyads():
    """P passes a change point on the way back from the lower toggle to the start: the
    circuit closes there, in the pose it began in, after one swing each way."""
    c = peaucellier(turn=(0.0, 2 * np.pi))
    found = limits(c)
    assert all(set(end.nodes) == {"A", "B"} for pair in found.intervals for end in pair)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = circuit(c)
    assert s.valid.all()
    for p in ("A", "B", "P"):
        np.testing.assert_allclose(s[p][-1], s[p][0], atol=1e-9)
    step = np.diff(s.inputs["theta"])
    assert np.count_nonzero(step[:-1] * step[1:] < 0) == 2


@pytest.mark.parametrize("values", [[1e308, -1e308, 1e308, 0.5], [0.0, 1e30, 0.5],
                                    [0.0, 1e6, 2e6]])
def test_steps_of_any_size_never_change_a_branch_whose_roots_never_meet(values):
    s = sweep(fourbar(), values)
    with np.errstate(invalid="ignore"):
        exact = closed_form_left(np.asarray(values), 24.0, 10.55, 25.0, 14.0)
    assert s.valid.all()
    # a crank-rocker's roots never meet: the closed form, to the inputs' own rounding
    np.testing.assert_allclose(s["B"], exact, atol=1e-6)


def touching_far_away(offset, crank, kind="circles"):
    """A crank about O = (offset, 0), and B where two curves touch all along.

    Circles about A and O (B 0.4 of the way from A to O), or the line through
    A square to the crank and the circle about O through A (B at A).
    """
    c = Construction("touching far from the origin")
    c.input("theta")
    c.fixed("O", offset, 0)
    c.polar("A", "O", crank, "theta")
    if kind == "circles":
        c.circle_circle("B", ("A", "O"), (0.4 * crank, 0.6 * crank), branch="left")
    else:
        c.local("T", "A", "O", (0, crank))
        c.line_circle("B", ("A", "T"), "O", crank, branch="first")
    return c


TOUCHING_PATHS = {"one step": [0.0, 0.01], "a turn": list(np.linspace(0, 2 * np.pi, 13)),
                  "turning back": [0.0, 1.0, 0.5, 2.0, -1.0], "repeated": [0.3, 0.3, 0.3]}


def touching_report(cases):
    """Sweep each (offset, crank, path, kind) of :func:`touching_far_away`; return what
    the test checks.

    For each: whether every sample assembles, the number of branch events,
    B's largest distance from where the curves touch over the crank, and the
    sweep's peak memory (tracemalloc).
    """
    import tracemalloc

    report = []
    for offset, crank, path, kind in cases:
        tracemalloc.start()
        s = sweep(touching_far_away(offset, crank, kind), np.asarray(TOUCHING_PATHS[path]))
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        a = s["A"]
        touching = a + 0.4 * (np.array([offset, 0.0]) - a) if kind == "circles" else a
        off = np.hypot(*(s["B"] - touching).T).max() / crank
        report.append((bool(s.valid.all()), len(s.events), float(off), peak))
    return report


def in_a_limited_process(call):
    """Return what ``call`` (Python text, from this module) gives, as JSON, run alone.

    In a process of its own, held to 3 GB: a sweep looking into rounding
    noise without end would otherwise take all the memory there is.
    """
    import json
    import subprocess
    import sys

    resource = pytest.importorskip("resource")  # limits are set the POSIX way
    code = ("import json, sys; sys.path.insert(0, 'tests');"
            "import test_branch_tracking as t;"
            f"print(json.dumps(t.{call}))")

    def limit():
        hard = resource.getrlimit(resource.RLIMIT_AS)[1]
        most = 3 * 2**30 if hard == resource.RLIM_INFINITY else min(3 * 2**30, hard)
        resource.setrlimit(resource.RLIMIT_AS, (most, hard))

    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=600, preexec_fn=limit, cwd=str(Path(__file__).parents[1]))
    assert run.returncode == 0, run.stderr[-2000:]
    return json.loads(run.stdout)


def test_roots_touching_all_along_far_from_the_origin_meet_without_being_looked_into():
    """Their distance is rounding noise above MEET_RTOL: they meet within the rounding.

    Coordinates 100 to 10,000 times the node's size; and 100,000 times, past
    any resolution, where the sweep must still end, in bounded memory.
    """
    cases = [(offset, crank, path, kind)
             for offset, crank in [(1.0, 0.001), (1e4, 1.0), (1e3, 10.0)]
             for path in TOUCHING_PATHS for kind in ("circles", "line")]
    hopeless = (1e6, 10.0, "a turn", "circles")
    report = in_a_limited_process(f"touching_report({[*cases, hopeless]!r})")
    for case, (valid, events, off, peak) in zip(cases, report[:-1], strict=True):
        assert valid and events == 0, case
        assert off < 1e-4, case
        assert peak < 2**24, case
    assert report[-1][3] < 2**28  # bounded, whatever it finds


def variants_beside_noise():
    """A four-bar just short of folding at pi, alone and swept with noisy variants.

    The others are circles touching all along, 1e5 times their size from the
    origin. Returns the first variant's events and last position of B, alone
    and among them.
    """
    c = Construction("a near toggle beside noise")
    for name in ("X", "d", "a", "b", "c"):
        c.parameter(name, 1.0)
    c.input("theta")
    c.fixed("O", "X", 0)
    c.fixed("O4", "X + d", 0)
    c.polar("A", "O", "a", "theta")
    c.circle_circle("B", ("A", "O4"), ("b", "c"), branch="left")
    theta = np.linspace(0.1, 2 * np.pi + 0.1, 13)
    genuine = {"X": 0.0, "d": 40.0, "a": 10.0, "b": 25.0, "c": 25.0 + 1.2e-12}
    noise = {"X": 1e6, "d": 0.0, "a": 10.0, "b": 4.0, "c": 6.0}
    alone = sweep(c, theta, parameters={k: [v] for k, v in genuine.items()})
    among = sweep(c, theta, parameters={k: [genuine[k]] + [noise[k]] * 4 for k in genuine})
    return [([(e.index, e.fraction) for e in s.events if e.variant == 0], s["B"][0, -1].tolist())
            for s in (alone, among)]


def test_a_variant_is_tracked_as_alone_beside_variants_of_rounding_noise():
    """How long the tracker looks into a step is the step's own affair."""
    alone, among = in_a_limited_process("variants_beside_noise()")
    assert alone == among
    assert alone[0] == []  # it never folds: 1.2e-12 short of it


def island_report(offsets):
    """Sweep a dyad on a dyad over one step whose ends cannot be assembled.

    B assembles only for |theta| < 39 degrees, inside the step from -60 to
    60; C touches B's circle about O4 wherever B is found. For each offset
    of the whole from the origin: the events of the two-sample sweep, and of
    a dense sweep of the same step.
    """
    report = []
    for x in offsets:
        c = Construction("an island of assembly")
        c.input("theta")
        c.fixed("O2", x, x)
        c.fixed("O4", x + 20, x)
        c.polar("A", "O2", 10, "theta")
        c.circle_circle("B", ("A", "O4"), (8, 5.75), branch="left")
        c.circle_circle("C", ("B", "O4"), (2.3, 3.45), branch="left")
        coarse = sweep(c, np.radians([-60.0, 60.0]))
        dense = sweep(c, np.radians(np.linspace(-60, 60, 2001)))
        report.append((len(coarse.events), len(dense.events)))
    return report


def test_an_island_of_assembly_far_from_the_origin_changes_no_branch():
    """The tolerance of a step whose ends fail comes from where the node is found."""
    assert in_a_limited_process("island_report([0.0, 3e3, 1e4])") == [[0, 0]] * 3


def dyad_born_beside_a_change_point(x):
    """A line-circle dyad D on a parallelogram's coupler, pivots shifted by ``x``.

    D cannot be assembled at the first sample; its roots are born 3e-5 of
    the step before the parallelogram's change point, where the coupler,
    and with it D's line, is known only to about 1e-10: D's gap's edge
    flickers over 1e-9 of the step, with islands of assembly between whose
    roots seem to meet and part by rounding.
    """
    c = Construction("parallelogram and a line dyad")
    c.input("theta")
    ground, crank = 1.9452995946842748, 1.8569450049350469
    c.fixed("O2", x, 0)
    c.fixed("O4", x + ground, 0)
    c.fixed("O6", x - 0.34617028400752925, 2.5796101297675644)
    c.polar("A", "O2", crank, "theta")
    c.circle_circle("B", ("A", "O4"), (ground, crank), branch="left")
    c.local("CP", "A", "B", (0.3553752477335389, 1.6336804888560523))
    c.line_circle("D", ("A", "CP"), "O6", 0.92793310128828, branch="first")
    return c


@pytest.mark.parametrize("x", [0.0, 1.0, 100.0])
@pytest.mark.parametrize("samples", [2, 3, 20001])
def test_an_edge_that_flickers_by_rounding_is_one_edge(x, samples):
    """D comes out of its gap on the branch it went in on; the parallelogram changes."""
    s = sweep(dyad_born_beside_a_change_point(x), np.linspace(2.967076, 3.214118, samples))
    assert not s.valid[0] and s.valid[-1]
    assert [e.node for e in s.events] == ["B"]
    assert (s.branches["D"] == 0).all()


def dyad_on_a_coupler_meeting_twice(d):
    """A dyad D whose roots cross at pi - d and pi + d, on a parallelogram's coupler.

    The parallelogram's change point is at pi, between D's meetings, where
    the coupler is known only to about sqrt(eps); D's circles are centred at
    A and at G, 2 along the coupler from A: their distance, and D's roots',
    does not depend on that rounding.
    """
    c = Construction("a dyad meeting twice around a change point")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 2, 0)
    c.polar("A", "O2", 1, "theta")
    c.circle_circle("B", ("A", "O4"), (2, 1), branch="left")
    c.local("G", "A", "B", (2, 0))
    c.circle_circle("D", ("A", "G"), (f"1 + ((theta - (pi - {d})) * (theta - (pi + {d}))) ** 2",
                                      1), branch="left")
    return c


def pivot_touching_twice():
    """D touches its circle twice, 0.02 apart, on a pivot where two fixed circles touch.

    The pivot is rounded once, the same at every sample: no noise.
    """
    c = Construction("a dyad on a pivot of touching circles")
    c.input("t")
    c.fixed("O1", 0, 0)
    c.fixed("O2", 2, 0)
    c.circle_circle("P", ("O1", "O2"), (1, 1), branch="left")
    c.fixed("Q", 3, 0)
    c.circle_circle("D", ("P", "Q"), ("1 + ((t - 0.4900037) * (t - 0.5100041)) ** 2", 1),
                    branch="left")
    return c


def dyad_on_the_coupler_joint_meeting_twice():
    """D is centred on the parallelogram's B, its roots crossing at pi - 0.01 and pi + 0.01.

    Its margin does depend on where B is, which is known only to about
    sqrt(eps) at B's change point, at pi: but not half way to D's meetings.
    """
    c = Construction("a dyad on a coupler joint meeting twice")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 2, 0)
    c.fixed("F", 1, -1)
    c.polar("A", "O2", 1, "theta")
    c.circle_circle("B", ("A", "O4"), (2, 1), branch="left")
    distance = "sqrt((1 + cos(theta))**2 + (sin(theta) + 1)**2)"  # |B - F|
    c.circle_circle("D", ("B", "F"), (f"{distance} - 0.5 + ((theta - pi)**2 - 0.01**2)**2", 0.5),
                    branch="left")
    return c


@pytest.mark.parametrize("make, path, meetings", [
    (dyad_on_the_coupler_joint_meeting_twice, (np.pi - 0.02, np.pi + 0.027),
     (np.pi - 0.01, np.pi + 0.01)),
    (lambda: dyad_on_a_coupler_meeting_twice(0.02), (np.pi - 0.03, np.pi + 0.03),
     (np.pi - 0.02, np.pi + 0.02)),
    (lambda: dyad_on_a_coupler_meeting_twice(0.003), (np.pi - 0.0100123, np.pi + 0.0100456),
     (np.pi - 0.003, np.pi + 0.003)),
    (pivot_touching_twice, (0.0, 1.0), (0.4900037, 0.5100041)),
    (pivot_touching_twice, (0.3, 0.7), (0.4900037, 0.5100041))])
def test_meetings_next_to_an_earlier_meeting_stay_apart_where_rounding_cannot_join_them(
        make, path, meetings):
    """Two meetings of D in one step, each passed where it was made to be."""
    s = sweep(make(), np.array(path))
    found = [path[0] + e.fraction * (path[1] - path[0]) for e in s.events if e.node == "D"]
    np.testing.assert_allclose(found, meetings, rtol=0, atol=2e-5)
    assert s.branches["D"][-1] == s.branches["D"][0]


@pytest.mark.parametrize("turns", [2, 3])
def test_a_change_point_on_an_island_no_sample_sees_is_passed(turns):
    """A change-point four-bar assembles only within 0.83 rad of a whole turn.

    One step from 0.5 to ``2 turns`` pi - 0.5 leaves the assembly, crosses
    ``turns - 1`` islands (each through its change point at a whole turn) and
    comes back to it: the branch changes as often as in a dense sweep.
    """
    c = fourbar(0.5528881343007654, 0.5316564310361038, 0.23032365423520818,
                0.2090919509705466, branch="right")
    theta = np.array([0.5, 2 * turns * np.pi - 0.5])
    coarse = sweep(c, theta)
    dense = sweep(c, np.linspace(*theta, 20_000 * turns + 1))
    assert not dense.valid.all() and coarse.valid.all()
    assert len(coarse.events) == len(dense.events) == turns - 1
    np.testing.assert_array_equal(coarse.branches["B"], dense.branches["B"][[0, -1]])


def test_a_flat_near_miss_is_looked_into_until_it_is_settled():
    """Roots whose distance has a flat minimum 5 MEET_RTOL wide leave many pieces open.

    They never meet: coarse steps across the minimum find no event, as a dense
    sweep finds none.
    """
    c = Construction("a flat near miss")
    c.input("theta")
    c.fixed("P", 0, 0)
    c.fixed("Q", 20, 0)
    c.circle_circle("B", ("P", "Q"), (10, "10 + 1e-11 + (1 - cos(theta))**2"), branch="left")
    for step in (30, 90, 7):
        assert not sweep(c, np.radians(np.arange(-11.1, 720, step))).events, step
    assert not sweep(c, np.radians(np.arange(-1.85, 720, 0.01))).events


def test_a_near_miss_between_fixed_circles_far_from_the_origin_is_not_a_meeting():
    """Fixed points are rounded once: they widen nothing, and translating decides nothing.

    Two circles about fixed centres, their radii changing with a length input,
    come within 1e-6 of their scale of each other (ten times MEET_RTOL) but
    never meet, at the origin as 1e6 from it.
    """
    def build(x):
        c = Construction("a near miss")
        c.input("s", kind="length", range=(5, 15))
        c.fixed("P", x, 0)
        c.fixed("Q", x + 20, 0)
        c.circle_circle("B", ("P", "Q"), ("s", "20 + 4e-11 + 0.01 * (s - 10) * (s - 10) - s"),
                        branch="left")
        return c

    values = np.linspace(5, 15, 1001) + 0.00357
    near, far = sweep(build(0.0), values), sweep(build(1e6), values)
    assert not near.events and not far.events
    np.testing.assert_array_equal(far.branches["B"], near.branches["B"])
    np.testing.assert_allclose(far["B"] - [1e6, 0], near["B"], rtol=0, atol=1e-8)


@pytest.mark.parametrize("offset", [(0.0, 0.0), (1e3, -2e3), (1e5, 1e5)])
def test_change_points_far_from_the_origin_are_found_as_near_it(offset):
    """Widening the meeting tolerance for far coordinates keeps every true meeting."""
    c = Construction("parallelogram")
    c.input("theta")
    c.fixed("O2", offset[0], offset[1])
    c.fixed("O4", offset[0] + 10, offset[1])
    c.polar("A", "O2", 4, "theta")
    c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
    theta = np.linspace(0.5, 0.5 + 4 * np.pi, 1441)
    s = sweep(c, theta)
    # the change points: where the crank lies along the ground, at 0 and 180 degrees
    where = np.array([e.index - 1 + e.fraction for e in s.events])
    crossings = np.array([np.pi, 2 * np.pi, 3 * np.pi, 4 * np.pi])
    expected = (crossings - 0.5) / (theta[1] - theta[0])
    np.testing.assert_allclose(where, expected, rtol=0, atol=1e-3)
    # on its branch, B keeps the link lengths everywhere
    np.testing.assert_allclose(np.hypot(*(s["B"] - s["A"]).T), 10, rtol=1e-7)
    np.testing.assert_allclose(np.hypot(*(s["B"] - s[("O4")]).T), 4, rtol=1e-7)
