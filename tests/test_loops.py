import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from geokin import AssemblyError, Construction, sweep
from geokin.analysis import grashof
from geokin.loops import (
    fourbar_closed_form,
    fourbar_loop,
    newton_continuation,
    quick_return_closed_form,
    quick_return_loop,
)

SEED_004 = dict(ground=24.0, input_link=10.55, coupler=25.0, output_link=14.0)


def fourbar(ground, input_link, coupler, output_link, crossed=False, theta1=0.0):
    """O2 at the origin, O4 at angle theta1: open (not crossed) is B left of A -> O4."""
    c = Construction("four-bar")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", ground * np.cos(theta1), ground * np.sin(theta1))
    c.polar("A", "O2", input_link, "theta")
    c.circle_circle("B", ("A", "O4"), (coupler, output_link),
                    branch="right" if crossed else "left")
    return c


def positions(ground, input_link, coupler, output_link, theta2, theta3, theta4, theta1=0.0):
    """Points A and B from the loop's angles, B both from the coupler and the output."""
    e = np.stack
    a = input_link * e([np.cos(theta2), np.sin(theta2)], axis=-1)
    o4 = ground * np.array([np.cos(theta1), np.sin(theta1)])
    b_out = o4 + output_link * e([np.cos(theta4), np.sin(theta4)], axis=-1)
    b_cpl = a + coupler * e([np.cos(theta3), np.sin(theta3)], axis=-1)
    return a, b_out, b_cpl


@pytest.mark.parametrize("crossed", [False, True])
def test_engine_agrees_with_closed_form_and_newton_seed_004(crossed):
    theta = np.linspace(0, 6 * np.pi, 3 * 720 + 1)
    s = sweep(fourbar(**SEED_004, crossed=crossed), theta)
    assert s.valid.all()
    t3, t4 = fourbar_closed_form(**SEED_004, theta2=theta, crossed=crossed)
    a, b_out, b_cpl = positions(*SEED_004.values(), theta, t3, t4)
    np.testing.assert_allclose(s["A"], a, atol=1e-9)
    np.testing.assert_allclose(s["B"], b_out, atol=1e-9)
    np.testing.assert_allclose(s["B"], b_cpl, atol=1e-9)
    # Newton from a rough guess on the right side, continued over three turns
    guess = (-0.4, -0.8) if crossed else (0.4, 0.8)
    sol = fourbar_loop(**SEED_004, theta2=theta, guess=guess)
    assert sol.valid.all() and sol.residual.max() < 1e-11
    _, b_out, b_cpl = positions(*SEED_004.values(), theta, sol["theta3"], sol["theta4"])
    np.testing.assert_allclose(s["B"], b_out, atol=1e-9)
    np.testing.assert_allclose(s["B"], b_cpl, atol=1e-9)
    np.testing.assert_allclose(np.cos(sol["theta4"] - t4), 1, atol=1e-15)


def test_closed_form_angles_keep_their_quadrant():
    # the coupler angle of the crossed circuit lies beyond 90 degrees: atan would fold it
    theta = np.linspace(-np.pi, np.pi, 721)
    t3, t4 = fourbar_closed_form(**SEED_004, theta2=theta, crossed=True)
    assert np.any(np.abs(t3) > np.pi / 2) or np.any(np.abs(t4) > np.pi / 2)
    a, b_out, b_cpl = positions(*SEED_004.values(), theta, t3, t4)
    np.testing.assert_allclose(b_out, b_cpl, atol=1e-12)
    assert np.all((t3 > -np.pi) & (t3 <= np.pi) & (t4 > -np.pi) & (t4 <= np.pi))


def test_triple_rocker_seed_000_within_its_limits():
    # seed 000: r1=7, r2=5, r3=6, r4=5, crank range -132.1774 to 132.1774 degrees
    lengths = dict(ground=7.0, input_link=5.0, coupler=6.0, output_link=5.0)
    limit = np.arccos((7**2 + 5**2 - 11**2) / (2 * 7 * 5))
    assert np.degrees(limit) == pytest.approx(132.1774, abs=5e-5)
    theta = np.linspace(-limit, limit, 1001)[1:-1]
    for crossed in (False, True):
        s = sweep(fourbar(**lengths, crossed=crossed), theta)
        assert s.valid.all()
        t3, t4 = fourbar_closed_form(**lengths, theta2=theta, crossed=crossed)
        _, b_out, _ = positions(*lengths.values(), theta, t3, t4)
        np.testing.assert_allclose(s["B"], b_out, atol=1e-9)
    beyond = fourbar_closed_form(**lengths, theta2=[limit + 0.01, np.pi])
    assert np.isnan(beyond).all()


lengths = st.floats(1.0, 20.0)


@given(lengths, lengths, lengths, lengths, st.floats(-np.pi, np.pi), st.booleans())
def test_closed_form_matches_the_engine(g, i, c, o, theta1, crossed):
    """Wherever the engine assembles a four-bar, the closed form gives the same points."""
    assume(grashof(g, i, c, o).kind not in ("immobile", "unassemblable"))
    theta = np.linspace(-np.pi, np.pi, 181)
    s = sweep(fourbar(g, i, c, o, crossed, theta1), theta)
    assume(not s.events)  # a change point: the engine may change circuit there
    t3, t4 = fourbar_closed_form(g, i, c, o, theta, crossed=crossed, theta1=theta1)
    _, b_out, b_cpl = positions(g, i, c, o, theta, t3, t4, theta1)
    margin = s.margins["B"]
    # away from tangency and from coincident centres (a kite's A on O4), where the
    # position of B is ill-conditioned for both
    diagonal = np.hypot(*(s["A"] - s["O4"]).T)
    well = s.valid & (margin > 1e-6) & (diagonal > 1e-6 * (g + i + c + o))
    np.testing.assert_allclose(s["B"][well], b_out[well], atol=1e-9 * (g + i + c + o))
    np.testing.assert_allclose(s["B"][well], b_cpl[well], atol=1e-9 * (g + i + c + o))
    assert np.all(np.isnan(t4[~s.valid & (margin < -1e-6)]))


def test_quick_return_seed_001_at_30_degrees():
    theta2 = np.radians(30)
    q = quick_return_closed_form(60, 40, 60, theta2)
    # from seed 001's own starting guess (1, 1, 1, 1), as its notebook does
    sol = quick_return_loop(60, 40, 60, [theta2], guess=(1, 1, 1, 1))
    for name in ("r3", "r4", "r5", "theta3"):
        assert sol[name][0] == pytest.approx(float(q[name]), rel=1e-12)
    # the seed's table, which truncates to two decimals
    assert sol["r3"][0] == pytest.approx(87.17, abs=0.01)
    assert sol["r5"][0] == pytest.approx(51.96, abs=0.01)
    assert np.degrees(sol["theta3"][0]) == pytest.approx(66.58, abs=0.01)
    # r4 is 130.767 (the seed's Newton run prints 130.76696831); its analytical 130.75
    # comes from the rounded r3 = 87.17: 120 * 87.17 / 80 = 130.755
    assert sol["r4"][0] == pytest.approx(130.76696831, abs=1e-8)
    assert 120 * 87.17 / 80 == pytest.approx(130.755)


def test_quick_return_newton_over_a_turn():
    theta = np.radians(np.arange(0, 361))
    sol = quick_return_loop(60, 40, 60, theta, guess=(100, 120, 80, 1.2))
    assert sol.valid.all() and sol.iterations.max() <= 6
    q = quick_return_closed_form(60, 40, 60, theta)
    for name in ("r3", "r4", "r5"):
        np.testing.assert_allclose(sol[name], q[name], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(sol["theta3"], q["theta3"], atol=1e-12)
    # and the construction engine: the lever through the crank pin meets the ram's line
    c = Construction("quick return")
    c.input("theta2")
    c.fixed("O1", 0, 0)
    c.fixed("O2", 0, 60)
    c.fixed("C", 0, 120)
    c.fixed("E", 1, 120)
    c.polar("A", "O2", 40, "theta2")
    c.line_line("B", ("O1", "A"), ("C", "E"))
    s = sweep(c, theta)
    np.testing.assert_allclose(np.hypot(*s["A"].T), sol["r3"], rtol=1e-12)
    np.testing.assert_allclose(np.hypot(*s["B"].T), sol["r4"], rtol=1e-12)
    np.testing.assert_allclose(s["B"][:, 0], sol["r5"], atol=1e-9)
    np.testing.assert_allclose(np.arctan2(s["A"][:, 1], s["A"][:, 0]), sol["theta3"], atol=1e-12)


def test_newton_failure_is_reported():
    # seed 000's triple rocker driven past its limit of 132.18 degrees
    theta = np.radians(np.arange(0, 181, 1.0))
    with pytest.raises(AssemblyError, match=r"sample 133 \(theta2 = 2\.32\d*\).*residual"):
        fourbar_loop(7, 5, 6, 5, theta, guess=(1.0, 2.0))
    sol = fourbar_loop(7, 5, 6, 5, theta, guess=(1.0, 2.0), on_failure="mask")
    assert sol.valid[:133].all() and not sol.valid[133:].any()
    assert np.isnan(sol.x[133:]).all() and np.all(sol.residual[133:] > 1e-6)
    with pytest.raises(ValueError, match="on_failure"):
        fourbar_loop(7, 5, 6, 5, theta, guess=(1.0, 2.0), on_failure="ignore")


def test_newton_continues_after_a_gap():
    # out of reach in the middle, back in reach after: the masked solver resumes
    sol = newton_continuation(lambda x, u: x ** 2 - u, lambda x, u: np.diag(2 * x),
                              [1.0, 4.0, -1.0, 9.0], [1.0], names=("root",), on_failure="mask")
    np.testing.assert_allclose(sol["root"], [1, 2, np.nan, 3])
    assert sol.valid.tolist() == [True, True, False, True]


def test_quick_return_three_ways_example():
    import subprocess
    import sys
    from pathlib import Path

    script = Path(__file__).parents[1] / "examples" / "quick_return_three_ways.py"
    run = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                         check=True)
    rows = {line.split()[0]: line.split() for line in run.stdout.splitlines()
            if len(line.split()) == 8}
    assert rows["r4"][3:6] == ["130.7669683062"] * 3
    assert float(rows["theta3"][3]) == pytest.approx(66.5867755536)
    for row in rows.values():
        assert abs(float(row[6])) < 1e-9 and abs(float(row[7])) < 1e-9
