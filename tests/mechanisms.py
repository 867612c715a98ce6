"""Constructions shared by the engine tests, built with the Python API."""

import numpy as np

from geokin import Construction

SIXBAR = dict(x=168, y=20, l1=10, l2=20, l2p=5, l3=100, l3p=70, l4=100, l5=140)
FOURBAR_004 = dict(a=10.55, b=25, c=14, d=24)


def sixbar():
    """Seed 003's six-bar, with the seed's point names and primitive choices."""
    c = Construction("six-bar")
    for name, value in SIXBAR.items():
        c.parameter(name, value)
    c.input("theta", range=(0, np.radians(1800)), step=np.radians(16))
    c.fixed("D", 0, 0)
    c.fixed("mid", 0, "y")
    c.fixed("A0", 0, "y + l1")
    c.fixed("B0", "x", "l1")
    c.polar("A", "A0", "l2", "theta")
    c.circle_circle("B", ("A", "B0"), ("l3", "l4"), branch="left")
    c.line_circle("Ap", ("A0", "A"), "A", "l2p", branch="first")
    c.line_circle("C", ("A", "B"), "Ap", "l3p", branch="second")
    c.ray_circle("M", ("Ap", "C"), "Ap", "l5", branch="second")
    c.link("crank", "A0", "Ap", "A")
    c.link("coupler", "A", "B", "C")
    c.link("rocker", "B", "B0")
    c.link("output", "Ap", "M")
    c.slider("block", "C", ("Ap", "M"))
    c.trace("M")
    return c


def fourbar(ground=24.0, crank=10.55, coupler=25.0, rocker=14.0, branch="left",
            ground_at=(0.0, 0.0), **input_options):
    """A four-bar O2-A-B-O4, crank angle theta; O2 at ``ground_at``, O4 ``ground`` to its right."""
    c = Construction("four-bar")
    c.input("theta", **input_options)
    x, y = ground_at
    c.fixed("O2", x, y)
    c.fixed("O4", x + ground, y)
    c.polar("A", "O2", crank, "theta")
    c.circle_circle("B", ("A", "O4"), (coupler, rocker), branch=branch)
    return c


def coupler_fourbar():
    """The benchmark four-bar: pivots 40 apart, crank 10, coupler 35, rocker 30, point P."""
    c = fourbar(40, 10, 35, 30)
    c.polar("P", "A", 20, np.radians(30), reference=("A", "B"))
    return c


R1, R2, R3, R4 = 7.0, 5.0, 6.0, 5.0  # seed 000: ground, crank, coupler, follower


def triple_rocker(driver, branch="left", input_range=None):
    """Seed 000's four-bar with the crank, coupler or follower driving.

    ``input_range`` (radians) is the driving input's declared range, one turn
    from 0 by default.
    """
    c = Construction(f"triple rocker, {driver} driving")
    c.fixed("A", 0, 0)
    c.fixed("D", R1, 0)
    if driver == "crank":
        c.input("theta2", range=input_range)
        c.polar("B", "A", R2, "theta2")
        c.circle_circle("C", ("B", "D"), (R3, R4), branch=branch)
    elif driver == "coupler":
        c.input("theta3", range=input_range)
        # B is r3 behind C along the coupler: it lies on the follower circle shifted back
        c.polar("Dp", "D", R3, "theta3 + pi")
        c.circle_circle("B", ("A", "Dp"), (R2, R4), branch=branch)
        c.polar("C", "B", R3, "theta3")
    else:
        c.input("theta4", range=input_range)
        c.polar("C", "D", R4, "theta4")
        c.circle_circle("B", ("A", "C"), (R2, R3), branch=branch)
    c.link("crank", "A", "B")
    c.link("coupler", "B", "C")
    c.link("follower", "D", "C")
    return c


def parallelograms_in_series(x=0.0, y=0.0):
    """O2-A-B-O4 and O4-B-C-O6, both parallelograms: B and C meet together at pi."""
    c = Construction("two parallelograms in series")
    c.input("theta")
    c.fixed("O2", x, y)
    c.fixed("O4", x + 52.6, y)
    c.fixed("O6", x + 93.9, y)
    c.polar("A", "O2", 30.25, "theta")
    c.circle_circle("B", ("A", "O4"), (52.6, 30.25), branch="left")
    c.circle_circle("C", ("B", "O6"), (41.3, 30.25), branch="left")
    return c


def change_point_fourbar(ground=10.0, crank=4.0, coupler=9.0, rocker=5.0, start=None):
    """A four-bar whose B is on circles about A (radius parameter ``l3``) and O4, left branch.

    By default a change-point crank-rocker (4 + 10 = 9 + 5): at pi A, O4 and
    B line up, and B's roots meet. With ``start``, the input's range is the
    turn from there.
    """
    c = Construction("change-point four-bar")
    c.input("theta", range=None if start is None else (start, start + 2 * np.pi))
    c.parameter("l3", coupler)
    c.fixed("O2", 0, 0)
    c.fixed("O4", ground, 0)
    c.polar("A", "O2", crank, "theta")
    c.circle_circle("B", ("A", "O4"), ("l3", rocker), branch="left")
    c.link("rocker", "O4", "B")
    return c


def fourbar_closed_form(theta2, a, b, c, d, omega2=1.0, sign=-1):
    """Coupler and rocker angles and rates of a four-bar, by Freudenstein and Norton.

    Crank a at ``theta2`` turning at the constant rate ``omega2``, coupler b,
    rocker c, ground d along the x axis. The rocker angle is the half-angle
    solution ``theta4 = 2 atan2(-B + sign sqrt(B^2 - 4AC), 2A)`` (``sign``
    -1 for the open circuit), the coupler's follows from the loop, and the
    rates from the loop equation differentiated once and twice. Returns
    ``(theta3, theta4, omega3, omega4, alpha3, alpha4)``, radians.
    """
    t2 = np.asarray(theta2, dtype=float)
    k1, k2, k3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    qa = np.cos(t2) - k1 - k2 * np.cos(t2) + k3
    qb = -2 * np.sin(t2)
    qc = k1 - (k2 + 1) * np.cos(t2) + k3
    t4 = 2 * np.arctan2(-qb + sign * np.sqrt(qb * qb - 4 * qa * qc), 2 * qa)
    t3 = np.arctan2(c * np.sin(t4) - a * np.sin(t2), d + c * np.cos(t4) - a * np.cos(t2))
    w3 = a * omega2 * np.sin(t4 - t2) / (b * np.sin(t3 - t4))
    w4 = a * omega2 * np.sin(t2 - t3) / (c * np.sin(t4 - t3))
    na, nb, nd, ne = c * np.sin(t4), b * np.sin(t3), c * np.cos(t4), b * np.cos(t3)
    nc = a * omega2**2 * np.cos(t2) + b * w3**2 * np.cos(t3) - c * w4**2 * np.cos(t4)
    nf = -a * omega2**2 * np.sin(t2) - b * w3**2 * np.sin(t3) + c * w4**2 * np.sin(t4)
    al3 = (nc * nd - na * nf) / (na * ne - nb * nd)
    al4 = (nc * ne - nb * nf) / (na * ne - nb * nd)
    return t3, t4, w3, w4, al3, al4


def slider_crank_closed_form(theta, r, rod, e, omega=1.0):
    """Block position, velocity and acceleration of an offset slider-crank.

    Crank r about the origin at ``theta`` turning at the constant rate
    ``omega``, rod ``rod``, block on the horizontal line y = e, ahead of the
    crank: ``x = r cos t + sqrt(rod^2 - (r sin t - e)^2)``, differentiated.
    """
    t = np.asarray(theta, dtype=float)
    g, dg, ddg = r * np.sin(t) - e, r * np.cos(t), -r * np.sin(t)
    root = np.sqrt(rod * rod - g * g)
    x = r * np.cos(t) + root
    dx = -r * np.sin(t) - g * dg / root
    ddx = -r * np.cos(t) - (dg * dg + g * ddg) / root - (g * dg) ** 2 / root**3
    return x, dx * omega, ddx * omega**2


def five_bar(second_turns=1, links=60, ground=50, cranks=20):
    """Two cranks of ``cranks`` on pivots ``ground`` apart, driven together, and links
    meeting at C.

    The second crank turns ``second_turns`` times while the first turns once
    (clockwise for a negative number); the links are ``links`` long.
    """
    c = Construction("five-bar")
    c.input("t1")
    c.input("t2", range=(0.0, second_turns * 2 * np.pi))
    c.fixed("O1", 0, 0)
    c.fixed("O2", ground, 0)
    c.polar("A", "O1", cranks, "t1")
    c.polar("B", "O2", cranks, "t2")
    c.circle_circle("C", ("A", "B"), (links, links), branch="left")
    c.link("crank1", "O1", "A")
    c.link("crank2", "O2", "B")
    c.link("left", "A", "C")
    c.link("right", "B", "C")
    c.trace("C")
    return c


def offset_slider_crank(crank, rod, offset, samples=361):
    """A crank about O at (0, 0) and a rod to a block B on the line y = e (parameter e)."""
    c = Construction("offset slider-crank")
    c.parameter("e", offset)
    c.input("theta", samples=samples)
    c.fixed("O", 0, 0)
    c.fixed("G1", 0, "e")
    c.fixed("G2", 1, "e")
    c.polar("A", "O", crank, "theta")
    c.line_circle("B", ("G1", "G2"), "A", rod, branch="second")
    c.link("crank", "O", "A")
    c.link("rod", "A", "B")
    c.slider("slider", "B", ("G1", "G2"))
    return c
