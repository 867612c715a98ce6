import inspect
import time
import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from mechanisms import sixbar

import geokin
from geokin import Construction, ConstructionError, GeokinError, sweep
from geokin.expressions import as_expr, parse
from geokin.io import loads
from geokin.loops import fourbar_closed_form
from geokin.nodes import NODE_KINDS

SEED_004 = (24.0, 10.55, 25.0, 14.0)  # ground, input, coupler, output: a crank-rocker


def base():
    c = Construction("test")
    c.parameter("l3", 100)
    c.input("theta")
    c.fixed("A0", 0, 0)
    c.fixed("B0", 40, 0)
    c.polar("A", "A0", 10, "theta")
    return c


def check(error_info, node, field, kind="node"):
    err = error_info.value
    assert isinstance(err, GeokinError)
    assert err.node == node and err.field == field and err.kind == kind
    assert str(err).startswith(f"{kind} {node!r}")
    if field is not None:
        assert f"field {field!r}" in str(err)


def test_unknown_point_names_the_node_field_and_closest_name():
    c = base()
    c.circle_circle("B", ("A", "B00"), ("l3", 30), branch="left")
    with pytest.raises(ConstructionError, match="unknown point 'B00'; did you mean 'B0'") as info:
        c.compile()
    check(info, "B", "centers[1]")


def test_unknown_value_name_suggests_the_closest_parameter():
    c = base()
    c.circle_circle("B", ("A", "B0"), ("l33", 30), branch="left")
    with pytest.raises(ConstructionError, match="unknown parameter or input 'l33'; "
                                                "did you mean 'l3'") as info:
        c.compile()
    check(info, "B", "radii[0]")


def test_a_point_used_as_a_value_is_explained():
    c = base()
    c.polar("P", "A", "A0", 0)
    with pytest.raises(ConstructionError, match="'A0' is a point, not a parameter") as info:
        c.compile()
    check(info, "P", "distance")


def test_a_parameter_used_as_a_point_is_explained():
    c = base()
    c.polar("P", "l3", 5, 0)
    with pytest.raises(ConstructionError, match="'l3' is a parameter, not a point") as info:
        c.compile()
    check(info, "P", "origin")


def test_cycles_name_their_points():
    c = base()
    c.circle_circle("P", ("A", "Q"), (1, 1), branch="left")
    c.circle_circle("Q", ("P", "B0"), (1, 1), branch="left")
    with pytest.raises(ConstructionError, match=r"cycle: P -> Q -> P") as info:
        c.compile()
    check(info, "P", "centers")


def test_a_point_built_on_itself_is_a_cycle():
    c = base()
    c.polar("P", "P", 1, 0)
    with pytest.raises(ConstructionError, match="built on itself") as info:
        c.compile()
    check(info, "P", "origin")


@pytest.mark.parametrize("declare", [
    lambda c: c.fixed("A", 1, 1),
    lambda c: c.parameter("A0", 1),
    lambda c: c.input("l3"),
    lambda c: c.link("theta", "A0", "A"),
])
def test_duplicate_names_are_refused(declare):
    with pytest.raises(ConstructionError, match="duplicate name") as info:
        declare(base())
    assert info.value.field == "name"


@pytest.mark.parametrize(("declare", "node", "field", "match"), [
    (lambda c: c.circle_circle("B", ("A",), (1, 2), branch="left"), "B", "centers",
     "expected 2 point names, got 1"),
    (lambda c: c.circle_circle("B", ("A", "B0"), (1, 2, 3), branch="left"), "B", "radii",
     "expected 2 values, got 3"),
    (lambda c: c.line_circle("B", ("A", "B0", "A0"), "A", 1, branch="first"), "B", "line",
     "expected 2 point names, got 3"),
    (lambda c: c.line_line("B", ("A", "B0"), "A0"), "B", "second",
     "expected a list of point names"),
    (lambda c: c.link("bar", "A"), "bar", "points", "at least 2 points"),
    (lambda c: c.polar("P", 3, 1, 0), "P", "origin", "expected a point name"),
    (lambda c: c.polar("P", "A", [1], 0), "P", "distance", "expected a number or an expression"),
    (lambda c: c.polar("P", "A", "1 +", 0), "P", "distance", "not a valid expression"),
    (lambda c: c.polar("P", "A", "os.system('x')", 0), "P", "distance", "plain function names"),
    (lambda c: c.polar("P", "A", "l3.real", 0), "P", "distance", "Attribute is not allowed"),
    (lambda c: c.circle_circle("B", ("A", "B0"), (1, 2)), "B", "branch",
     "choose one with branch"),
    (lambda c: c.circle_circle("B", ("A", "B0"), (1, 2), branch="lefft"), "B", "branch",
     "did you mean 'left'"),
    (lambda c: c.ray_circle("B", ("A", "B0"), "A", 1, branch="left"), "B", "branch",
     "'first' or 'second'"),
    (lambda c: c.circle_circle("B", ("A", "B0"), (1, 2), branch="left", near=(0, 0)), "B",
     "branch", "either branch or near"),
    (lambda c: c.circle_circle("B", ("A", "B0"), (1, 2), near=(0,)), "B", "near",
     "expected two numbers"),
    (lambda c: c.input("s", kind="length"), "s", "range", "needs a range"),
    (lambda c: c.input("s", kind="lenght", range=(0, 1)), "s", "kind", "did you mean 'length'"),
    (lambda c: c.input("s", samples=1), "s", "samples", "at least 2"),
    (lambda c: c.input("s", step=-1.0), "s", "step", "towards range"),
    (lambda c: c.parameter("k", "sqrt(-1)"), "k", "value", r"finite number; 'sqrt\(-1\)' is nan"),
    (lambda c: c.parameter("k", "1 / 0"), "k", "value", "finite number"),
    (lambda c: c.parameter("k", "l3 + 1"), "k", "value", "must be a number"),
    (lambda c: c.fixed("2P", 0, 0), "2P", "name", "identifier"),
    (lambda c: c.fixed("pi", 0, 0), "pi", "name", "reserved"),
])
def test_declaration_errors_name_node_and_field(declare, node, field, match):
    # a point is a node of the construction; the link, input and parameters above are
    # called what they are
    kind = {"bar": "link", "s": "input", "k": "parameter"}.get(node, "node")
    with pytest.raises(ConstructionError, match=match) as info:
        declare(base())
    check(info, node, field, kind)


def test_links_sliders_and_traces_must_name_points():
    for declare, kind, node, field in [
        (lambda c: c.link("bar", "A0", "Aa"), "link", "bar", "points[1]"),
        (lambda c: c.slider("block", "A", ("A0", "Bo")), "slider", "block", "along[1]"),
        (lambda c: c.trace("AA"), "node", "trace", "points[0]"),
    ]:
        c = base()
        declare(c)
        with pytest.raises(ConstructionError, match="unknown point") as info:
            c.compile()
        check(info, node, field, kind)


def test_compile_orders_by_dependency_then_declaration():
    c = Construction()
    c.input("t")
    c.polar("A", "O", 1, "t")  # declared before its origin
    c.fixed("Z", 5, 0)
    c.fixed("O", 0, 0)
    c.circle_circle("B", ("A", "Z"), (5, 5), branch="right")
    assert c.compile().point_names == ("Z", "O", "A", "B")
    assert c.compile().as_list()[-1] == ("B", "circle_circle", "A", "Z", "right")


def test_compile_is_cached_until_the_construction_changes():
    c = base()
    first = c.compile()
    assert c.compile() is first
    c.fixed("Q", 1, 1)
    assert c.compile() is not first and "Q" in c.compile().point_names


def test_every_node_kind_describes_itself():
    c = base()
    c.along("P1", ("A0", "A"), 3)
    c.line_line("P2", ("A0", "A"), ("B0", "P1"))
    c.line_circle("P3", ("A0", "B0"), "A", 20, branch="first")
    c.segment_circle("P4", ("A0", "B0"), "A", 20, branch="second")
    c.ray_circle("P5", ("A0", "B0"), "A", 20, near=(1, 2))
    c.circle_circle("P6", ("A", "B0"), (30, 30), branch="right")
    c.polar("P7", "A", 2, 0.5, reference=("A0", "A"))
    c.local("P8", "A", "B0", (3, "1 + 1"))
    text = str(c.compile())
    kinds = {step.node.kind for step in c.compile()}
    assert kinds == set(NODE_KINDS)
    for fragment in ["along(A0->A, 3)", "line_line(A0-A; B0-P1)", "line_circle(A0-B0; A, 20)",
                     "segment_circle(A0..B0; A, 20)  [second]", "near (1, 2)",
                     "polar(A, 2, 28.64788975654116 deg from A0->A)", "local(A->B0, 3, 1 + 1)"]:
        assert fragment in text


def test_the_step_list_shows_angles_in_degrees_and_the_construction_keeps_radians():
    """Numbers that are angles, or terms of one, read in degrees with the unit; factors,
    names and function arguments as they are; the values and repr stay radians."""
    c = Construction("angles")
    c.input("theta")
    c.fixed("O", 0, 0)
    c.polar("A", "O", 1, np.radians(30))
    c.polar("B", "O", 1, f"theta - {float(np.radians(45))!r}")
    c.polar("C", "O", 1, -np.pi)
    c.polar("D", "O", 1, "2 * theta + radians(10) + 0.25 * pi")
    c.polar("E", "O", 1, f"-({float(np.radians(5))!r} + theta)")
    compiled = c.compile()
    assert str(compiled).splitlines()[2:] == [
        "  2  A = polar(O, 1, 30 deg)",
        "  3  B = polar(O, 1, theta - 45 deg)",
        "  4  C = polar(O, 1, -180 deg)",
        "  5  D = polar(O, 1, 2 * theta + radians(10) + 0.25 * pi)",
        "  6  E = polar(O, 1, -(5 deg + theta))",
    ]
    assert compiled.step_named("A").node.angle.evaluate({}) == np.radians(30)
    assert repr(compiled.step_named("C")) == "<Step 4: C = polar(O, 1, -3.141592653589793)>"
    assert "-3.141592653589793" in compiled.listing(degrees=False)
    s = sweep(c, [0.0])
    np.testing.assert_allclose(s["A"][0], [np.cos(np.pi / 6), 0.5], rtol=1e-15)


def test_a_point_built_only_on_ground_with_values_that_use_no_input_is_ground():
    """A fixed guide's second point, polar from a fixed point, never moves: it is ground."""
    c = Construction()
    c.input("theta")
    c.input("s", kind="length", range=(0, 1))
    c.polar("H", "G", 5, 0.5)  # declared before the point it is built on
    c.fixed("O", 0, 0)
    c.polar("G", "O", 5, 1.0)
    c.local("K", "G", "H", (1, 2))
    c.circle_circle("X", ("G", "H"), (4, 4), branch="left")
    c.fixed("S", "s", 0)  # a fixed kind, but moved by an input
    c.polar("A", "O", 1, "theta")
    c.polar("Y", "G", "s", 0)  # on ground, but its value uses an input
    c.local("Z", "G", "A", (1, 0))  # on a moving point
    c.along("W", ("O", "S"), 1)
    assert c.compile().ground == {"O", "G", "H", "K", "X"}


def test_constructions_compare_by_content():
    assert sixbar() == sixbar()
    other = sixbar()
    other.parameter("extra", 1)
    assert sixbar() != other


def test_expressions_round_trip_through_text_and_evaluate_with_numpy():
    for text in ["a + b * c", "(a + b) * c", "a - (b - c)", "a / (b * c)", "-a ** 2",
                 "(-a) ** 2", "2 ** 3 ** 2", "(2 ** 3) ** 2", "atan2(y, x) + pi",
                 "sqrt(a ** 2 + b ** 2)", "degrees(radians(30))", "a - b - c", "-(a + b)"]:
        expr = parse(text)
        assert parse(str(expr)) == expr, text
        env = dict(a=1.5, b=np.array([2.0, 3.0]), c=0.5, x=1.0, y=2.0)
        assert np.allclose(parse(str(expr)).evaluate(env), eval(text, vars(np), env)), text
    assert (as_expr("l3") + 5) * 2 == parse("(l3 + 5) * 2")


def test_names_are_declared_and_referred_to_as_expressions_read_them():
    """NFKC folds compatibility forms: 'ℓ' and fullwidth 'Ｏ' are 'l' and 'O' everywhere."""
    c = Construction()
    c.parameter("ℓ", 3)
    assert list(c.parameters) == ["l"]
    c.input("θ")
    c.fixed("Ｏ", 0, 0)
    c.polar("A", "O", "ℓ * 2", "θ")
    c.polar("B", "Ｏ", "l", "θ")
    assert c.nodes["B"].origin == "O"
    s = sweep(c, np.array([0.0]))
    np.testing.assert_allclose(s["A"], [[6.0, 0.0]])
    np.testing.assert_allclose(s["B"], [[3.0, 0.0]])
    with pytest.raises(ConstructionError, match="duplicate name \\('ｌ' reads as 'l'\\): a "
                                                "parameter 'l' is already declared") as info:
        c.fixed("ｌ", 1, 1)
    check(info, "l", "name")


@pytest.mark.parametrize(("first", "second", "letters"), [
    ("B0", "В0", "'В' (cyrillic capital letter ve) stands for 'B'"),
    ("В0", "B0", "'B' (latin capital letter b) stands for 'В'"),
    ("poc", "рос", "'р' (cyrillic small letter er) stands for 'p'"),  # all Cyrillic
    ("A1", "Α1", "'Α' (greek capital letter alpha) stands for 'A'"),
    ("Оо", "Οο", "'Ο' (greek capital letter omicron) stands for 'О'"),  # Cyrillic, Greek
])
def test_names_that_differ_only_by_look_alike_letters_are_refused(first, second, letters):
    """Two names that read the same cannot both be declared, in either order."""
    c = Construction()
    c.fixed(first, 0, 0)
    with pytest.raises(ConstructionError, match="looks like the point") as info:
        c.parameter(second, 1)
    assert letters in str(info.value)
    check(info, second, "name", "parameter")
    c.parameter("other", 1)  # a refused name leaves no trace
    assert list(c.nodes) == [first] and list(c.parameters) == ["other"]


def test_a_reference_that_looks_like_a_declared_name_says_so():
    c = Construction()
    c.fixed("B0", 0, 0)
    c.polar("P", "В0", 1, 0)  # Cyrillic Ve
    with pytest.raises(ConstructionError, match="unknown point 'В0'; it looks like 'B0' but "
                                                "is another name") as info:
        c.compile()
    check(info, "P", "origin")


@pytest.mark.parametrize(("name", "match"), [
    ("pаram", "mixes Latin and Cyrillic letters"),
    ("if", "reserved word"),
    ("None", "reserved word"),
    ("lambda", "reserved word"),
    ("sqrt", "reserved for the built-in function"),
    ("a" * 201, "at most 200 characters"),
    ("a b", "identifier"),
])
def test_names_that_cannot_be_names_are_refused(name, match):
    c = Construction()
    with pytest.raises(ConstructionError, match=match) as info:
        c.parameter(name, 1)
    assert info.value.field == "name"
    assert len(str(info.value)) < 300


def test_a_10_mb_name_is_refused_without_being_echoed():
    name = "p" * 10_000_000
    c = Construction()
    for declare in (lambda: c.parameter(name, 1), lambda: c.fixed(name, 0, 0),
                    lambda: c.polar("P", name, 1, 0)):
        with pytest.raises(ConstructionError, match="10,000,000 characters") as info:
            declare()
        assert len(str(info.value)) < 300


@pytest.mark.parametrize(("value", "match"), [
    ("1 / 0", "is inf"), ("sqrt(-1)", "is nan"), ("10 ** 400", "is inf"),
])
def test_constant_values_must_be_finite(value, match):
    c = base()
    c.circle_circle("B", ("A", "B0"), (value, 30), branch="left")
    with pytest.raises(ConstructionError, match=match) as info:
        c.compile()
    check(info, "B", "radii[0]")


def test_a_constant_radius_cannot_be_negative():
    c = base()
    c.circle_circle("B", ("A", "B0"), (35, -30), branch="left")
    with pytest.raises(ConstructionError, match="cannot be negative") as info:
        c.compile()
    check(info, "B", "radii[1]")


# -- degenerate fixed geometry: a sample that cannot be assembled, with its reason ----

DEGENERATE = {
    "coincident centres": lambda c: (
        c.fixed("P", 1, 2), c.fixed("Q", 1, 2),
        c.circle_circle("X", ("P", "Q"), (1, 1), branch="left")),
    "parallel guides": lambda c: (
        c.fixed("P", 0, 0), c.fixed("Q", 1, 0), c.fixed("R", 0, 1), c.fixed("S", 2, 1),
        c.line_line("X", ("P", "Q"), ("R", "S"))),
    "coincident guides": lambda c: (
        c.fixed("P", 0, 0), c.fixed("Q", 1, 1), c.fixed("R", 2, 2), c.fixed("S", 3, 3),
        c.line_line("X", ("P", "Q"), ("R", "S"))),
    "zero-length guide": lambda c: (
        c.fixed("P", 0, 0), c.fixed("Q", 0, 0), c.fixed("R", 0, 1), c.fixed("S", 1, 1),
        c.line_line("X", ("P", "Q"), ("R", "S"))),
    "zero-length line to a circle": lambda c: (
        c.fixed("P", 3, 3), c.fixed("Q", 3, 3), c.fixed("C", 0, 0),
        c.line_circle("X", ("P", "Q"), "C", 5, branch="first")),
    "zero-length reference": lambda c: (
        c.fixed("P", 3, 3), c.fixed("Q", 3, 3),
        c.polar("X", "P", 2, 0.5, reference=("P", "Q"))),
    "zero-length line along": lambda c: (
        c.fixed("P", 3, 3), c.fixed("Q", 3, 3), c.along("X", ("P", "Q"), 2)),
}


@pytest.mark.parametrize("case", sorted(DEGENERATE))
def test_degenerate_fixed_geometry_is_an_invalid_sample_with_its_reason(case):
    """Fixed (Python float) operands give invalid samples naming the node, not an exception."""
    c = Construction(case)
    c.input("t")
    DEGENERATE[case](c)
    c.polar("M", "X", 1, "t")  # a moving point after the degenerate one
    s = sweep(c, np.linspace(0, 1, 4))
    assert not s.valid.any()
    assert set(s.failed_node) == {"X"}
    assert all(r.startswith("degenerate input") for r in s.failure_reason)
    assert np.isnan(s["M"]).all()


# -- extreme scales: right answers far from 1 ----------------------------------------


@pytest.mark.parametrize("scale", [1e200, 1e-200, 1e-285, 1e285])
def test_a_scaled_four_bar_moves_as_the_closed_form_says(scale):
    """A four-bar 1e200 (or 1e-200) times larger gives the closed form's points, scaled."""
    g, i, cpl, o = SEED_004
    c = Construction("scaled")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", g * scale, 0)
    c.polar("A", "O2", i * scale, "theta")
    c.circle_circle("B", ("A", "O4"), (cpl * scale, o * scale), branch="left")
    c.polar("P", "A", 0.5 * cpl * scale, 0.3, reference=("A", "B"))
    theta = np.linspace(0, 2 * np.pi, 73)
    s = sweep(c, theta)
    assert s.valid.all()
    t3, t4 = fourbar_closed_form(g, i, cpl, o, theta)
    b = np.stack([g + o * np.cos(t4), o * np.sin(t4)], axis=-1)
    p = i * np.stack([np.cos(theta), np.sin(theta)], axis=-1) + 0.5 * cpl * np.stack(
        [np.cos(t3 + 0.3), np.sin(t3 + 0.3)], axis=-1)
    np.testing.assert_allclose(s["B"] / scale, b, rtol=0, atol=1e-12 * g)
    np.testing.assert_allclose(s["P"] / scale, p, rtol=0, atol=1e-12 * g)
    np.testing.assert_allclose(s.margins["B"], sweep(_unit_fourbar(), theta).margins["B"],
                               rtol=1e-12, atol=1e-14)


def _unit_fourbar():
    g, i, cpl, o = SEED_004
    c = Construction("unit")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", g, 0)
    c.polar("A", "O2", i, "theta")
    c.circle_circle("B", ("A", "O4"), (cpl, o), branch="left")
    return c


# -- numbers beyond floats, and steps too small to count ------------------------------

HUGE_INT = 10**400  # a TOML integer may be this large; float() of it overflows


@pytest.mark.parametrize(("declare", "node", "field"), [
    (lambda c: c.input("s", range=(0, HUGE_INT)), "s", "range"),
    (lambda c: c.input("s", range=(0, 16**5000)), "s", "range"),  # too long to print
    (lambda c: c.input("s", range=(0, 1), step=HUGE_INT), "s", "step"),
    (lambda c: c.input("s", speed=HUGE_INT), "s", "speed"),
    (lambda c: c.input("s", speed=-(16**5000)), "s", "speed"),
    (lambda c: c.input("s", samples=HUGE_INT), "s", "samples"),
    (lambda c: c.input("s", samples=16**5000), "s", "samples"),
    (lambda c: c.circle_circle("B", ("A", "B0"), (1, 2), near=(HUGE_INT, 0)), "B", "near"),
    (lambda c: c.fixed("P", HUGE_INT, 0), "P", "x"),
    (lambda c: c.parameter("k", 16**5000), "k", "value"),
])
def test_integers_beyond_floats_are_errors_naming_node_and_field(declare, node, field):
    with pytest.raises(ConstructionError) as info:
        declare(base())
    check(info, node, field, {"s": "input", "k": "parameter"}.get(node, "node"))
    assert len(str(info.value)) < 300


@pytest.mark.parametrize(("options", "match"), [
    (dict(range=(0, 1), step=1e-320), "makes inf samples"),
    (dict(range=(0, 1), step=1e-9), "makes 1e\\+09 samples"),
    (dict(range=(-1e308, 1e308)), "wider than floating-point numbers reach"),
    (dict(speed=1e-320), "speed must be a positive number from 1e-290"),
    (dict(speed=0.0), "speed must be a positive number"),
])
def test_input_options_that_cannot_be_swept_are_errors(options, match):
    with pytest.raises(ConstructionError, match=match) as info:
        Construction().input("s", **options)
    assert info.value.node == "s"


def test_a_step_that_makes_the_most_samples_is_accepted():
    c = Construction()
    c.input("s", kind="length", range=(0, 999_999e-6), step=1e-6)
    assert len(c.inputs["s"].values()) == 1_000_000


# -- the scales geokin computes with ----------------------------------------------------


@pytest.mark.parametrize(("declare", "node", "field", "match"), [
    (lambda c: c.fixed("P", 3e290, 0), "P", "x", "larger than the lengths"),
    (lambda c: c.polar("P", "A0", "l3 * 1e289", 0), "P", "distance", "larger than the lengths"),
    (lambda c: c.input("s", kind="length", range=(0, 1e300)), "s", "range",
     "larger than the lengths"),
])
def test_lengths_beyond_the_scale_range_are_refused(declare, node, field, match):
    c = base()
    with pytest.raises(ConstructionError, match=match) as info:
        declare(c)
        c.compile()
    check(info, node, field, "input" if node == "s" else "node")


def test_a_mechanism_smaller_than_the_scale_range_is_refused_but_a_tiny_offset_is_not():
    c = _unit_fourbar()
    c.fixed("T", 0, 1e-300)  # a tiny coordinate in a mechanism of size 24 is fine
    c.compile()
    tiny = Construction()
    tiny.input("t")
    tiny.fixed("O", 0, 0)
    tiny.fixed("Q", 2e-300, 0)
    tiny.polar("A", "O", 1e-300, "t")
    with pytest.raises(ConstructionError, match="largest length is 2e-300") as info:
        tiny.compile()
    check(info, "Q", "x")


@given(st.floats(-320, 308), st.floats(0, 2 * np.pi))
def test_a_four_bar_at_any_scale_is_refused_or_right(exponent, theta1):
    """Scaled by 10**exponent, a four-bar is refused when declared or compiled, or right."""
    scale = 10.0**exponent
    g, i, cpl, o = SEED_004
    largest = cpl * scale  # the coupler is the longest length
    theta = np.linspace(0, 2 * np.pi, 37) + theta1
    try:
        with np.errstate(all="ignore"):
            c = Construction("scaled")
            c.input("theta")
            c.fixed("O2", 0, 0)
            c.fixed("O4", g * scale * np.cos(theta1), g * scale * np.sin(theta1))
            c.polar("A", "O2", i * scale, "theta")
            c.circle_circle("B", ("A", "O4"), (cpl * scale, o * scale), branch="left")
            c.polar("P", "A", 0.5 * cpl * scale, 0.3, reference=("A", "B"))
        s = sweep(c, theta)
    except ConstructionError as err:
        assert "length" in str(err) or "finite number" in str(err)
        assert not 1e-290 <= largest <= 1e290
        return
    assert 1e-290 <= largest <= 1e290
    assert s.valid.all()
    t3, t4 = fourbar_closed_form(g, i, cpl, o, theta - theta1)
    t3, t4 = t3 + theta1, t4 + theta1
    o4 = g * np.array([np.cos(theta1), np.sin(theta1)])
    b = o4 + o * np.stack([np.cos(t4), np.sin(t4)], axis=-1)
    p = i * np.stack([np.cos(theta), np.sin(theta)], axis=-1) + 0.5 * cpl * np.stack(
        [np.cos(t3 + 0.3), np.sin(t3 + 0.3)], axis=-1)
    np.testing.assert_allclose(s["B"] / scale, b, rtol=0, atol=1e-11 * g)
    np.testing.assert_allclose(s["P"] / scale, p, rtol=0, atol=1e-11 * g)


# -- declaring many names takes a time linear in their number -------------------------


def test_forty_thousand_parameters_and_twenty_thousand_points_are_quick():
    """Each declaration used to rebuild the table of every name: 60 s for 40,000."""
    start = time.process_time()
    c = Construction()
    for k in range(40_000):
        c.parameter(f"p{k}", k)
    c.input("t")
    c.fixed("O", 0, 0)
    for k in range(20_000):
        c.polar(f"P{k}", f"P{k - 1}" if k else "O", "p1", "t")
    compiled = c.compile()
    assert len(compiled) == 20_001
    assert time.process_time() - start < 5


# -- whatever is declared, the outcome is a construction or a GeokinError ---------------

hostile_number = st.one_of(
    st.floats(), st.integers(), st.sampled_from([10**400, -(16**5000), 1e-320, 0, True]),
)
hostile_text = st.one_of(
    st.text(max_size=12), st.sampled_from(["A", "B0", "l3", "theta", "В0", "ｌ3", "1/0",
                                           "sqrt(-1)", "1e999", "0x" + "f" * 400, "if",
                                           "a\x1b[2J", "+".join(["1"] * 300), "x" * 300]))
_deep = as_expr("l3")
for _ in range(150):
    _deep = _deep * 2
hostile = st.one_of(hostile_number, hostile_text, st.none(),
                    st.sampled_from([_deep, as_expr("theta") / 0, np.float64("nan")]),
                    st.lists(st.one_of(hostile_number, hostile_text), max_size=3))


@given(st.lists(st.tuples(st.sampled_from(["parameter", "input", "fixed", "polar", "local", "along",
                                           "line_line", "circle_circle", "line_circle",
                                           "link", "slider", "trace"]),
                          st.lists(hostile, min_size=1, max_size=5)), max_size=6))
def test_hostile_declarations_give_a_construction_or_a_geokin_error(declarations):
    """Any arguments to any declaring method, then compile and sweep: no other exception."""
    c = base()
    for method, args in declarations:
        declare = getattr(c, method)
        try:
            inspect.signature(declare).bind(*args)
        except TypeError:
            continue  # the wrong number of arguments: Python's own check, before geokin's
        try:
            declare(*args)
        except GeokinError:
            pass
    try:
        s = sweep(c, np.linspace(0, 1, 5))
    except GeokinError:
        return
    assert s.valid.shape == (5,)


def test_ground_is_decided_by_the_compiled_steps_not_by_who_builds_them():
    import dataclasses

    c = Construction()
    c.input("s", kind="length", range=(0, 5))
    c.fixed("O", 0, 0)
    c.fixed("S", "s", 0)  # driven along a line: a joint, not ground
    c.polar("A", "O", 1, 0.5)
    compiled = c.compile()
    assert compiled.ground == {"O", "A"}  # A, at a constant angle from O, never moves
    # a compiled construction rebuilt from its own fields names the same ground
    fields = {f.name: getattr(compiled, f.name) for f in dataclasses.fields(compiled) if f.init}
    assert type(compiled)(**fields).ground == {"O", "A"}
    with pytest.raises(TypeError):
        type(compiled)(**fields, ground=frozenset())


def test_with_parameters_changes_the_values_the_sweep_uses_and_nothing_else():
    c = Construction("four-bar")
    c.parameter("b", 35)
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 40, 0)
    c.polar("A", "O2", 10, "theta")
    c.circle_circle("B", ("A", "O4"), ("b", 30), branch="left")
    compiled = c.compile()
    longer = compiled.with_parameters({"b": 36.5})
    s = sweep(longer, np.linspace(0, 2 * np.pi, 9))
    assert np.allclose(np.hypot(*(s["B"] - s["A"]).T), 36.5)
    assert compiled.parameters["b"] == 35.0  # the original is left as it was
    assert longer.steps is compiled.steps and longer.ground == compiled.ground
    with pytest.raises(ConstructionError, match=r"no parameter 'bb'; did you mean 'b'\? "
                                                r"\(parameters: b\)"):
        compiled.with_parameters({"bb": 1})
    for bad in (float("nan"), "x", float("inf")):
        with pytest.raises(ConstructionError, match="parameter 'b'"):
            compiled.with_parameters({"b": bad})
    with pytest.raises(ConstructionError, match="radius cannot be negative"):
        compiled.with_parameters({"b": -1})


# -- what an error calls the thing it is about ------------------------------------------


@pytest.mark.parametrize(("declare", "kind", "name", "field"), [
    (lambda c: c.link("rocker", "A0", "A"), "link", "rocker", "name"),
    (lambda c: c.slider("rocker", "A", ("A0", "B0")), "slider", "rocker", "name"),
    (lambda c: c.input("rocker"), "input", "rocker", "name"),
    (lambda c: c.parameter("rocker", 1), "parameter", "rocker", "name"),
    (lambda c: c.closure("rocker", ["Q"], [("A", "Q", 1), ("B0", "Q", 1)], near={"Q": (0, 1)}),
     "group", "rocker", "name"),
    (lambda c: c.fixed("rocker", 0, 0), "node", "rocker", "name"),
    (lambda c: c.input("phi", speed=-1), "input", "phi", "speed"),
    (lambda c: c.slider("block", "A", ("A0",)), "slider", "block", "along"),
    (lambda c: c.closure("g", ["Q"], [("A", "Q", 1)], near={"Q": (0, 1)}), "group", "g",
     "distances"),
])
def test_an_error_about_a_declaration_calls_it_what_it_is(declare, kind, name, field):
    """A second 'rocker' is called what it is declared as, whatever the first one is."""
    c = base()
    c.link("rocker", "A0", "A")
    with pytest.raises(ConstructionError) as info:
        declare(c)
    check(info, name, field, kind)


def test_a_closure_groups_point_that_is_declared_already_is_a_node():
    c = base()
    with pytest.raises(ConstructionError, match="duplicate name") as info:
        c.closure("g", ["A"], [("A0", "A", 1), ("B0", "A", 1)], near={"A": (0, 1)})
    check(info, "A", "name", "node")


def test_errors_of_a_motion_and_a_sweep_call_inputs_and_parameters_so():
    from geokin import motion

    c = base()
    c.link("crank", "A0", "A")
    s = sweep(c, np.linspace(0, 1, 5))
    with pytest.raises(ConstructionError) as info:
        motion(s, speed=-1)
    check(info, "theta", "speed", "input")
    with pytest.raises(ConstructionError) as info:
        sweep(c, {"thta": [0.0]})
    check(info, "thta", None, "input")
    with pytest.raises(ConstructionError) as info:
        sweep(c, [0.0], parameters={"l3": [1.0, np.nan]})
    check(info, "l3", None, "parameter")
    with pytest.raises(ConstructionError) as info:
        c.compile().with_parameters({"l33": 1})
    check(info, "l33", None, "parameter")


SCRIPT_IN_DEGREES = """
[inputs.theta]
range = [0, 360]

[points]
O = { op = "fixed", at = [0, 0] }
A = { op = "polar", origin = "O", distance = 10, angle = "theta" }
P = { op = "polar", origin = "A", distance = 5, angle = 40, reference = ["O", "A"] }
"""


def test_degrees_given_where_radians_are_taken_are_warned_of():
    """range=(0, 360) is 57 turns in radians; an angle of 40 is 6.4 turns."""
    c = Construction()
    with pytest.warns(geokin.DegreesWarning,
                      match=r"input 'theta': a range of 0 to 360 is 57.3 turns in radians.*"
                            r"np.radians converts degrees") as caught:
        c.input("theta", range=(0, 360))
    assert caught[0].filename == __file__  # the warning points at the call
    c.fixed("O", 0, 0)
    c.polar("A", "O", 10, "theta")
    with pytest.warns(geokin.DegreesWarning, match="point 'P': an angle of 40 is 6.37 turns"):
        c.polar("P", "A", 5, 40, reference=("O", "A"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c.input("phi", range=(0, 2 * np.pi))  # radians, as they should be
        c.input("s", kind="length", range=(0, 360))  # a length
        c.polar("Q", "A", 5, np.radians(40), reference=("O", "A"))
        c.polar("R", "A", 5, 3, reference=("O", "A"))  # 3 rad: a radian value
        # a script's degrees are converted, whole numbers of them too, into radians
        # that may be whole numbers themselves
        loaded = loads(SCRIPT_IN_DEGREES)
        loads(SCRIPT_IN_DEGREES.replace("range = [0, 360]", "range = [0, 1.7e+308]"))
    assert loaded.inputs["theta"].range[1] == pytest.approx(2 * np.pi)


def test_sweeps_and_searches_given_degrees_are_warned_of():
    """np.arange(0, 361) swept, or limits searched from 0 to 360, are 57 turns in radians."""
    c = Construction()
    c.input("theta")
    c.fixed("O", 0, 0)
    c.polar("A", "O", 10, "theta")
    for call in (lambda: geokin.sweep(c, np.arange(0, 361)),
                 lambda: geokin.sweep(c, {"theta": np.linspace(-90, 90, 7)})):
        with pytest.warns(geokin.DegreesWarning, match=r"sweep: input 'theta' runs from -?\d+ "
                          r"to \d+, which is \d+(\.\d+)? turns in radians") as caught:
            call()
        assert caught[0].filename == __file__
    with pytest.warns(geokin.DegreesWarning, match="limits of 'theta': a search range of 0 to "
                      "360 is 57.3 turns in radians") as caught:
        geokin.limits(c, search_range=(0, 360))
    assert caught[0].filename == __file__
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        geokin.sweep(c, np.linspace(0, 2 * np.pi, 9))
        geokin.sweep(c, np.arange(0, 4))  # 3 rad: a radian value
        geokin.sweep(c, [40.0])  # one sample: a single angle, not a sweep
        geokin.sweep(c, np.linspace(0, 3e5, 5))  # beyond any sweep in degrees
        geokin.limits(c, search_range=(0, 6))
        geokin.sweep(loads(SCRIPT_IN_DEGREES))  # a script's own range
