"""The shipped constructions reproduce the figures of the seed documents."""

import math
import pathlib

import numpy as np
import pytest
import shapely

import geokin
from geokin import analysis, sweep

CONSTRUCTIONS = pathlib.Path(__file__).resolve().parent.parent / "constructions"


def load(name):
    return geokin.load(CONSTRUCTIONS / f"{name}.toml")


def distance(s, p, q):
    return np.hypot(*(s[p] - s[q]).T)


def direction(s, p, q):
    return np.arctan2(*(s[q] - s[p]).T[::-1])


def same_angle(a, b):
    return np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b)))))


# -- seed 003: the six-bar -------------------------------------------------------

SEED_003 = dict(x=168, y=20, l1=10, l2=20, l2p=5, l3=100, l3p=70, l4=100, l5=140)


def test_sixbar_has_the_seed_dimensions_points_and_input():
    c = load("sixbar")
    assert {k: p.value for k, p in c.parameters.items()} == SEED_003
    assert list(c.nodes) == ["D", "mid", "A0", "B0", "A", "B", "Ap", "C", "M"]
    assert c.traced == ("M",)
    assert [(s.point, s.along) for s in c.sliders.values()] == [("C", ("Ap", "M"))]
    s = sweep(c)
    np.testing.assert_allclose(np.degrees(s.inputs["theta"]), np.arange(0, 1800, 16))
    assert len(s) == 113
    assert c.compile().as_list() == [
        ("D", "fixed"), ("mid", "fixed"), ("A0", "fixed"), ("B0", "fixed"),
        ("A", "polar", "A0"), ("B", "circle_circle", "A", "B0", "left"),
        ("Ap", "line_circle", "A0", "A", "first"), ("C", "line_circle", "A", "B", "Ap", "second"),
        ("M", "ray_circle", "Ap", "C", "second")]


def test_sixbar_link_lengths_and_incidences():
    s = sweep(load("sixbar"))
    p = SEED_003
    np.testing.assert_allclose(s["D"], 0, atol=0)
    np.testing.assert_allclose(s["mid"], [[0, p["y"]]] * len(s))
    np.testing.assert_allclose(s["A0"], [[0, p["y"] + p["l1"]]] * len(s))
    np.testing.assert_allclose(s["B0"], [[p["x"], p["l1"]]] * len(s))
    for a, b, length in [("A0", "A", p["l2"]), ("A", "B", p["l3"]), ("B0", "B", p["l4"]),
                         ("A", "Ap", p["l2p"]), ("A0", "Ap", p["l2"] - p["l2p"]),
                         ("Ap", "C", p["l3p"]), ("Ap", "M", p["l5"])]:
        np.testing.assert_allclose(distance(s, a, b), length, rtol=1e-12, err_msg=f"{a}{b}")
    # A' lies between A0 and A; C on the line AB; M on the ray from A' through C
    np.testing.assert_allclose(distance(s, "A0", "Ap") + distance(s, "Ap", "A"), p["l2"])
    ab, ac = s["B"] - s["A"], s["C"] - s["A"]
    np.testing.assert_allclose(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0], 0, atol=1e-9)
    np.testing.assert_allclose(direction(s, "Ap", "M"), direction(s, "Ap", "C"), atol=1e-12)
    # B is left of A -> B0, the seed's first root
    ab0, ab = s["B0"] - s["A"], s["B"] - s["A"]
    assert (ab0[:, 0] * ab[:, 1] - ab0[:, 1] * ab[:, 0] > 0).all()


def seed_003_matlab(theta_degrees):
    """The seed's MATLAB program endsem6bar.m, transcribed, one sample at a time."""
    p = SEED_003

    def circle_circle(ca, ra, cb, rb):
        d = cb - ca
        length = np.linalg.norm(d)
        u = d / length
        m = (length * length + ra * ra - rb * rb) / (2 * length)
        chord = ca + m * u
        w = np.array([-u[1], u[0]])
        h = math.sqrt(ra * ra - m * m)
        return chord + h * w, chord - h * w

    def line_circle(start, end, centre, r):
        d = end - start
        length = np.linalg.norm(d)
        w = d / length
        t1 = w @ (centre - start)
        t2 = math.sqrt(r * r - (w[0] * (start[1] - centre[1]) - w[1] * (start[0] - centre[0])) ** 2)
        ta, tb = t1 + t2, t1 - t2
        a = start + ta * w if 0 <= ta <= length else None
        b = start + tb * w if 0 <= tb <= length else None
        return a, b

    def ray_circle(start, through, centre, r):
        w = (through - start) / np.linalg.norm(through - start)
        return start + r * w  # the centre is the ray's start: one root on the ray

    a0 = np.array([0.0, p["y"] + p["l1"]])
    b0 = np.array([float(p["x"]), p["l1"]])
    rows = []
    for theta in np.radians(theta_degrees):
        a = a0 + p["l2"] * np.array([math.cos(theta), math.sin(theta)])
        b, _ = circle_circle(a, p["l3"], b0, p["l4"])
        _, ap = line_circle(a0, a, a, p["l2p"])
        c, _ = line_circle(a, b, ap, p["l3p"])
        m = ray_circle(ap, c, ap, p["l5"])
        rows.append(np.concatenate([a, b, ap, c, m]))
    return np.array(rows)


def test_sixbar_reproduces_the_seed_program():
    s = sweep(load("sixbar"))
    expected = seed_003_matlab(np.arange(0, 1800, 16))
    ours = np.hstack([s[name] for name in ("A", "B", "Ap", "C", "M")])
    np.testing.assert_allclose(ours, expected, atol=1e-9)


def test_sixbar_has_one_degree_of_freedom():
    mobility = analysis.degrees_of_freedom(load("sixbar"))
    assert (mobility.moving_links, mobility.lower_pairs, mobility.dof) == (5, 7, 1)


@pytest.mark.parametrize("path", sorted(CONSTRUCTIONS.glob("*.toml")), ids=lambda p: p.name)
def test_every_construction_has_as_many_degrees_of_freedom_as_inputs(path):
    c = geokin.load(path)
    assert analysis.degrees_of_freedom(c).dof == len(c.inputs)


# -- seed 001: the quick return ---------------------------------------------------


def quick_return_unknowns(s):
    """r3, r4, r5 and theta3 (degrees) read from the trace, as the file's header says."""
    a, b, c = s["A"], s["B"], s["C"]
    return (np.hypot(a[:, 0], a[:, 1]), np.hypot(b[:, 0], b[:, 1]), b[:, 0] - c[:, 0],
            np.degrees(np.arctan2(a[:, 1], a[:, 0])))


def test_quick_return_table_at_30_degrees():
    s = sweep(load("quick_return"), np.radians([30.0]))
    r3, r4, r5, theta3 = (v[0] for v in quick_return_unknowns(s))
    # the seed's table, truncated to two decimals
    assert math.floor(r3 * 100) / 100 == 87.17
    assert math.floor(r5 * 100) / 100 == 51.96
    assert math.floor(theta3 * 100) / 100 == 66.58
    # its table's r4 = 130.75 is 0.017 off its own equations and Newton-Raphson run
    assert r4 == pytest.approx(130.75, abs=0.02)
    # the seed's Newton-Raphson output at 30 degrees
    np.testing.assert_allclose([r3, r4, r5], [87.17797887, 130.76696831, 51.96152423],
                               atol=1e-8)


def test_quick_return_follows_the_seed_equations_over_a_turn():
    c = load("quick_return")
    r1, r2, r6 = (c.parameters[k].value for k in ("r1", "r2", "r6"))
    s = sweep(c)
    assert len(s) == 361 and s.valid.all()
    t2 = s.inputs["theta2"]
    r3, r4, r5, theta3 = quick_return_unknowns(s)
    np.testing.assert_allclose(r3, np.sqrt(r1**2 + r2**2 + 2 * r1 * r2 * np.sin(t2)), rtol=1e-12)
    ratio = np.abs((r1 + r2 * np.sin(t2)) / (r2 * np.cos(t2)))
    with np.errstate(divide="ignore"):
        seed_theta3 = np.where(np.cos(t2) >= 0, np.arctan(ratio), np.pi - np.arctan(ratio))
    np.testing.assert_allclose(theta3, np.degrees(seed_theta3), atol=1e-9)
    np.testing.assert_allclose(r4, (r1 + r6) / np.sin(seed_theta3), rtol=1e-12)
    np.testing.assert_allclose(r5, r2 * (r1 + r6) * np.cos(t2) / (r1 + r2 * np.sin(t2)),
                               atol=1e-9)
    # the loop-closure equations (I) to (IV) of the seed
    th3 = np.radians(theta3)
    np.testing.assert_allclose(r1 + r2 * np.sin(t2), r3 * np.sin(th3), atol=1e-9)
    np.testing.assert_allclose(r2 * np.cos(t2), r3 * np.cos(th3), atol=1e-9)
    np.testing.assert_allclose(r1 + r6, r4 * np.sin(th3), atol=1e-9)
    np.testing.assert_allclose(r5, r4 * np.cos(th3), atol=1e-9)


# -- seed 004: the four-bar, open and crossed ---------------------------------------

SEED_004 = dict(a=10.55, b=25.0, c=14.0, d=24.0)


def fourbar_closed_form(theta2, sign):
    """theta4 and theta3 by the half-angle formula of the seed's notebook."""
    a, b, c, d = SEED_004.values()
    k1, k2, k3 = d / a, d / c, (a**2 - b**2 + c**2 + d**2) / (2 * a * c)
    k4, k5 = d / b, (c**2 - d**2 - a**2 - b**2) / (2 * a * b)
    cos2 = np.cos(theta2)
    A = cos2 - k1 - k2 * cos2 + k3
    B = -2 * np.sin(theta2)
    C = k1 - (k2 + 1) * cos2 + k3
    D = cos2 - k1 + k4 * cos2 + k5
    F = k1 + (k4 - 1) * cos2 + k5
    theta4 = 2 * np.arctan2(-B + sign * np.sqrt(B**2 - 4 * A * C), 2 * A)
    theta3 = 2 * np.arctan2(-B + sign * np.sqrt(B**2 - 4 * D * F), 2 * D)
    return theta4, theta3


@pytest.mark.parametrize("name, sign", [("fourbar_open", -1), ("fourbar_crossed", +1)])
def test_fourbar_matches_the_closed_form(name, sign):
    c = load(name)
    assert {k: p.value for k, p in c.parameters.items()} == SEED_004
    s = sweep(c)
    assert len(s) == 361 and s.valid.all()
    theta4, theta3 = fourbar_closed_form(s.inputs["theta2"], sign)
    assert same_angle(direction(s, "O4", "B"), theta4).max() < 1e-9
    assert same_angle(direction(s, "A", "B"), theta3).max() < 1e-9
    # the other root of the formula is the other configuration
    other4, _ = fourbar_closed_form(s.inputs["theta2"], -sign)
    assert same_angle(direction(s, "O4", "B"), other4).min() > 0.1


def test_open_is_convex_and_crossed_crosses_at_90_degrees():
    rings = {}
    for name in ("fourbar_open", "fourbar_crossed"):
        s = sweep(load(name), np.radians([90.0]))
        rings[name] = shapely.LinearRing([s[p][0] for p in ("O2", "A", "B", "O4")])
    assert rings["fourbar_open"].is_simple
    assert not rings["fourbar_crossed"].is_simple


def test_fourbar_link_lengths():
    for name in ("fourbar_open", "fourbar_crossed"):
        s = sweep(load(name))
        for p, q, length in [("O2", "A", 10.55), ("A", "B", 25), ("O4", "B", 14), ("O2", "O4", 24)]:
            np.testing.assert_allclose(distance(s, p, q), length, rtol=1e-12)


# -- seed 000: the triple rocker ---------------------------------------------------

TRIPLE_ROCKER = dict(r1=7.0, r2=5.0, r3=6.0, r4=5.0)
DRIVERS = ["triple_rocker_crank", "triple_rocker_coupler", "triple_rocker_follower"]


@pytest.mark.parametrize("name", DRIVERS)
def test_triple_rocker_lengths_are_constant(name):
    c = load(name)
    assert {k: p.value for k, p in c.parameters.items()} == TRIPLE_ROCKER
    s = sweep(c)
    assert s.valid.all() and len(s) > 200
    np.testing.assert_allclose(s["A"], 0, atol=0)
    np.testing.assert_allclose(s["D"], [[7, 0]] * len(s))
    for p, q, length in [("A", "B", 5), ("B", "C", 6), ("D", "C", 5), ("A", "D", 7)]:
        np.testing.assert_allclose(distance(s, p, q), length, rtol=1e-12)


def test_triple_rocker_is_non_grashof():
    lengths = sorted(TRIPLE_ROCKER.values())
    assert lengths[0] + lengths[-1] > lengths[1] + lengths[2]


@pytest.mark.parametrize("name, input_name, limit", [
    ("triple_rocker_crank", "theta2", (-132.1774, 132.1774)),
    ("triple_rocker_coupler", "theta3", (-100.29, 100.29)),
    ("triple_rocker_follower", "theta4", (47.82, 312.18)),
])
def test_triple_rocker_ranges_lie_inside_the_limits(name, input_name, limit):
    c = load(name)
    r1, r2, r3, r4 = TRIPLE_ROCKER.values()
    exact = {"theta2": math.acos((r1**2 + r2**2 - (r3 + r4) ** 2) / (2 * r1 * r2)),
             "theta3": math.acos((r1**2 + r3**2 - (r2 + r4) ** 2) / (2 * r1 * r3)),
             "theta4": math.acos(((r2 + r3) ** 2 - r1**2 - r4**2) / (2 * r1 * r4))}[input_name]
    if input_name == "theta4":
        exact_range = (exact, 2 * math.pi - exact)
    else:
        exact_range = (-exact, exact)
    np.testing.assert_allclose(np.degrees(exact_range), limit, atol=0.005)
    lo, hi = c.inputs[input_name].range
    assert exact_range[0] < lo < hi < exact_range[1]
    inside = sweep(c, np.array(exact_range) + [1e-9, -1e-9])
    outside = sweep(c, np.array(exact_range) + [-1e-6, 1e-6])
    assert inside.valid.all() and not outside.valid.any()


def test_triple_rocker_crank_is_the_seed_first_root():
    """C is the seed's o4_1: the + sign of its half-angle formula."""
    s = sweep(load("triple_rocker_crank"))
    r1, r2, r3, r4 = TRIPLE_ROCKER.values()
    t2 = s.inputs["theta2"]
    a = 2 * r1 * r4 - 2 * r2 * r4 * np.cos(t2)
    b = -2 * r2 * r4 * np.sin(t2)
    c = r1**2 + r2**2 + r4**2 - r3**2 - 2 * r1 * r2 * np.cos(t2)
    o4_1 = 2 * np.arctan((-b + np.sqrt(a * a + b * b - c * c)) / (c - a))
    assert same_angle(direction(s, "D", "C"), o4_1).max() < 1e-9
    # the seed's theta3 from Eq2/Eq1, with the quadrant atan2 gives
    o3 = np.arctan2(r4 * np.sin(o4_1) - r2 * np.sin(t2), r1 + r4 * np.cos(o4_1) - r2 * np.cos(t2))
    assert same_angle(direction(s, "B", "C"), o3).max() < 1e-9


def test_the_three_drivers_move_the_same_assembly():
    crank = sweep(load("triple_rocker_crank"), np.radians(np.arange(0.0, 133.0)))
    theta3 = direction(crank, "B", "C")
    theta4 = np.mod(direction(crank, "D", "C"), 2 * np.pi)
    for name, values in (("triple_rocker_coupler", theta3), ("triple_rocker_follower", theta4)):
        # where the driving angle turns back, the crank's motion has passed the
        # driver's own toggle, which samples that turn back short of it never pass:
        # the motion from there on is the driver's other branch
        turn = np.flatnonzero(np.diff(values)[1:] * np.diff(values)[:-1] < 0)
        ends = [0, *(turn + 1), len(values) - 1]
        c = load(name)
        node = next(n for n, v in c.nodes.items() if v.roots == 2)
        declared = c.nodes[node].branch
        other_branch = [b for b in c.nodes[node].branch_names if b != declared][0]
        # the coupler's angle turns back once over the crank's 0..132 degrees
        assert len(ends) == (3 if name == "triple_rocker_coupler" else 2)
        for k, (a, b) in enumerate(zip(ends[:-1], ends[1:], strict=True)):
            part = sweep(c, values[a:b + 1], start_branches={node: (declared, other_branch)[k % 2]})
            assert part.valid.all() and part.events == ()
            # the sample where the driver turns back lies on either side of its toggle
            keep = slice(0, -1) if k == 0 else slice(1, None)
            for p in "ABCD":
                np.testing.assert_allclose(part[p][keep], crank[p][a:b + 1][keep], atol=1e-9,
                                           err_msg=f"{name} {p}")


# -- the everyday examples -----------------------------------------------------------


def test_crank_rocker_coupler_point_rides_on_the_coupler():
    s = sweep(load("crank_rocker"))
    np.testing.assert_allclose(distance(s, "A", "P"), 20, rtol=1e-12)
    np.testing.assert_allclose(distance(s, "B", "P"), np.sqrt(35**2 + 20**2 - 2 * 35 * 20 *
                                                              np.cos(np.radians(30))), rtol=1e-12)
    assert shapely.LineString(s["P"]).length > 0


def test_offset_slider_crank_stroke():
    s = sweep(load("slider_crank_offset"))
    r, rod, e = 20, 70, 10
    np.testing.assert_allclose(s["B"][:, 1], e)
    np.testing.assert_allclose(distance(s, "A", "B"), rod, rtol=1e-12)
    fine = sweep(load("slider_crank_offset"), np.radians(np.linspace(0, 360, 36001)))
    stroke = np.ptp(fine["B"][:, 0])
    exact = math.sqrt((rod + r) ** 2 - e**2) - math.sqrt((rod - r) ** 2 - e**2)
    assert stroke == pytest.approx(exact, abs=1e-6)
    assert stroke > 2 * r


def test_the_boom_follows_its_cylinder_by_the_cosine_rule():
    """|O-C| = 50, |O-R| = 60 and |C-R| = s: the boom's angle is atan2(-40, 30) plus the
    angle at O of that triangle; the tip T lies 200 along it, the barrel's X 35 along C-R."""
    c = load("boom_cylinder")
    s = sweep(c)
    length = s.inputs["s"]
    phi = math.atan2(-40, 30) + np.arccos((60**2 + 50**2 - length**2) / (2 * 60 * 50))
    np.testing.assert_allclose(s["T"], 200 * np.c_[np.cos(phi), np.sin(phi)], atol=1e-11)
    np.testing.assert_allclose(distance(s, "C", "R"), length, rtol=1e-13)
    np.testing.assert_allclose(distance(s, "C", "X"), 35, rtol=1e-13)
    report = analysis.analyze(c, degrees=True)
    boom = report.strokes["boom.angle"]
    np.testing.assert_allclose([boom.minimum, boom.maximum], np.degrees(phi[[0, -1]]),
                               atol=1e-9)
    assert report.strokes["rod.position"].stroke == pytest.approx(60, abs=1e-9)
    mobility = analysis.degrees_of_freedom(c)
    assert (mobility.moving_links, mobility.lower_pairs, mobility.dof) == (3, 4, 1)


def inclined_closed_form(theta, r=20.0, rod=70.0, e=10.0, beta=math.pi / 6):
    """B and the rod point P of the inclined offset slider-crank, from the loop by hand.

    In the guide's frame (x axis along the guide at beta, y to its left) the
    pin A is r (cos(theta - beta), sin(theta - beta)) and the guide is the
    line y = e; B is the root ahead of A's foot on it.
    """
    u = np.array([np.cos(beta), np.sin(beta)])
    n = np.array([-np.sin(beta), np.cos(beta)])
    along = r * np.cos(theta - beta)
    across = r * np.sin(theta - beta)
    s = along + np.sqrt(rod**2 - (e - across) ** 2)
    a = np.outer(along, u) + np.outer(across, n)
    b = np.outer(s, u) + e * n
    axis = (b - a) / rod
    left = np.stack([-axis[:, 1], axis[:, 0]], axis=-1)
    return s, b, a + rod / 2 * axis + 10 * left


def test_inclined_slider_crank_matches_the_closed_form():
    theta = np.radians(np.linspace(0, 360, 721))
    s = sweep(load("slider_crank_inclined"), theta)
    assert s.valid.all()
    position, b, p = inclined_closed_form(theta)
    np.testing.assert_allclose(s["B"], b, rtol=0, atol=1e-12)
    np.testing.assert_allclose(s["P"], p, rtol=0, atol=1e-12)
    np.testing.assert_allclose(distance(s, "G", "B"), np.abs(position), rtol=1e-13)
    np.testing.assert_allclose(distance(s, "O", "G"), 10, rtol=1e-14)


def test_inclined_slider_crank_is_the_offset_one_turned_by_its_guide_angle():
    """Turned back by beta, with the crank beta behind, it is slider_crank_offset.toml."""
    beta = np.radians(30)
    theta = np.radians(np.linspace(0, 360, 361))
    inclined = sweep(load("slider_crank_inclined"), theta)
    level = sweep(load("slider_crank_offset"), theta - beta)
    c, s_ = np.cos(-beta), np.sin(-beta)
    turned = inclined["B"] @ np.array([[c, s_], [-s_, c]])
    np.testing.assert_allclose(turned, level["B"], rtol=0, atol=1e-12)


def test_inclined_slider_crank_guide_is_ground_and_its_stroke_and_time_ratio_are_exact():
    c = load("slider_crank_inclined")
    assert c.compile().ground == {"O", "G", "H"}
    mobility = analysis.degrees_of_freedom(c)
    assert mobility.guides == {"slider": "ground"} and mobility.dof == 1
    stroke = geokin.analyze(c, degrees=True).strokes["slider.position"]
    r, rod, e = 20, 70, 10
    exact = math.sqrt((rod + r) ** 2 - e**2) - math.sqrt((rod - r) ** 2 - e**2)
    assert stroke.stroke == pytest.approx(exact, abs=1e-9)
    a = math.degrees(math.asin(e / (rod - r)) - math.asin(e / (rod + r)))
    assert stroke.time_ratio == pytest.approx((180 - a) / (180 + a), rel=1e-9)


# -- the examples that use the shipped scripts ------------------------------------------

EXAMPLES = pathlib.Path(__file__).resolve().parent.parent / "examples"


def run_example(name, *argv, monkeypatch, capsys):
    import runpy
    import sys

    monkeypatch.setattr(sys, "argv", [name, *map(str, argv)])
    runpy.run_path(str(EXAMPLES / name), run_name="__main__")
    return capsys.readouterr().out


def test_example_quick_return_table(monkeypatch, capsys):
    out = run_example("quick_return_table.py", monkeypatch=monkeypatch, capsys=capsys)
    assert "     30    87.18   130.77    51.96   66.59" in out
    assert len(out.splitlines()) == 14


def test_example_sixbar_trace(monkeypatch, capsys, tmp_path):
    from PIL import Image

    path = tmp_path / "six.png"
    out = run_example("sixbar_trace.py", path, monkeypatch=monkeypatch, capsys=capsys)
    assert "113 samples, all assembled: True" in out
    with Image.open(path) as image:
        assert image.size == (800, 600)


def test_example_script_from_python(monkeypatch, capsys):
    out = run_example("script_from_python.py", monkeypatch=monkeypatch, capsys=capsys)
    assert 'angle = 30, reference = ["A", "B"]' in out
    assert float(out.split("between the two: ")[1].split()[0]) < 1e-9
