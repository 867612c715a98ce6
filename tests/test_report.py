from pathlib import Path

import numpy as np
import pytest

from geokin import Construction, load
from geokin.analysis import analyze

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
    mu = report["transmission_angles"]["C"]
    assert round(mu["min"], 2) == 34.92 and round(mu["max"], 2) == 180.0
    assert report["four_bars"][0]["class"].startswith("triple-rocker")


def test_triple_rocker_report_has_its_limits_dof_and_class():
    report = analyze(fourbar(7, 5, 6, 5), degrees=True)
    assert report["dof"] == 1 and report["mobility"]["matches_inputs"]
    [[lo, hi]] = report["inputs"]["theta2"]["intervals"]
    assert (round(lo, 4), round(hi, 4)) == (-132.1774, 132.1774)
    assert [limit["kind"] for limit in report["inputs"]["theta2"]["limits"]] == ["tangent"] * 2
    assert report["four_bars"][0]["code"] == "RRR1"
    # the circuit's coupler curve is closed
    assert report["curves"]["C"]["closed"]


def test_crank_rocker_turns_fully_and_has_a_time_ratio():
    report = analyze(fourbar(40, 10, 35, 30))
    assert report["inputs"]["theta2"]["full_turn"]
    assert report["four_bars"][0]["class"] == "crank-rocker"
    follower = report["strokes"]["follower.angle"]
    # the follower's dead positions: crank and coupler in line, B at 10 + 35 or 35 - 10
    # from A; B above the ground, on the left of A -> D as declared
    angles, cranks = [], []
    for reach, crank_turn in ((45.0, 0.0), (25.0, np.pi)):
        cos_b = (40**2 + 30**2 - reach**2) / (2 * 40 * 30)  # angle at D in triangle A-D-B
        angles.append(np.pi - np.arccos(cos_b))  # direction D -> B
        bx, by = 40 + 30 * np.cos(angles[-1]), 30 * np.sin(angles[-1])
        cranks.append(np.arctan2(by, bx) + crank_turn)  # A on the line A-B, or against it
    low, high = min(angles), max(angles)
    assert follower["min"] == pytest.approx(low, abs=1e-6)
    assert follower["max"] == pytest.approx(high, abs=1e-6)
    forward = (cranks[angles.index(high)] - cranks[angles.index(low)]) % (2 * np.pi)
    assert follower["time_ratio"] == pytest.approx(forward / (2 * np.pi - forward), rel=1e-6)


def test_quick_return_time_ratio_matches_the_closed_form():
    report = analyze(load(CONSTRUCTIONS / "quick_return.toml"), degrees=True)
    alpha = 2 * np.degrees(np.arcsin(40 / 60))
    ratio = report["strokes"]["lever.angle"]["time_ratio"]
    assert max(ratio, 1 / ratio) == pytest.approx((180 + alpha) / (180 - alpha), rel=1e-6)


def test_the_shipped_sixbar_has_one_degree_of_freedom():
    report = analyze(load(CONSTRUCTIONS / "sixbar.toml"))
    assert report["dof"] == 1
    assert report["mobility"]["moving_links"] == 5 and report["mobility"]["lower_pairs"] == 7


def test_a_rocker_swing_is_measured_between_samples():
    """Ground 40, crank 30, coupler 20, follower 25: the follower swings between the
    angles where crank and coupler line up, cos(phi) = (50^2 - 40^2 - 25^2) / (2 40 25)."""
    report = analyze(fourbar(40, 30, 20, 25), degrees=True)
    swing = report["strokes"]["follower.angle"]
    extreme = np.degrees(np.arccos((50**2 - 40**2 - 25**2) / (2 * 40 * 25)))
    got = sorted(v % 360 for v in (swing["min"], swing["max"]))
    np.testing.assert_allclose(got, [extreme, 360 - extreme], atol=1e-4)


def test_an_output_with_two_strokes_a_turn_has_no_time_ratio():
    """The quick return's ram block rises and falls twice a turn; its lever once."""
    strokes = analyze(load(CONSTRUCTIONS / "quick_return.toml"))["strokes"]
    assert strokes["ram_block.position"]["strokes_per_turn"] == 2
    assert strokes["ram_block.position"]["time_ratio"] is None
    assert strokes["lever.angle"]["strokes_per_turn"] == 1
    assert strokes["lever.angle"]["time_ratio"] is not None


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
    for node, mu in base["transmission_angles"].items():
        assert scaled["transmission_angles"][node]["min"] == pytest.approx(mu["min"], rel=1e-12)
        assert scaled["transmission_angles"][node]["max"] == pytest.approx(mu["max"], rel=1e-12)
    assert set(scaled["strokes"]) == set(base["strokes"])
    assert scaled["strokes"]["P.x"]["stroke"] == pytest.approx(
        base["strokes"]["P.x"]["stroke"] * 2.0**k, rel=1e-9)
    assert scaled["curves"]["P"]["length"] == pytest.approx(
        base["curves"]["P"]["length"] * 2.0**k, rel=1e-12)
    # an area beyond the normal range of floats is not given, rather than given wrong
    assert scaled["curves"]["P"]["area"] is None
