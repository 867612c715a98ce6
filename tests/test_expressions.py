import sys
import time

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from geokin import Construction, ConstructionError
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
    called = st.one_of(
        st.builds(lambda f, x: Call(f, (x,)),
                  st.sampled_from([f for f, (n, _) in FUNCTIONS.items() if n == 1]), children),
        st.builds(lambda x, y: Call("atan2", (x, y)), children, children))
    return st.one_of(binary, negated, called)


@given(st.recursive(leaves, _extend, max_leaves=25))
def test_printed_expressions_parse_back_to_themselves(expr):
    """str() writes an expression that parses to the same tree, of the same depth."""
    again = parse(str(expr))
    assert again == expr
    assert again.depth == expr.depth <= MAX_EXPRESSION_DEPTH
    env = {"a": np.array([0.5, 2.0]), "b": 3.0}
    with np.errstate(all="ignore"):
        np.testing.assert_array_equal(again.evaluate(env), expr.evaluate(env))
