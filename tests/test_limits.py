import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from mechanisms import (
    R1,
    R2,
    R3,
    R4,
    change_point_fourbar,
    coupler_fourbar,
    five_bar,
    fourbar,
    triple_rocker,
)

import geokin
from geokin import AssemblyError, Construction, ConstructionError, sweep
from geokin.analysis import grashof
from geokin.circuits import circuit, describe_limit, limits

# closed forms of seed 000's triple rocker limits (see test_kinematics for the constructions)
CRANK = np.arccos((R1**2 + R2**2 - (R3 + R4) ** 2) / (2 * R1 * R2))
FOLLOWER = np.arccos(((R2 + R3) ** 2 - R1**2 - R4**2) / (2 * R1 * R4))
COUPLER = np.arccos((R1**2 + R3**2 - (R2 + R4) ** 2) / (2 * R1 * R3))
EXPECTED = {
    "crank": (-CRANK, CRANK, "C"),
    "follower": (FOLLOWER, 2 * np.pi - FOLLOWER, "B"),
    "coupler": (-COUPLER, COUPLER, "B"),
}


def test_seed_000_crank_range_is_plus_minus_132_1774_degrees():
    found = limits(triple_rocker("crank"))
    [(lo, hi)] = found.as_values()
    assert np.degrees(hi).round(4) == 132.1774 and np.degrees(lo).round(4) == -132.1774


@pytest.mark.parametrize("driver", ["crank", "coupler", "follower"])
@pytest.mark.parametrize("branch", ["left", "right"])
def test_limits_match_the_closed_form_to_1e_9(driver, branch):
    c = triple_rocker(driver, branch, input_range=(0, 2 * np.pi) if driver == "follower"
                      else None)
    found = limits(c)
    assert not found.full_turn
    [(lo, hi)] = found.intervals
    expected_lo, expected_hi, node = EXPECTED[driver]
    assert abs(lo.value - expected_lo) < 1e-9 and abs(hi.value - expected_hi) < 1e-9
    assert (lo.node, lo.kind, hi.node, hi.kind) == (node, "tangent", node, "tangent")


def test_a_crank_that_turns_fully_has_no_limits():
    found = limits(coupler_fourbar())
    assert found.full_turn and len(found.intervals) == 1


@pytest.mark.parametrize("start", [0.0, -np.pi, 1.0, 2.5])
def test_a_search_range_of_one_turn_is_searched_as_a_turn(start):
    """Wherever a searched whole turn starts, a crank that turns fully turns fully,
    and the triple rocker's crank rocks over one interval across the turn's seam,
    between its closed-form limits."""
    turn = (start, start + 2 * np.pi)
    assert limits(coupler_fourbar(), search_range=turn).full_turn
    found = limits(triple_rocker("crank"), search_range=turn)
    assert not found.full_turn
    [(lo, hi)] = found.intervals
    expected_lo, expected_hi, _ = EXPECTED["crank"]
    # the interval may be given a turn on or back: its width and ends are the same
    assert abs((hi.value - lo.value) - (expected_hi - expected_lo)) < 1e-9
    assert abs(np.angle(np.exp(1j * (lo.value - expected_lo)))) < 1e-9


def test_limits_where_a_slider_leaves_its_segment_are_ends():
    c = Construction()
    c.input("s", kind="length", range=(0, 10))
    c.fixed("O", 0, 0)
    c.fixed("Q", 10, 0)
    c.fixed("R", 0, 3)
    c.polar("Cs", "R", "s", 0)
    c.segment_circle("P", ("O", "Q"), "Cs", 5, branch="second")
    [(lo, hi)] = limits(c).intervals
    assert lo.kind == "range" and lo.value == 0
    assert hi.kind == "end" and hi.node == "P" and abs(hi.value - 6) < 1e-9


def test_an_unassemblable_construction_says_so():
    c = Construction()
    c.input("t")
    c.fixed("O", 0, 0)
    c.fixed("Q", 100, 0)
    c.polar("A", "O", 1, "t")
    c.circle_circle("B", ("A", "Q"), (2, 2), branch="left")
    with pytest.raises(AssemblyError, match="cannot be assembled anywhere"):
        limits(c)


@pytest.mark.parametrize("driver", ["crank", "coupler", "follower"])
def test_a_circuit_passes_both_toggles_and_closes(driver):
    c = triple_rocker(driver)
    s = circuit(c, samples_per_pass=721)
    assert s.valid.all()
    # it closes: the same configuration at the start and the end
    for point in ("B", "C"):
        np.testing.assert_allclose(s[point][0], s[point][-1], atol=1e-9)
    # the link lengths hold all the way round
    for a, b, length in [("A", "B", R2), ("B", "C", R3), ("D", "C", R4)]:
        np.testing.assert_allclose(np.hypot(*(s[a] - s[b]).T), length, rtol=1e-12)
    # both toggles are passed on the node that becomes tangent, and the motion is continuous
    node = EXPECTED[driver][2]
    assert [e.node for e in s.events] == [node, node]
    assert len(set(s.branches[node])) == 2
    jumps = np.hypot(*np.diff(s["C"], axis=0).T)
    assert jumps.max() < 3 * np.median(jumps)
    lo, hi, _ = EXPECTED[driver]
    history = s.input_values
    assert abs(history.max() - hi) < 1e-9 and abs(history.min() - lo) < 1e-9


def test_a_circuit_of_a_crank_that_turns_fully_is_one_turn():
    s = circuit(coupler_fourbar(), start=0.3)
    assert s.valid.all() and s.events == ()
    np.testing.assert_allclose(s.input_values[-1] - s.input_values[0], 2 * np.pi)
    np.testing.assert_allclose(s["P"][0], s["P"][-1], atol=1e-9)


def assert_on_the_smooth_curve(s, dense_factor=50):
    """Every sample of ``s`` has B 9 from A and 5 from O4 (closed form) and is where a
    sweep 50 times denser along the same path, tracked from the same branch, puts it."""
    theta = s.input_values
    a = np.column_stack([4 * np.cos(theta), 4 * np.sin(theta)])
    np.testing.assert_allclose(np.hypot(*(s["B"] - a).T), 9, rtol=1e-9)
    np.testing.assert_allclose(np.hypot(*(s["B"] - [10, 0]).T), 5, rtol=1e-9)
    dense = sweep(s.construction, np.linspace(theta[0], theta[-1],
                                              (len(theta) - 1) * dense_factor + 1),
                  start_branches={"B": int(np.ravel(s.branches["B"])[0])})
    np.testing.assert_allclose(dense["B"][::dense_factor], s["B"], rtol=0, atol=1e-9)


@pytest.mark.parametrize("start", [0.0, 0.3, np.pi, np.pi - 0.01])
def test_a_circuit_through_a_change_point_turns_on_till_its_node_is_back(start):
    """After one turn B is on its other branch, in its mirror pose: a second turn brings
    it back, wherever the turn starts (pi - 0.01: the change point within the first step
    of each turn). Each event is where the change point is."""
    s = circuit(change_point_fourbar(start=start))
    theta = s.input_values
    # a change of branch at each change point the path passes, not at its ends
    inside = [k for k in range(-3, 6) if theta[0] < (2 * k + 1) * np.pi < theta[-1]]
    assert s.valid.all() and len(s.events) == len(inside) >= 1
    for event in s.events:
        step = theta[event.index] - theta[event.index - 1]
        met = theta[event.index - 1] + event.fraction * step
        assert abs(np.angle(np.exp(1j * (met - np.pi)))) < 1e-6
    np.testing.assert_allclose(s.input_values[-1] - s.input_values[0], 4 * np.pi)
    np.testing.assert_allclose(s["B"][-1], s["B"][0], atol=1e-9)
    assert_on_the_smooth_curve(s)


@pytest.mark.parametrize("start", [np.pi - 0.01, np.pi - np.pi / 180])
def test_a_circuit_with_a_group_passes_a_node_through_a_change_point_at_a_turns_seam(start):
    """A closure group driven by the same crank continues from turn to turn; the
    node's change point within the first step of the second turn, or on its second
    sample, still changes its branch there."""
    c = change_point_fourbar(start=start)
    c.fixed("O6", -40, 0)
    alone = Construction("the group's four-bar with a circle node")
    alone.input("theta")
    alone.fixed("O2", 0, 0)
    alone.fixed("O6", -40, 0)
    alone.polar("A", "O2", 4, "theta")
    alone.circle_circle("D", ("A", "O6"), (35, 30), branch="left")
    sketch = sweep(alone, np.array([start]))["D"][0]
    c.closure("dyad", ["D"], [("A", "D", 35), ("O6", "D", 30)], near={"D": tuple(sketch)})
    s = circuit(c)
    assert s.valid.all() and len(s.events) == 2
    np.testing.assert_allclose(s.input_values[-1] - s.input_values[0], 4 * np.pi)
    np.testing.assert_allclose(s["B"][-1], s["B"][0], atol=1e-9)
    np.testing.assert_allclose(s["D"], sweep(alone, s.input_values)["D"], rtol=0, atol=1e-9)
    assert_on_the_smooth_curve(s)


@pytest.mark.parametrize("start, backwards", [(np.pi - 0.01, False), (np.pi + 0.01, True),
                                              (np.pi - np.pi / 180, False)])
def test_a_groups_change_point_in_the_first_step_of_a_turn_is_passed_each_turn(start,
                                                                             backwards):
    """B as a one-point closure group of the change-point crank-rocker, its change point
    within the first step of each turn (or on its second sample), either way round: two
    turns, back where it began, every sample where the circle node's circuit puts B."""
    ends = (start + 2 * np.pi, start) if backwards else (start, start + 2 * np.pi)
    c = Construction("change-point crank-rocker, B by a group")
    c.input("theta", range=ends)
    c.fixed("O2", 0, 0)
    c.fixed("O4", 10, 0)
    c.polar("A", "O2", 4, "theta")
    near = circuit(change_point_fourbar(start=start))["B"][0]
    c.closure("dyad", ["B"], [("A", "B", 9), ("O4", "B", 5)], near={"B": tuple(near)})
    s = circuit(c)
    assert s.valid.all()
    np.testing.assert_allclose(abs(s.input_values[-1] - s.input_values[0]), 4 * np.pi)
    np.testing.assert_allclose(s["B"][-1], s["B"][0], atol=1e-9)
    # the smooth motion: B by circles, tracked along the same path from the same pose
    by_circles = [sweep(change_point_fourbar(start=start), s.input_values,
                        start_branches={"B": branch}) for branch in (0, 1)]
    same = min(by_circles, key=lambda other: float(np.abs(other["B"][0] - s["B"][0]).max()))
    np.testing.assert_allclose(s["B"], same["B"], rtol=0, atol=1e-6)


def test_a_circuit_start_outside_every_interval_is_an_error_in_radians():
    toggle = np.arccos((R1 * R1 + R2 * R2 - (R3 + R4) ** 2) / (2 * R1 * R2))
    interval = f"{-toggle:.6g} to {toggle:.6g} rad"
    with pytest.raises(AssemblyError, match=rf"= 3.14159 rad is outside every assemblable "
                                            rf"interval: {interval}$"):
        circuit(triple_rocker("crank"), start=np.pi)



def test_a_circuit_starts_at_its_angle_however_many_turns_out_it_is_given():
    """150 rad is -45.63 deg after 24 turns back; a whole number like it may be degrees."""
    with pytest.warns(geokin.DegreesWarning, match="a start of 150 is 23.9 turns in radians"):
        s = circuit(triple_rocker("crank"), start=150)
    assert s.input_values[0] == pytest.approx(150 - 24 * 2 * np.pi, abs=1e-12)
    s = circuit(coupler_fourbar(), start=0.3 + 7 * 2 * np.pi)  # a full turn, 7 turns out
    assert s.input_values[0] == pytest.approx(0.3, abs=1e-12)
    np.testing.assert_allclose(s.input_values[-1] - s.input_values[0], 2 * np.pi)


def test_limits_and_circuit_for_a_line_circle_toggle():
    """P on the line y = 8 at 5 from a crank pin of radius 5: sin(theta) >= 3/5."""
    c = Construction("pin on a line")
    c.input("theta", range=(np.pi / 2 - 0.1, np.pi / 2 + 0.1))
    c.fixed("O", 0, 0)
    c.fixed("G1", 0, 8)
    c.fixed("G2", 1, 8)
    c.polar("A", "O", 5, "theta")
    c.line_circle("P", ("G1", "G2"), "A", 5, branch="second")
    [(lo, hi)] = limits(c).intervals
    assert abs(lo.value - np.arcsin(0.6)) < 1e-9 and abs(hi.value - (np.pi - np.arcsin(0.6))) < 1e-9
    assert (lo.node, lo.kind, hi.kind) == ("P", "tangent", "tangent")
    s = circuit(c)
    assert s.valid.all() and [e.node for e in s.events] == ["P", "P"]
    np.testing.assert_allclose(np.hypot(*(s["P"] - s["A"]).T), 5, rtol=1e-12)
    np.testing.assert_allclose(s["P"][:, 1], 8)
    np.testing.assert_allclose(s["P"][0], s["P"][-1], atol=1e-9)


def test_a_circuit_turns_back_where_the_branch_past_a_toggle_leaves_its_segment():
    """B slides in a slot x = 15, |y| <= 15, at 12 from a crank pin of radius 10.

    On the first branch the crank swings from where B reaches the slot's lower end
    (A 12 from (15, -15): -45 + 16.87 deg) up to the toggle (cos theta = 0.3); past
    the toggle, on the second branch, B reaches the upper end at 45 + 16.87 deg, long
    before the first branch's lower limit: the crank turns back there, passes the
    toggle again and swings down on the first branch.
    """
    c = Construction("slot")
    c.input("t")
    c.fixed("O", 0, 0)
    c.fixed("S1", 15, -15)
    c.fixed("S2", 15, 15)
    c.polar("A", "O", 10, "t")
    c.segment_circle("B", ("S1", "S2"), "A", 12, branch="first")
    s = circuit(c, start=0.0)
    # A at 10 from O and 12 from a slot end (15, +-15) lies at +-45 deg +- this
    reach = np.degrees(np.arccos((100 + 450 - 144) / (2 * 10 * np.sqrt(450))))
    toggle = np.degrees(np.arccos(0.3))
    t = np.degrees(s.inputs["t"])
    turns = t[np.flatnonzero(np.diff(np.sign(np.diff(t)))) + 1]
    np.testing.assert_allclose(turns, [toggle, 45 + reach, toggle, -45 + reach], atol=1e-8)
    assert s.valid.all() and t[0] == t[-1] == 0
    assert [(e.before, e.after) for e in s.events] == [("first", "second"), ("second", "first")]
    np.testing.assert_allclose(np.hypot(*(s["B"] - s["A"]).T), 12, rtol=1e-12)
    assert np.abs(s["B"][:, 0] - 15).max() < 1e-12 and np.abs(s["B"][:, 1]).max() < 15 + 1e-9
    # a motion, not a jump across poses it cannot take
    assert np.hypot(*np.diff(s["B"], axis=0).T).max() < 0.2
    low, high = limits(c).intervals[0]
    assert (low.kind, high.kind) == ("end", "tangent")
    assert describe_limit(low) == "node 'B': its root leaves its segment"


def _crank_rocker_slot(ground, crank, coupler, rocker, branch, s1, s2, radius):
    """A crank, a rocker's pin B, and C in a slot S1..S2 at ``radius`` from B."""
    c = Construction("crank, rocker B, C in a slot")
    c.input("t")
    c.fixed("O", 0, 0)
    c.fixed("O4", ground, 0)
    c.fixed("S1", *s1)
    c.fixed("S2", *s2)
    c.polar("A", "O", crank, "t")
    c.circle_circle("B", ("A", "O4"), (coupler, rocker), branch=branch)
    c.segment_circle("C", ("S1", "S2"), "B", radius, branch="first")
    return c, {("A", "B"): coupler, ("O4", "B"): rocker, ("B", "C"): radius}


def _assert_a_motion_that_closes(c, s, lengths):
    """Every sample assembled, every length kept, no point jumping, back where it began,
    and every turn of the input at a limit: a hair beyond it, on the branches held
    there, the mechanism cannot be assembled."""
    assert s.valid.all()
    for (p, q), length in lengths.items():
        np.testing.assert_allclose(np.hypot(*(s[p] - s[q]).T), length, rtol=1e-9)
    moves = np.max([np.hypot(*np.diff(s[p], axis=0).T) for p in "ABC"], axis=0)
    assert moves.max() < 0.05 * np.abs(np.stack([s[p] for p in "ABC"])).max()
    for p in "ABC":
        np.testing.assert_allclose(s[p][-1], s[p][0], atol=1e-9)
    t = s.inputs["t"]
    step = np.diff(t)
    for i in np.flatnonzero(step[:-1] * step[1:] < 0) + 1:
        held = {k: int(np.broadcast_to(v, t.shape)[i]) for k, v in s.branches.items()}
        beyond = geokin.engine.evaluate(
            c, {"t": np.array([t[i] + np.sign(step[i - 1]) * 1e-7])}, 1, held=held, track=False)
        assert not beyond.valid[0], np.degrees(t[i])


def test_a_circuit_back_on_its_branches_in_another_interval_runs_on_to_its_own():
    """On B left and C first this mechanism assembles on 27.07..27.94 and 54.57..83.50
    deg, on B right on 27.07..83.50: started at 69 deg, the circuit comes back to its
    starting branches in the first interval, and must go on to the second before it
    closes, never across the gap between them."""
    c, lengths = _crank_rocker_slot(7.355, 7.923, 3.282, 6.900, "left", (4.324, -9.286),
                                    (6.827, 0.298), 6.663)
    _assert_a_motion_that_closes(c, circuit(c, start=np.radians(69)), lengths)


def test_a_circuit_takes_as_many_passes_as_its_toggles_and_slot_ends_need():
    """A rocker's two toggles and a slot's two ends: thirteen passes before the circuit
    from 63.27 deg is back where it began."""
    c, lengths = _crank_rocker_slot(9.4005, 3.7919, 4.0937, 6.4475, "right",
                                    (-0.8658, -8.3040), (-3.3626, 8.5416), 7.4070)
    s = circuit(c, start=np.radians(63.27))
    _assert_a_motion_that_closes(c, s, lengths)
    step = np.diff(s.inputs["t"])
    assert 1 + np.count_nonzero(step[:-1] * step[1:] < 0) > 8


def test_a_circuit_turns_back_on_a_sliver_narrower_than_the_search_grid():
    """Past each of C's toggles, on its other branch, C leaves its slot within 0.03 deg:
    a stretch the 0.05-deg grid of a whole turn's search steps over, looked for again
    about the toggle; the circuit turns back there instead of striding across."""
    c = Construction("crank, rocker B, C in a slot")
    c.input("t", range=(np.radians(473.9307874), np.radians(113.9307874)))
    c.fixed("O", 0, 0)
    c.fixed("O4", 8.850196129433217, 0)
    c.polar("A", "O", 2.4715565112133637, "t")
    c.circle_circle("B", ("A", "O4"), (9.79139419035821, 8.638282361636161), branch="right")
    c.fixed("S1", 8.25141437125678, -8.48023037679857)
    c.fixed("S2", 10.220435770269045, 0.4719047894613091)
    c.segment_circle("C", ("S1", "S2"), "B", 3.5784199636267866, branch="second")
    lengths = {("A", "B"): 9.79139419035821, ("O4", "B"): 8.638282361636161,
               ("B", "C"): 3.5784199636267866}
    _assert_a_motion_that_closes(c, circuit(c), lengths)


def test_a_limit_where_circles_become_concentric_says_so():
    """A five-bar's second crank (cranks 15 on pivots 30 apart, the first at 0) brings
    its pin onto the first's at 180 deg: the circles of the coupler joint are concentric."""
    c = five_bar(links=30, ground=30, cranks=15)
    [(low, high)] = limits(c, "t2", at={"t1": 0.0}).intervals
    assert abs(high.value - np.pi) < 1e-9 and high.kind == "end"
    assert "coincident centres" in describe_limit(high)


def test_a_parallelogram_stays_a_parallelogram_round_its_circuit():
    """At a change point the roots meet and part; the smooth motion keeps the shape."""
    c = Construction("parallelogram")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 20, 0)
    c.polar("A", "O2", 10, "theta")
    c.circle_circle("B", ("A", "O4"), (20, 10), near=(20, 10))
    for s in (circuit(c, start=0.5), sweep(c, np.linspace(0, 4 * np.pi, 721))):
        assert s.valid.all()
        expected = np.c_[20 + 10 * np.cos(s.input_values), 10 * np.sin(s.input_values)]
        np.testing.assert_allclose(s["B"], expected, atol=1e-6)
        assert s.events  # the branch changes at each change point, and it is recorded


@settings(max_examples=60)
@given(lengths=st.lists(st.floats(1.0, 10.0), min_size=4, max_size=4))
def test_limits_agree_with_grashof_and_the_closed_form(lengths):
    """The crank turns fully exactly when Grashof says so; otherwise its limits are where
    the coupler and the follower line up: cos(t) = (a^2 + d^2 - (b +- c)^2) / (2 a d)."""
    d, a, b, c = lengths
    cos_outer = (a**2 + d**2 - (b + c) ** 2) / (2 * a * d)
    cos_inner = (a**2 + d**2 - (b - c) ** 2) / (2 * a * d)
    # stay clear of the borderline cases (change points, barely assemblable chains)
    assume(all(abs(abs(v) - 1) > 1e-3 for v in (cos_outer, cos_inner)))
    assume(max(lengths) < sum(lengths) - max(lengths) - 1e-3)
    c4 = Construction()
    c4.input("theta", range=(-np.pi, np.pi))
    c4.fixed("O2", 0, 0)
    c4.fixed("O4", d, 0)
    c4.polar("A", "O2", a, "theta")
    c4.circle_circle("B", ("A", "O4"), (b, c), branch="left")
    found = limits(c4, samples=3601)
    assert found.full_turn == grashof(d, a, b, c).input_turns
    if found.full_turn:
        return
    expected = [np.arccos(v) for v in (cos_outer, cos_inner) if abs(v) < 1]
    ends = [end.value for pair in found.intervals for end in pair]
    assert all(end.kind == "tangent" for pair in found.intervals for end in pair)
    # each limit is one of the closed-form angles (either sign, any turn), to 1e-9
    for value in ends:
        gaps = [abs(np.angle(np.exp(1j * (value - sign * e))))
                for e in expected for sign in (1, -1)]
        assert min(gaps) < 1e-9


def test_limits_of_a_large_length_input_end_at_float_resolution():
    """Above about 8192 no two floats are 1e-12 apart: the bisection must still stop."""
    c = Construction()
    c.input("s", kind="length", range=(9000, 11000))
    c.fixed("O", 0, 0)
    c.fixed("Q", 20000.3, 0)
    c.circle_circle("B", ("O", "Q"), ("s", 10000), branch="left")
    [(lo, hi)] = limits(c).intervals
    assert lo.kind == "tangent" and abs(lo.value - 10000.3) <= 4 * np.spacing(10000.3)
    assert hi.kind == "range" and hi.value == 11000
    [(lo2, _)] = limits(c, search_range=(11000, 9000)).intervals  # a reversed range is sorted
    assert lo2.value == lo.value


def test_a_circuit_reaches_a_toggle_beyond_an_end_of_the_range():
    """C on circles of 20 about O and 15 about S = (s, 0): assembles from s = 5 (a
    toggle) to the range's end at 30; C.x = (s^2 + 175) / 2s runs from sqrt(175) to 20."""
    c = Construction()
    c.input("s", kind="length", range=(0, 30))
    c.fixed("O", 0, 0)
    c.fixed("S", "s", 0)
    c.circle_circle("C", ("O", "S"), (20, 15), branch="left")
    s = circuit(c)
    assert s.valid.all()
    assert s.inputs["s"].min() == pytest.approx(5, abs=1e-9)
    assert s.inputs["s"].max() == pytest.approx(30, abs=1e-12)
    assert s["C"][:, 0].max() == pytest.approx(20, abs=1e-6)
    assert s["C"][:, 0].min() == pytest.approx(np.sqrt(175), abs=1e-3)
    assert {e.node for e in s.events} == {"C"}


def test_a_circuit_starts_on_the_interval_the_declared_range_covers():
    """A Grashof double-rocker (ground 40, input 30, coupler 10, output 35) assembles on
    +-(38.62..78.58) degrees; declared over 0..60 degrees, its circuit is the positive one."""
    c = Construction()
    c.input("theta", range=(0, np.radians(60)))
    c.fixed("O2", 0, 0)
    c.fixed("O4", 40, 0)
    c.polar("A", "O2", 30, "theta")
    c.circle_circle("B", ("A", "O4"), (10, 35), branch="left")
    s = circuit(c)
    assert s.valid.all() and (s.inputs["theta"] > 0).all()
    np.testing.assert_allclose(np.degrees([s.inputs["theta"].min(), s.inputs["theta"].max()]),
                               np.degrees(np.arccos([1875 / 2400, 475 / 2400])), atol=1e-6)


@pytest.mark.parametrize("declared, positive", [((0, 2 * np.pi), True),
                                                ((2 * np.pi, 0), False)])
def test_of_two_mirrored_intervals_a_circuit_takes_the_one_its_range_meets_first(declared,
                                                                                positive):
    """Chebyshev's double rocker (ground 20, crank 25, coupler 10, rocker 25) assembles in
    two mirrored intervals, 36.87..101.54 deg and its negative, equally inside a declared
    full turn that starts at neither: the turn from 0 meets the positive one first, the
    turn from 360 down the other."""
    c = fourbar(20, 25, 10, 25, range=declared)
    low = np.arccos(0.8)  # where crank and coupler fold: |A - O4| = 15
    theta = np.mod(circuit(c).inputs["theta"], 2 * np.pi)
    assert np.all((theta > np.pi) != positive)
    np.testing.assert_allclose(min(theta.min(), 2 * np.pi - theta.max()), low, atol=1e-9)


def test_limits_and_circuit_take_start_branches_as_sweep_does():
    c = triple_rocker("crank")
    assert limits(c, start_branches={"C": "right"}).held_branches == {"C": 1}
    assert limits(c, start_branches={"C": 1}).held_branches == {"C": 1}
    assert circuit(c, start_branches={"C": "right"}).events[0].before == "right"
    with pytest.raises(ConstructionError, match="no two-root node 'X'"):
        limits(c, start_branches={"X": "right"})
    with pytest.raises(ConstructionError, match="unknown branch 'up'"):
        circuit(c, start_branches={"C": "up"})


# -- a grid sample within the primitives' tolerances of a limit -------------------------


@pytest.mark.parametrize("past", [5e-10, 5e-9])
def test_a_grid_sample_just_past_a_slider_end_leaves_the_end_where_it_is(past):
    """P reaches the segment's end E at s = 6; a grid sample lies ``past`` it.

    The primitives take P as on the segment that close past its end (their
    tolerance is 1e-9 of its length): the limit is still at 6, on the
    assembled side.
    """
    c = Construction()
    c.input("s", kind="length", range=(0.0, 12.0))
    c.fixed("S", 0, 0)
    c.fixed("E", 10, 0)
    c.fixed("Q", 0, 3)
    c.polar("C", "Q", "s", 0)
    c.segment_circle("P", ("S", "E"), "C", 5, branch="second")  # |P - C| = 5: P = E at s = 6
    [(_, hi)] = limits(c, search_range=(0.0, 2 * (6 + past)), samples=1201).intervals
    assert hi.kind == "end" and -1e-12 <= 6 - hi.value <= 1e-12


@pytest.mark.parametrize("inside", [2e-9, 5e-9, 1e-7])
def test_a_grid_sample_just_inside_a_real_gap_keeps_the_gap(inside):
    """A coupler 1e-6 too long: a gap of 3.4e-4 rad about 0, one grid sample ``inside`` it.

    Its edges, in closed form: A to O4 is sqrt(a^2 + d^2 - 2ad cos t), at
    least b - c where B is found.
    """
    a, b, c, d = 30.25, 52.6 + 1e-6, 30.25, 52.6
    edge = np.arccos((a * a + d * d - (b - c) ** 2) / (2 * a * d))
    middle = -edge + inside  # the grid's middle sample
    found = limits(fourbar(d, a, b, c, range=(middle - np.pi, middle + np.pi)))
    assert not found.full_turn
    [(lo, hi)] = found.intervals
    assert lo.kind == hi.kind == "tangent"
    np.testing.assert_allclose([lo.value, hi.value], [edge - 2 * np.pi, -edge], rtol=0,
                               atol=1e-9)


@pytest.mark.parametrize("past", [1e-13, 1e-12, 5e-12, 1e-9])
def test_a_toggle_just_inside_the_searched_range_stays_a_limit(past):
    """Seed 000's crank toggles where coupler and follower align, ``past`` short of the range end.

    Beyond the toggle nothing assembles, however close to it the range ends:
    the limit is the toggle, on the assembled side. Closed form: A to C is
    then r3 + r4, so cos t = (r1^2 + r2^2 - (r3 + r4)^2) / (2 r1 r2).
    """
    toggle = np.arccos((R1 * R1 + R2 * R2 - (R3 + R4) ** 2) / (2 * R1 * R2))
    for search in ((0.0, toggle + past), (-toggle - past, 0.0)):
        [(lo, hi)] = limits(triple_rocker("crank"), search_range=search).intervals
        end = hi if search[0] == 0.0 else lo
        assert end.kind == "tangent" and end.node == "C"
        assert 0 <= toggle - abs(end.value) <= 1e-12


def test_a_value_where_the_input_name_goes_is_refused_with_where_it_goes():
    c = triple_rocker("crank")
    for call in (circuit, limits):
        with pytest.raises(ConstructionError, match=r"name of an input.*by keyword"):
            call(c, np.radians(150))
