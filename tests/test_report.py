import dataclasses
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from mechanisms import five_bar, parallelograms_in_series

import geokin
from geokin import Construction, circuit, load, sweep
from geokin.analysis import analyze
from geokin.errors import AnalysisError
from geokin.kinematics import link_angles

CONSTRUCTIONS = Path(__file__).parents[1] / "constructions"


def fourbar(ground, crank, coupler, follower):
    c = Construction(f"four-bar {ground}, {crank}, {coupler}, {follower}")
    c.input("theta2", range=(-np.pi, np.pi))
    c.fixed("A", 0, 0)
    c.fixed("D", ground, 0)
    c.polar("B", "A", crank, "theta2")
    c.circle_circle("C", ("B", "D"), (coupler, follower), branch="left")
    c.link("crank", "A", "B")
    c.link("coupler", "B", "C")
    c.link("follower", "D", "C")
    c.trace("C")
    return c


def test_seed_000_transmission_angle_extremes_for_7_4_5_5():
    report = analyze(fourbar(7, 4, 5, 5), degrees=True)
    mu = report.transmission_angles["C"]
    assert round(mu.minimum, 2) == 34.92 and round(mu.maximum, 2) == 180.0
    assert report.four_bars[0].kind.startswith("triple-rocker")


def test_triple_rocker_report_has_its_limits_dof_and_class():
    report = analyze(fourbar(7, 5, 6, 5), degrees=True)
    assert report.dof == 1 and report.mobility.matches_inputs
    [(lo, hi)] = report.inputs["theta2"].intervals
    assert (round(lo, 4), round(hi, 4)) == (-132.1774, 132.1774)
    assert [limit.kind for limit in report.inputs["theta2"].limits] == ["tangent"] * 2
    assert report.four_bars[0].code == "RRR1"
    # the circuit's coupler curve is closed
    assert report.curves["C"].closed


def test_a_loop_whose_input_turns_fully_only_alone_says_so():
    """A crank-rocker (ground 4, crank 1, coupler 4, rocker 3) whose rocker pin B carries
    a dyad to F = (1, 4) of 1 and 1.5: E exists only while B is within 2.5 of F, which
    the rocker's swing from (4, 3) to (2, 2.24) crosses, so the crank cannot turn fully."""
    c = Construction("crank-rocker with a dyad")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 4, 0)
    c.fixed("F", 1, 4)
    c.polar("A", "O2", 1, "theta")
    c.circle_circle("B", ("A", "O4"), (4, 3), branch="left")
    c.circle_circle("E", ("B", "F"), (1, 1.5), branch="left")
    report = analyze(c, degrees=True)
    assert not report.inputs["theta"].full_turn
    assert report.four_bars[0].turning == ("input",)
    assert ("four-bar O2-A-B-O4 (ground 4, input 1, coupler 4, output 3): crank-rocker "
            "(GCRR); input turns fully in this loop alone") in report.to_text().splitlines()


def test_a_crank_declared_over_a_quarter_turn_is_analysed_over_a_whole_one_and_says_so():
    """The report's figures are of the circuit: for a crank that turns fully, one turn,
    whatever range it is declared over; the rocker's swing is the cosine rule's."""
    c = Construction("crank-rocker")
    c.input("theta2", range=(0, np.pi / 2))
    c.fixed("A", 0, 0)
    c.fixed("D", 40, 0)
    c.polar("B", "A", 10, "theta2")
    c.circle_circle("C", ("B", "D"), (35, 30), branch="left")
    c.link("follower", "D", "C")
    report = analyze(c, degrees=True)
    assert report.warnings == ("input 'theta2' turns fully: the figures below are of one "
                               "whole turn, not of its declared range (0 to 90 deg)",)
    # the rocker's extremes: crank and coupler stretched out (45) and folded (25)
    swing = [np.degrees(np.arccos((900 + 1600 - d * d) / 2400)) for d in (25, 45)]
    rocker = report.strokes["follower.angle"]
    np.testing.assert_allclose([180 - rocker.maximum, 180 - rocker.minimum], swing, atol=1e-6)
    assert analyze(fourbar(40, 10, 35, 30), degrees=True).warnings == ()


def test_crank_rocker_turns_fully_and_has_a_time_ratio():
    report = analyze(fourbar(40, 10, 35, 30))
    assert report.inputs["theta2"].full_turn
    assert report.four_bars[0].kind == "crank-rocker"
    follower = report.strokes["follower.angle"]
    # the follower's dead positions: crank and coupler in line, B at 10 + 35 or 35 - 10
    # from A; B above the ground, on the left of A -> D as declared
    angles, cranks = [], []
    for reach, crank_turn in ((45.0, 0.0), (25.0, np.pi)):
        cos_b = (40**2 + 30**2 - reach**2) / (2 * 40 * 30)  # angle at D in triangle A-D-B
        angles.append(np.pi - np.arccos(cos_b))  # direction D -> B
        bx, by = 40 + 30 * np.cos(angles[-1]), 30 * np.sin(angles[-1])
        cranks.append(np.arctan2(by, bx) + crank_turn)  # A on the line A-B, or against it
    low, high = min(angles), max(angles)
    assert follower.minimum == pytest.approx(low, abs=1e-6)
    assert follower.maximum == pytest.approx(high, abs=1e-6)
    forward = (cranks[angles.index(high)] - cranks[angles.index(low)]) % (2 * np.pi)
    assert follower.time_ratio == pytest.approx(forward / (2 * np.pi - forward), rel=1e-6)


def test_quick_return_time_ratio_matches_the_closed_form():
    report = analyze(load(CONSTRUCTIONS / "quick_return.toml"), degrees=True)
    alpha = 2 * np.degrees(np.arcsin(40 / 60))
    ratio = report.strokes["lever.angle"].time_ratio
    assert max(ratio, 1 / ratio) == pytest.approx((180 + alpha) / (180 - alpha), rel=1e-6)


def test_the_shipped_sixbar_has_one_degree_of_freedom():
    report = analyze(load(CONSTRUCTIONS / "sixbar.toml"))
    assert report.dof == 1
    assert report.mobility.moving_links == 5 and report.mobility.lower_pairs == 7


def test_a_rocker_swing_is_measured_between_samples():
    """Ground 40, crank 30, coupler 20, follower 25: the follower swings between the
    angles where crank and coupler line up, cos(phi) = (50^2 - 40^2 - 25^2) / (2 40 25)."""
    report = analyze(fourbar(40, 30, 20, 25), degrees=True)
    swing = report.strokes["follower.angle"]
    extreme = np.degrees(np.arccos((50**2 - 40**2 - 25**2) / (2 * 40 * 25)))
    got = sorted(v % 360 for v in (swing.minimum, swing.maximum))
    np.testing.assert_allclose(got, [extreme, 360 - extreme], atol=1e-4)


def test_the_quick_returns_strokes_and_time_ratios_match_the_closed_form():
    """Seed 001: crank r2 = 40 turning about O2, r1 = 60 above the lever's pivot O1; the ram's
    guide r1 + r6 = 120 above O1. The lever swings beta = asin(r2 / r1) either side of
    upright, where it is tangent to the crank circle: the crank turns 180 + 2 beta degrees
    from the lever's right extreme to its left one, 180 - 2 beta back. The block on the
    ram's pin slides out to 120 / cos(beta) and back to 120 twice a turn: no time ratio."""
    strokes = analyze(load(CONSTRUCTIONS / "quick_return.toml")).strokes
    beta = np.arcsin(40 / 60)
    slow = (np.pi + 2 * beta) / (np.pi - 2 * beta)
    lever = strokes["lever.angle"]
    assert lever.minimum == pytest.approx(np.pi / 2 - beta, abs=1e-9)
    assert lever.maximum == pytest.approx(np.pi / 2 + beta, abs=1e-9)
    assert lever.stroke == pytest.approx(2 * beta, abs=1e-9)
    assert lever.time_ratio == pytest.approx(slow, rel=5e-7)
    assert lever.strokes_per_turn == 1
    # the ram, 120 tan(beta) either side of the guide's point C, left while the lever swings left
    for ram in (strokes["B.x"], strokes["ram.position"]):
        assert (ram.minimum, ram.maximum) == pytest.approx(
            (-120 * np.tan(beta), 120 * np.tan(beta)), rel=1e-9)
        assert ram.time_ratio == pytest.approx(1 / slow, rel=5e-7)
        # the usual figure: the slower stroke over the faster, here the ram's return
        assert ram.quick_return_ratio == pytest.approx(slow, rel=5e-7)
        assert ram.slower_stroke == "max->min"
    assert lever.quick_return_ratio == lever.time_ratio and lever.slower_stroke == "min->max"
    # the block on the crank pin, from O1: r1 - r2 at the bottom, r1 + r2 at the top, half
    # a turn apart
    pin = strokes["pin_block.position"]
    assert (pin.minimum, pin.maximum, pin.stroke) == pytest.approx((20, 100, 80), rel=1e-12)
    assert pin.time_ratio == pytest.approx(1, rel=1e-12)
    assert pin.quick_return_ratio >= 1 and pin.slower_stroke is None
    block = strokes["ram_block.position"]
    assert (block.minimum, block.maximum) == pytest.approx((120, 120 / np.cos(beta)), rel=1e-9)
    assert block.strokes_per_turn == 2 and block.time_ratio is None


def test_a_crank_turning_clockwise_makes_the_other_stroke_of_a_quick_return_slower(tmp_path):
    """Seed 001's quick return declared over [360, 0] degrees: its crank turns clockwise,
    so the lever swings left in 180 - 2 beta degrees of crank and back in 180 + 2 beta
    (beta = asin(r2 / r1)), and every time ratio is the inverse of the turn the other way."""
    text = (CONSTRUCTIONS / "quick_return.toml").read_text()
    assert text.count("range = [0, 360]") == 1
    script = tmp_path / "clockwise.toml"
    script.write_text(text.replace("range = [0, 360]", "range = [360, 0]"))
    construction = load(script)
    assert (np.diff(circuit(construction).inputs["theta2"]) < 0).all()
    strokes = analyze(construction).strokes
    beta = np.arcsin(40 / 60)
    slow = (np.pi + 2 * beta) / (np.pi - 2 * beta)
    lever = strokes["lever.angle"]
    assert lever.time_ratio == pytest.approx(1 / slow, rel=5e-7)
    assert lever.slower_stroke == "max->min"
    for ram in (strokes["B.x"], strokes["ram.position"]):
        assert ram.time_ratio == pytest.approx(slow, rel=5e-7)
        assert ram.slower_stroke == "min->max"
    assert lever.minimum == pytest.approx(np.pi / 2 - beta, abs=1e-9)


def test_the_text_gives_the_time_ratio_at_least_1_and_the_slower_stroke():
    """Seed 001's quick return: (180 + alpha) / (180 - alpha), alpha = 2 asin(r2 / r1), the
    lever slower from its minimum to its maximum angle, the ram slower coming back."""
    report = analyze(load(CONSTRUCTIONS / "quick_return.toml"), degrees=True)
    alpha = 2 * np.degrees(np.arcsin(40 / 60))
    slow = f"{(180 + alpha) / (180 - alpha):.4f}"
    lines = dict(line.split(": ", 1) for line in report.to_text("mm").splitlines()
                 if ": " in line)
    assert lines["lever.angle"].endswith(f", time ratio {slow} (min->max slower)")
    assert lines["ram.position"].endswith(f", time ratio {slow} (max->min slower)")
    assert lines["pin_block.position"].endswith(", time ratio 1.0000 (strokes equal)")
    assert lines["ram_block.position"].endswith(", 2 strokes per turn")
    data = report.to_dict()["strokes"]
    assert data["ram.position"]["time_ratio"] == pytest.approx(1 / float(slow), rel=1e-4)
    assert data["ram.position"]["quick_return_ratio"] == pytest.approx(float(slow), rel=1e-4)
    assert data["ram.position"]["slower_stroke"] == "max->min"
    assert data["pin_block.position"]["slower_stroke"] is None
    assert data["ram_block.position"]["quick_return_ratio"] is None


@pytest.mark.parametrize("k", [-660, -530, 530, 660])
def test_analyze_at_any_scale_gives_the_same_figures_scaled_or_none(k):
    """A crank-rocker 2**k times larger: angles equal, lengths 2**k times, no wrong zeros."""
    def crank_rocker(f):
        c = Construction("crank-rocker")
        c.input("theta")
        c.fixed("O2", 0, 0)
        c.fixed("O4", 40 * f, 0)
        c.polar("A", "O2", 10 * f, "theta")
        c.circle_circle("B", ("A", "O4"), (35 * f, 30 * f), branch="left")
        c.polar("P", "A", 20 * f, np.radians(30), reference=("A", "B"))
        c.link("crank", "O2", "A")
        c.link("coupler", "A", "B", "P")
        c.link("rocker", "O4", "B")
        c.trace("P")
        return c

    base, scaled = analyze(crank_rocker(1.0)), analyze(crank_rocker(2.0**k))
    for node, mu in base.transmission_angles.items():
        assert scaled.transmission_angles[node].minimum == pytest.approx(mu.minimum, rel=1e-12)
        assert scaled.transmission_angles[node].maximum == pytest.approx(mu.maximum, rel=1e-12)
    assert set(scaled.strokes) == set(base.strokes)
    assert scaled.strokes["P.x"].stroke == pytest.approx(
        base.strokes["P.x"].stroke * 2.0**k, rel=1e-9)
    assert scaled.curves["P"].length == pytest.approx(
        base.curves["P"].length * 2.0**k, rel=1e-12)
    # an area beyond the normal range of floats is not given, rather than given wrong
    assert scaled.curves["P"].area is None


# -- the report as data ------------------------------------------------------------------


def shape(data):
    """The keys of nested dicts in order, and the items of lists: a report's shape."""
    if isinstance(data, dict):
        return [(key, shape(value)) for key, value in data.items()]
    if isinstance(data, list):
        return [shape(value) for value in data]
    return None


def crank_rocker_closed_form(theta):
    """The shipped crank-rocker 40/10/35/30 with P 20 from A at 30 degrees off A->B."""
    a = np.c_[10 * np.cos(theta), 10 * np.sin(theta)]
    d = np.array([40.0, 0.0]) - a
    dist = np.hypot(*d.T)[:, None]
    along = (35**2 - 30**2 + dist**2) / (2 * dist)
    across = np.sqrt(35**2 - along**2)
    b = a + (along * d + across * np.c_[-d[:, 1], d[:, 0]]) / dist  # left of A -> O4
    u = (b - a) / 35
    turn = np.radians(30)
    p = a + 20 * np.c_[u[:, 0] * np.cos(turn) - u[:, 1] * np.sin(turn),
                       u[:, 0] * np.sin(turn) + u[:, 1] * np.cos(turn)]
    angles = {"coupler.angle": np.degrees(np.unwrap(np.arctan2(*(b - a).T[::-1]))),
              "rocker.angle": np.degrees(np.arctan2(b[:, 1], b[:, 0] - 40))}
    return p, angles


def stroke_of(theta, values):
    """Extremes and time ratio of an output over a dense turn, each extreme's place
    refined by the parabola through its neighbours."""
    def extreme(i):
        left, mid, right = values[i - 1], values[i], values[i + 1]
        shift = 0.5 * (left - right) / (left - 2 * mid + right)
        return theta[i] + shift * (theta[1] - theta[0]), mid - 0.25 * (left - right) * shift
    (at_min, low), (at_max, high) = extreme(np.argmin(values)), extreme(np.argmax(values))
    forward = (at_max - at_min) % (2 * np.pi)
    back = 2 * np.pi - forward
    return {"turns": False, "min": pytest.approx(low, abs=1e-8),
            "max": pytest.approx(high, abs=1e-8), "stroke": pytest.approx(high - low, abs=1e-8),
            "time_ratio": pytest.approx(forward / back, rel=1e-7),
            "quick_return_ratio": pytest.approx(max(forward, back) / min(forward, back),
                                                rel=1e-7),
            "slower_stroke": "min->max" if forward > back else "max->min",
            "strokes_per_turn": 1}


def test_the_report_as_data_has_the_shape_and_values_of_the_closed_form():
    """The shipped crank-rocker, every figure of the JSON report against its closed form:
    the transmission angle at B from the law of cosines at theta = 0 and 180 degrees,
    strokes from a dense sampling of the loop's solution, the path of P as sampled."""
    dense = np.linspace(0, 2 * np.pi, 2_000_001)[:-1]
    p, angles = crank_rocker_closed_form(dense)
    strokes = {"P.x": stroke_of(dense, p[:, 0]), "P.y": stroke_of(dense, p[:, 1]),
               "crank.angle": {"turns": True},
               "coupler.angle": stroke_of(dense, angles["coupler.angle"]),
               "rocker.angle": stroke_of(dense, angles["rocker.angle"])}
    path, _ = crank_rocker_closed_form(np.radians(np.arange(361.0)))  # the circuit's samples
    x, y = path[:, 0], path[:, 1]

    def mu(diagonal):  # the angle at B between B->A and B->O4
        return pytest.approx(np.degrees(np.arccos((35**2 + 30**2 - diagonal**2) / (2 * 35 * 30))),
                             rel=1e-12)

    expected = {
        "construction": "crank-rocker with coupler point",
        "angle_unit": "deg",
        "dof": 1,
        "mobility": {"moving_links": 3, "revolute_joints": 4, "prismatic_pairs": 0,
                     "lower_pairs": 4, "higher_pairs": 0, "inputs": 1, "matches_inputs": True,
                     "formula": "DOF = 3(3) - 2(4) - 0 = 1; 1 input"},
        "inputs": {"theta": {"kind": "angle", "full_turn": True, "intervals": [[0.0, 360.0]],
                             "limits": [], "circuit_turns": 1}},
        "warnings": [],
        "four_bars": [{"node": "B", "points": ["O2", "A", "B", "O4"],
                       "ground": pytest.approx(40, rel=1e-12),
                       "input": pytest.approx(10, rel=1e-12),
                       "coupler": pytest.approx(35, rel=1e-12),
                       "output": pytest.approx(30, rel=1e-12),
                       "class": "crank-rocker", "code": "GCRR", "grashof": True,
                       "turning": ["input"]}],
        "transmission_angles": {"B": {"min": mu(40 - 10), "max": mu(40 + 10),
                                      "at_min": {"theta": 0.0}, "at_max": {"theta": 180.0}}},
        "strokes": strokes,
        "curves": {"P": {
            "length": pytest.approx(np.hypot(*np.diff(path, axis=0).T).sum(), rel=1e-12),
            "closed": True,
            "area": pytest.approx(0.5 * abs(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1])), rel=1e-12),
            "bounds": [pytest.approx(v, rel=1e-12) for v in (x.min(), y.min(), x.max(), y.max())],
            "double_points": []}},
    }
    data = analyze(load(CONSTRUCTIONS / "crank_rocker.toml"), degrees=True).to_dict()
    assert data == expected
    assert shape(data) == shape(expected)


@pytest.mark.parametrize("lengths", [(2, 4, 4, 3), (4, 1, 4, 3), (7, 5, 6, 5), (10, 4, 10, 4)])
def test_the_text_says_turn_of_several_links_and_turns_of_one(lengths):
    report = analyze(fourbar(*lengths), degrees=True)
    [bar] = report.four_bars
    turning = ", ".join(bar.turning) or "no link"
    verb = "turns" if len(bar.turning) <= 1 else "turn"
    [line] = [line for line in report.to_text().splitlines()
              if line.startswith(f"four-bar {'-'.join(bar.points)} ")]
    assert line.endswith(f"; {turning} {verb} fully")


def test_the_text_gives_angles_in_the_reports_unit():
    c = fourbar(7, 5, 6, 5)
    degrees, radians = analyze(c, degrees=True).to_text(), analyze(c).to_text()
    assert "input theta2: assemblable from -132.177419 to 132.177419 deg" in degrees
    assert "input theta2: assemblable from -2.306931 to 2.306931 rad" in radians
    assert "transmission angle at C: 18.19 to 180.00 deg" in degrees
    assert "transmission angle at C: 0.32 to 3.14 rad" in radians
    assert " deg" not in radians and " rad" not in degrees


@pytest.mark.parametrize("units, squared", [("mm", "mm^2"), ("length units",
                                                              "(length units)^2")])
def test_the_text_gives_a_curves_area_in_the_square_of_the_length_unit(units, squared):
    c = fourbar(40, 10, 35, 30)
    c.polar("P", "B", 20, np.radians(30), reference=("B", "C"))
    c.trace("P")
    report = analyze(c, degrees=True)
    curve = report.curves["P"]
    assert curve.closed and curve.area > 100
    [line] = [line for line in report.to_text(units).splitlines()
              if line.startswith("path of P:")]
    found = re.fullmatch(rf"path of P: length (\S+) {units}, closed, encloses (\S+) "
                         rf"{re.escape(squared)}, \d+ double point\(s\)", line)
    assert found, line
    # four decimals, or six significant digits
    assert float(found[1]) == pytest.approx(curve.length, rel=1e-5, abs=1e-4)
    assert float(found[2]) == pytest.approx(curve.area, rel=1e-5, abs=1e-4)
    # without a unit, neither has one
    [line] = [line for line in report.to_text().splitlines() if line.startswith("path of P:")]
    assert re.fullmatch(r"path of P: length \S+, closed, encloses \S+, \d+ double point\(s\)",
                        line)
    assert report.to_dict()["curves"]["P"]["area"] == curve.area  # the data: a number alone


def test_a_joint_swinging_out_and_back_encloses_no_area():
    """The triple rocker's C runs along an arc of its follower and back: no area.

    Sampled differently on the way out and back, the path's two polylines
    leave slivers between them; within what the sampling can resolve, they
    are none.
    """
    report = analyze(fourbar(7, 5, 6, 5), degrees=True)
    curve = report.curves["C"]
    assert curve.closed and curve.area == 0.0
    assert report.to_dict()["curves"]["C"]["area"] == 0.0
    [line] = [line for line in report.to_text("mm").splitlines() if line.startswith("path of C")]
    assert ", closed, encloses no area, 0 double point(s)" in line


def test_a_circuits_extremes_are_those_of_a_dense_sweep_of_the_same_circuit():
    """The triple rocker's samples are far apart near its limits: the extremes between
    them come from the mechanism evaluated again, not from a parabola by index."""
    from geokin import circuit
    from geokin.analysis import refine_extreme
    from geokin.kinematics import link_angles

    c = fourbar(7, 5, 6, 5)
    report = analyze(c, degrees=True)
    dense = circuit(c, samples_per_pass=20_001)
    theta = dense.inputs["theta2"]

    def extreme(values, sign):  # on the dense samples, then between them
        i = int(np.nanargmax(sign * values))
        return refine_extreme(theta[i - 1:i + 2], values[i - 1:i + 2])[1]

    angles = {name: np.degrees(v) for name, v in link_angles(dense).items()}
    for name in ("follower", "coupler"):
        swing = report.strokes[f"{name}.angle"]
        np.testing.assert_allclose(
            [swing.minimum, swing.maximum],
            [extreme(angles[name], -1), extreme(angles[name], 1)], rtol=0, atol=1e-7)
    np.testing.assert_allclose(report.strokes["C.x"].maximum, extreme(dense["C"][:, 0], 1),
                               rtol=0, atol=1e-8)


def coupler_point_fourbar(ground, crank, coupler, rocker, start, point):
    c = Construction("four-bar with a coupler point")
    c.input("t", range=(start, start + 2 * np.pi))
    c.fixed("O2", 0, 0)
    c.fixed("O4", ground, 0)
    c.polar("A", "O2", crank, "t")
    c.circle_circle("B", ("A", "O4"), (coupler, rocker), branch="left")
    c.local("P", "A", "B", point)
    c.trace("P")
    c.link("crank", "O2", "A")
    c.link("coupler", "A", "B", "P")
    c.link("rocker", "O4", "B")
    return c


def dense_extremes(c, name):
    """An output's extremes over a circuit of 20,001 samples a pass, placed between them."""
    from geokin import circuit
    from geokin.analysis import refine_extreme
    from geokin.kinematics import link_angles

    dense = circuit(c, samples_per_pass=20_001)
    x = dense.inputs[next(iter(dense.inputs))]
    point, what = name.split(".")
    values = (np.degrees(link_angles(dense)[point]) if what == "angle"
              else dense[point][:, "xy".index(what)])

    def extreme(sign):
        i = int(np.nanargmax(sign * values))
        if 0 < i < len(values) - 1:
            return refine_extreme(x[i - 1:i + 2], values[i - 1:i + 2])[1]
        return values[i]

    return extreme(-1), extreme(1)


def test_an_extreme_in_the_step_beside_a_toggle_is_placed_inside_it():
    # the coupler point's least x lies between the circuit's limit and the next sample
    c = coupler_point_fourbar(3.9676, 8.0959, 3.7288, 5.0815, -2.2994, (-0.969, -2.965))
    swing = analyze(c).strokes["P.x"]
    np.testing.assert_allclose([swing.minimum, swing.maximum], dense_extremes(c, "P.x"),
                               rtol=0, atol=1e-7)


def test_an_extreme_at_a_closed_circuits_seam_is_placed_between_samples(tmp_path):
    # seed 000's triple rocker declared over -20 to 20 degrees: its circuit starts and ends
    # at -20, beside the follower's extreme
    text = (CONSTRUCTIONS / "triple_rocker_crank.toml").read_text()
    assert "range = [-132, 132]" in text
    script = tmp_path / "narrow.toml"
    script.write_text(text.replace("range = [-132, 132]", "range = [-20, 20]"))
    c = load(script)
    swing = analyze(c, degrees=True).strokes["follower.angle"]
    low, high = dense_extremes(c, "follower.angle")
    turns = 360 * round((swing.minimum - low) / 360)  # a swing is told centred on (-180, 180]
    assert -180 < 0.5 * (swing.minimum + swing.maximum) <= 180
    np.testing.assert_allclose([swing.minimum, swing.maximum], [low + turns, high + turns],
                               rtol=0, atol=1e-6)


@pytest.mark.parametrize("at, ground, crank, reference", [
    ((0.0, 0.0), 52.6, 30.25, False), ((5000.3, -1800.7), 52.6, 30.25, False),
    ((100000.3, 7.1), 52.6, 30.25, False), ((100000.3, 7.1), 52.6, 30.25, True),
    ((0.0, 0.0), 100.0, 1.0, False)])
def test_parallelogram_rockers_turn_fully_through_their_change_points(at, ground, crank,
                                                                       reference):
    """Two parallelograms in series: each rocker stays parallel to the crank, so turns fully.

    At the change points the roots are known only to the meeting tolerance,
    which once left the second rocker 8e-8 rad short of spanning a turn
    (2e-6 with a ground 100 times the crank). A fixed point at (0, 0) far
    from the rest changes nothing.
    """
    x, y = at
    c = Construction("two parallelograms in series")
    c.input("theta")
    c.fixed("O2", x, y)
    c.fixed("O4", x + ground, y)
    c.fixed("O6", x + 2 * ground, y)
    if reference:
        c.fixed("REF", 0, 0)
    c.polar("A", "O2", crank, "theta")
    c.circle_circle("B", ("A", "O4"), (ground, crank), branch="left")
    c.circle_circle("C", ("B", "O6"), (ground, crank), branch="left")
    for name, points in {"crank": ("O2", "A"), "coupler1": ("A", "B"), "rocker1": ("O4", "B"),
                         "coupler2": ("B", "C"), "rocker2": ("O6", "C")}.items():
        c.link(name, *points)
    strokes = analyze(c).strokes
    assert {k for k, v in strokes.items() if k.endswith(".angle") and v.turns} == {
        "crank.angle", "rocker1.angle", "rocker2.angle"}
    # the couplers stay parallel to the ground: they do not move, to what they are known to
    assert "coupler1.angle" not in strokes and "coupler2.angle" not in strokes


def pointer_on_crank(ratio, parallelogram=False):
    """A pointer at theta / ratio on the crank pin A: it does not come back in a turn.

    With ``parallelogram``, A also drives a parallelogram (ground 52.6, crank
    30.25), whose change points give the motion branch events.
    """
    c = Construction()
    c.input("theta")
    c.fixed("O", 0, 0)
    c.polar("A", "O", 30.25, "theta")
    c.polar("P", "A", 1, f"theta / {ratio}")
    c.link("crank", "O", "A")
    c.link("pointer", "A", "P")
    if parallelogram:
        c.fixed("O4", 52.6, 0)
        c.circle_circle("B", ("A", "O4"), (52.6, 30.25), branch="left")
        c.link("rocker", "O4", "B")
    return c


@pytest.mark.parametrize("parallelogram", [False, True])
@pytest.mark.parametrize("ratio", [1.0001, 1.0005, 2.0])
def test_a_link_that_falls_short_of_a_turn_over_a_turn_of_the_input_does_not_turn(
        ratio, parallelogram):
    """359.96, 359.8 or 180 degrees over the turn: a stroke from 0 to 2 pi / ratio.

    The pointer is found from no node whose roots meet: its angle is known
    to rounding, also on a motion through change points, and ending 6e-4
    rad short of a whole turn is short of one. It does not go out and back:
    no time ratio.
    """
    report = analyze(pointer_on_crank(ratio, parallelogram))
    swing = report.strokes["pointer.angle"]
    assert not swing.turns and swing.time_ratio is None
    np.testing.assert_allclose([swing.minimum, swing.maximum], [0, 2 * np.pi / ratio],
                               rtol=0, atol=1e-12)
    if parallelogram:
        assert report.strokes["rocker.angle"].turns


@pytest.mark.parametrize("start", [0.0, np.pi / 2, np.pi, 1.0])
def test_every_output_keeps_its_time_ratio_wherever_the_turn_starts(start):
    """A crank-rocker whose turn starts at ``start``: the same strokes and time ratios.

    At pi / 2 and pi a coordinate of the crank pin begins and ends at zero,
    to rounding; it still comes back, and is timed.
    """
    def report(at):
        c = Construction("crank-rocker")
        c.input("theta", range=(at, at + 2 * np.pi))
        c.fixed("O2", 0, 0)
        c.fixed("O4", 40, 0)
        c.polar("A", "O2", 10, "theta")
        c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
        c.link("crank", "O2", "A")
        c.link("rocker", "O4", "B")
        c.trace("A", "B")
        return analyze(c).strokes

    moved, reference = report(start), report(0.0)
    assert set(moved) == set(reference) == {"A.x", "A.y", "B.x", "B.y", "crank.angle",
                                            "rocker.angle"}
    for label, swing in reference.items():
        if swing.turns:
            assert moved[label].turns
            continue
        assert moved[label].time_ratio is not None
        np.testing.assert_allclose(moved[label].time_ratio, swing.time_ratio, rtol=1e-6)
    # the crank pin's coordinates go out and back in half a turn each way
    assert moved["A.x"].time_ratio == pytest.approx(1, abs=1e-6)
    assert moved["A.y"].time_ratio == pytest.approx(1, abs=1e-6)


def test_a_turn_through_change_points_is_timed_against_a_dense_sweep():
    """A kite (ground 10, crank 4, coupler 4, rocker 10) and a parallelogram, one turn each.

    The circuit passes change points; the strokes and time ratios are those
    of a sweep 5,000 times denser along the same turn, on the same branches.
    """
    for ground, crank, coupler, rocker in ((10, 4, 4, 10), (10, 4, 10, 4)):
        c = Construction("change point")
        c.input("theta")
        c.fixed("O2", 0, 0)
        c.fixed("O4", ground, 0)
        c.polar("A", "O2", crank, "theta")
        c.circle_circle("B", ("A", "O4"), (coupler, rocker), branch="left")
        c.polar("P", "B", 3, 1.0)
        c.link("rocker", "O4", "B")
        c.trace("P")
        whole = circuit(c)
        assert whole.events
        theta = whole.inputs["theta"]
        dense = np.linspace(theta[0], theta[-1], 1_800_001)
        start = {"B": int(np.ravel(whole.branches["B"])[0])}
        fine = sweep(c, dense, start_branches=start)
        assert fine.valid.all()
        strokes = analyze(c).strokes
        outputs = {"P.x": fine["P"][:, 0], "P.y": fine["P"][:, 1],
                   "rocker.angle": link_angles(fine)["rocker"]}
        for label, values in outputs.items():
            if strokes[label].turns:
                continue
            low, high = int(np.argmin(values)), int(np.argmax(values))
            rising = (dense[high] - dense[low]) % (2 * np.pi)
            swing = strokes[label]
            np.testing.assert_allclose([swing.minimum, swing.maximum],
                                       [values[low], values[high]], rtol=0, atol=1e-8)
            assert swing.strokes_per_turn is not None  # timed over the turn
            if swing.strokes_per_turn == 1:  # out and back once: one time ratio
                np.testing.assert_allclose(swing.time_ratio, rising / (2 * np.pi - rising),
                                           rtol=1e-5)
            else:
                assert swing.time_ratio is None
        assert strokes["rocker.angle"].turns == (rocker == crank)


@pytest.mark.parametrize("at", [(0.0, 0.0), (5000.3, -1800.7)])
@pytest.mark.parametrize("arm", [500.0, 2000.0, 5000.0])
def test_every_link_of_a_rigid_body_that_does_not_turn_is_left_out(at, arm):
    """The second coupler carries a point ``arm`` out along it: B, C and P are one body.

    It stays parallel to the ground through the change points; its noise,
    carried out to P, is no stroke of any of its links.
    """
    c = parallelograms_in_series(*at)
    c.local("P", "B", "C", (arm, 0))
    c.link("coupler", "B", "C")
    c.link("arm", "B", "P")
    c.link("tip", "C", "P")
    c.link("rocker", "O6", "C")
    strokes = analyze(c).strokes
    assert set(strokes) == {"rocker.angle"} and strokes["rocker.angle"].turns


def change_point_fourbar():
    """Ground 10, crank 4, coupler 9, rocker 5: back on the first branch after two turns."""
    c = Construction("change point, two turns")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 10, 0)
    c.polar("A", "O2", 4, "theta")
    c.circle_circle("B", ("A", "O4"), (9, 5), branch="left")
    c.local("P", "A", "B", (-9, 0))
    c.link("crank", "O2", "A")
    c.link("coupler", "A", "B", "P")
    c.link("rocker", "O4", "B")
    c.trace("B", "P")
    return c


def test_a_change_point_circuit_turns_on_till_the_mechanism_is_back():
    """After one turn B is on its other branch: the circuit makes a second turn.

    The first turn ends in B's mirror pose (in closed form), the second
    back where it began; the report says so, and its strokes are those of
    both turns, checked on a sweep of them 1,000 times denser, tracked
    through the same change points.
    """
    c = change_point_fourbar()
    report = analyze(c)
    whole = circuit(c)
    theta = whole.inputs["theta"]
    assert len(whole.events) == 2 and whole.valid.all()
    np.testing.assert_allclose(np.ptp(theta), 4 * np.pi)
    one_turn = int(np.flatnonzero(np.isclose(theta - theta[0], 2 * np.pi))[0])
    np.testing.assert_allclose(whole["B"][one_turn], whole["B"][0] * [1, -1], atol=1e-9)
    np.testing.assert_allclose(whole["B"][-1], whole["B"][0], atol=1e-9)
    # B in closed form: 9 from A and 5 from O4, on the side the branch says
    a = np.column_stack([4 * np.cos(theta), 4 * np.sin(theta)])
    np.testing.assert_allclose(np.hypot(*(whole["B"] - a).T), 9, rtol=1e-9)
    np.testing.assert_allclose(np.hypot(*(whole["B"] - [10, 0]).T), 5, rtol=1e-9)
    assert report.inputs["theta"].circuit_turns == 2
    assert "turns fully, its motion repeating after 2 turns" in report.to_text()
    assert not report.warnings and report.strokes["crank.angle"].turns
    assert report.curves["B"].closed and report.curves["P"].closed
    dense = sweep(c, np.linspace(theta[0], theta[-1], 720_001),
                  start_branches={"B": int(np.ravel(whole.branches["B"])[0])})
    np.testing.assert_allclose(dense["B"][-1], whole["B"][0], atol=1e-9)
    for label in ("B.x", "B.y", "P.x", "P.y"):
        swing = report.strokes[label]
        # periodic in two turns, not in one: no time ratio
        assert swing.time_ratio is None and swing.strokes_per_turn is None
        values = dense[label[0]][:, "xy".index(label[-1])]
        np.testing.assert_allclose([swing.minimum, swing.maximum], [values.min(), values.max()],
                                   rtol=0, atol=1e-7)


@pytest.mark.parametrize("gearing, turns", [("theta / 2", False), ("theta * 1.5", True)])
def test_a_geared_pointer_is_not_timed(gearing, turns):
    """A pointer geared to the crank does not repeat every turn: no time ratio for its tip."""
    c = Construction("geared pointer")
    c.input("theta")
    c.fixed("O", 0, 0)
    c.polar("A", "O", 3, "theta")
    c.polar("P", "O", 1, gearing)
    c.link("crank", "O", "A")
    c.link("pointer", "O", "P")
    c.trace("A", "P")
    report = analyze(c)
    assert report.strokes["pointer.angle"].turns == turns
    assert report.strokes["A.y"].time_ratio == pytest.approx(1)  # the crank pin repeats
    for label in ("P.x", "P.y"):
        assert report.strokes[label].time_ratio is None
    assert any("('P' ends elsewhere)" in w for w in report.warnings)


@pytest.mark.parametrize("guide_at", [(10.0, 4.0), (6.0, 0.0), (12.0, 2 * np.sqrt(3))])
def test_a_guide_point_the_rocker_passes_over_does_not_hide_the_slider(guide_at):
    """A slider Q on a guide through a point of the rocker's circle, driven by a rod from B.

    B passes over the guide's first point to rounding, which fixes nothing
    of Q together with B: the block still strokes, checked on the circuit's
    own positions.
    """
    c = Construction("parallelogram and a slider")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 10, 0)
    c.polar("A", "O2", 4, "theta")
    c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
    c.fixed("G1", *guide_at)
    c.polar("G2", "G1", 10, 0.0)
    c.line_circle("Q", ("G1", "G2"), "B", 9, branch="second")
    c.link("crank", "O2", "A")
    c.link("rocker", "O4", "B")
    c.link("rod", "B", "Q")
    c.slider("block", "Q", ("G1", "G2"))
    c.trace("Q")
    strokes = analyze(c).strokes
    x = circuit(c)["Q"][:, 0]
    assert {"Q.x", "block.position", "rod.angle"} <= set(strokes)
    assert strokes["Q.x"].stroke == pytest.approx(np.ptp(x), rel=1e-3)


def test_two_inputs_swept_together_get_strokes_over_their_path_and_say_so():
    """Cranks turning together keep A-B level: C runs on a circle of 20 about (25, h)."""
    report = analyze(five_bar(), degrees=True)
    assert any("2 inputs swept together over 361 samples" in w
               and "not over every combination" in w for w in report.warnings)
    h = np.sqrt(60**2 - 25**2)
    assert report.strokes["C.x"].minimum == pytest.approx(5, abs=1e-9)
    assert report.strokes["C.x"].maximum == pytest.approx(45, abs=1e-9)
    assert report.strokes["C.y"].minimum == pytest.approx(h - 20, abs=1e-9)
    assert report.strokes["C.y"].maximum == pytest.approx(h + 20, abs=1e-9)
    # the links translate: their angles do not move
    assert "left.angle" not in report.strokes and "right.angle" not in report.strokes
    assert all(s.quick_return_ratio is None for s in report.strokes.values())
    with pytest.raises(AnalysisError, match="2 inputs, swept together"):
        analyze(five_bar(), start=1.0)


def test_two_inputs_at_different_speeds_get_the_extremes_of_a_dense_sweep_of_the_path():
    c = five_bar(second_turns=2)
    report = analyze(c)
    dense = sweep(c, {"t1": np.linspace(0, 2 * np.pi, 200_001),
                      "t2": np.linspace(0, 4 * np.pi, 200_001)})
    for axis, coordinate in enumerate("xy"):
        values = dense["C"][:, axis]
        found = report.strokes[f"C.{coordinate}"]
        assert found.minimum == pytest.approx(values.min(), abs=1e-6)
        assert found.maximum == pytest.approx(values.max(), abs=1e-6)


def test_where_transmission_extremes_of_several_inputs_lie_reads_as_two_lists():
    report = analyze(five_bar(second_turns=-2), degrees=True)
    mu = report.transmission_angles["C"]
    line = next(line for line in report.to_text().splitlines() if "transmission" in line)
    low, high = ((f"t1 = {at['t1']:.4f} deg, t2 = {at['t2']:.4f} deg")
                 for at in (mu.at_minimum, mu.at_maximum))
    assert line.endswith(f"(at {low}; and at {high})")


def double_rocker(angle="theta", branch="left"):
    """A Grashof double rocker (ground 100, input 60, coupler 30, output 80): two circuits.

    The input link stands at ``angle`` (an expression of the input theta).
    """
    c = Construction("double rocker")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 100, 0)
    c.polar("A", "O2", 60, angle)
    c.circle_circle("B", ("A", "O4"), (30, 80), branch=branch)
    c.link("input", "O2", "A")
    c.link("coupler", "A", "B")
    c.link("output", "O4", "B")
    return c


def test_an_input_of_two_intervals_names_the_circuit_analysed_and_start_picks_the_other():
    c = double_rocker()
    # the cosine rule: the input's toggles, where A-B-O4 folds out or in
    edges = [np.degrees(np.arccos((60**2 + 100**2 - r**2) / (2 * 60 * 100))) for r in (50, 110)]
    first = analyze(c, degrees=True)
    [(lo1, hi1), (lo2, hi2)] = first.inputs["theta"].intervals
    assert (lo1, hi1) == pytest.approx(edges, abs=1e-6)
    assert (lo2, hi2) == pytest.approx([360 - edges[1], 360 - edges[0]], abs=1e-6)
    [note] = [w for w in first.warnings if "2 intervals" in w]
    other = analyze(c, degrees=True, start=300.0)
    [other_note] = [w for w in other.warnings if "2 intervals" in w]
    spans = {f"from {lo1:.6f} to {hi1:.6f} deg", f"from {lo2:.6f} to {hi2:.6f} deg"}
    assert {span for span in spans if span in note} != {span for span in spans
                                                          if span in other_note}
    assert f"from {lo2:.6f} to {hi2:.6f} deg" in other_note
    # the input link's swing is that circuit's interval, told as the input is
    swing = other.strokes["input.angle"]
    assert (swing.minimum, swing.maximum) == pytest.approx((lo2, hi2), abs=1e-6)
    assert other.strokes["input.angle"].stroke == pytest.approx(hi2 - lo2, abs=1e-6)


def test_a_swing_reads_the_same_whichever_link_drives():
    """Seed 000's follower swings 47.82 to 312.18 deg whether the crank or it drives."""
    crank = analyze(fourbar(7, 5, 6, 5), degrees=True).strokes["follower.angle"]
    c = Construction("follower driving")
    c.input("theta4", range=(np.radians(60), np.radians(300)))
    c.fixed("A", 0, 0)
    c.fixed("D", 7, 0)
    c.polar("C", "D", 5, "theta4")
    c.circle_circle("B", ("A", "C"), (5, 6), branch="right")
    c.link("crank", "A", "B")
    c.link("follower", "D", "C")
    follower = analyze(c, degrees=True).strokes["follower.angle"]
    # at the toggles crank and coupler lie in line, 11 from A: C is 180 - angle ADC off +x
    edge = 180 - np.degrees(np.arccos((7**2 + 5**2 - 11**2) / (2 * 7 * 5)))
    for swing in (crank, follower):
        assert (swing.minimum, swing.maximum) == pytest.approx((edge, 360 - edge), abs=1e-6)


def test_transmission_extremes_are_placed_between_samples_where_the_closed_form_has_them():
    """cos mu = (b^2 + c^2 - d^2 - a^2 + 2 a d cos theta) / (2 b c): extremes at 0 and 180 deg.

    The crank is sampled every 10 degrees from 7: no sample falls on either.
    """
    d, a, b, c = 40.0, 10.0, 35.0, 30.0
    four = Construction("crank-rocker, sampled off its extremes")
    four.input("theta", range=(np.radians(7), np.radians(367)), samples=37)
    four.fixed("O2", 0, 0)
    four.fixed("O4", d, 0)
    four.polar("A", "O2", a, "theta")
    four.circle_circle("B", ("A", "O4"), (b, c), branch="left")
    four.link("crank", "O2", "A")
    four.link("coupler", "A", "B")
    four.link("rocker", "O4", "B")
    report = analyze(four, degrees=True)
    mu = report.transmission_angles["B"]

    def closed_form(theta):
        return np.degrees(np.arccos((b * b + c * c - d * d - a * a + 2 * a * d * np.cos(theta))
                                    / (2 * b * c)))

    assert mu.minimum == pytest.approx(closed_form(0.0), abs=1e-6)
    assert mu.maximum == pytest.approx(closed_form(np.pi), abs=1e-6)
    assert (mu.at_minimum["theta"] + 180) % 360 - 180 == pytest.approx(0.0, abs=1e-3)
    assert mu.at_maximum["theta"] % 360 == pytest.approx(180.0, abs=1e-3)
    [line] = [line for line in report.to_text().splitlines() if line.startswith("transmission")]
    assert line.endswith(f"(at theta = {mu.at_minimum['theta']:.4f} deg and theta = "
                         f"{mu.at_maximum['theta']:.4f} deg)")


def test_a_construction_without_inputs_is_reported_as_it_stands():
    c = Construction("still")
    c.fixed("O", 0, 0)
    c.polar("A", "O", 2, 0.5)
    c.link("arm", "O", "A")
    c.trace("A")
    report = analyze(c)
    assert report.dof == 0 and not report.inputs and not report.strokes
    assert report.warnings == ()
    assert "0 inputs" in report.to_text()


def test_a_start_outside_every_interval_is_refused_in_the_reports_units():
    with pytest.raises(AnalysisError, match=r"a start of 200 deg: input 'theta' cannot be "
                                            r"assembled there \(it can from 22.331645 to "
                                            r"82.819244 deg, 277.180756 to 337.668355 deg\)"):
        analyze(double_rocker(), degrees=True, start=200.0)
    # 780 deg is 60 deg two turns on: the first circuit
    report = analyze(double_rocker(), degrees=True, start=780.0)
    assert "from 22.331645 to 82.819244 deg" in report.warnings[0]


def test_a_start_copied_from_the_report_starts_at_that_interval_end():
    """The report gives interval ends to six decimals; such a start is that end."""
    c = fourbar(6.611, 7.99, 6.517, 9.256)
    [(low, high)] = analyze(c, degrees=True).inputs["theta2"].intervals
    for end in (low, high):
        report = analyze(c, degrees=True, start=round(end, 6))
        assert report.inputs["theta2"].intervals == ((low, high),)
    with pytest.raises(AnalysisError, match=r"a start of .*: input 'theta2' cannot be"):
        analyze(c, degrees=True, start=round(high, 6) + 1e-4)
    for bad in (np.nan, np.inf):
        with pytest.raises(AnalysisError, match="a start must be a finite number"):
            analyze(c, start=bad)
    # a whole number of radians far beyond a turn: most likely degrees
    with pytest.raises(AnalysisError, match=r"a start of 50 rad: .*; angles are in radians "
                                            r"here \(degrees=True takes degrees\)"), \
            pytest.warns(geokin.DegreesWarning, match="analyze: a start of 50 is 7.96 turns"):
        analyze(double_rocker(), start=50)


def test_a_start_that_looks_like_degrees_is_warned_of_where_a_circuit_takes_it():
    """45 rad lies in the crank-rocker's one interval, a full turn, seven turns on: taken,
    with a warning at the call, since 45 is much likelier degrees."""
    c = fourbar(40, 10, 35, 30)
    with pytest.warns(geokin.DegreesWarning, match="analyze: a start of 45 is 7.16 turns in "
                      r"radians.*degrees=True takes degrees") as caught:
        analyze(c, start=45)
    assert [w.filename for w in caught] == [__file__]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        analyze(c, start=0.75)
        analyze(c, degrees=True, start=45)


def test_a_crank_turned_otherwise_than_with_its_input_is_told_as_any_link():
    """A crank at -theta does not read as theta does: its swing is centred on zero, the
    input's interval (where the pin is 50 to 110 from O4, by the cosine rule) negated."""
    c = double_rocker(angle="-theta", branch="right")
    low, high = (np.degrees(np.arccos((100**2 + 60**2 - d**2) / (2 * 100 * 60)))
                 for d in (50, 110))
    for start in (None, -300.0):
        swing = analyze(c, degrees=True, start=start).strokes["input.angle"]
        assert -180 < 0.5 * (swing.minimum + swing.maximum) <= 180
        assert (swing.minimum, swing.maximum) == pytest.approx((-high, -low), abs=1e-6)


def test_transmission_extremes_of_a_full_turn_are_told_in_the_declared_turn():
    """Started at 97 deg, the crank-rocker's circuit runs to 457: its extremes are at 0, 180."""
    c = fourbar(40, 10, 35, 30)
    c.inputs["theta2"] = dataclasses.replace(c.inputs["theta2"], range=(0.0, 2 * np.pi))
    mu = analyze(c, degrees=True, start=97.0).transmission_angles["C"]
    assert sorted([mu.at_minimum["theta2"], mu.at_maximum["theta2"]]) == pytest.approx(
        [0.0, 180.0], abs=1e-3)


@pytest.mark.parametrize("declared, expected", [((0.0, -2 * np.pi), [-180.0, 0.0]),
                                                ((np.pi, -np.pi), [0.0, 180.0])])
def test_transmission_extremes_are_told_in_the_turn_a_decreasing_range_runs(declared,
                                                                           expected):
    """A range run downwards from its start holds the turn below it, start included: the
    crank-rocker's extremes (at 0 and 180 deg by the cosine rule) read in that turn."""
    c = fourbar(40, 10, 35, 30)
    c.inputs["theta2"] = dataclasses.replace(c.inputs["theta2"], range=declared)
    mu = analyze(c, degrees=True).transmission_angles["C"]
    assert sorted([mu.at_minimum["theta2"], mu.at_maximum["theta2"]]) == pytest.approx(
        expected, abs=1e-3)


@pytest.mark.parametrize("first", [0.3, 180.3])
def test_transmission_extremes_at_the_seam_of_a_full_turn_are_placed_there(first):
    """Swept from 0.3 deg, the crank-rocker's least transmission angle (at 0 deg by the
    cosine rule) lies in the step across the seam of the turn, between its last sample and
    its first: it is placed there, not at the first sample."""
    c = fourbar(40, 10, 35, 30)
    c.inputs["theta2"] = dataclasses.replace(c.inputs["theta2"],
                                             range=(np.radians(first), np.radians(first + 360)))
    mu = analyze(c, degrees=True).transmission_angles["C"]

    def cosine_rule(theta):
        d2 = 40**2 + 10**2 - 2 * 40 * 10 * np.cos(theta)
        return np.degrees(np.arccos((35**2 + 30**2 - d2) / (2 * 35 * 30)))

    assert (mu.minimum, mu.maximum) == pytest.approx((cosine_rule(0), cosine_rule(np.pi)),
                                                     abs=1e-9)
    assert mu.at_minimum["theta2"] % 360 == pytest.approx(0, abs=1e-6) or \
        mu.at_minimum["theta2"] % 360 == pytest.approx(360, abs=1e-6)
    assert mu.at_maximum["theta2"] % 360 == pytest.approx(180, abs=1e-6)


def test_extremes_next_to_a_gap_of_two_inputs_swept_together_are_placed_at_its_edge():
    """Two cranks of 20, 50 apart, turned opposite ways, with links of 32: the links fall in
    line where the cranks' pins are 64 apart, and the motion stops. There the transmission
    angle is 180 deg and the left link's angle is least; the edge is found here by bisection
    on the pins' distance."""
    report = analyze(five_bar(second_turns=-1, links=32), degrees=True)

    def pins(u):  # along the path: t1 = 2 pi u, t2 = -2 pi u
        a = 20 * np.array([np.cos(2 * np.pi * u), np.sin(2 * np.pi * u)])
        return a, np.array([50.0, 0.0]) + 20 * np.array([np.cos(2 * np.pi * u),
                                                          -np.sin(2 * np.pi * u)])

    lo, hi = 0.0, 0.25  # the pins 30 apart, then 68 apart
    for _ in range(100):
        middle = 0.5 * (lo + hi)
        a, b = pins(middle)
        lo, hi = (middle, hi) if np.hypot(*(b - a)) < 64 else (lo, middle)
    a, b = pins(lo)
    least = np.degrees(np.arctan2(*((a + b) / 2 - a)[::-1]))
    mu = report.transmission_angles["C"]
    assert mu.maximum == pytest.approx(180, abs=1e-4)
    assert mu.at_maximum["t1"] % 180 == pytest.approx(360 * lo, abs=1e-6)
    assert report.strokes["left.angle"].minimum == pytest.approx(least, abs=1e-5)
