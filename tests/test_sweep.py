import dataclasses

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from mechanisms import FOURBAR_004, SIXBAR, coupler_fourbar, fourbar, sixbar, triple_rocker

from geokin import Construction, ConstructionError, sweep
from geokin.engine import evaluate
from geokin.loops import fourbar_closed_form
from geokin.nodes import DEGENERATE, REASONS


def distance(s, p, q):
    return np.hypot(*(s[p] - s[q]).T)


def cross(s, origin, p, q):
    u, v = s[p] - s[origin], s[q] - s[origin]
    return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]


# -- seed 003: the six-bar ----------------------------------------------------


def test_sixbar_compiles_to_the_seed_step_list():
    text = str(sixbar().compile())
    assert text.splitlines()[1:] == [
        "  1  D   = fixed(0, 0)",
        "  2  mid = fixed(0, y)",
        "  3  A0  = fixed(0, y + l1)",
        "  4  B0  = fixed(x, l1)",
        "  5  A   = polar(A0, l2, theta)",
        "  6  B   = circle_circle(A, l3; B0, l4)  [left]",
        "  7  Ap  = line_circle(A0-A; A, l2p)  [first]",
        "  8  C   = line_circle(A-B; Ap, l3p)  [second]",
        "  9  M   = ray_circle(Ap->C; Ap, l5)  [second]",
    ]


def test_sixbar_seed_sweep_keeps_every_length_and_incidence():
    c = sixbar()
    theta = c.inputs["theta"].values()
    assert len(theta) == 113 and np.isclose(np.degrees(theta[-1]), 1792)
    s = sweep(c)
    assert s.valid.all()
    p = SIXBAR
    np.testing.assert_allclose(s["A0"], np.broadcast_to([0, p["y"] + p["l1"]], (113, 2)))
    np.testing.assert_allclose(s["B0"], np.broadcast_to([p["x"], p["l1"]], (113, 2)))
    for a, b, length in [("A0", "A", p["l2"]), ("A", "B", p["l3"]), ("B", "B0", p["l4"]),
                         ("Ap", "A", p["l2p"]), ("Ap", "C", p["l3p"]), ("Ap", "M", p["l5"]),
                         ("A0", "Ap", p["l2"] - p["l2p"])]:
        np.testing.assert_allclose(distance(s, a, b), length, rtol=1e-12, err_msg=f"{a}{b}")
    # C on line AB, A' on line A0A between A0 and A, M on the ray A'C beyond C
    np.testing.assert_allclose(cross(s, "A", "B", "C") / (p["l3"] * p["l3p"]), 0, atol=1e-12)
    np.testing.assert_allclose(cross(s, "A0", "A", "Ap") / p["l2"] ** 2, 0, atol=1e-12)
    along = np.einsum("ij,ij->i", s["C"] - s["Ap"], s["M"] - s["Ap"])
    np.testing.assert_allclose(along, p["l3p"] * p["l5"], rtol=1e-12)


def test_sixbar_branches_match_the_seed_choices():
    s = sweep(sixbar())
    # B: left of A->B0 is above the ground for this mechanism
    assert (s["B"][:, 1] > s["A"][:, 1]).all()
    # A' lies between A0 and A; C is the root beyond A' along A->B
    t = np.einsum("ij,ij->i", s["Ap"] - s["A0"], s["A"] - s["A0"]) / SIXBAR["l2"] ** 2
    np.testing.assert_allclose(t, 0.75)
    assert (np.einsum("ij,ij->i", s["C"] - s["A"], s["B"] - s["A"]) > 0).all()
    assert all((s.named_branches(n) == b).all()
               for n, b in [("B", "left"), ("Ap", "first"), ("C", "second"), ("M", "second")])
    assert s.events == ()


def test_sixbar_is_periodic_in_the_crank_angle():
    s = sweep(sixbar(), np.radians([0, 360, 720, 16, 376]))
    np.testing.assert_allclose(s["M"][0], s["M"][1], atol=1e-10)
    np.testing.assert_allclose(s["M"][0], s["M"][2], atol=1e-10)
    np.testing.assert_allclose(s["M"][3], s["M"][4], atol=1e-10)


# -- seed 004: the four-bar, open and crossed ------------------------------------


def fourbar_004_closed_form(theta2, open_):
    """Rocker angle by the half-angle formula of seed 004, with atan2.

    The open configuration takes the minus sign of the root (the seed's Python
    labels the plus sign "open", a sign slip: it draws the crossed one).
    """
    a, b, c, d = (FOURBAR_004[k] for k in "abcd")
    k1, k2, k3 = d / a, d / c, (a**2 - b**2 + c**2 + d**2) / (2 * a * c)
    big_a = np.cos(theta2) - k1 - k2 * np.cos(theta2) + k3
    big_b = -2 * np.sin(theta2)
    big_c = k1 - (k2 + 1) * np.cos(theta2) + k3
    root = np.sqrt(big_b**2 - 4 * big_a * big_c)
    return 2 * np.arctan2(-big_b + (-root if open_ else root), 2 * big_a)


@pytest.mark.parametrize(("branch", "open_"), [("left", True), ("right", False)])
def test_fourbar_004_open_and_crossed_match_the_closed_form(branch, open_):
    a, b, c, d = (FOURBAR_004[k] for k in "abcd")
    theta = np.linspace(0, 6 * 2 * np.pi, 2000)
    s = sweep(fourbar(d, a, b, c, branch=branch), theta)
    assert s.valid.all()
    theta4 = fourbar_004_closed_form(theta, open_)
    expected = np.stack([d + c * np.cos(theta4), c * np.sin(theta4)], axis=-1)
    np.testing.assert_allclose(s["B"], expected, atol=1e-9)
    np.testing.assert_allclose(distance(s, "A", "B"), b, rtol=1e-12)
    np.testing.assert_allclose(distance(s, "B", "O4"), c, rtol=1e-12)


def test_open_and_crossed_are_mirror_images_across_the_line_a_o4():
    left = sweep(fourbar(branch="left"))
    right = sweep(fourbar(branch="right"))
    assert (cross(left, "A", "O4", "B") > 0).all()
    assert (cross(right, "A", "O4", "B") < 0).all()


# -- branch choice and tracking ---------------------------------------------------


def test_near_picks_the_root_nearer_the_sketch_at_the_first_sample():
    c = Construction()
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 24, 0)
    c.polar("A", "O2", 10.55, "theta")
    c.circle_circle("B", ("A", "O4"), (25, 14), near=(30, -10))
    s = sweep(c)
    assert s.named_branches("B")[0] == "right"
    assert (s.branches["B"] == 1).all()
    assert s["B"][0, 1] < 0


def test_branch_override_at_sweep_time():
    s = sweep(fourbar(branch="left"), start_branches={"B": "right"})
    np.testing.assert_allclose(s["B"], sweep(fourbar(branch="right"))["B"])
    with pytest.raises(ConstructionError, match="did you mean 'B'"):
        sweep(fourbar(), start_branches={"b": "left"})
    with pytest.raises(ConstructionError, match="'left' or 'right'"):
        sweep(fourbar(), start_branches={"B": "up"})


def test_unreachable_samples_are_data_naming_the_failing_node():
    theta = np.radians(np.arange(0, 360, 1.0))
    s = sweep(triple_rocker("crank"), theta)
    limit = np.degrees(np.arccos((5**2 + 7**2 - 11**2) / (2 * 5 * 7)))  # 132.1774 degrees
    reachable = (np.degrees(theta) <= limit) | (np.degrees(theta) >= 360 - limit)
    np.testing.assert_array_equal(s.valid, reachable)
    assert set(s.failed_node[~s.valid]) == {"C"}
    assert set(s.failed_node[s.valid]) == {""}
    assert all(r.startswith("no intersection") for r in s.failure_reason[~s.valid])
    assert np.isnan(s["C"][~s.valid]).all() and np.isnan(s["B"][~s.valid]).all()
    assert np.isfinite(s["C"][s.valid]).all()
    assert s.explain(180).startswith("sample 180 (theta2 = 180 deg): node 'C' cannot be "
                                     "assembled: no intersection")


def test_after_a_gap_the_branch_resumes_by_continuity_not_by_default():
    # 0 -> 300 degrees crosses the unreachable stretch; the samples beyond it
    # must be the configuration reached by turning the crank backwards from 0
    forward = sweep(triple_rocker("crank"), np.radians(np.arange(0, 301.0)))
    backward = sweep(triple_rocker("crank"), np.radians(np.arange(0, -61.0, -1.0)))
    np.testing.assert_allclose(forward["C"][-1], backward["C"][-1], atol=1e-12)
    assert len(set(forward.branches["C"])) == 1
    # out to the limit and back: the crank retraces the same motion
    theta = np.radians(np.r_[np.arange(0, 200.0), np.arange(200, -1.0, -1)])
    there_and_back = sweep(triple_rocker("crank"), theta)
    np.testing.assert_allclose(there_and_back["C"][:100], there_and_back["C"][-1:-101:-1],
                               atol=1e-12)


def test_a_peer_defect_coming_back_on_the_other_branch_does_not_happen():
    # start on the right branch: the resumed samples are on the right branch too
    s = sweep(triple_rocker("crank"), np.radians(np.arange(0, 360.0)),
              start_branches={"C": "right"})
    valid = s.valid
    assert (s.named_branches("C")[valid] == "right").all()


def grazing():
    """Two unit circles whose centres come exactly 2 apart and part again at s = 0."""
    c = Construction("graze")
    c.input("s", kind="length", range=(-1, 1), samples=201)
    c.fixed("O", 0, 0)
    c.polar("Q", "O", "2 - s ** 2", 0)
    c.circle_circle("P", ("O", "Q"), (1, 1), branch="left")
    return c


@pytest.mark.parametrize("samples", [200, 201, 20, 21])
def test_a_graze_changes_branch_so_the_motion_continues_smoothly(samples):
    s = sweep(grazing(), samples=samples)
    assert s.valid.all()
    y = s["P"][:, 1]
    # the smooth motion runs from the upper half through the touching point to the lower
    assert (np.diff(y) < 0).all()
    assert len(s.events) == 1 and s.events[0].node == "P"
    assert s.events[0].before == "left" and s.events[0].after == "right"
    assert (s.named_branches("P")[y > 1e-9] == "left").all()
    assert (s.named_branches("P")[y < -1e-9] == "right").all()


def test_no_branch_change_where_roots_stay_apart():
    s = sweep(coupler_fourbar(), np.linspace(0, 4 * np.pi, 50))
    assert s.events == () and (s.branches["B"] == 0).all()


def test_a_whole_sweep_matches_the_closed_form_four_bar():
    """The benchmark four-bar's coupler point by the law of cosines, independently."""
    theta = np.linspace(0, 2 * np.pi, 1001)
    whole = sweep(coupler_fourbar(), theta)
    ax, ay = 10 * np.cos(theta), 10 * np.sin(theta)
    d = np.hypot(40 - ax, -ay)
    # B left of A -> O4: the direction to O4 turned by the angle at A of triangle A-B-O4
    at_a = np.arctan2(-ay, 40 - ax) + np.arccos((35**2 + d**2 - 30**2) / (2 * 35 * d))
    p_angle = at_a + np.radians(30)
    expected = np.c_[ax + 20 * np.cos(p_angle), ay + 20 * np.sin(p_angle)]
    np.testing.assert_allclose(whole["P"], expected, atol=1e-12)


def test_inputs_mapping_and_errors():
    c = coupler_fourbar()
    s = sweep(c, {"theta": np.linspace(0, 1, 7)})
    assert len(s) == 7 and s.input_values.shape == (7,)
    assert len(sweep(c)) == c.inputs["theta"].samples
    with pytest.raises(ConstructionError, match="unknown input 'thta'; did you mean 'theta'"):
        sweep(c, {"thta": [0.0]})
    with pytest.raises(ConstructionError, match="one-dimensional"):
        sweep(c, np.zeros((2, 3)))
    with pytest.raises(KeyError, match="did you mean 'P'"):
        sweep(c, [0.0])["p"]


def test_every_branch_is_recorded_at_every_sample():
    s = sweep(sixbar())
    assert set(s.branches) == {"B", "Ap", "C", "M"}
    assert all(b.shape == (len(s),) for b in s.branches.values())
    assert set(s.margins) == set(s.branches)


def test_nearly_coincident_centres_are_degenerate_not_an_arbitrary_root():
    c = Construction()
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 1, 0)
    c.polar("A", "O2", 1.0000000000000002, "theta")
    c.circle_circle("B", ("A", "O4"), (2, 2), branch="right")
    s = sweep(c, [0.0, 0.5])
    assert list(s.valid) == [False, True]
    assert s.failure_reason[0].startswith("degenerate")


def test_inputs_of_different_lengths_are_a_clear_error():
    c = Construction()
    c.input("a", samples=5)
    c.input("b", kind="length", range=(0, 1), samples=7)
    c.fixed("O", 0, 0)
    c.polar("A", "O", "b + 1", "a")
    with pytest.raises(ConstructionError, match=r"different lengths \(a: 3, b: 4\)"):
        sweep(c, {"a": np.zeros(3), "b": np.zeros(4)})
    assert len(sweep(c, {"a": np.zeros(3), "b": 0.5})) == 3
    # defaulted inputs share one sampling: the given one's, else the first input's
    assert len(sweep(c)) == 5
    np.testing.assert_allclose(sweep(c).inputs["b"], np.linspace(0, 1, 5))
    assert len(sweep(c, {"b": np.zeros(9)})) == 9
    with pytest.raises(ConstructionError, match="at least one sample"):
        sweep(c, {"a": [], "b": []})


def test_a_point_with_a_finite_x_but_no_y_is_not_assembled():
    c = Construction()
    c.input("s", kind="length", range=(0, 10), samples=11)
    c.fixed("P", 0, "sqrt(s - 5)")
    s = sweep(c)
    np.testing.assert_array_equal(s.valid, np.arange(11) >= 5)
    assert set(s.failed_node[~s.valid]) == {"P"}


def test_near_on_a_ray_picks_a_root_on_the_ray():
    c = Construction()
    c.input("t")
    c.fixed("O", 0, 0)
    c.fixed("X", 1, 0)
    c.polar("Q", "O", 1, "t")
    c.ray_circle("P", ("O", "X"), "O", 5, near=(-5, 0))  # the root at -5 is off the ray
    s = sweep(c, [0.0, 0.1])
    assert s.valid.all() and s.named_branches("P")[0] == "second"


def test_a_node_tangent_all_along_is_valid_and_needs_no_branch_changes():
    """A circle rolling along a line at its radius touches it at every sample."""
    c = Construction()
    c.input("s", kind="length", range=(0, 10), samples=10_001)
    c.fixed("G1", 0, 0)
    c.fixed("G2", 1, 0)
    c.fixed("O", 0, 2)
    c.polar("Q", "O", "s", 0)
    c.line_circle("T", ("G1", "G2"), "Q", 2, branch="first")
    s = sweep(c)
    assert s.valid.all() and s.events == ()
    np.testing.assert_allclose(s["T"], np.c_[np.linspace(0, 10, 10_001), np.zeros(10_001)],
                               atol=1e-12)


def test_roots_that_stay_close_without_meeting_keep_their_branch():
    """Circles that all but touch all the way round: no branch change, whatever N."""
    c = Construction()
    c.input("theta")
    c.fixed("O", 0, 0)
    c.polar("Q", "O", 2 - 1e-10, "theta")
    c.circle_circle("B", ("O", "Q"), (1, 1), branch="left")
    for n in (37, 1000, 100_000):
        s = sweep(c, np.linspace(0, 2 * np.pi, n))
        assert s.valid.all() and s.events == ()
    s = sweep(grazing(), samples=100_001)  # one real graze among many samples
    assert len(s.events) == 1


def parallelogram():
    c = Construction("parallelogram")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 40, 0)
    c.polar("A", "O2", 10, "theta")
    c.circle_circle("B", ("A", "O4"), (40, 10), near=(50, 5))
    return c


@pytest.mark.parametrize("start", [0.0, 0.3])
@pytest.mark.parametrize("samples", [37, 60, 97, 100, 150, 1000])
def test_a_parallelogram_stays_one_through_its_change_points(start, samples):
    """Its roots meet at every half turn; the sweep keeps the parallelogram, to the sample."""
    theta = np.radians(np.linspace(start, start + 1800, samples))
    s = sweep(parallelogram(), theta)
    assert s.valid.all()
    wrong = np.hypot(*(s["B"] - s["A"] - [40, 0]).T) > 1e-6
    # a meeting of the roots closer to a sample than the sampling can tell (0.3 degrees
    # in steps of 50) may put that one sample on the other root, which is then within
    # 1% of the coupler's length: the mechanism never turns into the crossed form
    separation = 2 * 40 * np.sqrt(np.maximum(s.margins["B"], 0))
    assert (separation[wrong] < 0.01 * 40).all()
    assert wrong.sum() <= 2
    if samples >= 97:  # steps of 19 degrees or less: exact but for the two end samples
        assert not wrong[1:-1].any()


def test_a_point_is_found_by_any_spelling_of_its_name_that_reads_the_same():
    c = Construction()
    c.input("t")
    c.fixed("O", 0, 0)
    c.polar("Ａ", "O", 1, "t")  # a fullwidth letter: declared, and kept, as plain A
    s = sweep(c, [0.0])
    np.testing.assert_array_equal(s["Ａ"], s["A"])
    np.testing.assert_allclose(s["A"][0], [1.0, 0.0])


def test_a_sweep_and_its_construction_cannot_be_changed_once_made():
    c = fourbar()
    theta = np.linspace(0, 1, 5)
    s = sweep(c, theta)
    for array in (s.valid, s.failed_step, s.reason_code, s["B"], s.inputs["theta"],
                  s.branches["B"], s.margins["B"]):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 0
    assert theta.flags.writeable  # the caller's own array is left as it was
    # what sweeps may share (no failing step, one branch throughout) cannot be made
    # writeable again through one of them, nor through what it is a view of
    for array in (s.failed_step, s.reason_code, s.branches["B"]):
        while isinstance(array, np.ndarray):
            with pytest.raises(ValueError):
                array.flags.writeable = True
            array = array.base
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.events = ()  # type: ignore[misc]
    compiled = c.compile()
    with pytest.raises(TypeError):
        compiled.parameters["crank"] = 1.0  # type: ignore[index]
    with pytest.raises(TypeError):
        compiled.inputs["theta"] = compiled.inputs["theta"]  # type: ignore[index]
    # a second sweep of the same compiled construction sees it as the first did
    np.testing.assert_array_equal(sweep(c, np.linspace(0, 1, 5))["B"], s["B"])


@pytest.mark.parametrize("block", [7, 45, 64])
def test_a_sweep_in_blocks_is_the_sweep_in_one_pass(monkeypatch, block):
    """Block boundaries on a change point (sample 360 of the parallelogram), in a gap
    of the six-bar's coarse sampling, anywhere: every array and event the same."""
    import geokin.engine

    parallelogram = fourbar(10, 4, 10, 4)
    cases = [(parallelogram, np.linspace(0, 2 * np.pi, 721)),
             (sixbar(), np.radians(np.arange(0, 1800.0, 7.3))),
             (triple_rocker("crank"), np.linspace(-np.pi, np.pi, 400))]
    whole = [sweep(c, theta) for c, theta in cases]
    untracked = [evaluate(one.construction, one.inputs, len(one), held=one.branches, track=False)
                 for one in whole]
    monkeypatch.setattr(geokin.engine, "BLOCK_SAMPLES", block)
    monkeypatch.setattr(geokin.engine, "BLOCKED_ABOVE", block)
    for (c, theta), one, alone in zip(cases, whole, untracked, strict=True):
        # evaluated at isolated inputs on given branches (as kinematics does), in parts
        parts = evaluate(one.construction, one.inputs, len(one), held=one.branches, track=False)
        np.testing.assert_array_equal(parts.valid, alone.valid)
        np.testing.assert_array_equal(parts.reason_code, alone.reason_code)
        for name in one.construction.point_names:
            np.testing.assert_array_equal(parts[name], alone[name])
        blocked = sweep(c, theta)
        assert blocked.events == one.events
        np.testing.assert_array_equal(blocked.valid, one.valid)
        np.testing.assert_array_equal(blocked.failed_step, one.failed_step)
        np.testing.assert_array_equal(blocked.reason_code, one.reason_code)
        for name in one.construction.point_names:
            np.testing.assert_array_equal(blocked[name], one[name])
        for name in one.branches:
            np.testing.assert_array_equal(blocked.branches[name], one.branches[name])
            np.testing.assert_array_equal(blocked.margins[name], one.margins[name])


def test_require_assembled_names_every_cause_when_no_sample_assembles():
    import re

    from geokin import AssemblyError

    c = Construction("reach")
    c.input("r", kind="length", range=(1, 10), samples=10)
    c.fixed("O", 0, 0)
    c.fixed("Q", 4, 0)
    c.circle_circle("P", ("O", "Q"), ("r", 1), branch="left")     # meets for 3 <= r <= 5
    s = sweep(c)
    assert s.require_assembled() is s  # one sample that assembles is enough
    c.circle_circle("R", ("O", "Q"), ("r", 100), branch="left")   # for 96 <= r <= 104
    s = sweep(c)
    assert not s.valid.any()
    with pytest.raises(AssemblyError, match=re.escape(
            "no sample can be assembled: nodes fail: node 'P' at 7 of 10 samples (no "
            "intersection: the curves do not meet), node 'R' at 3 of 10 samples (no "
            "intersection: the curves do not meet)")) as caught:
        s.require_assembled()
    assert caught.value.node == "P"


# -- a point in a link's own frame ---------------------------------------------------


def test_a_coupler_point_in_the_couplers_frame_is_the_polar_point_and_the_closed_form():
    """local(A->B, 20 cos 30°, 20 sin 30°) is polar(A, 20, 30° from A->B), and the loop's answer."""
    c = coupler_fourbar()
    alpha = np.radians(30)
    c.local("Q", "A", "B", (20 * np.cos(alpha), 20 * np.sin(alpha)))
    theta = np.linspace(0, 2 * np.pi, 721)
    s = sweep(c, theta)
    assert s.valid.all()
    np.testing.assert_allclose(s["Q"], s["P"], rtol=0, atol=1e-12)
    theta3, _ = fourbar_closed_form(40, 10, 35, 30, theta)
    a = 10 * np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    expected = a + 20 * np.stack([np.cos(theta3 + alpha), np.sin(theta3 + alpha)], axis=-1)
    np.testing.assert_allclose(s["Q"], expected, rtol=0, atol=1e-10)


@given(st.floats(-80, 80), st.floats(-80, 80), st.floats(0, 2 * np.pi))
def test_a_point_in_a_links_frame_moves_with_the_link(u, v, start):
    """Over the motion a local point keeps its distances to both points of its frame.

    It is hypot(u, v) from the origin, hypot(35 - u, v) from the other end of
    the 35-long coupler, and on the side of the coupler that v's sign says.
    """
    c = fourbar(40, 10, 35, 30)
    c.local("P", "A", "B", (u, v))
    s = sweep(c, start + np.linspace(0, 2 * np.pi, 37))
    assert s.valid.all()
    scale = 1e-12 * max(80, abs(u), abs(v))
    np.testing.assert_allclose(distance(s, "P", "A"), np.hypot(u, v), rtol=0, atol=scale)
    np.testing.assert_allclose(distance(s, "P", "B"), np.hypot(35 - u, v), rtol=0, atol=scale)
    np.testing.assert_allclose(cross(s, "A", "B", "P") / 35, v, rtol=0, atol=scale)


def test_a_frame_whose_two_points_meet_is_degenerate_at_those_samples():
    c = Construction()
    c.input("s", kind="length", range=(-1, 1), samples=5)
    c.fixed("O", 0, 0)
    c.fixed("T", "s", 0)
    c.local("P", "O", "T", (2, 1))
    s = sweep(c)
    assert s.valid.tolist() == [True, True, False, True, True]
    np.testing.assert_allclose(s["P"][[0, 4]], [[-2, -1], [2, 1]], atol=1e-15)
    assert s.failure_reason[2] == REASONS[DEGENERATE]
    assert s.failure_reason[2].startswith("degenerate input")
    assert "node 'P' cannot be assembled" in s.explain(2)


def test_fixed_points_move_with_the_frame_of_an_origin():
    """A fixed point found once in the plan is found again, shifted, in another frame."""
    c = coupler_fourbar().compile()
    theta = np.linspace(0, 2 * np.pi, 50)
    plain = evaluate(c, {"theta": theta}, 50)
    shifted = evaluate(c, {"theta": theta}, 50, origin=(5.0, -3.0))
    assert shifted.points.coords("O4") == (35.0, 3.0)
    np.testing.assert_allclose(shifted["P"] + (5.0, -3.0), plain["P"], rtol=0, atol=1e-12)


def test_a_points_coordinates_cannot_be_written_through():
    """The coordinates a sweep gives are read-only: its points are stacked from them."""
    swept = sweep(coupler_fourbar(), np.linspace(0, 6, 10))
    x, y = swept.points.coords("B")
    with pytest.raises(ValueError, match="read-only"):
        x[0] = 99.0
    assert np.hypot(*(swept["B"][0] - swept["O4"][0])) == pytest.approx(30)


# -- points in the frame of a joint and the centre of its circle ---------------------


def frames_on_circles():
    """A four-bar whose coupler and rocker carry points in frames whose length is a radius.

    B is on circles of radius l3 about A and l4 about O4: each frame below is
    as long as one of them, which the evaluation takes instead of measuring.
    """
    c = Construction("frames on circles")
    c.input("theta")
    c.parameter("l3", 35)
    c.parameter("l4", 30)
    c.fixed("O2", 0, 0)
    c.fixed("O4", 40, 0)
    c.polar("A", "O2", 10, "theta")
    c.circle_circle("B", ("A", "O4"), ("l3", "l4"), branch="left")
    c.local("P1", "A", "B", (20, 7))
    c.local("P2", "B", "A", (-5, 3))
    c.local("P3", "O4", "B", (12, -4))
    c.polar("P4", "A", 9, np.radians(40), reference=("B", "O4"))
    c.along("P5", ("O4", "B"), -6)
    return c


def in_frame(s, origin, toward, u, v):
    """(u, v) in the frame of two points of a sweep, its length measured."""
    d = s[toward] - s[origin]
    d = d / np.hypot(d[..., 0], d[..., 1])[..., None]
    return s[origin] + u * d + v * np.stack([-d[..., 1], d[..., 0]], axis=-1)


@pytest.mark.parametrize("variants", [None, {"l3": [30.0, 35.0, 40.0], "l4": [28.0, 30.0, 33.0]}])
def test_points_in_frames_on_circles_are_where_the_measured_frame_puts_them(variants):
    """Each point against its frame measured on the sweep's own joints, for the
    construction's lengths and for variants whose lengths (the frames') differ."""
    c = frames_on_circles()
    theta = np.linspace(0, 2 * np.pi, 361)
    s = sweep(c, theta, parameters=variants)
    assert s.valid.all()
    angle = np.radians(40)
    expected = {"P1": in_frame(s, "A", "B", 20, 7), "P2": in_frame(s, "B", "A", -5, 3),
                "P3": in_frame(s, "O4", "B", 12, -4),
                "P4": s["A"] + in_frame(s, "B", "O4", 9 * np.cos(angle), 9 * np.sin(angle))
                - s["B"],
                "P5": in_frame(s, "O4", "B", -6, 0)}
    for name, where in expected.items():
        np.testing.assert_allclose(s[name], where, rtol=0, atol=1e-12 * 50, err_msg=name)
