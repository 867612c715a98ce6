import itertools

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from mechanisms import five_bar, sixbar

from geokin import Construction, circuit, sweep
from geokin.analysis import (
    KINDS,
    curve_measures,
    degrees_of_freedom,
    fourbar_transmission_extremes,
    fourth_link_range,
    grashof,
    link_angles,
    stroke,
    time_ratio,
    transmission_angles,
)

lengths = st.floats(0.5, 20.0, allow_nan=False, allow_infinity=False)


def fourbar(ground, crank, coupler, rocker, branch="left"):
    c = Construction("four-bar")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", ground, 0)
    c.polar("A", "O2", crank, "theta")
    c.circle_circle("B", ("A", "O4"), (coupler, rocker), branch=branch)
    c.link("crank", "O2", "A")
    c.link("coupler", "A", "B")
    c.link("rocker", "O4", "B")
    return c


def quick_return(r1=60.0, r2=40.0, r6=60.0):
    """Seed 001's crank and slotted lever: lever pivot O1 at the origin, slider B on y = r1 + r6.

    The crank pin A drives a block sliding in the lever's slot; a second
    block in the slot is pinned at B to the ram, which slides on the ground.
    """
    c = Construction("quick return")
    c.input("theta2")
    c.fixed("O1", 0, 0)
    c.fixed("O2", 0, r1)
    c.fixed("C", 0, r1 + r6)
    c.fixed("E", 1, r1 + r6)
    c.polar("A", "O2", r2, "theta2")
    c.line_line("B", ("O1", "A"), ("C", "E"))
    c.along("L", ("O1", "A"), 3 * (r1 + r6))
    c.link("crank", "O2", "A")
    c.link("lever", "O1", "L")
    c.slider("pin", "A", ("O1", "L"))
    c.slider("slot", "B", ("O1", "L"))
    c.slider("ram", "B", ("C", "E"))
    return c


# -- Grashof ---------------------------------------------------------------------------


@pytest.mark.parametrize("lengths, kind, turning", [
    ((24, 10.55, 25, 14), "crank-rocker", ("input",)),
    ((2, 4, 5, 4.5), "double-crank", ("input", "coupler", "output")),
    ((4, 5, 2, 4.5), "double-rocker", ("coupler",)),
    ((4, 4.5, 5, 2), "rocker-crank", ("output",)),
    ((7, 5, 6, 5), "triple-rocker RRR1", ()),
    ((5, 7, 6, 5), "triple-rocker RRR2", ()),
    ((5, 6, 7, 5), "triple-rocker RRR3", ()),
    ((5, 5, 6, 7), "triple-rocker RRR4", ()),
    ((2, 1, 2, 1), "change-point", ("input", "output")),
    ((1, 2, 3, 6), "immobile", ()),
    ((1, 2, 3, 7), "unassemblable", ()),
])
def test_grashof_kinds(lengths, kind, turning):
    g = grashof(*lengths)
    assert g.kind == kind
    assert g.code == KINDS[kind]
    assert g.turning == turning


def test_grashof_keywords_and_seed_000():
    g = grashof(ground=7, input_link=4, coupler=5, output_link=5)
    assert g.kind == "triple-rocker RRR1" and not g.grashof
    assert (g.s_plus_l, g.p_plus_q) == (11.0, 10.0)
    assert g.shortest == ("input",) and g.longest == ("ground",)
    with pytest.raises(ValueError, match="coupler"):
        grashof(1, 1, -1, 1)


def test_change_point_turning():
    # a parallelogram: every joint turns fully; a kite: only the short pair's joint
    para = grashof(2, 1, 2, 1)
    assert para.input_turns and para.output_turns
    assert para.input_turns_on_coupler and para.output_turns_on_coupler
    kite = grashof(1, 1, 3, 3)
    assert kite.kind == "change-point"
    assert kite.input_turns and not kite.output_turns_on_coupler


@given(lengths, lengths, lengths, lengths, st.floats(0.1, 10))
def test_grashof_invariant_under_mirror_and_scale(g, i, c, o, k):
    """Reversing the chain swaps input and output; scaling changes nothing."""
    a = grashof(g, i, c, o)
    mirrored = grashof(g, o, c, i)
    swap = {"crank-rocker": "rocker-crank", "rocker-crank": "crank-rocker",
            "triple-rocker RRR2": "triple-rocker RRR4",
            "triple-rocker RRR4": "triple-rocker RRR2"}
    assert mirrored.kind == swap.get(a.kind, a.kind)
    assert (mirrored.input_turns, mirrored.output_turns) == (a.output_turns, a.input_turns)
    assert mirrored.coupler_turns == a.coupler_turns
    assert grashof(k * g, k * i, k * c, k * o).kind == a.kind


@given(lengths, lengths, lengths, lengths)
def test_grashof_shortest_link_rule(g, i, c, o):
    """In a Grashof linkage exactly the joints of the shortest link turn fully; else none."""
    a = grashof(g, i, c, o)
    assume(a.kind != "change-point")
    assert a.grashof == (a.s_plus_l <= a.p_plus_q)
    joints = {("ground", "input"): a.input_turns, ("ground", "output"): a.output_turns,
              ("input", "coupler"): a.input_turns_on_coupler,
              ("coupler", "output"): a.output_turns_on_coupler}
    for pair, turns in joints.items():
        assert turns == (a.grashof and a.shortest[0] in pair), (pair, a)


@given(lengths, lengths, lengths, lengths)
def test_grashof_input_turns_as_the_engine_finds(g, i, c, o):
    """A crank predicted to turn assembles at every sample of a turn; a rocker does not."""
    a = grashof(g, i, c, o)
    assume(a.kind not in ("change-point", "immobile", "unassemblable"))
    assume(abs(a.s_plus_l - a.p_plus_q) > 1e-3 * a.p_plus_q)
    s = sweep(fourbar(g, i, c, o), np.linspace(0, 2 * np.pi, 721))
    assert bool(s.valid.all()) == a.input_turns


# -- range of the fourth link ---------------------------------------------------------------


def _inside(x, intervals):
    return any(lo < x < hi or lo == hi == x for lo, hi in intervals)


def test_fourth_link_range_seed_000():
    # seed 000's range(7, 5, 6): triple rocker for 4 < r4 < 6 or 8 < r4 < 18
    assert fourth_link_range(7, 5, 6, "non-grashof") == [(4.0, 6.0), (8.0, 18.0)]
    assert fourth_link_range(7, 5, 6, "triple-rocker RRR1") == [(4.0, 6.0)]
    assert fourth_link_range(7, 5, 6, "RRR4") == [(8.0, 18.0)]
    assert fourth_link_range(7, 5, 6, "grashof") == [(0.0, 4.0), (6.0, 8.0)]
    assert fourth_link_range(7, 5, 6, "rocker-crank") == [(0.0, 4.0)]
    assert fourth_link_range(7, 5, 6, "crank-rocker") == [(6.0, 8.0)]
    assert fourth_link_range(7, 5, 6, "unassemblable") == [(18.0, np.inf)]
    assert fourth_link_range(7, 5, 6, "immobile") == [(18.0, 18.0)]
    with pytest.raises(ValueError, match="did you mean"):
        fourth_link_range(7, 5, 6, "crank-rocke")


@pytest.mark.parametrize("known", [(7, 5, 6), (7, 4, 5), (2, 9, 4), (1, 1, 1), (10, 3, 3),
                                   (24, 10.55, 25), (3, 5, 4)])
def test_fourth_link_range_against_brute_force(known):
    ranges = {kind: fourth_link_range(*known, kind) for kind in KINDS}
    for x in np.linspace(0.01, sum(known) * 1.2, 4001):
        kind = grashof(*known, x).kind
        where = [k for k, r in ranges.items() if _inside(x, r)]
        if kind == "change-point" or kind == "immobile":
            # a grid point can hit a change point only up to rounding
            assert where in ([kind], []), (x, kind, where)
        else:
            assert where == [kind], (x, kind, where)
    for kind in ("change-point", "immobile"):
        for lo, hi in ranges[kind]:
            assert lo == hi and grashof(*known, lo).kind == kind


@given(lengths, lengths, lengths, st.floats(0.01, 70))
def test_fourth_link_range_agrees_with_grashof(g, i, c, x):
    ranges = fourth_link_range(g, i, c, grashof(g, i, c, x).kind)
    edges = [v for r in ranges for v in r]
    assume(all(abs(x - e) > 1e-7 * (1 + x) for e in edges))
    assert _inside(x, ranges)


@given(lengths, lengths, lengths)
def test_fourth_link_ranges_partition_the_line(g, i, c):
    everything = sorted(r for kind in KINDS for r in fourth_link_range(g, i, c, kind))
    assert everything[0][0] == 0.0 and everything[-1][1] == np.inf
    for (_, hi), (lo, _) in itertools.pairwise(everything):
        assert hi == pytest.approx(lo, rel=1e-12, abs=1e-12)


# -- transmission angle ---------------------------------------------------------------------


def test_transmission_extremes_seed_000():
    low, high = fourbar_transmission_extremes(ground=7, input_link=4, coupler=5, output_link=5)
    assert np.degrees(low) == pytest.approx(34.915, abs=5e-3)
    assert round(float(np.degrees(low)), 2) == 34.92
    assert np.degrees(high) == pytest.approx(180.0)


def test_transmission_angles_match_the_closed_form_over_a_sweep():
    # seed 000's triple rocker 7, 4, 5, 5 over its whole input range
    limit = np.arccos((7**2 + 4**2 - 10**2) / (2 * 7 * 4))
    s = sweep(fourbar(7, 4, 5, 5), np.linspace(-limit, limit, 2001))
    assert s.valid.all()
    mu = transmission_angles(s)["B"]
    low, high = fourbar_transmission_extremes(7, 4, 5, 5)
    assert mu.minimum == pytest.approx(low, abs=1e-12)
    assert mu.at_minimum["theta"] == pytest.approx(0.0, abs=1e-12)
    assert np.degrees(mu.maximum) > 179.9
    assert abs(mu.at_maximum["theta"]) == pytest.approx(limit)
    # seed 004's crank-rocker, both circuits: extremes at theta = 0 and pi
    for branch in ("left", "right"):
        s = sweep(fourbar(24, 10.55, 25, 14, branch), np.linspace(0, 2 * np.pi, 721))
        mu = transmission_angles(s)["B"]
        assert (mu.minimum, mu.maximum) == pytest.approx(
            fourbar_transmission_extremes(24, 10.55, 25, 14), abs=1e-12)
        assert mu.at_maximum["theta"] == pytest.approx(np.pi)


@given(lengths, lengths, lengths, lengths)
def test_transmission_extremes_bound_the_sweep(g, i, c, o):
    a = grashof(g, i, c, o)
    assume(a.kind not in ("immobile", "unassemblable"))
    s = sweep(fourbar(g, i, c, o), np.linspace(-np.pi, np.pi, 721))
    assume(s.valid.any())
    mu = transmission_angles(s)["B"]
    low, high = fourbar_transmission_extremes(g, i, c, o)
    # the engine accepts near-tangent circles (squared margin 1e-10): 1e-5 in angle
    assert low - 2e-5 <= mu.minimum and mu.maximum <= high + 2e-5
    if a.input_turns and a.kind != "change-point":
        assert (mu.minimum, mu.maximum) == pytest.approx((low, high), abs=1e-9)


def test_transmission_angle_at_every_circle_circle_node():
    s = sweep(sixbar(), np.radians(np.arange(0, 1801, 16)))
    angles = transmission_angles(s)
    assert list(angles) == ["B"]
    a, b0 = s["A"], s["B0"]
    e = np.hypot(*(a - b0).T)
    expected = np.arccos((100**2 + 100**2 - e**2) / (2 * 100 * 100))
    np.testing.assert_allclose(angles["B"].angle, expected, atol=1e-9)
    assert angles["B"].worst == pytest.approx(min(expected.min(), np.pi - expected.max()))


# -- degrees of freedom ------------------------------------------------------------------------


def test_dof_seed_003():
    m = degrees_of_freedom(sixbar())
    assert (m.moving_links, m.revolute_joints, m.prismatic_pairs) == (5, 6, 1)
    assert (m.lower_pairs, m.higher_pairs, m.dof) == (7, 0, 1)
    assert m.matches_inputs
    assert m.guides == {"block": "output"}
    assert m.joints["C"] == ("coupler", "block")
    assert "ground" not in m.bodies
    assert str(m) == "DOF = 3(5) - 2(7) - 0 = 1; 1 input"


def test_dof_of_other_linkages():
    assert degrees_of_freedom(fourbar(24, 10.55, 25, 14)).dof == 1
    # slider-crank: crank, rod and block; the block slides on the ground
    c = Construction("slider-crank")
    c.input("theta")
    c.fixed("O", 0, 0)
    c.fixed("E1", -1, 0)
    c.fixed("E2", 1, 0)
    c.polar("A", "O", 1, "theta")
    c.line_circle("B", ("E1", "E2"), "A", 3, branch="second")
    c.link("crank", "O", "A")
    c.link("rod", "A", "B")
    c.slider("block", "B", ("E1", "E2"))
    m = degrees_of_freedom(c)
    assert (m.moving_links, m.lower_pairs, m.dof, m.guides) == (3, 4, 1, {"block": "ground"})
    # seed 001's quick return: crank, lever, two blocks in the slot, the ram
    m = degrees_of_freedom(quick_return())
    assert (m.moving_links, m.revolute_joints, m.prismatic_pairs, m.dof) == (5, 4, 3, 1)
    assert m.guides == {"pin": "lever", "slot": "lever", "ram": "ground"}
    assert m.joints["B"] == ("slot", "ram")
    # a five-bar needs two inputs; declared with one, its second crank geared to the
    # first (a constraint the count cannot see), it does not match
    def five_bar(second_crank):
        c = Construction("five-bar")
        c.input("t1")
        c.fixed("O1", 0, 0)
        c.fixed("O2", 3, 0)
        c.polar("A", "O1", 1, "t1")
        c.polar("C", "O2", 1, second_crank)
        c.circle_circle("B", ("A", "C"), (3, 3), branch="left")
        for name, pts in dict(l1=("O1", "A"), l2=("A", "B"), l3=("B", "C"),
                              l4=("C", "O2")).items():
            c.link(name, *pts)
        return c

    m = degrees_of_freedom(five_bar("2 * t1"))
    assert m.dof == 2 and m.inputs == 1 and not m.matches_inputs
    assert "mismatch" in str(m)
    # its second crank held at a constant angle is part of the frame: C never moves, and
    # the linkage is the four-bar O1-A-B-C it moves as
    c = five_bar(2.0)
    assert c.compile().ground == {"O1", "O2", "C"}
    m = degrees_of_freedom(c)
    assert (m.moving_links, m.lower_pairs, m.dof) == (3, 4, 1) and m.matches_inputs


# -- stroke and time ratio ----------------------------------------------------------------------


@pytest.mark.parametrize("r1, r2", [(60, 40), (60, 20), (100, 75)])
def test_quick_return_time_ratio_closed_form(r1, r2):
    r6 = 60.0
    theta = np.linspace(0, 2 * np.pi, 3601)
    s = sweep(quick_return(r1, r2, r6), theta)
    assert s.valid.all()
    alpha = np.degrees(2 * np.arcsin(r2 / r1))
    expected = (180 + alpha) / (180 - alpha)
    result = stroke(s["B"][:, 0], theta)
    assert result.quick_return_ratio == pytest.approx(expected, rel=1e-7)
    assert result.stroke == pytest.approx(2 * (r1 + r6) * np.tan(np.arcsin(r2 / r1)), rel=1e-9)
    assert result.forward + result.back == pytest.approx(2 * np.pi)
    # the lever angle has the same extremes in time
    lever = link_angles(s)["lever"]
    assert time_ratio(lever, theta) == pytest.approx(1 / result.time_ratio, rel=1e-7)
    # extremes where the lever is tangent to the crank circle: O2-A normal to O1-A
    tangent = np.sort((-np.pi / 2 + np.array([-1, 1]) * np.arccos(r2 / r1)) % (2 * np.pi))
    found = np.sort([result.input_at_min, result.input_at_max])
    np.testing.assert_allclose(found, tangent, atol=1e-7)


def test_stroke_rejects_bad_input():
    t = np.linspace(0, np.pi, 10)
    with pytest.raises(ValueError, match="less than one turn"):
        stroke(np.sin(t), t)
    with pytest.raises(ValueError, match="increase or decrease"):
        stroke(np.sin(t), np.r_[t[:5], t[4::-1]])


def test_a_stroke_over_a_turn_the_other_way_runs_its_time_ratio_with_the_samples():
    """y = sin(t) + 0.25 sin(2t) peaks at cos t = (sqrt 3 - 1) / 2 (t = 1.1961) and
    bottoms at minus that: turning t from 2 pi down to 0, it rises from its trough to its
    peak in 2 pi - 2 * 1.1961 rad of travel and falls in the rest of the turn."""
    t = np.linspace(2 * np.pi, 0, 3601)
    peak = np.arccos((np.sqrt(3) - 1) / 2)
    found = stroke(np.sin(t) + 0.25 * np.sin(2 * t), t)
    assert found.back == pytest.approx(2 * peak, rel=1e-9)
    assert found.time_ratio == pytest.approx((2 * np.pi - 2 * peak) / (2 * peak), rel=1e-9)
    assert found.input_at_max == pytest.approx(peak, abs=1e-9)
    assert found.input_at_min == pytest.approx(2 * np.pi - peak, abs=1e-9)


# -- link angles -----------------------------------------------------------------------------------


def test_link_angles_unwrap_over_turns():
    theta = np.linspace(0, 6 * np.pi, 1081)
    s = sweep(fourbar(24, 10.55, 25, 14), theta)
    angles = link_angles(s)
    np.testing.assert_allclose(angles["crank"], theta, atol=1e-12)
    assert np.ptp(angles["rocker"]) < np.pi  # a rocker does not turn
    assert angles["coupler"].shape == (1081,)


def crank_and_rocker_both_ways(crank="a"):
    """A crank-rocker (ground 40, crank ``crank``, coupler 35, rocker 30) with each link
    declared from either end: the crank from its pivot and back."""
    c = Construction("crank both ways")
    c.parameter("a", 10)
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 40, 0)
    c.polar("A", "O2", crank, "theta")
    c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
    c.link("crank", "O2", "A")
    c.link("back", "A", "O2")
    c.link("rocker", "O4", "B")
    return c


@given(st.floats(-1000, 1000), st.floats(-3, 3).filter(lambda turns: abs(turns) > 0.01))
def test_a_crank_reads_in_the_turn_of_its_input_wherever_the_sweep_starts(start, turns):
    """The crank's angle is its input's (plus a half turn from its other end), at every
    sample; a rocker's starts where atan2 puts it."""
    theta = np.radians(start) + np.linspace(0, 2 * np.pi * turns, 50)
    s = sweep(crank_and_rocker_both_ways(), theta)
    angles = link_angles(s)
    np.testing.assert_allclose(angles["crank"], theta, rtol=0, atol=1e-9)
    np.testing.assert_allclose(angles["back"], theta + np.pi, rtol=0, atol=1e-9)
    b = s["B"][0] - s["O4"][0]
    assert angles["rocker"][0] == pytest.approx(np.arctan2(b[1], b[0]), abs=1e-12)
    assert np.ptp(angles["rocker"]) < np.pi


def test_a_crank_reads_in_its_input_turn_across_a_gap_and_in_each_variant():
    """Variants of crank 10 and 60: the long crank cannot be assembled for most of the turn,
    and its angle, which no unwrapping can carry across the gap, is still its input's."""
    theta = np.radians(np.arange(300, 700, 30.0))
    s = sweep(crank_and_rocker_both_ways(), theta, parameters={"a": [10, 60]})
    assert s.valid[0].all() and not s.valid[1].all() and s.valid[1, [0, -1]].all()
    angles = link_angles(s)
    for row in range(2):
        found = s.valid[row]
        np.testing.assert_allclose(angles["crank"][row][found], theta[found], rtol=0, atol=1e-9)
        assert np.isnan(angles["crank"][row][~found]).all()


def test_an_input_that_does_not_move_turns_no_link():
    """At one sample, or with an input held, every link keeps a constant angle from the
    input: none is a crank for it, and each reads as atan2 gives it."""
    s = sweep(crank_and_rocker_both_ways(), [np.radians(1000.0)])
    for name, (a, b) in (("crank", ("O2", "A")), ("rocker", ("O4", "B"))):
        d = s[b][0] - s[a][0]
        assert link_angles(s)[name][0] == pytest.approx(np.arctan2(d[1], d[0]), abs=1e-12)
    held = sweep(five_bar(), {"t1": np.linspace(0, 1, 5), "t2": np.full(5, 7.0)})
    angles = link_angles(held)
    np.testing.assert_allclose(angles["crank1"], held.inputs["t1"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(angles["crank2"], 7.0 - 2 * np.pi, rtol=0, atol=1e-9)


def test_each_crank_of_a_five_bar_reads_in_the_turn_of_its_own_input():
    s = sweep(five_bar(second_turns=-2), {"t1": np.linspace(5, 5 + 2 * np.pi, 73),
                                           "t2": np.linspace(-3, -3 - 4 * np.pi, 73)})
    angles = link_angles(s)
    np.testing.assert_allclose(angles["crank1"], s.inputs["t1"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(angles["crank2"], s.inputs["t2"], rtol=0, atol=1e-9)


# -- curve measures -------------------------------------------------------------------------------


def test_curve_measures_circle():
    t = np.linspace(0, 2 * np.pi, 4001)
    circle = np.c_[3 + 2 * np.cos(t), 2 * np.sin(t)]
    m = curve_measures(circle)
    assert m.closed and m.simple
    assert m.length == pytest.approx(4 * np.pi, rel=1e-6)
    assert m.signed_area == pytest.approx(4 * np.pi, rel=1e-6)
    assert m.area == pytest.approx(m.signed_area, rel=1e-12)
    assert m.bounds == pytest.approx((1, -2, 5, 2))
    assert curve_measures(circle[::-1]).signed_area == pytest.approx(-m.signed_area)


@pytest.mark.parametrize("n", [25, 100, 1000])
def test_the_area_tolerance_is_what_an_inscribed_polygon_misses_of_its_circle(n):
    t = np.linspace(0, 2 * np.pi, n + 1)
    r = 3.0
    m = curve_measures(np.c_[5 + r * np.cos(t), r * np.sin(t)])
    missed = np.pi * r * r - 0.5 * n * r * r * np.sin(2 * np.pi / n)
    assert m.area == pytest.approx(np.pi * r * r - missed, rel=1e-9)
    assert m.area_tolerance == pytest.approx(missed, rel=0.02)


@given(out=st.integers(8, 400), back=st.integers(8, 400), span=st.floats(0.2, 6.0),
       radius=st.floats(1e-3, 1e3), shift=st.just(0.0) | st.floats(0.05, 0.95))
def test_an_arc_run_out_and_back_encloses_no_more_than_its_area_tolerance(out, back, span,
                                                                          radius, shift):
    """Out and back along one arc, sampled differently each way: slivers only."""
    there = np.linspace(0, span, out + 1)
    back_at = np.concatenate([[span], np.sort(shift * span / back
                                               + np.linspace(0, span, back + 1)[:-1])[::-1],
                              [0.0]])
    angle = np.concatenate([there, back_at[1:]])
    m = curve_measures(np.c_[radius * np.cos(angle), radius * np.sin(angle)])
    assert m.closed
    assert m.area <= m.area_tolerance
    assert m.area_tolerance <= 0.5 * span * radius * radius  # far below the arc's sector


def test_curve_measures_square_and_open_curve():
    m = curve_measures([(0, 0), (0, 1), (1, 1), (1, 0), (0, 0)])
    assert (m.length, m.signed_area, m.area, m.closed) == (4.0, -1.0, 1.0, True)
    m = curve_measures([(0, 0), (1, 0), (1, 1)])
    assert not m.closed and np.isnan(m.area) and np.isnan(m.signed_area) and m.length == 2.0


@pytest.mark.parametrize("n", [2001, 1998])
def test_curve_measures_lemniscate(n):
    # Bernoulli's lemniscate: lobes of area a**2 / 2 each, a double point at the origin
    a = 2.0
    t = np.linspace(0, 2 * np.pi, n)
    d = 1 + np.sin(t) ** 2
    eight = np.c_[a * np.cos(t) / d, a * np.sin(t) * np.cos(t) / d]
    m = curve_measures(eight)
    assert m.closed and not m.simple
    assert m.double_points.shape == (1, 2)
    np.testing.assert_allclose(m.double_points[0], (0, 0), atol=1e-12 if n == 2001 else 1e-5)
    assert m.signed_area == pytest.approx(0, abs=1e-9)
    assert m.area == pytest.approx(a * a, rel=1e-5)


def test_curve_measures_gaps_and_errors():
    pts = np.array([(0, 0), (1, 0), (np.nan, np.nan), (2, 0), (2, 1)])
    m = curve_measures(pts)
    assert m.length == 2.0 and not m.closed
    with pytest.raises(ValueError, match="shape"):
        curve_measures([1, 2, 3])
    # a figure crossing itself between two open pieces
    m = curve_measures([(0, 0), (2, 2), (np.nan, np.nan), (0, 2), (2, 0)])
    np.testing.assert_allclose(m.double_points, [[1, 1]])


def test_transmission_chart_example(tmp_path):
    import subprocess
    import sys
    from pathlib import Path

    script = Path(__file__).parents[1] / "examples" / "transmission_chart.py"
    out = tmp_path / "chart.png"
    run = subprocess.run([sys.executable, str(script), str(out)], capture_output=True,
                         text=True, check=True)
    assert "mu_min = 34.92 deg, mu_max = 180.00 deg" in run.stdout
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_path_run_back_over_itself_has_no_double_points():
    """A rocker's joint goes out along an arc and back on other samples: no crossing."""
    out = np.linspace(0, 2, 37)
    back = np.linspace(2, 0, 53)
    t = np.r_[out, back[1:]]
    arc = np.c_[np.cos(t), np.sin(t)]
    assert curve_measures(arc).simple
    # a real crossing next to it is still found
    t = np.linspace(0, 2 * np.pi, 201)
    eight = np.c_[np.sin(t), np.sin(t) * np.cos(t)]
    assert len(curve_measures(eight).double_points) == 1


def test_a_traced_point_that_never_moves_has_a_path_of_no_length():
    from geokin.analysis import curve_measures

    curve = curve_measures(np.zeros((5, 2)))
    assert curve.length == 0 and len(curve.double_points) == 0


def test_a_joint_run_out_and_back_unevenly_has_no_double_point():
    """A crank pin found from a block driven along a line swings out and back on its circle.

    The block's even steps move the pin in steps that grow tenfold towards
    the end of the stroke, and the way back is sampled differently: its
    chords cross the way out's at the turn of the circle over a step,
    which is no crossing of the path.
    """
    c = Construction("slider-driven crank")
    c.input("s", kind="length", range=(80, 158), samples=101)
    c.fixed("O", 0, 0)
    c.fixed("B", "s", 20)
    c.circle_circle("A", ("O", "B"), (40, 120), branch="left")
    s = circuit(c)
    assert np.allclose(np.hypot(*s["A"].T), 40)
    m = curve_measures(s["A"])
    assert m.closed and m.simple and m.area <= m.area_tolerance
    # a true crossing at a shallow angle on the same scale is still one
    t = np.linspace(-1, 1, 201)
    x = np.concatenate([t, t[::-1]])
    y = np.concatenate([0.2 * t, -0.2 * t[::-1]])
    crossing = curve_measures(np.c_[x, y] * 40)
    assert crossing.double_points.shape == (1, 2)
    np.testing.assert_allclose(crossing.double_points[0], (0, 0), atol=1e-9)


@pytest.mark.parametrize("radius, centre", [(1.0, 0.0), (1e-5, 1000.0), (1e-3, 1e6)])
def test_an_arc_run_out_and_back_far_from_the_origin_has_no_double_point(radius, centre):
    """The search for the segments through a node scales with the curve, not its place."""
    a = np.concatenate([np.linspace(0, 2, 51), np.linspace(2, 0, 38)])
    m = curve_measures(np.c_[centre + radius * np.cos(a), radius * np.sin(a)])
    assert m.closed and m.simple and m.area <= m.area_tolerance
    # a figure eight there keeps its one double point, at its centre
    t = np.linspace(0, 2 * np.pi, 2001)
    d = 1 + np.sin(t) ** 2
    eight = curve_measures(np.c_[centre + radius * 2 * np.cos(t) / d,
                                 radius * 2 * np.sin(t) * np.cos(t) / d])
    assert eight.double_points.shape == (1, 2)
    np.testing.assert_allclose(eight.double_points[0], (centre, 0.0), atol=1e-6 * radius)
