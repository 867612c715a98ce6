import numpy as np
import pytest
from mechanisms import (
    R1,
    R2,
    R3,
    R4,
    change_point_fourbar,
    coupler_fourbar,
    slider_crank_closed_form,
    triple_rocker,
)

from geokin import Construction, sweep
from geokin.kinematics import (
    GUIDE_RTOL,
    RELATIVE_STEP,
    input_derivatives,
    motion,
    slider_offsets,
    slider_positions,
    sliders_off_guide,
)


def loop_rates(theta, omega_driver, alpha_driver, driver):
    """Angular velocities and accelerations from the four-bar loop equations.

    r2 e^{i t2} + r3 e^{i t3} - r4 e^{i t4} - r1 = 0, differentiated once and
    twice; the two unknown rates solve a 2x2 linear system (Cramer's rule).
    """
    t2, t3, t4 = theta
    lengths = {"crank": R2, "coupler": R3, "follower": -R4}
    angles = {"crank": t2, "coupler": t3, "follower": t4}
    unknown = [k for k in lengths if k != driver]
    lk, ak = lengths[driver], angles[driver]
    (l1, a1), (l2, a2) = [(lengths[u], angles[u]) for u in unknown]
    det = l1 * l2 * np.sin(a2 - a1)
    # velocity: l1 w1 i e^{i a1} + l2 w2 i e^{i a2} = -lk wk i e^{i ak}
    rhs = -lk * omega_driver * np.exp(1j * ak)
    w1 = (rhs.real * l2 * np.sin(a2) - rhs.imag * l2 * np.cos(a2)) / det
    w2 = (rhs.imag * l1 * np.cos(a1) - rhs.real * l1 * np.sin(a1)) / det
    omega = {driver: omega_driver + 0 * t2, unknown[0]: w1, unknown[1]: w2}
    # acceleration: sum l (alpha i - w^2) e^{i a} = 0
    known = -lk * (1j * alpha_driver - omega_driver**2) * np.exp(1j * ak)
    known += l1 * w1**2 * np.exp(1j * a1) + l2 * w2**2 * np.exp(1j * a2)
    known = -1j * known  # i (l1 al1 e^{i a1} + l2 al2 e^{i a2}) = known
    al1 = (known.real * l2 * np.sin(a2) - known.imag * l2 * np.cos(a2)) / det
    al2 = (known.imag * l1 * np.cos(a1) - known.real * l1 * np.sin(a1)) / det
    alpha = {driver: alpha_driver + 0 * t2, unknown[0]: al1, unknown[1]: al2}
    return omega, alpha


def node_angle(s, node, first, second):
    u, v = s[first] - s[node], s[second] - s[node]
    cos = np.einsum("ij,ij->i", u, v) / np.hypot(*u.T) / np.hypot(*v.T)
    return np.degrees(np.arccos(np.clip(cos, -1, 1)))


@pytest.mark.parametrize("driver", ["crank", "coupler", "follower"])
@pytest.mark.parametrize("branch", ["left", "right"])
@pytest.mark.parametrize(("speed", "input_acceleration"), [(1.0, 0.0), (3.0, -2.0)])
def test_rates_match_the_loop_equations(driver, branch, speed, input_acceleration):
    c = triple_rocker(driver, branch)
    s = sweep(c, np.linspace(-np.pi, np.pi, 361))
    m = motion(s, speed=speed, acceleration=input_acceleration)
    theta = [np.arctan2(*(s[b] - s[a]).T[::-1]) for a, b in [("A", "B"), ("B", "C"), ("D", "C")]]
    omega, alpha = loop_rates(theta, speed, input_acceleration, driver)
    node = {"crank": ("C", "B", "D"), "coupler": ("B", "A", "Dp"), "follower": ("B", "A", "C")}
    mu = node_angle(s, *node[driver])
    good = s.valid & (mu >= 10) & (mu <= 170)
    assert good.sum() > 100
    assert not m.flagged[good].any()
    # relative to the largest rate of any link, so a link at constant speed counts too
    scale_w = max(np.max(np.abs(w[good])) for w in omega.values())
    scale_a = max(np.max(np.abs(a[good])) for a in alpha.values())
    for link in ("crank", "coupler", "follower"):
        np.testing.assert_allclose(m.angular_velocity[link][good], omega[link][good],
                                   rtol=1e-7, atol=1e-7 * scale_w, err_msg=link)
        np.testing.assert_allclose(m.angular_acceleration[link][good], alpha[link][good],
                                   rtol=1e-5, atol=1e-5 * scale_a, err_msg=link)


def test_derivatives_do_not_depend_on_how_coarse_the_sweep_is():
    c = triple_rocker("crank")
    fine = sweep(c, np.linspace(-2, 2, 401))
    coarse = sweep(c, np.linspace(-2, 2, 5))
    np.testing.assert_allclose(motion(coarse).velocity["C"], motion(fine).velocity["C"][::100],
                               rtol=1e-9)


def test_samples_next_to_a_toggle_use_one_sided_stencils_and_are_flagged():
    c = triple_rocker("crank")
    limit = np.arccos((R2**2 + R1**2 - (R3 + R4) ** 2) / (2 * R2 * R1))
    h = RELATIVE_STEP
    # central on -h, h and 2h, and -2h too near a toggle; one-sided where one is missing
    theta = np.array([0.0, limit - 1.5 * h, limit - 1e-3 * h, -limit + 0.5 * h,
                      -limit + 1.5 * h])
    s = sweep(c, theta)
    assert list(input_derivatives(s).stencil) == [0, -1, -1, 1, 1]
    # the rates blow up at the toggle: those samples are flagged, not reported as exact
    assert list(motion(s).flagged) == [False, True, True, True, True]


def test_one_sided_stencils_are_exact_where_a_segment_ends():
    """P = (s + 4, 0) on the segment O..Q until s = 6: dP/ds = (1, 0) up to the end."""
    c = Construction()
    c.input("s", kind="length", range=(0, 6))
    c.fixed("O", 0, 0)
    c.fixed("Q", 10, 0)
    c.fixed("R", 0, 3)
    c.polar("Cs", "R", "s", 0)
    c.segment_circle("P", ("O", "Q"), "Cs", 5, branch="second")
    h = RELATIVE_STEP * 10  # a length input's step: a fraction of the mechanism's size
    s = sweep(c, [3.0, 6 - 1.5 * h, 6.0])
    d = input_derivatives(s)
    assert d.step == h
    assert list(d.stencil) == [0, -1, -1]
    np.testing.assert_allclose(d.first["P"], [[1, 0]] * 3, atol=1e-9)
    np.testing.assert_allclose(d.second["P"], 0, atol=1e-5)
    assert not motion(s).flagged.any()
    assert np.isnan(input_derivatives(sweep(c, [6.1])).first["P"]).all()


def test_unassemblable_samples_have_no_derivatives():
    s = sweep(triple_rocker("crank"), np.radians([0, 180]))
    m = motion(s)
    assert np.isfinite(m.velocity["C"][0]).all()
    assert np.isnan(m.velocity["C"][1]).all() and np.isnan(m.acceleration["C"][1]).all()


def test_time_follows_the_input_speed():
    c = triple_rocker("crank")
    s = sweep(c, np.linspace(0, 1, 11))
    np.testing.assert_allclose(motion(s, speed=2.0).time, np.linspace(0, 0.5, 11))
    np.testing.assert_allclose(motion(s).time, np.linspace(0, 1, 11) / (2 * np.pi))


def test_slider_crank_against_its_closed_form():
    """x = r cos t + sqrt(rod^2 - (r sin t - e)^2) for an offset slider-crank."""
    r, rod, e, w = 3.0, 10.0, 1.0, 5.0
    c = Construction()
    c.input("t")
    c.fixed("O", 0, 0)
    c.fixed("G", 1, e)
    c.fixed("H", 0, e)
    c.polar("A", "O", r, "t")
    c.ray_circle("P", ("H", "G"), "A", rod, branch="second")
    t = np.linspace(0, 2 * np.pi, 73)
    m = motion(sweep(c, t), speed=w)
    root = np.sqrt(rod**2 - (r * np.sin(t) - e) ** 2)
    dx = -r * np.sin(t) - (r * np.sin(t) - e) * r * np.cos(t) / root
    np.testing.assert_allclose(m.velocity["P"][:, 0], dx * w, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(m.velocity["P"][:, 1], 0, atol=1e-9)
    # crank tip: |a| = r w^2
    np.testing.assert_allclose(np.hypot(*m.acceleration["A"].T), r * w**2, rtol=1e-7)


@pytest.mark.parametrize("guide", [("H", "G"), ("G", "H")])
def test_a_slider_on_a_fixed_guide_against_the_slider_crank_closed_form(guide):
    """The block of an offset slider-crank, measured from either end of its guide.

    The guide's first point is 0 (H) or 1 (G) along x: the position is x or
    1 - x, and the rates change sign with the guide's direction.
    """
    r, rod, e, w = 3.0, 10.0, 1.0, 5.0
    c = Construction()
    c.input("t")
    c.fixed("O", 0, 0)
    c.fixed("H", 0, e)
    c.fixed("G", 1, e)
    c.polar("A", "O", r, "t")
    c.ray_circle("P", ("H", "G"), "A", rod, branch="second")
    c.slider("block", "P", guide)
    t = np.linspace(0, 2 * np.pi, 721)
    s = sweep(c, t)
    m = motion(s, speed=w)
    x, v, a = slider_crank_closed_form(t, r, rod, e, w)
    start, sense = (0.0, 1.0) if guide[0] == "H" else (1.0, -1.0)
    np.testing.assert_allclose(slider_positions(s)["block"], sense * (x - start),
                               rtol=0, atol=1e-13 * rod)
    np.testing.assert_array_equal(m.slider_position["block"], slider_positions(s)["block"])
    # as accurate as stated wherever unflagged: the fastest point and the largest
    # acceleration at each sample are the crank tip's or the block's
    ok = ~m.flagged
    assert ok.all()
    fastest, largest = np.fmax(r * w, np.abs(v)), np.fmax(r * w * w, np.abs(a))
    assert (np.abs(m.slider_velocity["block"] - sense * v) <= 1e-7 * fastest)[ok].all()
    assert (np.abs(m.slider_acceleration["block"] - sense * a) <= 1e-5 * largest)[ok].all()


@pytest.mark.parametrize("far", [1e9, 1e12])
def test_link_and_slider_rates_far_from_the_origin_against_the_closed_form(far):
    """An offset slider-crank standing far from (0, 0): its rod's and block's rates.

    The rod's angle is asin((e - r sin t) / rod), the block's position the
    closed form's x; however far the mechanism stands, both rates are as
    accurate as stated wherever they are not flagged.
    """
    r, rod, e, w = 3.0, 10.0, 1.0, 5.0
    c = Construction()
    c.input("t")
    c.fixed("O", far, far)
    c.fixed("H", far, far + e)
    c.fixed("G", far + 1, far + e)
    c.polar("A", "O", r, "t")
    c.ray_circle("P", ("H", "G"), "A", rod, branch="second")
    c.link("rod", "A", "P")
    c.slider("block", "P", ("H", "G"))
    t = np.linspace(0, 2 * np.pi, 361)
    m = motion(sweep(c, t), speed=w)
    x, v, a = slider_crank_closed_form(t, r, rod, e, w)
    sine = (e - r * np.sin(t)) / rod  # of the rod's angle beta from A to P
    cosine = np.sqrt(1 - sine**2)
    rate = -r * w * np.cos(t) / (rod * cosine)  # beta'
    rate2 = (r * w * w * np.sin(t) + rod * rate**2 * sine) / (rod * cosine)  # beta''
    ok = ~m.flagged
    assert ok.all()
    turn = np.max(np.abs(rate))
    assert np.max(np.abs(m.angular_velocity["rod"] - rate)) <= 1e-7 * turn
    assert np.max(np.abs(m.angular_acceleration["rod"] - rate2)) <= 1e-5 * max(
        np.max(np.abs(rate2)), turn**2)
    fastest, largest = np.fmax(r * w, np.abs(v)), np.fmax(r * w * w, np.abs(a))
    assert (np.abs(m.slider_velocity["block"] - v) <= 1e-7 * fastest).all()
    assert (np.abs(m.slider_acceleration["block"] - a) <= 1e-5 * largest).all()


@pytest.mark.parametrize("far", [0.0, 1e12])
def test_a_slider_on_a_turning_guide_against_the_closed_form(far):
    """An inverted slider-crank: the crank pin A slides in a lever turning about O1.

    The same wherever it stands: 1e12 from the origin, the lever's direction
    is taken where its rates were found, not from positions rounded to 1e-4.

    O1 = (0, 0), crank O2 = (0, d) of radius r at a constant w: the block's
    position along the lever is s = |A|, so s s' = A.v and s s'' + s'^2 =
    v.v + A.a, with v and a the crank pin's velocity and acceleration.
    """
    r, d, w = 3.0, 5.0, 2.0
    c = Construction()
    c.input("t")
    c.fixed("O1", far, far)
    c.fixed("O2", far, far + d)
    c.polar("A", "O2", r, "t")
    c.along("L", ("O1", "A"), 12)  # a point of the lever, 12 from its pivot
    c.slider("block", "A", ("O1", "L"))
    t = np.linspace(0, 2 * np.pi, 721)
    s = sweep(c, t)
    m = motion(s, speed=w)
    np.testing.assert_array_equal(m.slider_position["block"], slider_positions(s)["block"])
    pin = np.c_[r * np.cos(t), d + r * np.sin(t)]
    v = r * w * np.c_[-np.sin(t), np.cos(t)]
    a = -r * w * w * np.c_[np.cos(t), np.sin(t)]
    position = np.hypot(*pin.T)
    speed = (pin * v).sum(axis=1) / position
    accel = ((v * v).sum(axis=1) + (pin * a).sum(axis=1) - speed**2) / position
    # positions 1e12 from the origin are rounded to about 1e-4
    np.testing.assert_allclose(m.slider_position["block"], position, rtol=1e-14,
                               atol=1e-15 * far)
    ok = ~m.flagged
    assert ok.all()
    # the lever's end L is the fastest point: 12 times the lever's rate
    lever = (pin[:, 0] * v[:, 1] - pin[:, 1] * v[:, 0]) / position**2
    fastest = np.fmax(r * w, 12 * np.abs(lever))
    largest = np.max([np.hypot(*q.T) for q in m.acceleration.values()], axis=0)
    assert (np.abs(m.slider_velocity["block"] - speed) <= 1e-7 * fastest).all()
    assert (np.abs(m.slider_acceleration["block"] - accel) <= 1e-5 * largest).all()


def test_a_circuit_runs_time_forwards_and_the_input_backwards_on_the_return():
    from geokin.circuits import circuit

    s = circuit(triple_rocker("crank"), samples_per_pass=181)
    m = motion(s, speed=2.0)
    assert (np.diff(m.time) > 0).all()
    # each sample moves the way the input arrived there
    going_up = np.r_[False, np.diff(s.input_values) > 0]
    going_down = np.r_[False, np.diff(s.input_values) < 0]
    np.testing.assert_allclose(m.angular_velocity["crank"][going_up], 2.0, rtol=1e-9)
    np.testing.assert_allclose(m.angular_velocity["crank"][going_down & ~m.flagged], -2.0,
                               rtol=1e-9)
    # velocities agree with the motion itself: finite differences of the positions over time
    ok = ~m.flagged[1:-1]
    numeric = (s["C"][2:] - s["C"][:-2]) / (m.time[2:] - m.time[:-2])[:, None]
    scale = np.abs(m.velocity["C"]).max()
    assert np.abs(numeric - m.velocity["C"][1:-1])[ok].max() < 0.05 * scale


def test_a_sweep_run_backwards_turns_the_crank_backwards():
    c = triple_rocker("crank")
    m = motion(sweep(c, np.linspace(1, 0, 11)), speed=3.0)
    np.testing.assert_allclose(m.angular_velocity["crank"], -3.0, rtol=1e-9)
    np.testing.assert_allclose(m.time, np.linspace(0, 1 / 3, 11))


def five_bar(ground=4, cranks=2, links=4):
    """Two cranks on pivots ``ground`` apart, joined by two links meeting at C."""
    c = Construction("five-bar")
    c.input("t1", range=(0, 1), speed=2.0)
    c.input("t2", range=(1, 3), speed=1.0)
    c.fixed("O1", 0, 0)
    c.fixed("O2", ground, 0)
    c.polar("A", "O1", cranks, "t1")
    c.polar("B", "O2", cranks, "t2")
    c.circle_circle("C", ("A", "B"), (links, links), branch="left")
    return c


def test_with_two_inputs_moving_together_the_rates_follow_both():
    """v = dp/dt1 * w1 + dp/dt2 * w2, with t2 moving in step with t1."""
    c = five_bar()
    t1 = np.linspace(0, 1, 2001)
    s = sweep(c, {"t1": t1, "t2": 1 + 2 * t1})
    m = motion(s)  # t1 drives at 2 rad/s; t2 moves twice as far: 4 rad/s
    assert m.input_name == "t1"
    d1 = input_derivatives(s, "t1")
    d2 = input_derivatives(s, "t2")
    expected = d1.first["C"] * 2.0 + d2.first["C"] * 4.0
    np.testing.assert_allclose(m.velocity["C"], expected, rtol=1e-7, atol=1e-9)
    # and it is the motion's own rate of change: compare with the positions over time
    numeric = np.gradient(s["C"], m.time, axis=0)
    np.testing.assert_allclose(m.velocity["C"][5:-5], numeric[5:-5], rtol=1e-4, atol=1e-4)
    second = d1.second["C"] * 4.0 + d2.second["C"] * 16.0
    ahead, behind = (input_derivatives(sweep(c, {"t1": t1 + e, "t2": 1 + 2 * t1}), "t2")
                     for e in (1e-4, -1e-4))
    cross = (ahead.first["C"] - behind.first["C"]) / 2e-4  # d2p/dt1dt2, central
    expected = second + 2 * cross * 8.0
    scale = np.abs(expected).max()
    np.testing.assert_allclose(m.acceleration["C"], expected, rtol=1e-5, atol=1e-5 * scale)


def test_a_second_input_swept_unevenly_flags_what_its_sampled_rate_cannot_promise():
    """t2 = pi/2 + sin(t1) / 2: t2's rate and its change are read off its samples, to
    the square of their spacing. At 361 samples a turn that misses 1e-7 in velocity, and
    every sample doing so is flagged; at 36,001 only the two samples at either end are,
    where the change is read one-sided, and every other is within it. The
    reference: the coupler joint C of the five-bar in closed form, differentiated by
    central differences of steps 1e-5 (velocity) and 1e-3 (acceleration)."""
    def joint(t1):
        a = 3 * np.c_[np.cos(t1), np.sin(t1)]
        t2 = np.pi / 2 + 0.5 * np.sin(t1)
        c = np.c_[6 + 3 * np.cos(t2), 3 * np.sin(t2)]
        u = c - a
        d = np.hypot(*u.T)[:, None]
        m = d / 2  # equal coupler links of 7
        h = np.sqrt(49 - m * m)
        return a + m * u / d + h * np.c_[-u[:, 1], u[:, 0]] / d

    k = five_bar(ground=6, cranks=3, links=7)
    for n in (361, 36_001):
        t1 = np.linspace(0, 2 * np.pi, n)
        m = motion(sweep(k, {"t1": t1, "t2": np.pi / 2 + 0.5 * np.sin(t1)}), "t1", speed=1.0)
        assert np.allclose(m.sweep["C"], joint(t1), atol=1e-12)
        v = (joint(t1 + 1e-5) - joint(t1 - 1e-5)) / 2e-5
        a = (joint(t1 + 1e-3) - 2 * joint(t1) + joint(t1 - 1e-3)) / 1e-6
        v_error = np.hypot(*(m.velocity["C"] - v).T) / np.hypot(*v.T).max()
        a_error = np.hypot(*(m.acceleration["C"] - a).T) / np.hypot(*a.T).max()
        missed = (v_error > 1e-7) | (a_error > 1e-5)
        assert not (missed & ~m.flagged).any(), n
        if n == 361:
            assert missed.any()
        else:
            assert np.flatnonzero(m.flagged).tolist() == [0, 1, n - 2, n - 1]


def test_an_input_in_step_with_a_varying_speed_takes_its_rate_by_the_chain_rule():
    """The second crank turns at half the first's angle while the first speeds up and
    slows down: its pin's velocity and acceleration are the closed form's, and nothing
    is flagged. Where the driving input stands still while the other moves, there is
    no clock for the other's rate: every sample is flagged."""
    k = five_bar(ground=6, cranks=3, links=7)
    t1 = np.linspace(0, 2 * np.pi, 361)
    t2 = 1.5 + 0.5 * t1
    omega = 1 + 0.5 * np.sin(t1)
    alpha = 0.5 * np.cos(t1) * omega  # d omega / dt
    m = motion(sweep(k, {"t1": t1, "t2": t2}), "t1", speed=omega, acceleration=alpha)
    turn = np.c_[-np.sin(t2), np.cos(t2)]
    v = 3 * turn * (0.5 * omega)[:, None]
    a = 3 * (-np.c_[np.cos(t2), np.sin(t2)] * ((0.5 * omega) ** 2)[:, None]
             + turn * (0.5 * alpha)[:, None])
    assert not m.flagged.any()
    np.testing.assert_allclose(m.velocity["B"], v, atol=1e-9 * np.abs(v).max())
    np.testing.assert_allclose(m.acceleration["B"], a, atol=1e-7 * np.abs(a).max())
    paused = motion(sweep(k, {"t1": [0.0, 0.1, 0.1, 0.2, 0.3], "t2": [1.0, 1.1, 1.2, 1.3, 1.4]}),
                    "t1", speed=1.0)
    assert paused.flagged.all()


def test_an_input_in_step_with_a_falling_driver_is_flagged_as_with_a_rising_one():
    """The same sweep run backwards: the second crank's rate, read off a cubic in the
    first's angle over 21 samples, is as unsure either way, and every sample left
    unflagged is within the stated accuracy of the closed form."""
    k = five_bar(ground=6, cranks=3, links=7)
    t1 = np.linspace(0.0, 1.0, 21)
    flags = []
    for t in (t1, t1[::-1]):
        t2 = 1 + 2 * t**3
        m = motion(sweep(k, {"t1": t, "t2": t2}), "t1", speed=1.0)
        sense = np.sign(t[-1] - t[0])
        v = 3 * np.c_[-np.sin(t2), np.cos(t2)] * (6 * t * t * sense)[:, None]
        error = np.max(np.abs(m.velocity["B"] - v), axis=1) / np.abs(v).max()
        assert not ((error > 1e-7) & ~m.flagged).any()
        flags.append(m.flagged)
    np.testing.assert_array_equal(flags[0], flags[1][::-1])


def test_an_input_that_stays_put_is_held():
    c = five_bar()
    s = sweep(c, {"t1": np.linspace(0, 1, 11), "t2": 2.0})
    m = motion(s)
    np.testing.assert_allclose(m.velocity["C"], input_derivatives(s, "t1").first["C"] * 2.0,
                               rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("shift", [1e5, 1e7])
def test_rates_do_not_depend_on_where_the_mechanism_stands(shift):
    """The same four-bar moved far from the origin has the same velocities and accelerations."""
    def fourbar(at):
        c = Construction()
        c.input("t")
        c.fixed("A", at, at)
        c.fixed("D", at + 7, at)
        c.polar("B", "A", 5, "t")
        c.circle_circle("C", ("B", "D"), (6, 5), branch="left")
        return c

    theta = np.linspace(-1, 1, 50)
    here, there = (motion(sweep(fourbar(at), theta), speed=1.0) for at in (0.0, shift))
    for kind in ("velocity", "acceleration"):
        ours, theirs = getattr(here, kind)["C"], getattr(there, kind)["C"]
        # each as accurate as its own estimate says, however far from (0, 0)
        error = getattr(here, f"{kind}_error") + getattr(there, f"{kind}_error")
        assert (np.hypot(*(theirs - ours).T) <= error).all(), kind
        np.testing.assert_allclose(theirs, ours, rtol=0, atol=1e-7 * np.abs(ours).max())


def fourbar_rates(s, omega, crank_pin="A", joint="B", pivot="O4", crank_pivot="O2", point=None):
    """Velocities and accelerations of a four-bar's joints by the vector loop, in closed form.

    With a = A - O2, b = B - A, c = B - O4 and w x r = w (-ry, rx) for a crank
    at constant rate ``omega``: vA + w3 x b = w4 x c, dotted with c and with b
    to eliminate one unknown each; twice for the accelerations. ``point``
    (a coupler point) moves with the coupler.
    """
    A, B, O2, O4 = (s[name] for name in (crank_pin, joint, crank_pivot, pivot))
    a, b, c = A - O2, B - A, B - O4
    va = omega * np.c_[-a[:, 1], a[:, 0]]
    cross = b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0]
    w3 = -(va * c).sum(axis=1) / cross
    w4 = -(va * b).sum(axis=1) / cross
    vb = w4[:, None] * np.c_[-c[:, 1], c[:, 0]]
    aa = -omega**2 * a
    k = aa - w3[:, None] ** 2 * b + w4[:, None] ** 2 * c
    al3 = -(k * c).sum(axis=1) / cross
    al4 = -(k * b).sum(axis=1) / cross
    ab = al4[:, None] * np.c_[-c[:, 1], c[:, 0]] - w4[:, None] ** 2 * c
    rates = {crank_pin: (va, aa), joint: (vb, ab)}
    if point is not None:
        q = s[point] - A
        vp = va + w3[:, None] * np.c_[-q[:, 1], q[:, 0]]
        ap = aa + al3[:, None] * np.c_[-q[:, 1], q[:, 0]] - w3[:, None] ** 2 * q
        rates[point] = (vp, ap)
    return rates


def assert_unflagged_samples_as_accurate_as_stated(m, rates):
    """Every unflagged sample: each velocity within 1e-7 of the sample's fastest speed,
    each acceleration within 1e-5 of its largest acceleration (as Motion.flagged states)."""
    ok = ~m.flagged & m.sweep.valid
    fastest = np.max([np.hypot(*v.T) for v, _ in rates.values()], axis=0)
    largest = np.max([np.hypot(*a.T) for _, a in rates.values()], axis=0)
    for name, (v, a) in rates.items():
        error_v = np.hypot(*(m.velocity[name] - v).T)[ok]
        error_a = np.hypot(*(m.acceleration[name] - a).T)[ok]
        assert (error_v <= 1e-7 * fastest[ok]).all(), (name, np.max(error_v / fastest[ok]))
        assert (error_a <= 1e-5 * largest[ok]).all(), (name, np.max(error_a / largest[ok]))
        # and the estimate is not below the error it estimates
        assert (error_v <= m.velocity_error[ok] * 1.0001 + 1e-15 * fastest[ok]).all(), name
        assert (error_a <= m.acceleration_error[ok] * 1.0001 + 1e-12 * largest[ok]).all(), name


def double_rocker():
    """Ground 10, input 8, coupler 3, output 9: a Grashof double-rocker, its input
    rocking between two toggles; and the limits of its first assembly region."""
    from geokin.circuits import limits

    c = Construction()
    c.input("t")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 10, 0)
    c.polar("A", "O2", 8, "t")
    c.circle_circle("B", ("A", "O4"), (3, 9), branch="left")
    (lo, hi), _ = limits(c).as_values()  # two assembly regions: the first
    return c, lo, hi


def near_toggles(lo, hi, nearest=1e-9, count=400, middle=200):
    """Input values dense near both limits, where the rates grow without bound."""
    ends = np.geomspace(nearest, 0.3, count)
    inside = np.linspace(lo + 0.3, hi - 0.3, middle) if middle else []
    return np.concatenate([lo + ends, inside, hi - ends[::-1]])


def test_a_grashof_double_rocker_is_accurate_wherever_it_is_not_flagged():
    """The input rocks between two toggles."""
    c, lo, hi = double_rocker()
    t = near_toggles(lo, hi)
    s = sweep(c, t)
    assert s.valid.all()
    m = motion(s, speed=1.0)
    assert_unflagged_samples_as_accurate_as_stated(m, fourbar_rates(s, 1.0))
    # flags only near the toggles: the middle of the swing is clean
    middle = np.abs(t - 0.5 * (lo + hi)) < 0.3 * (hi - lo)
    assert not m.flagged[middle].any() and m.flagged.any()


def test_the_quick_stencil_alone_flags_every_sample_it_cannot_make_accurate(monkeypatch):
    """Without the second look near the toggles, fewer samples pass, each as accurate as stated."""
    import geokin.kinematics

    c, lo, hi = double_rocker()
    s = sweep(c, near_toggles(lo, hi))
    both = motion(s, speed=1.0)
    monkeypatch.setattr(geokin.kinematics, "REFINED_BELOW", 1e-30)  # never looked at again
    quick = motion(s, speed=1.0)
    assert_unflagged_samples_as_accurate_as_stated(quick, fourbar_rates(s, 1.0))
    assert (~quick.flagged).sum() < (~both.flagged).sum()
    # where the quick stencil is trusted the two agree within their estimates
    ok = ~quick.flagged
    for kind in ("velocity", "acceleration"):
        gap = np.hypot(*(getattr(quick, kind)["B"] - getattr(both, kind)["B"]).T)[ok]
        assert (gap <= (getattr(quick, f"{kind}_error") + getattr(both, f"{kind}_error"))[ok]).all()


@pytest.mark.parametrize("radius", [1e3, 1e5, 1e7])
def test_a_large_point_turning_regularly_does_not_hide_a_small_one_at_its_toggle(radius):
    """The double-rocker's B next to its toggle, beside a crank point far larger."""
    c, lo, hi = double_rocker()
    c.polar("P", "O2", radius, "t")
    s = sweep(c, near_toggles(lo, hi, nearest=1e-6, count=200, middle=0))
    m = motion(s, speed=1.0)
    rates = fourbar_rates(s, 1.0)
    rates["P"] = (np.c_[-s["P"][:, 1], s["P"][:, 0]], -s["P"])
    assert_unflagged_samples_as_accurate_as_stated(m, rates)


def test_links_do_not_flag_samples_far_from_the_toggles():
    """A link's rates are judged on its own ends' errors, not the largest point's.

    The double-rocker with a coupler point 20 out accelerates far more than
    its crank, whose rate is constant: the point's error, within its own
    bound, must not flag the crank's samples in the middle of the swing.
    """
    c, _, _ = double_rocker()
    c.polar("P", "A", 20, 0.0, reference=("A", "B"))
    for name, ends in (("crank", ("O2", "A")), ("coupler", ("A", "B")), ("rocker", ("O4", "B"))):
        c.link(name, *ends)
    t = np.radians(np.linspace(36.9, 82.8, 3601))  # toggle to toggle
    m = motion(sweep(c, t), speed=1.0)
    middle = (t > np.radians(40)) & (t < np.radians(80))
    assert not m.flagged[middle].any() and m.flagged.any()
    np.testing.assert_allclose(m.angular_velocity["crank"][~m.flagged], 1.0, rtol=1e-7)
    # each point's own errors, whose largest is the sample's
    errors = np.max([m.derivatives.first_errors[p] for p in ("A", "B", "P")], axis=0)
    np.testing.assert_array_equal(errors, m.velocity_error)


def test_the_benchmark_four_bar_and_its_coupler_point_match_the_closed_form():
    c = Construction()
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 40, 0)
    c.polar("A", "O2", 10, "theta")
    c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
    c.polar("P", "A", 20, np.radians(30), reference=("A", "B"))
    s = sweep(c, np.linspace(0, 2 * np.pi, 3601))
    m = motion(s, speed=2 * np.pi)
    assert not m.flagged.any()
    assert_unflagged_samples_as_accurate_as_stated(m, fourbar_rates(s, 2 * np.pi, point="P"))


@pytest.mark.parametrize("driver", ["crank", "coupler", "follower"])
def test_the_triple_rocker_is_accurate_wherever_it_is_not_flagged(driver):
    """Against the loop equations, every unflagged sample, right up to the toggles."""
    c = triple_rocker(driver, "left")
    from geokin.circuits import limits

    [(lo, hi)] = limits(c).as_values()
    t = np.concatenate([lo + np.geomspace(1e-9, 0.3, 300), np.linspace(lo + 0.3, hi - 0.3, 101),
                        hi - np.geomspace(0.3, 1e-9, 300)])
    s = sweep(c, t)
    m = motion(s, speed=1.0)
    theta = [np.arctan2(*(s[b] - s[a]).T[::-1]) for a, b in [("A", "B"), ("B", "C"), ("D", "C")]]
    omega, alpha = loop_rates(theta, 1.0, 0.0, driver)
    ok = ~m.flagged
    fastest = np.max([np.abs(w) for w in omega.values()], axis=0)[ok]
    largest = np.fmax(np.max([np.abs(a) for a in alpha.values()], axis=0)[ok], fastest**2)
    for link in ("crank", "coupler", "follower"):
        assert (np.abs(m.angular_velocity[link][ok] - omega[link][ok]) <= 1e-7 * fastest).all()
        assert (np.abs(m.angular_acceleration[link][ok] - alpha[link][ok])
                <= 1e-5 * largest).all()
    assert ok.sum() > 150


def test_blocks_of_samples_give_the_same_derivatives_as_one_pass(monkeypatch):
    """Block boundaries fall on the change point of a parallelogram and next to a toggle."""
    import geokin.engine
    import geokin.kinematics

    c = Construction()
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 10, 0)
    c.polar("A", "O2", 4, "theta")
    c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
    c.polar("P", "A", 3, 0.5, reference=("A", "B"))
    theta = np.linspace(0, 2 * np.pi, 721)  # sample 360 is the change point at 180 degrees
    s = sweep(c, theta)
    assert s.events
    whole = motion(s)
    monkeypatch.setattr(geokin.kinematics, "SAMPLES_PER_BLOCK", 45)  # 360 = 8 * 45
    # as in use, the engine evaluates a block's perturbations in one piece
    monkeypatch.setattr(geokin.engine, "BLOCK_SAMPLES", 45)
    monkeypatch.setattr(geokin.engine, "BLOCKED_ABOVE", 4 * 45)
    blocked = motion(s)
    for name in ("A", "B", "P"):
        np.testing.assert_array_equal(blocked.velocity[name], whole.velocity[name])
        np.testing.assert_array_equal(blocked.acceleration[name], whole.acceleration[name])
    np.testing.assert_array_equal(blocked.flagged, whole.flagged)
    np.testing.assert_array_equal(blocked.derivatives.stencil, whole.derivatives.stencil)


def test_motions_one_after_another_and_in_threads_each_keep_their_own_results():
    """The stencil's memory is kept from motion to motion: no result may depend on it."""
    from concurrent.futures import ThreadPoolExecutor

    sweeps = [sweep(triple_rocker("crank"), np.linspace(0, 2 * np.pi, 3001)),  # 2 moving
              sweep(coupler_fourbar(), np.linspace(0.3, 5.0, 2000))]         # 3 moving
    alone = [motion(s) for s in sweeps]
    after_the_other = [motion(s) for s in sweeps[::-1]][::-1]
    with ThreadPoolExecutor(8) as pool:
        threaded = list(pool.map(motion, sweeps * 12))
    for got in (after_the_other, *zip(threaded[::2], threaded[1::2], strict=True)):
        for m, expected in zip(got, alone, strict=True):
            for name in expected.velocity:
                np.testing.assert_array_equal(m.velocity[name], expected.velocity[name])
                np.testing.assert_array_equal(m.acceleration[name], expected.acceleration[name])
            np.testing.assert_array_equal(m.velocity_error, expected.velocity_error)
            np.testing.assert_array_equal(m.flagged, expected.flagged)


@pytest.mark.parametrize("speed", [0.0, -1.0, np.nan, np.inf])
def test_a_speed_that_is_not_a_positive_number_is_refused(speed):
    from geokin import ConstructionError

    s = sweep(triple_rocker("crank"), [0.0, 0.1])
    with pytest.raises(ConstructionError, match="positive number"):
        motion(s, speed=speed)


def test_time_one_way_at_one_speed_is_the_distance_over_the_speed():
    # no running sum: each sample's time is rounded once, however many samples before it
    c, lo, hi = double_rocker()
    theta = np.linspace(hi, lo, 20_001)  # backwards: time still runs forwards
    m = motion(sweep(c, theta), speed=3.0)
    np.testing.assert_array_equal(m.time, (theta[0] - theta) / 3.0)


def slider_crank_with_guides(offset):
    """A slider-crank whose block B runs on the line y = 10; guides on it and across it."""
    c = Construction("slider-crank")
    c.input("theta")
    c.fixed("O", 0, 0)
    c.fixed("G1", 0, 10)
    c.fixed("G2", 1, 10)
    c.fixed("V", 0, 30)
    c.polar("A", "O", 20, "theta")
    c.line_circle("B", ("G1", "G2"), "A", 70, branch="second")
    c.slider("block", "B", ("G1", "G2"))
    c.slider("across", "B", ("V", "O"))  # a vertical line the block crosses once
    c.fixed("H1", 0, 10 + offset)
    c.fixed("H2", 1, 10 + offset)
    c.slider("beside", "B", ("H1", "H2"))  # a parallel line ``offset`` above the block
    return c


@pytest.mark.parametrize("offset", [1e-3, 1e-9, 0.0])
def test_a_sliders_point_off_its_guide_line_is_found_where_it_is_farthest(offset):
    s = sweep(slider_crank_with_guides(offset), np.linspace(0, 2 * np.pi, 73))
    x, y = s["B"].T
    offsets = slider_offsets(s)
    # the guide V->O points down: its left is +x; the line above the block is ``offset`` away
    np.testing.assert_allclose(offsets["across"], x, rtol=1e-15)
    np.testing.assert_allclose(offsets["beside"], -offset, rtol=0, atol=1e-12)
    assert np.abs(offsets["block"]).max() <= 1e-15 * 90
    found = sliders_off_guide(s)
    farthest = int(np.argmax(np.abs(x)))
    assert found["across"] == (farthest, pytest.approx(x[farthest], rel=1e-15))
    # off by more than GUIDE_RTOL of the mechanism's size, the extent of all its points
    size = np.ptp(np.concatenate([s[p] for p in s.construction.point_names]), axis=0).max()
    assert ("beside" in found) == (offset > GUIDE_RTOL * size)
    assert "block" not in found


# -- samples on a change point ---------------------------------------------------------


@pytest.mark.parametrize("variants", [None, {"l3": [10.0, 10.0]}])
def test_a_parallelogram_is_differentiated_on_its_motion_at_its_change_points(variants):
    """A parallelogram's rocker turns with its crank: B = O4 + 4 (cos, sin) at every
    sample, its change points at 0, 180 and 360 deg included, where B's roots meet and a
    perturbation past the sample on the same branch would be on the crossed assembly."""
    c = change_point_fourbar(10, 4, 10, 4)
    theta = np.linspace(0, 2 * np.pi, 361)
    m = motion(sweep(c, theta, parameters=variants), speed=1.0)
    turn = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    velocity, acceleration = m.velocity["B"], m.acceleration["B"]
    np.testing.assert_allclose(velocity, np.broadcast_to(4 * turn @ [[0, 1], [-1, 0]],
                                                         velocity.shape), rtol=0, atol=1e-6)
    np.testing.assert_allclose(acceleration, np.broadcast_to(-4 * turn, acceleration.shape),
                               rtol=0, atol=1e-4)
    np.testing.assert_allclose(m.angular_velocity["rocker"], 1.0, rtol=0, atol=1e-6)


@pytest.mark.parametrize("theta", [np.linspace(0, 2 * np.pi, 361),
                                   np.radians(np.arange(178.0, 183.0)),
                                   np.radians(np.r_[np.arange(170.0, 180.0),
                                                    np.arange(180.0, 169.0, -1)]),
                                   np.radians([178.0, 179.0, 180.0, 180.0, 181.0, 182.0]),
                                   np.linspace(0, np.pi, 181)])
def test_a_sample_on_a_change_point_is_differentiated_on_the_motion_through_it(theta):
    """Ground 10, crank 4, coupler 9, rocker 5: B's roots meet at 180 deg, where the
    motion goes on smoothly on the other branch. The rates there are those of a dense
    sweep through it, tracked across it: on the path, where it turns back there, where it
    stands still there a sample and where it ends there."""
    c = change_point_fourbar(10, 4, 9, 5)
    m = motion(sweep(c, theta), speed=1.0)
    at = int(np.argmin(np.abs(theta - np.pi)))
    assert theta[at] == np.pi
    delta = 1e-3
    # the direction the path arrives in: from below 180 deg on every path here
    dense = sweep(c, np.pi + np.array([-delta, 0.0, delta]),
                  start_branches={"B": int(np.ravel(m.sweep.branches["B"])[at - 1])})
    b = dense["B"]
    np.testing.assert_allclose(m.velocity["B"][at], (b[2] - b[0]) / (2 * delta), rtol=0,
                               atol=1e-5)
    np.testing.assert_allclose(m.acceleration["B"][at], (b[2] - 2 * b[1] + b[0]) / delta**2,
                               rtol=0, atol=1e-4)


def test_samples_denser_than_the_perturbation_are_differentiated_on_the_motion_near_it():
    """36,001 samples a turn, closer than the perturbation's reach: the samples near the
    change point at 180 deg are differentiated on the path, where their perturbations
    pass it, as central differences of a tracked sweep about each of them say."""
    c = change_point_fourbar(10, 4, 9, 5)
    theta = np.linspace(0, 2 * np.pi, 36_001)
    s = sweep(c, theta)
    m = motion(s, speed=1.0)
    near = np.flatnonzero((np.abs(theta - np.pi) < 1e-3) & (np.abs(theta - np.pi) > 1e-6))
    assert near.size >= 8
    delta = 1e-7
    for i in near:
        around = sweep(c, theta[i] + np.array([-delta, 0.0, delta]),
                       start_branches={"B": int(np.ravel(s.branches["B"])[i])})
        b = around["B"]
        np.testing.assert_allclose(m.velocity["B"][i], (b[2] - b[0]) / (2 * delta), rtol=0,
                                   atol=1e-3, err_msg=f"sample {i}")
