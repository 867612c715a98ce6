import re
import sys
import time

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from geokin import Construction, ConstructionError, sweep
from geokin.budgets import MAX_EXPRESSION_DEPTH, MAX_EXPRESSION_LENGTH, MAX_NAME_LENGTH
from geokin.expressions import (
    FUNCTIONS,
    BinOp,
    Call,
    Name,
    Neg,
    Number,
    as_expr,
    look_alike,
    normal_name,
    parse,
    skeleton,
)
from geokin.nodes import NOT_FINITE, REASONS

# -- depth: printing and evaluating recurse once per level, so the depth is bounded ----


@pytest.mark.parametrize("terms", [102, 500, 990, 4000])
def test_a_long_chain_is_refused_as_too_deep(terms):
    """500 to 990 chained terms used to parse, then die printing with RecursionError."""
    with pytest.raises(ConstructionError, match="nested too deeply.*at most 100 levels"):
        parse("+".join(["1"] * terms))


def test_a_long_chain_in_a_construction_names_node_and_field():
    c = Construction()
    with pytest.raises(ConstructionError, match="nested too deeply") as info:
        c.fixed("P", "+".join(["x"] * 600), 0)
    assert (info.value.node, info.value.field) == ("P", "x")


def _nested(depth):
    """An expression exactly ``depth`` levels deep that mixes every kind of level."""
    text = "a"
    for i in range(depth):
        text = ["sqrt({})", "-({})", "({}) * b", "2 ** ({})"][i % 4].format(text)
    return text


def test_the_deepest_allowed_expression_prints_evaluates_and_round_trips_deep_in_a_stack():
    expr = parse(_nested(MAX_EXPRESSION_DEPTH))
    assert expr.depth == MAX_EXPRESSION_DEPTH

    def at_depth(frames):  # leave the expression only what a deep caller leaves it
        if frames:
            return at_depth(frames - 1)
        return str(expr), expr.evaluate({"a": 0.5, "b": np.array([1.0, 1.0])}), expr.names()

    headroom = sys.getrecursionlimit() - MAX_EXPRESSION_DEPTH * 3 - 100
    text, value, names = at_depth(headroom)
    assert parse(text) == expr and names == {"a", "b"} and value.shape == (2,)
    with pytest.raises(ConstructionError, match="nested too deeply"):
        parse(_nested(MAX_EXPRESSION_DEPTH + 1))


def test_an_expression_built_in_python_is_held_to_the_same_depth():
    deep = as_expr("a")
    for _ in range(MAX_EXPRESSION_DEPTH):
        deep = deep + 1
    assert as_expr(deep) is deep
    with pytest.raises(ConstructionError, match=f"nested {MAX_EXPRESSION_DEPTH + 1} levels"):
        as_expr(deep * 2, node="P", field="x")


@pytest.mark.parametrize(("text", "depth"), [
    ("1", 0), ("a", 0), ("1 + 1 + 1", 2), ("sqrt(-(a * b))", 3), ("atan2(y, x + 1)", 2),
    ("-5", 0), ("+a", 0),
])
def test_depth_counts_operations_and_calls(text, depth):
    assert parse(text).depth == depth


# -- length and numbers ---------------------------------------------------------------


def test_a_10_mb_expression_is_refused_at_once():
    text = "1+" * 5_000_000 + "1"
    start = time.process_time()
    with pytest.raises(ConstructionError, match="longer than the 10,000 characters") as info:
        parse(text)
    assert time.process_time() - start < 0.5
    assert len(str(info.value)) < 300


def test_the_longest_allowed_expression_parses():
    text = " + ".join(f"a{i}" for i in range(60))
    text += " " * (MAX_EXPRESSION_LENGTH - len(text))
    assert len(parse(text).names()) == 60


@pytest.mark.parametrize("text", ["0x" + "f" * 5000, "0o" + "7" * 5000, "0b" + "1" * 9000,
                                  "1" * 5000, "-0x" + "f" * 300])
def test_integers_beyond_floats_and_beyond_printing_are_clear_errors(text):
    """A hex literal over 4,300 digits made str() raise ValueError while reporting it."""
    with pytest.raises(ConstructionError, match="too large|digits") as info:
        parse(text)
    assert len(str(info.value)) < 300


def test_a_huge_integer_value_is_a_clear_error():
    with pytest.raises(ConstructionError, match="an integer of 401 digits") as info:
        as_expr(10**400, node="P", field="x")
    assert info.value.field == "x"


# -- names -----------------------------------------------------------------------------


def test_names_in_expressions_are_read_in_nfkc():
    assert parse("ｌ1 + ℓ2").names() == {"l1", "l2"}
    assert parse("ｌ1") == parse("l1")


@pytest.mark.parametrize("name", ["θ2", "длина", "長さ", "長さ_L1", "ラ_x", "길이1", "ψ_1",
                                  "café", "ａ"])
def test_names_of_one_script_are_accepted(name):
    assert normal_name(name).isidentifier()
    assert parse(f"{name} + 1").names() == {normal_name(name)}


@pytest.mark.parametrize(("name", "scripts"), [
    ("pаram", "Latin and Cyrillic"),  # Cyrillic а
    ("Вx", "Cyrillic and Latin"),
    ("θx", "Greek and Latin"),
    ("aα", "Latin and Greek"),
    ("длинаλ", "Cyrillic and Greek"),
])
def test_names_mixing_scripts_are_refused(name, scripts):
    with pytest.raises(ConstructionError, match=f"mixes {scripts} letters"):
        normal_name(name)
    with pytest.raises(ConstructionError, match=f"mixes {scripts} letters"):
        parse(f"1 + {name}")


def test_a_name_too_long_is_refused_without_echoing_it():
    name = "a" * (MAX_NAME_LENGTH + 1)
    assert normal_name(name[:-1]) == name[:-1]
    with pytest.raises(ConstructionError, match="at most 200 characters") as info:
        parse(name)
    assert len(str(info.value)) < 300


@given(st.text(alphabet="aBoОοcсeеpрxхyу01_", min_size=1, max_size=6))
def test_skeletons_are_latin_and_only_look_alikes_share_one(name):
    """The skeleton replaces look-alike letters only; a name and its skeleton look alike."""
    key = skeleton(name)
    assert key.isascii()
    assert len(key) == len(name)
    assert all(a == b or not a.isascii() for a, b in zip(name, key, strict=True))
    if key != name:
        assert look_alike(name, [key, "zz"]) == key
    assert look_alike(name, [name]) is None


# -- round trips of generated expressions ------------------------------------------------

leaves = st.one_of(st.sampled_from([Name("a"), Name("b"), Name("pi")]),
                   st.floats(-100, 100, allow_nan=False).map(Number))


def _extend(children):
    binary = st.builds(BinOp, st.sampled_from(["+", "-", "*", "/", "**"]), children, children)
    negated = children.filter(lambda e: not isinstance(e, Number)).map(Neg)
    called = st.sampled_from(sorted(FUNCTIONS)).flatmap(
        lambda f: st.lists(children, min_size=_low(f), max_size=_low(f) + 2 * _variadic(f))
        .map(lambda args: Call(f, tuple(args))))
    return st.one_of(binary, negated, called)


def _low(function):
    arity = FUNCTIONS[function][0]
    return arity if isinstance(arity, int) else arity[0]


def _variadic(function):
    return not isinstance(FUNCTIONS[function][0], int)


@given(st.recursive(leaves, _extend, max_leaves=25))
def test_printed_expressions_parse_back_to_themselves(expr):
    """str() writes an expression that parses to the same tree, of the same depth."""
    again = parse(str(expr))
    assert again == expr
    assert again.depth == expr.depth <= MAX_EXPRESSION_DEPTH
    env = {"a": np.array([0.5, 2.0]), "b": 3.0}
    with np.errstate(all="ignore"):
        np.testing.assert_array_equal(again.evaluate(env), expr.evaluate(env))


# -- the functions: numpy's, elementwise, arity checked when parsing ---------------------

finite = st.floats(-1e6, 1e6, allow_nan=False)
samples = hnp.arrays(float, st.integers(1, 6), elements=finite)
in_unit = hnp.arrays(float, st.integers(1, 6), elements=st.floats(-1, 1))


@pytest.mark.parametrize(("text", "numpy"), [
    ("abs(x)", lambda x, y: np.abs(x)),
    ("hypot(x, y)", np.hypot),
    ("min(x, y)", np.minimum),
    ("max(x, y)", np.maximum),
    ("atan(x)", lambda x, y: np.arctan(x)),
    ("atan2(y, x)", lambda x, y: np.arctan2(y, x)),
    ("min(x, y, 0)", lambda x, y: np.minimum(np.minimum(x, y), 0)),
    ("max(0, x, y, -x)", lambda x, y: np.maximum(np.maximum(np.abs(x), 0), y)),
])
@given(x=samples, y=finite)
def test_functions_are_numpys_elementwise(text, numpy, x, y):
    """Over arrays of samples and plain numbers alike, a function gives what numpy gives."""
    np.testing.assert_array_equal(parse(text).evaluate({"x": x, "y": y}), numpy(x, y))
    assert float(parse(text).evaluate({"x": float(x[0]), "y": y})) == numpy(x[0], y)


@pytest.mark.parametrize(("text", "numpy"), [("asin(x)", np.arcsin), ("acos(x)", np.arccos)])
@given(x=in_unit)
def test_inverse_sine_and_cosine_are_numpys_and_give_radians(text, numpy, x):
    value = parse(text).evaluate({"x": x})
    np.testing.assert_array_equal(value, numpy(x))
    forward = np.sin if text.startswith("asin") else np.cos
    np.testing.assert_allclose(forward(value), x, atol=1e-15)


def test_min_and_max_broadcast_samples_against_numbers_and_keep_nan():
    x = np.array([-2.0, 0.5, 3.0, np.nan])
    np.testing.assert_array_equal(parse("min(1, x, 2)").evaluate({"x": x}), [-2, 0.5, 1, np.nan])
    np.testing.assert_array_equal(parse("max(x, 1, 0)").evaluate({"x": x}), [1, 1, 3, np.nan])
    assert parse("max(1, 2, 3, 4, 5)").evaluate({}) == 5


@pytest.mark.parametrize("x", [1.0000001, -1.5, 2.0])
def test_acos_and_asin_out_of_their_domain_give_nan(x):
    with np.errstate(invalid="ignore"):
        assert np.isnan(parse("acos(x)").evaluate({"x": x}))
        assert np.isnan(parse("asin(x)").evaluate({"x": x}))


@pytest.mark.parametrize(("text", "message"), [
    ("abs(a, b)", "abs() takes 1 argument, got 2"),
    ("hypot(a)", "hypot() takes 2 arguments, got 1"),
    ("hypot(a, b, c)", "hypot() takes 2 arguments, got 3"),
    ("acos()", "acos() takes 1 argument, got 0"),
    ("min(a)", "min() takes at least 2 arguments, got 1"),
    ("max()", "max() takes at least 2 arguments, got 0"),
    ("min(a, *b)", "Starred is not allowed"),
    ("max(a, b, key=c)", "max() takes no keyword arguments"),
    ("arccos(a)", "unknown function 'arccos'"),
])
def test_the_number_of_arguments_is_checked_when_parsing(text, message):
    with pytest.raises(ConstructionError, match=re.escape(message)):
        parse(text)


@pytest.mark.parametrize("name", ["abs", "min", "max", "hypot", "acos", "asin", "atan"])
def test_function_names_are_reserved(name):
    with pytest.raises(ConstructionError, match="reserved for the built-in function"):
        Construction().parameter(name, 1)


def test_a_value_out_of_its_domain_makes_its_samples_unassemblable_with_the_reason():
    """acos of a ratio above 1 is NaN at that sample: invalid, the node and reason named."""
    c = Construction()
    c.input("s", kind="length", range=(0, 2), samples=5)
    c.fixed("O", 0, 0)
    c.polar("A", "O", 10, "acos(s - 1) + asin(1 - s / 2)")
    with np.errstate(invalid="raise"):  # the engine keeps numpy's warnings to itself
        s = sweep(c, {"s": np.array([0.0, 1.0, 2.0, 2.5, -0.5])})
    assert s.valid.tolist() == [True, True, True, False, False]
    angle = np.arccos([-1.0, 0.0, 1.0]) + np.arcsin([1.0, 0.5, 0.0])
    np.testing.assert_allclose(s["A"][:3], 10 * np.stack([np.cos(angle), np.sin(angle)], -1),
                               atol=1e-12)
    assert s.failure_reason[3] == s.failure_reason[4] == REASONS[NOT_FINITE]
    assert "node 'A' cannot be assembled" in s.explain(3)
    assert "not finite" in s.explain(3)


def test_a_constant_value_out_of_its_domain_is_refused():
    c = Construction()
    c.fixed("O", 0, 0)
    c.polar("A", "O", "acos(2)", 0)
    with pytest.raises(ConstructionError, match="must be a finite number") as info:
        c.compile()
    assert (info.value.node, info.value.field) == ("A", "distance")
