"""Closure groups: points solved together by Newton's method along the sweep.

Checked against an independent solver written here (plain numpy Newton on
the same distance equations, one sample at a time from the previous
sample's solution), against the circle-circle node where a group of one
point is also constructible, and on input that cannot be solved.
"""

import time
import warnings

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

import geokin
from geokin.engine import evaluate
from geokin.errors import ConstructionError

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
SKETCH = {"F": (1, 0), "D": (1, 2.9), "E": (2.8, 1.5), "A": (3.3, 1.6), "B": (3.7, -1.2),
          "C": (4.7, 0), "G": (0, 0)}
PAIRS = [("F", "D"), ("F", "E"), ("D", "E"), ("C", "A"), ("C", "B"), ("A", "B"), ("D", "A"),
         ("E", "B")]
UNKNOWN = ["D", "E", "A", "B"]


def lengths():
    return [float(np.hypot(*np.subtract(SKETCH[p], SKETCH[q]))) for p, q in PAIRS]


def newton_reference(theta, known, unknown, pairs, d, sketch):
    """Solve a group sample by sample with plain Newton, each from the previous solution.

    ``known(t)`` gives the known points at input ``t``; ``pairs`` the
    distance equations |P - Q| = d, written as |P - Q|**2 - d**2 = 0.
    """
    z = np.array([c for p in unknown for c in sketch[p]], dtype=float)
    out = np.empty((len(theta), 2 * len(unknown)))
    for s, t in enumerate(theta):
        fixed = known(t)
        for _ in range(100):
            pos = {**fixed, **{p: z[2 * i:2 * i + 2] for i, p in enumerate(unknown)}}
            f = np.empty(len(pairs))
            jac = np.zeros((len(pairs), len(z)))
            for e, (p, q) in enumerate(pairs):
                diff = pos[p] - pos[q]
                f[e] = diff @ diff - d[e] ** 2
                for name, sign in ((p, 2), (q, -2)):
                    if name in unknown:
                        i = unknown.index(name)
                        jac[e, 2 * i:2 * i + 2] += sign * diff
            step = np.linalg.solve(jac, -f)
            z = z + step
            if np.max(np.abs(step)) < 1e-15:
                break
        out[s] = z
    return out


def reference_positions(theta):
    """Solve the triad sample by sample with plain Newton, from the previous solution."""
    return newton_reference(
        theta, lambda t: {"C": np.array([4.7, 0.0]), "F": np.array([np.cos(t), np.sin(t)])},
        UNKNOWN, PAIRS, lengths(), SKETCH)


def reference_motion(theta, z, omega):
    """Velocities and accelerations from the differentiated loop equations."""
    d = np.empty((len(theta), 8))
    a = np.empty((len(theta), 8))
    for s, t in enumerate(theta):
        pos = {"C": np.array([4.7, 0.0]), "F": np.array([np.cos(t), np.sin(t)])}
        vel = {"C": np.zeros(2), "F": omega * np.array([-np.sin(t), np.cos(t)])}
        acc = {"C": np.zeros(2), "F": -omega**2 * np.array([np.cos(t), np.sin(t)])}
        pos.update({p: z[s, 2 * i:2 * i + 2] for i, p in enumerate(UNKNOWN)})
        jac = np.zeros((8, 8))
        rhs_v = np.zeros(8)
        for e, (p, q) in enumerate(PAIRS):
            diff = pos[p] - pos[q]
            for name, sign in ((p, 1), (q, -1)):
                if name in UNKNOWN:
                    i = UNKNOWN.index(name)
                    jac[e, 2 * i:2 * i + 2] += sign * diff
                else:
                    rhs_v[e] -= sign * diff @ vel[name]
        v = np.linalg.solve(jac, rhs_v)
        vel.update({p: v[2 * i:2 * i + 2] for i, p in enumerate(UNKNOWN)})
        rhs_a = np.zeros(8)
        for e, (p, q) in enumerate(PAIRS):
            diff = pos[p] - pos[q]
            dv = vel[p] - vel[q]
            rhs_a[e] = -dv @ dv
            for name, sign in ((p, 1), (q, -1)):
                if name not in UNKNOWN:
                    rhs_a[e] -= sign * diff @ acc[name]
        d[s], a[s] = v, np.linalg.solve(jac, rhs_a)
    return d, a


@pytest.fixture(scope="module")
def stephenson():
    return geokin.load(ROOT / "constructions" / "stephenson3.toml")


def test_stephenson_positions_match_independent_newton(stephenson):
    theta = np.linspace(0, 2 * np.pi, 721)
    s = geokin.sweep(stephenson, theta)
    assert s.valid.all()
    expected = reference_positions(theta)
    for i, p in enumerate(UNKNOWN):
        assert np.max(np.abs(s[p] - expected[:, 2 * i:2 * i + 2])) < 1e-9, p
    # the sketch's assembly at theta = 0, and the same assembly after the full turn
    assert np.allclose(s["E"][0], SKETCH["E"], atol=1e-12)
    assert np.allclose(s["E"][-1], SKETCH["E"], atol=1e-9)


def test_stephenson_coarse_steps_keep_the_assembly(stephenson):
    """Steps of 30 degrees are crossed in pieces, never jumping to another assembly."""
    theta = np.linspace(0, 2 * np.pi, 13)
    s = geokin.sweep(stephenson, theta)
    expected = reference_positions(np.linspace(0, 2 * np.pi, 361))[::30]
    assert s.valid.all()
    assert np.max(np.abs(s["B"] - expected[:, 6:8])) < 1e-9


def test_stephenson_motion_matches_loop_equations(stephenson):
    theta = np.linspace(0, 2 * np.pi, 361)
    s = geokin.sweep(stephenson, theta)
    m = geokin.motion(s, speed=2 * np.pi)
    z = np.column_stack([s[p] for p in UNKNOWN])
    v, a = reference_motion(theta, z, 2 * np.pi)
    ok = ~m.flagged & s.valid
    assert ok.mean() > 0.95
    speed = max(np.max(np.abs(v)), 1.0)
    accel = max(np.max(np.abs(a)), 1.0)
    for i, p in enumerate(UNKNOWN):
        assert np.max(np.abs(m.velocity[p][ok] - v[ok, 2 * i:2 * i + 2])) < 1e-7 * speed
        assert np.max(np.abs(m.acceleration[p][ok] - a[ok, 2 * i:2 * i + 2])) < 1e-5 * accel


def fourbar(closure: bool, lengths=(40, 10, 35, 30), near=(35, 25), branch="left"):
    """A four-bar (ground, crank, coupler, rocker) with B by a one-point group or by
    circles, and the coupler point P."""
    ground, crank, coupler, rocker = lengths
    c = geokin.Construction("four-bar")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", ground, 0)
    c.polar("A", "O2", crank, "theta")
    if closure:
        c.closure("dyad", ["B"], [("A", "B", coupler), ("B", "O4", rocker)], near={"B": near})
    else:
        c.circle_circle("B", ("A", "O4"), (coupler, rocker), branch=branch)
    c.polar("P", "A", 20, np.radians(30), reference=("A", "B"))
    return c


def test_one_point_group_equals_circle_circle():
    theta = np.linspace(0, 4 * np.pi, 2001)
    by_circles = geokin.sweep(fourbar(False), theta)
    by_newton = geokin.sweep(fourbar(True), theta)
    assert by_newton.valid.all()
    for p in ("B", "P"):
        assert np.max(np.abs(by_newton[p] - by_circles[p])) < 1e-12


@pytest.mark.parametrize("far", [1e4, 1e9])
def test_a_group_far_from_the_origin_equals_circle_circle_there(far):
    """A group 1e4 or 1e9 from (0, 0) is assembled as its circles are, to their rounding.

    Its equations are solved to the rounding of its coordinates, which there
    is far above that of the group's size.
    """
    def shifted(closure):
        c = geokin.Construction("four-bar")
        c.input("theta")
        c.fixed("O2", far, far)
        c.fixed("O4", far + 40, far)
        c.polar("A", "O2", 10, "theta")
        if closure:
            c.closure("dyad", ["B"], [("A", "B", 35), ("B", "O4", 30)],
                      near={"B": (far + 35, far + 25)})
        else:
            c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
        return c

    theta = np.linspace(0, 2 * np.pi, 721)
    by_circles, by_newton = (geokin.sweep(shifted(group), theta) for group in (False, True))
    assert by_newton.valid.all()
    assert np.max(np.abs(by_newton["B"] - by_circles["B"])) <= 64 * np.finfo(float).eps * far


def triple_rocker(group: bool):
    """Seed 000's triple rocker (ground 7, crank 5, coupler 6, follower 5)."""
    c = geokin.Construction("triple rocker")
    c.input("theta2", range=(-np.pi, np.pi))
    c.fixed("A", 0, 0)
    c.fixed("D", 7, 0)
    c.polar("B", "A", 5, "theta2")
    if group:
        c.closure("dyad", ["C"], [("B", "C", 6), ("D", "C", 5)], near={"C": (6, 4)})
    else:
        c.circle_circle("C", ("B", "D"), (6, 5), branch="left")
    return c


def test_one_point_group_limits_of_a_triple_rocker():
    """The singular positions are the limits, found by bisection as toggles are."""
    c = triple_rocker(True)
    s = geokin.sweep(c, np.linspace(-np.pi, np.pi, 361))
    assert not s.valid.all() and s.valid.any()
    bad = np.flatnonzero(~s.valid)
    assert {s.failure_reason[i] for i in bad} <= {"the group reaches a singular position",
                                                   "Newton did not converge"}
    assert "the group reaches a singular position" in {s.failure_reason[i] for i in bad}
    found = geokin.limits(c)
    [(low, high)] = found.intervals
    exact = np.degrees(np.arccos(-47 / 70))  # B, C and D in line: |BD| = 6 + 5
    assert abs(np.degrees(high.value) - exact) < 1e-6
    assert abs(np.degrees(low.value) + exact) < 1e-6
    assert abs(exact - 132.177419) < 1e-6
    # the group's Jacobian is singular there: a toggle of the group, named by its node
    for end in (low, high):
        assert (end.node, end.kind, end.nodes) == ("C", "tangent", ("C",))
    assert repr(found) == ("<Limits of 'theta2': -2.30693 to 2.30693 "
                           "(tangent at 'C', tangent at 'C')>")
    # the same values as the circle-circle node's, whose tangency is exact
    by_circles = geokin.limits(triple_rocker(False)).as_values()[0]
    assert np.allclose(found.as_values()[0], by_circles, rtol=0, atol=1e-10)


def test_group_limit_beyond_a_fold_is_a_singular_position():
    """Solved from the inside end's solution, a sample just past the fold is singular."""
    c = triple_rocker(True)
    inside = np.arccos(-47 / 70) - 1e-7
    s = geokin.sweep(c, [inside])
    held = geokin.engine.assembly_guesses(s)
    beyond = geokin.engine.evaluate(c, {"theta2": np.array([inside + 2e-7])}, 1, held,
                                    track=False)
    assert not beyond.valid[0]
    assert beyond.failure_reason[0] == "the group reaches a singular position"


@pytest.mark.parametrize("count, word", [(1, "under-constrained"), (3, "over-constrained")])
def test_group_equation_count_is_checked(count, word):
    c = geokin.Construction()
    c.fixed("O", 0, 0)
    c.fixed("Q", 3, 0)
    c.fixed("R", 0, 3)
    distances = [("O", "P", 2), ("Q", "P", 2), ("R", "P", 2)][:count]
    with pytest.raises(ConstructionError, match=f"group 'g' is {word}"):
        c.closure("g", ["P"], distances, near={"P": (1, 1)})


def test_group_needs_every_sketch_position():
    c = geokin.Construction()
    c.fixed("O", 0, 0)
    c.fixed("Q", 3, 0)
    with pytest.raises(ConstructionError, match="every point of the group needs one"):
        c.closure("g", ["P", "S"], [("O", "P", 2), ("Q", "P", 2), ("P", "S", 1),
                                    ("O", "S", 1)], near={"P": (1, 1)})


def test_group_that_never_assembles_gives_reasons_quickly():
    c = geokin.Construction()
    c.input("t")
    c.fixed("O", 0, 0)
    c.polar("Q", "O", 3, "t")
    c.closure("g", ["P"], [("O", "P", 1), ("Q", "P", 1)], near={"P": (1.5, 0.5)})
    start = time.perf_counter()
    s = geokin.sweep(c, np.linspace(0, 2 * np.pi, 2001))
    assert time.perf_counter() - start < 5
    assert not s.valid.any()
    assert s.failed_node[0] == "P"
    assert s.failure_reason[0] == "Newton did not converge"
    with pytest.raises(geokin.AssemblyError, match="node 'P'"):
        s.require_assembled()


def test_sketch_far_from_any_assembly_still_ends():
    """A sketch far off: Newton's steps are cut to the group's size, and bounded."""
    c = fourbar(True)
    node = c.nodes["B"]
    c.nodes["B"] = type(node)("B", group="dyad", points=("B",), near=((1e6, -1e6),),
                              distances=node.distances)
    start = time.perf_counter()
    s = geokin.sweep(c, np.linspace(0, 2 * np.pi, 361))
    assert time.perf_counter() - start < 5
    # either an assembly (every sample on it, continuous) or reasons for each sample
    if s.valid.any():
        assert s.valid.all()
        assert np.max(np.abs(np.diff(s["B"], axis=0))) < 2
    else:
        assert set(s.failure_reason) == {"Newton did not converge"}


def test_script_round_trip_and_listing(stephenson):
    text = geokin.dump(stephenson)
    assert "[groups.triad]" in text
    again = geokin.io.loads(text)
    assert again == stephenson
    listing = str(stephenson.compile())
    assert "D = closure triad(D, E, A, B): |F-D| = FD" in listing
    assert "|E-B| = EB" in listing


def test_script_group_errors_name_the_group():
    text = (ROOT / "constructions" / "stephenson3.toml").read_text()
    broken = text.replace('["E", "B", "EB"],', "")
    with pytest.raises(geokin.errors.ScriptError,
                       match=r"\[groups\] triad.*under-constrained: 4 points need 8"):
        geokin.io.loads(broken, "s3.toml")


def test_point_on_line_constraint():
    """A slider-crank's block as a group: on the guide, at the rod's length from the pin."""
    c = geokin.Construction()
    c.input("theta")
    c.fixed("O", 0, 0)
    c.fixed("G", 10, 0)
    c.polar("A", "O", 1, "theta")
    c.closure("block", ["B"], [("A", "B", 3)], near={"B": (4, 0.5)}, lines=[("B", "O", "G")])
    theta = np.linspace(0, 2 * np.pi, 181)
    s = geokin.sweep(c, theta)
    assert s.valid.all()
    x = np.cos(theta) + np.sqrt(9 - np.sin(theta) ** 2)
    assert np.max(np.abs(s["B"][:, 0] - x)) < 1e-12
    assert np.max(np.abs(s["B"][:, 1])) < 1e-12
    assert geokin.io.loads(geokin.dump(c)) == c


TRIAD = {"A": None, "O4": (6.9, 0.9), "O6": (3.8, 4.8), "B": (1.1, 3.3), "C": (3.1, 2.7),
         "D": (4.1, 3.7)}
TRIAD_PAIRS = [("A", "B"), ("O4", "C"), ("O6", "D"), ("B", "C"), ("C", "D"), ("B", "D")]


def triad_reference(theta):
    """The triad B, C, D solved sample by sample by plain Newton, from the previous sample."""
    sketch = {**TRIAD, "A": (1.0, 0.0)}
    d = [float(np.hypot(*np.subtract(sketch[p], sketch[q]))) for p, q in TRIAD_PAIRS]
    return newton_reference(
        theta, lambda t: {"A": np.array([np.cos(t), np.sin(t)]), "O4": np.array(TRIAD["O4"]),
                          "O6": np.array(TRIAD["O6"])},
        ["B", "C", "D"], TRIAD_PAIRS, d, sketch)


def test_triad_sixbar_matches_independent_newton():
    """The second shipped group: three points on one ternary link, six equations."""
    c = geokin.load(ROOT / "constructions" / "triad_sixbar.toml")
    theta = np.linspace(0, 2 * np.pi, 721)
    s = geokin.sweep(c, theta)
    assert s.valid.all()
    expected = triad_reference(theta)
    for i, p in enumerate(["B", "C", "D"]):
        assert np.max(np.abs(s[p] - expected[:, 2 * i:2 * i + 2])) < 1e-9, p
    assert np.allclose(s["B"][0], TRIAD["B"], atol=1e-12)
    # the ternary link and its rockers are a four-bar: B goes to and fro on one curve
    assert geokin.limits(c).full_turn
    assert np.hypot(*np.diff(s["B"], axis=0).T).sum() == pytest.approx(4.0728, abs=1e-4)


def test_circuit_passes_a_group_through_its_folds():
    """The triple rocker as a group: both toggles passed, back to the start.

    The circle-circle version's circuit is the reference: at the group
    circuit's input values, with that circuit's branch at each sample, C is
    the same to 1e-9; at the two limit samples themselves, within 1e-12 of
    the fold where the two roots are 1e-6 apart, to 1e-6.
    """
    by_group = geokin.circuit(triple_rocker(True), start=0.0)
    by_circles = geokin.circuit(triple_rocker(False), start=0.0)
    assert by_group.valid.all()
    assert len(by_group) == len(by_circles)
    values = np.asarray(by_group.inputs["theta2"])
    assert np.max(np.abs(values - by_circles.inputs["theta2"])) < 1e-2
    label = np.asarray(by_circles.branches["C"])
    expected = geokin.engine.evaluate(triple_rocker(False), {"theta2": values}, len(values),
                                      {"C": label}, track=False)
    miss = np.max(np.abs(by_group["C"] - expected["C"]), axis=1)
    toggles = np.flatnonzero(np.diff(label))
    assert toggles.size == 2
    assert np.max(np.delete(miss, toggles)) < 1e-9
    assert np.max(miss[toggles]) < 1e-6
    # both branches of the coupler curve, and the start again at the end
    assert (by_group["C"][:, 1] > 0).any() and (by_group["C"][:, 1] < 0).any()
    assert np.allclose(by_group["C"][0], by_group["C"][-1], atol=1e-12)
    assert np.allclose(values[[0, -1]], 0.0)




def test_circuit_passes_a_triad_through_its_folds():
    """The Stephenson III with a crank of 2 rocks: its triad folds at both limits.

    The circuit runs to each fold and back on the triad's other assembly,
    and ends where it began; every sample keeps every link's length, and
    the two passes are two assemblies at the same input.
    """
    text = (ROOT / "constructions" / "stephenson3.toml").read_text().replace(
        "\nGF = 1\n", "\nGF = 2\n")
    c = geokin.loads(text)
    found = geokin.limits(c)
    assert not found.full_turn and found.intervals[0][1].kind == "tangent"
    s = geokin.circuit(c, samples_per_pass=181)
    # every sample, also each fold's within bisection's tolerance of it, where the
    # continuation may stop a sample short: Newton from the sample next to it reaches it
    assert s.valid.all()
    # each fold is an event of the group, at the sample where the input turns back
    folds = [e for e in s.events if e.node == "D"]
    turns = np.flatnonzero(np.diff(np.sign(np.diff(s.input_values))) != 0) + 1
    assert [e.index - 1 for e in folds] == turns.tolist()
    assert [(e.before, e.after) for e in folds] == [("assembly 0", "assembly 1"),
                                                   ("assembly 1", "assembly 0")]
    assert "the group folds" in str(folds[0])
    for p in ("D", "E", "A", "B"):
        assert np.allclose(s[p][0], s[p][-1], atol=1e-9), p
    lengths = {name: link for name, link in c.parameters.items()}
    assert lengths
    for a, b in (("F", "D"), ("F", "E"), ("D", "E"), ("C", "A"), ("C", "B"), ("A", "B"),
                 ("D", "A"), ("E", "B")):
        d = np.hypot(*(s[a] - s[b])[s.valid].T)
        assert np.ptp(d) < 1e-9, a + b
    values = s.input_values
    turn = int(np.argmax(values))
    here = turn // 2  # on the way out, and the same input on the way back
    back = turn + int(np.argmin(np.abs(values[turn:] - values[here])))
    assert abs(values[back] - values[here]) < 2e-2
    assert np.hypot(*(s["D"][here] - s["D"][back])) > 0.1


def test_newton_from_a_singular_solution_stays_there():
    """The step that polishes a converged solution is not taken where it flies off.

    At this assembly F, D and C are in line and the triad's Jacobian is
    singular: rounding divided by its zero pivot once moved D by a whole
    length, to another solution.
    """
    pts = {"F": (1.0, 0.0), "C": (0.0, 0.0), "D": (1.5, 0.0), "E": (1.5, 1.0),
           "A": (0.0, 1.0), "B": (1.5, 1.3780281786354962)}
    table = np.array([[np.hypot(*np.subtract(pts[p], pts[q])) for p, q in PAIRS]])
    known = {p: (np.full(1, pts[p][0]), np.full(1, pts[p][1])) for p in ("F", "C")}
    exact = np.array([[c for p in UNKNOWN for c in pts[p]]])
    z, ok, margin = geokin.closure.newton(geokin.closure.System(4, tuple(PAIRS)), UNKNOWN,
                                          known, table, exact)
    assert ok[0] and margin[0] < 1e-20
    assert np.max(np.abs(z - exact)) < 1e-12


# -- properties on random linkages ---------------------------------------------------

@given(st.floats(1.0, 3.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0),
       st.permutations(range(3)), st.floats(-0.3, 0.3), st.floats(-0.3, 0.3))
def test_random_crank_rocker_as_a_group_equals_circle_circle(crank, u, w, frac, order, dx, dy):
    """A four-bar's joint B as a group of one point is the circle-circle node's root.

    Random crank-rockers (Grashof, the crank shortest, at least 0.1 of the
    crank from the Grashof boundary), over two turns, the sketch off the true
    position by up to 0.3 of the crank.
    """
    p, q = crank + 1 + u * (9 - crank), crank + 1 + w * (9 - crank)
    longest = max(p, q) + frac * (p + q - 1.1 * crank - max(p, q))
    ground, coupler, rocker = (p, q, longest)[order[0]], (p, q, longest)[order[1]], \
        (p, q, longest)[order[2]]

    def build(group):
        c = geokin.Construction()
        c.input("theta")
        c.fixed("O2", 0, 0)
        c.fixed("O4", ground, 0)
        c.polar("A", "O2", crank, "theta")
        if group:
            at = geokin.sweep(build(False), [0.0])["B"][0]
            c.closure("dyad", ["B"], [("A", "B", coupler), ("B", "O4", rocker)],
                      near={"B": (at[0] + dx * crank, at[1] + dy * crank)})
        else:
            c.circle_circle("B", ("A", "O4"), (coupler, rocker), branch="left")
        return c

    theta = np.linspace(0, 4 * np.pi, 721)
    by_circles = geokin.sweep(build(False), theta)
    by_newton = geokin.sweep(build(True), theta)
    assert by_circles.valid.all() and by_newton.valid.all()
    assert np.max(np.abs(by_newton["B"] - by_circles["B"])) < 1e-10


POINT = st.tuples(st.floats(-5, 5), st.floats(-5, 5))


@given(POINT, POINT, POINT, POINT, POINT, st.floats(0.2, 1.5))
def test_random_triad_reproduces_its_assembly(d, e, a, b, c, crank):
    """A Stephenson-like triad built from a random assembly solves to that assembly.

    Every length comes from the assembly at theta = 0, as the shipped
    scripts take theirs: the sketch sample gives back the assembly, and
    every sample solved on the way keeps every length.
    """
    pts = {"G": (0.0, 0.0), "F": (crank, 0.0), "D": d, "E": e, "A": a, "B": b, "C": c}
    lengths = {pair: float(np.hypot(*np.subtract(pts[pair[0]], pts[pair[1]])))
               for pair in PAIRS}
    assume(min(lengths.values()) > 0.3)
    system = geokin.closure.System(4, tuple(PAIRS))
    known = {"F": (np.full(1, crank), np.zeros(1)), "C": (np.full(1, c[0]), np.full(1, c[1]))}
    exact = np.array([[*d, *e, *a, *b]])
    table = np.array([[lengths[pair] for pair in PAIRS]])
    _, ok, margin = geokin.closure.newton(system, UNKNOWN, known, table, exact)
    assume(ok[0] and margin[0] > 1e-4)
    con = geokin.Construction()
    con.input("theta")
    con.fixed("G", 0, 0)
    con.fixed("C", *c)
    con.polar("F", "G", crank, "theta")
    con.closure("triad", UNKNOWN, [(p, q, lengths[(p, q)]) for p, q in PAIRS],
                near={p: pts[p] for p in UNKNOWN})
    s = geokin.sweep(con, np.linspace(0, 0.5, 11))
    assert s.valid[0]
    for p in UNKNOWN:
        assert np.max(np.abs(s[p][0] - pts[p])) < 1e-9, p
    for (p, q), length in lengths.items():
        got = np.hypot(*(s[p][s.valid] - s[q][s.valid]).T)
        assert np.max(np.abs(got - length)) < 1e-9 * max(length, 1.0)


def test_analyze_reaches_a_triads_folds_and_finds_its_path_closed():
    """The rocking Stephenson III: its crank swings exactly between the limits, every sample
    of the circuit is assembled, and E comes back where it began."""
    text = (ROOT / "constructions" / "stephenson3.toml").read_text().replace(
        "\nGF = 1\n", "\nGF = 2\n")
    c = geokin.loads(text)
    (low, high), = geokin.limits(c).as_values()
    report = geokin.analyze(c)
    assert report.warnings == ()
    crank = report.strokes["crank.angle"]
    assert (crank.minimum, crank.maximum) == pytest.approx((low, high), abs=1e-9)
    assert report.curves["E"].closed


def test_a_group_is_followed_back_from_where_its_sketch_first_fits():
    """With AB = 2 the Stephenson III's sketch fits no assembly before theta = 78 deg:
    Newton from it converges first there. The triad is followed from there to the end of
    the turn and back to its start, on one assembly: every sample keeps every length, and
    no step jumps."""
    text = (ROOT / "constructions" / "stephenson3.toml").read_text().replace(
        '\nAB = "hypot(0.4, -2.8)"\n', "\nAB = 2\n")
    c = geokin.loads(text)
    s = geokin.sweep(c)
    assert s.valid.all()
    lengths = c.compile().parameters
    for a, b, name in (("F", "D", "FD"), ("F", "E", "FE"), ("D", "E", "DE"), ("C", "A", "CA"),
                       ("C", "B", "CB"), ("A", "B", "AB"), ("D", "A", "DA"), ("E", "B", "EB")):
        np.testing.assert_allclose(np.hypot(*(s[a] - s[b]).T), lengths[name], atol=1e-9)
    for p in ("D", "E", "A", "B"):
        steps = np.hypot(*np.diff(s[p], axis=0).T)
        assert steps.max() < 5 * np.median(steps) + 1e-9, p
    # no limit where the sketch first fits: the crank turns fully
    assert geokin.limits(c).full_turn
    # after a variant it is followed on its own samples as alone, before them too: each
    # path resumes where Newton from the last solution converges, and is followed back
    # from there
    compiled = c.compile()
    theta = np.linspace(0, 2 * np.pi, 73)
    nominal = geokin.load(ROOT / "constructions" / "stephenson3.toml").compile()
    both = evaluate(compiled, {"theta": theta}, 146, paths=2,
                    parameters={"AB": np.array([nominal.parameters["AB"], 2.0])})
    assert both.valid.all()
    np.testing.assert_allclose(both["D"][73:], geokin.sweep(c, theta)["D"], atol=1e-9)


STEPHENSON_PAIRS = (("F", "D", "FD"), ("F", "E", "FE"), ("D", "E", "DE"), ("C", "A", "CA"),
                    ("C", "B", "CB"), ("A", "B", "AB"), ("D", "A", "DA"), ("E", "B", "EB"))


def _triad_jacobian(s, i, lengths):
    """The Jacobian of the triad's eight distance equations in D, E, A, B at sample i,
    by central differences: its smallest singular value is zero at a fold."""
    names = "DEAB"
    z = np.concatenate([np.asarray(s[p])[i] for p in names])
    fixed = {p: np.asarray(s[p])[i] for p in "FC"}

    def residual(z):
        at = {**fixed, **{p: z[2 * k:2 * k + 2] for k, p in enumerate(names)}}
        return np.array([np.hypot(*(at[a] - at[b])) - lengths[n] for a, b, n in STEPHENSON_PAIRS])

    h = 1e-6
    return np.column_stack([(residual(z + h * e) - residual(z - h * e)) / (2 * h)
                            for e in np.eye(8)])


def test_a_group_at_its_fold_stops_rather_than_jump_to_another_assembly():
    """A Stephenson III whose triad folds at theta = 0.9292: past the fold its assembly
    is gone, though others go on. The sweep keeps every length, never moves a point far
    between samples, and stops at the fold, where the triad's Jacobian is singular."""
    lengths = {"GF": 1.1247, "FD": 2.5826, "FE": 2.5029, "DE": 2.5582, "CA": 2.2633,
               "CB": 1.8292, "AB": 2.4434, "DA": 2.7345, "EB": 2.8767}
    c = geokin.load(ROOT / "constructions" / "stephenson3.toml").compile().with_parameters(
        lengths)
    theta = np.linspace(0, 2 * np.pi, 3601)
    s = geokin.sweep(c, theta)
    ok = s.valid
    for a, b, name in STEPHENSON_PAIRS:
        np.testing.assert_allclose(np.hypot(*(s[a] - s[b]).T)[ok], lengths[name], atol=1e-9)
    moves = np.max([np.hypot(*np.diff(s[p], axis=0).T) for p in "DEAB"], axis=0)
    assert np.nanmax(moves) < 20 * np.nanmedian(moves)
    last = int(np.argmin(ok)) - 1  # the last sample before the first gap
    assert 0.92 < theta[last] < 0.93 and not ok[last + 1]
    singular = np.linalg.svd(_triad_jacobian(s, last, lengths), compute_uv=False)
    inside = np.linalg.svd(_triad_jacobian(s, 0, lengths), compute_uv=False)
    assert singular[-1] < 0.05 * inside[-1]


def test_a_group_over_coarse_steps_follows_its_assembly_as_the_crank_turns():
    """A double crank's coupler joint as a one-point group, swept a quarter turn a step:
    Newton from one sample converges on the mirror assembly at the next, and the chord
    between two crank pins passes where the links cannot reach. Followed with the crank
    turning between the samples, the group keeps its assembly, the circle intersection
    to the right of A->O4, at every sample."""
    def right_of(theta):  # B by hand: the circles about A (4.5) and O4 (6.5)
        a = 5.3125 * np.c_[np.cos(theta), np.sin(theta)]
        u = np.array([2.75, 0.0]) - a
        d = np.hypot(*u.T)[:, None]
        m = (d * d + 4.5**2 - 6.5**2) / (2 * d)
        h = np.sqrt(4.5**2 - m * m)
        return a + m * u / d + h * np.c_[u[:, 1], -u[:, 0]] / d

    for theta in (np.radians([0, 90, 180, 270, 360]), np.radians(np.arange(361.0))):
        s = geokin.sweep(fourbar(True, (2.75, 5.3125, 4.5, 6.5), near=(8.3, 3.3)), theta)
        assert s.valid.all()
        np.testing.assert_allclose(s["B"], right_of(theta), atol=1e-9)


def test_a_turn_searched_for_a_group_joins_its_ends_only_on_one_assembly():
    """With GF = 3 the Stephenson III's assembly at theta = 0 folds at +-1.8484. A
    sweep of the turn stops at +1.8484 and takes the assembly up again at 2 pi, where
    the inputs are those of 0: followed back from there, it is the assembly at 0
    followed down, sample for sample. Its limits are the two folds, one interval
    across 0, and its circuit comes back to where it began."""
    c = geokin.load(ROOT / "constructions" / "stephenson3.toml").compile().with_parameters(
        {"GF": 3.0})
    theta = np.linspace(0, 2 * np.pi, 721)
    s = geokin.sweep(c, theta)
    down = geokin.sweep(c, theta[::-1] - 2 * np.pi)  # from 0 down to -2 pi
    assert down.valid[::-1][-1] and s.valid[-1]
    stretch = s.valid & down.valid[::-1] & (theta > np.pi)
    assert stretch.sum() > 100
    for p in "DEAB":
        np.testing.assert_allclose(s[p][stretch], down[p][::-1][stretch], atol=1e-9)
    # the samples the sweep leaves unsolved are those neither way reaches
    np.testing.assert_array_equal(s.valid, (theta <= 1.8484) | (theta >= 2 * np.pi - 1.8484))
    [(low, high)] = geokin.limits(c).intervals
    assert (low.kind, high.kind) == ("tangent", "tangent")
    assert (low.value, high.value) == pytest.approx((-1.8484, 1.8484), abs=1e-4)
    s = geokin.circuit(c)
    assert s.valid.all()
    for p in "DEAB":
        np.testing.assert_allclose(s[p][-1], s[p][0], atol=1e-9)


def test_a_group_that_fails_one_sample_resumes_where_the_inputs_come_back():
    """With GF = 3 the triad folds at theta = 1.8484: the sample at 1.9 is past it.
    Swept 0, 1, 1.9, 1, 0, the group takes its assembly up again at 1 and 0, in
    the poses it had there on the way out."""
    c = geokin.load(ROOT / "constructions" / "stephenson3.toml").compile().with_parameters(
        {"GF": 3.0})
    s = geokin.sweep(c, [0.0, 1.0, 1.9, 1.0, 0.0])
    assert s.valid.tolist() == [True, True, False, True, True]
    assert s.failure_reason[2] == "the group reaches a singular position"
    for p in "DEAB":
        np.testing.assert_allclose(s[p][[3, 4]], s[p][[1, 0]], atol=1e-9)
    # a sample that Newton from the last solution misses, past the gap, is reached as
    # it is without the gap: moving the input from the last solved sample to it
    past = geokin.sweep(c, [0.3, 1.8, 1.9, 0.5])
    direct = geokin.sweep(c, [0.3, 1.8, 0.5])
    assert past.valid.tolist() == [True, True, False, True]
    for p in "DEAB":
        np.testing.assert_allclose(past[p][3], direct[p][2], atol=1e-9)


def test_a_coarse_step_of_a_triad_keeps_its_assembly():
    """One step of 26 deg with these lengths: Newton from the sample before lands on
    another assembly that also converges back. The group follows its own, as plain
    Newton over a thousand small steps of the same segment does."""
    lengths = {"GF": 1.408037, "FD": 1.128157, "FE": 2.450986, "DE": 1.324715,
               "CA": 1.688778, "CB": 4.968211, "AB": 3.289719, "DA": 2.827821, "EB": 3.68248}
    c = geokin.load(ROOT / "constructions" / "stephenson3.toml").compile().with_parameters(
        lengths)
    ends = np.array([0.44516, 0.90389])
    s = geokin.sweep(c, ends)
    assert s.valid.all()
    start = {p: tuple(s[p][0]) for p in UNKNOWN}
    theta = np.linspace(*ends, 1001)
    ref = newton_reference(
        theta, lambda t: {"C": np.array([4.7, 0.0]),
                          "F": lengths["GF"] * np.array([np.cos(t), np.sin(t)])},
        UNKNOWN, PAIRS, [lengths[a + b] for a, b in PAIRS], start)
    np.testing.assert_allclose(np.concatenate([s[p][1] for p in UNKNOWN]), ref[-1],
                               atol=1e-9)


@pytest.mark.parametrize("samples", [37, 360, 361, 7201])
def test_a_group_passes_a_change_point_as_a_circle_intersection_does(samples):
    """A parallelogram's coupler joint as a one-point group: at theta = pi the two
    circles touch and the parallelogram and its crossed form meet. Like the circle
    intersection node, which changes branch there, the group goes on along the
    parallelogram, B = A + (4, 0), at every sample."""
    theta = np.linspace(0.3, 0.3 + 2 * np.pi, samples)
    s = geokin.sweep(fourbar(True, (4.0, 2.0, 4.0, 2.0), near=(5.5, 1.9)), theta)
    assert s.valid.all()
    np.testing.assert_allclose(s["B"], s["A"] + [4.0, 0.0], atol=1e-9)


@pytest.mark.parametrize("start", [0.0, np.pi / 2])
@pytest.mark.parametrize("samples", [13, 361, 7201])
def test_a_group_steps_on_from_a_sample_on_a_change_point(start, samples):
    """Samples exactly on the parallelogram's change points (theta = 0 and pi, where
    it meets its crossed form), from 0 the first sample: the group goes on along the
    parallelogram at every sample, as its tangent there carries it."""
    theta = np.linspace(start, start + 2 * np.pi, samples)
    s = geokin.sweep(fourbar(True, (4.0, 2.0, 4.0, 2.0), near=(5.5, 1.9)), theta)
    assert s.valid.all()
    np.testing.assert_allclose(s["B"], s["A"] + [4.0, 0.0], atol=1e-6)
    regular = np.abs(np.sin(theta)) > 1e-3  # at a change point only to its rounding
    np.testing.assert_allclose(s["B"][regular], s["A"][regular] + [4.0, 0.0], atol=1e-11)


def _change_point_roots(theta):
    """The circles' two intersections (left, right of A to O4) of the crank-rocker with
    ground 100, crank 60, coupler 90, rocker 70, in closed form."""
    a = 60.0 * np.stack([np.cos(theta), np.sin(theta)], axis=1)
    ao = np.array([100.0, 0.0]) - a
    d = np.linalg.norm(ao, axis=1)[:, None]
    along = (90.0 ** 2 - 70.0 ** 2 + d ** 2) / (2 * d)
    across = np.sqrt(np.maximum(90.0 ** 2 - along ** 2, 0.0))
    e = ao / d
    normal = np.stack([-e[:, 1], e[:, 0]], axis=1)
    return a + along * e + across * normal, a + along * e - across * normal


def _change_point_fourbar(lengths=(100, 60, 90, 70), near=(30.9078, 11.237), group=True,
                          input_range=None):
    """A four-bar (ground, crank, coupler, rocker) on a change point, its joint B by a
    one-point group (sketched near ``near``) or by circles (B left of A to O4)."""
    ground, crank, coupler, rocker = lengths
    c = geokin.Construction("change point")
    c.input("theta", range=input_range)
    c.fixed("O2", 0, 0)
    c.fixed("O4", ground, 0)
    c.polar("A", "O2", crank, "theta")
    if group:
        c.closure("dyad", ["B"], [("A", "B", coupler), ("O4", "B", rocker)], near={"B": near})
    else:
        c.circle_circle("B", ("A", "O4"), (coupler, rocker), branch="left")
    return c


@pytest.mark.parametrize("start", [0.0, -np.pi])
@pytest.mark.parametrize("samples", [13, 361, 7201])
def test_a_change_point_crank_rocker_group_keeps_its_smooth_assembly(start, samples):
    """Ground 100, crank 60, coupler 90, rocker 70 (60 + 100 = 90 + 70): at theta = pi
    the circles touch, and the open assembly (B left of A to O4) goes on smoothly as
    the crossed one (right of it). A sample lands on pi; from [-pi, pi] the first does.
    Every sample is on that smooth assembly, in closed form."""
    theta = np.linspace(start, start + 2 * np.pi, samples)
    c = _change_point_fourbar(near=(88, 69), input_range=(start, start + 2 * np.pi))
    s = geokin.sweep(c, theta)
    assert s.valid.all()
    left, right = _change_point_roots(theta)
    past = theta > np.pi + 1e-9  # beyond the change point on the way out
    if start < 0:
        past = np.zeros_like(past)  # from just past it, on the sketch's side to the end
    expected = np.where(past[:, None], right, left)
    on = np.abs(np.abs(theta) - np.pi) < 1e-9
    assert on.sum() == (1 if start == 0 else 2)
    np.testing.assert_allclose(s["B"][~on], expected[~on], atol=1e-9)
    np.testing.assert_allclose(s["B"][on], [[30.0, 0.0]] * int(on.sum()), atol=1e-4)
    # nothing stops the crank: one interval, ended only by the searched turn (past
    # which, from 0, the group is on its crossed assembly)
    found = geokin.limits(c)
    assert len(found.intervals) == 1
    assert [end.node for end in found.intervals[0]] == [None, None]


@pytest.mark.parametrize("degrees", [
    [170, 180, 170], [170, 179.998, 170], [170, 180.01, 170], [170, 180.05, 170],
    [175, 180, 180, 185], [175, 180, 180, 175], [0, 180, 360, 180, 0],
    [179, 179.5, 180, 180.5, 180, 179.5, 179]])
def test_a_group_turning_back_at_a_change_point_stays_on_its_smooth_assembly(degrees):
    """The change-point crank-rocker's open assembly goes on as the crossed one at
    theta = pi: one smooth curve, B left of A to O4 below pi and right of it above.
    However the crank turns back on it, at the change point, next to it or past it, or
    stands on it for two samples, every sample is on that curve, in closed form."""
    theta = np.radians(degrees)
    s = geokin.sweep(_change_point_fourbar(), theta)
    assert s.valid.all()
    left, right = _change_point_roots(theta)
    expected = np.where((theta > np.pi)[:, None], right, left)  # up to 3 pi, its next
    on = np.abs(theta - np.pi) < 1e-9
    np.testing.assert_allclose(s["B"][~on], expected[~on], atol=1e-9)
    np.testing.assert_allclose(s["B"][on], expected[on], atol=1e-4)


def test_a_change_point_groups_circuit_makes_two_turns_on_its_smooth_assembly():
    """Nothing stops the change-point crank-rocker's crank, but its group comes round
    from one turn on its crossed assembly: the crank turns fully, and the circuit
    makes two turns, on the smooth curve (left of A to O4 below pi and above 3 pi,
    right between), back to where it began."""
    c = _change_point_fourbar()
    assert geokin.limits(c).full_turn
    s = geokin.circuit(c)
    assert s.valid.all()
    theta = s.input_values
    assert theta[-1] - theta[0] == pytest.approx(4 * np.pi)
    left, right = _change_point_roots(theta)
    crossed = (theta > np.pi) & (theta < 3 * np.pi)
    expected = np.where(crossed[:, None], right, left)
    on = np.min(np.abs(theta[:, None] - [np.pi, 3 * np.pi]), axis=1) < 1e-9
    np.testing.assert_allclose(s["B"][~on], expected[~on], atol=1e-9)
    np.testing.assert_allclose(s["B"][-1], s["B"][0], atol=1e-9)


def test_a_first_sample_near_singular_but_off_a_crossing_keeps_the_sketchs_assembly():
    """A triad whose sketch is an assembly at theta = 0, nearly singular (margin 6.7e-7)
    but 0.47 from any other: however far the sweep gets from it, its first sample is
    the sketch's assembly, not another one reached by starting later and following back."""
    pts = {"D": (1.6386, 2.5683), "E": (-1.1249, -1.6079), "A": (-0.9048, -4.501),
           "B": (-4.3289, 3.7184), "C": (2.1448, 3.715), "F": (0.8121, 0.0)}
    pairs = [("F", "D"), ("F", "E"), ("D", "E"), ("C", "A"), ("C", "B"), ("A", "B"),
             ("D", "A"), ("E", "B")]
    c = geokin.Construction("triad")
    c.input("theta")
    c.fixed("G", 0, 0)
    c.fixed("C", *pts["C"])
    c.polar("F", "G", pts["F"][0], "theta")
    c.closure("triad", list("DEAB"),
              [(p, q, float(np.hypot(*np.subtract(pts[p], pts[q])))) for p, q in pairs],
              near={p: pts[p] for p in "DEAB"})
    for samples in (13, 181):
        s = geokin.sweep(c, np.linspace(0, 2 * np.pi, samples))
        assert s.valid[0]
        for p in "DEAB":
            np.testing.assert_allclose(s[p][0], pts[p], atol=1e-9)


def _parallelogram(group: bool):
    c = _change_point_fourbar((100, 60, 100, 60), near=(160, 0.5), group=group,
                              input_range=(0, 2 * np.pi))  # from a change point
    c.link("crank", "O2", "A")
    c.link("coupler", "A", "B")
    c.link("rocker", "O4", "B")
    return c


def test_a_parallelogram_group_from_a_change_point_is_reported_as_its_circles_are():
    """Started on a change point, where the group is found to about the square root of
    its tolerance: the report is the circle intersection node's, a coupler that does
    not turn and a rocker that turns fully, with no warning, not a stroke of rounding."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        by_group = geokin.analyze(_parallelogram(True))
    by_circles = geokin.analyze(_parallelogram(False))
    assert sorted(by_group.strokes) == sorted(by_circles.strokes) == [
        "crank.angle", "rocker.angle"]
    assert by_group.strokes["rocker.angle"].turns
    assert by_group.warnings == by_circles.warnings == ()


@pytest.mark.parametrize(("samples", "start", "near"), [
    (7201, 10.0, (0.0, 0.0)), (37, 10.0, (0.0, 0.0)), (361, 0.0, (0.5, 0.5)),
    (13, -180.0, (0.001, 0.0)), (13, -180.0, (0.0, -0.001))])
def test_a_kites_folded_assembly_is_followed_over_its_change_points(samples, start, near):
    """A kite (ground 100, crank 40, coupler 40, rocker 100) folds onto itself: B = O2
    at every angle, where the solution does not move at all, crossing the unfolded
    assembly at theta = 0 and pi. Samples land on both."""
    c = geokin.Construction("kite")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 100, 0)
    c.polar("A", "O2", 40, "theta")
    c.closure("dyad", ["B"], [("A", "B", 40), ("O4", "B", 100)], near={"B": near})
    theta = np.radians(np.linspace(start, start + 360, samples))
    s = geokin.sweep(c, theta)
    assert s.valid.all()
    np.testing.assert_allclose(s["B"], 0.0, atol=1e-4)
    regular = np.abs(np.sin(theta)) > 1e-6
    np.testing.assert_allclose(s["B"][regular], 0.0, atol=1e-9)


def _curve_of_triad(lengths, z0, step=5e-3):
    """Trace the triad's solution curve in (D, E, A, B, theta) by arclength continuation
    from z0 at theta = 0, round to where it began: each step moves ``step`` along the
    curve's tangent (the Jacobian's null vector) and Newton brings it back with the
    arclength equation added. Returns the curve and the thetas where it turns back."""
    pairs = [(a, b, lengths[n]) for a, b, n in STEPHENSON_PAIRS]
    names = "DEAB"

    def residual_jacobian(x):
        at = {p: x[2 * i:2 * i + 2] for i, p in enumerate(names)}
        at["C"] = np.array([4.7, 0.0])
        at["F"] = lengths["GF"] * np.array([np.cos(x[8]), np.sin(x[8])])
        dfdt = lengths["GF"] * np.array([-np.sin(x[8]), np.cos(x[8])])
        f, jac = np.empty(8), np.zeros((8, 9))
        for e, (a, b, d) in enumerate(pairs):
            diff = at[a] - at[b]
            f[e] = diff @ diff - d * d
            for p, sign in ((a, 2), (b, -2)):
                if p in names:
                    jac[e, 2 * names.index(p):2 * names.index(p) + 2] += sign * diff
                elif p == "F":
                    jac[e, 8] += sign * diff @ dfdt
        return f, jac

    x = np.append(z0, 0.0)
    tangent = np.linalg.svd(residual_jacobian(x)[1])[2][-1]
    tangent *= np.sign(tangent[8])
    curve, turns = [x], []
    for _ in range(100_000):
        guess = x + step * tangent
        for _ in range(30):
            f, jac = residual_jacobian(guess)
            move = np.linalg.solve(np.vstack([jac, tangent]),
                                   -np.append(f, tangent @ (guess - x) - step))
            guess = guess + move
            if np.max(np.abs(move)) < 1e-13:
                break
        turned = np.linalg.svd(residual_jacobian(guess)[1])[2][-1]
        turned *= np.sign(turned @ tangent)
        if turned[8] * tangent[8] < 0:
            turns.append(guess[8])
        x, tangent = guess, turned
        curve.append(x)
        if len(curve) > 100 and np.max(np.abs(x - curve[0])) < 2 * step:
            break
    return np.array(curve), np.array(turns)


def test_a_triads_circuit_passes_each_fold_onto_the_assembly_beyond_it():
    """A Stephenson III whose triad's solution curve turns back six times, at
    +-43.257, +-41.752 and +-45.787 deg, as a continuation along the curve's
    arclength (written here) finds. The circuit turns back at those six folds in
    that order, passing each onto the assembly beyond, every sample lies on the
    curve, and it ends where it began."""
    lengths = {"GF": 1.484993, "FD": 2.425755, "FE": 4.922921, "DE": 2.701186,
               "CA": 0.317111, "CB": 2.231417, "AB": 2.067206, "DA": 1.641597,
               "EB": 2.968174}
    c = geokin.load(ROOT / "constructions" / "stephenson3.toml").compile().with_parameters(
        lengths)
    s = geokin.circuit(c)
    assert s.valid.all()
    z = np.column_stack([s[p] for p in "DEAB"])
    curve, turns = _curve_of_triad(lengths, z[0])
    theta = s.input_values
    moves = np.diff(theta)
    reversals = theta[np.flatnonzero(moves[:-1] * moves[1:] < 0) + 1]
    np.testing.assert_allclose(reversals, turns, atol=1e-4)
    assert len(s.events) == 6
    # each sample within a step of the traced curve
    points = np.column_stack([z, theta])
    nearest = [np.min(np.max(np.abs(curve - p), axis=1)) for p in points]
    assert max(nearest) < 5e-3
    np.testing.assert_allclose(z[-1], z[0], atol=1e-9)


def test_a_triads_circuit_over_more_than_two_assemblies_closes_in_its_first_pose():
    """A triad whose curve turns back six times over three assemblies: back at its
    start after two folds the group is on another assembly, and the circuit goes on
    until it is back in the pose it began in, turning back at each fold of the
    curve (+-1.2539, -0.946, -1.164, 1.164, 0.946 rad)."""
    lengths = {"GF": 1.671676, "FD": 2.059705, "FE": 1.683527, "DE": 2.613831,
               "CA": 0.235229, "CB": 4.991438, "AB": 5.09953, "DA": 2.359134, "EB": 1.6419}
    c = geokin.load(ROOT / "constructions" / "stephenson3.toml").compile().with_parameters(
        lengths)
    s = geokin.circuit(c)
    assert s.valid.all()
    z = np.column_stack([s[p] for p in "DEAB"])
    theta = s.input_values
    moves = np.diff(theta)
    reversals = theta[np.flatnonzero(moves[:-1] * moves[1:] < 0) + 1]
    np.testing.assert_allclose(reversals, [1.2539, -1.2539, -0.946, -1.164, 1.164, 0.946],
                               atol=1e-3)
    assert len(s.events) == 6
    np.testing.assert_allclose(z[-1], z[0], atol=1e-9)


def test_a_limit_a_rounding_past_a_groups_fold_is_its_fold():
    """Bisected to 1e-12 of this triad's fold at 0.7643, Newton just past it converges
    to within the residual's tolerance, all but singular: the limit is the group's
    fold, tangent at D, not an end that nothing stops. The circuit passes it onto the
    other assembly and closes after the curve's two folds."""
    lengths = {"GF": 0.833677, "FD": 2.37916, "FE": 2.584562, "DE": 0.296069,
               "CA": 2.768576, "CB": 4.836015, "AB": 2.083637, "DA": 2.957144,
               "EB": 4.763147}
    c = geokin.load(ROOT / "constructions" / "stephenson3.toml").compile().with_parameters(
        lengths)
    [(low, high)] = geokin.limits(c).intervals
    assert (low.kind, low.node, high.kind, high.node) == ("tangent", "D", "tangent", "D")
    s = geokin.circuit(c)
    theta = s.input_values
    moves = np.diff(theta)
    reversals = theta[np.flatnonzero(moves[:-1] * moves[1:] < 0) + 1]
    np.testing.assert_allclose(reversals, [0.7643, -0.7643], atol=1e-4)
    assert len(s.events) == 2 and s.valid.all()
    z = np.column_stack([s[p] for p in "DEAB"])
    np.testing.assert_allclose(z[-1], z[0], atol=1e-9)
