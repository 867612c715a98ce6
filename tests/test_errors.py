import time

import pytest

from geokin import ConstructionError, GeokinError
from geokin.errors import BudgetError, closest_name, did_you_mean, quote, show

HUGE = "B" * 10_000_000


def test_quote_cuts_a_long_name_and_says_how_long_it_was():
    text = quote(HUGE)
    assert len(text) < 80
    assert text.startswith("'BBBB") and "10,000,000 characters" in text


def test_quote_escapes_control_characters():
    text = quote("a\x1b]0;pwned\x07\nb")
    assert "\x1b" not in text and "\x07" not in text and "\n" not in text
    assert "\\x1b" in text


@pytest.mark.parametrize(("value", "expected"), [
    (16 ** 5000, "an integer of 6,021 digits"),  # str() of it raises ValueError
    (-(10 ** 400), "an integer of 401 digits"),
    (2 ** 1328, "an integer of 400 digits"),  # 1329 bits, yet 400 digits
    (10 ** 400 - 1, "an integer of 400 digits"),
    ([1, 10 ** 5000], "[1, an integer of 5,001 digits]"),
    ((0, "x" * 100_000), "(0, 'xxxxxxxxxxxxxxxxxxxxxxxxxx…xxxxxxxxxxxxx' [100,000 characters])"),
    ([[1] * 100], "[a list of 100 items]"),
    (list(range(10 ** 6)), "a list of 1,000,000 items"),
    ((1.5, 2), "(1.5, 2)"),
], ids=["hex-sized integer", "negative integer", "fewer digits than bits say", "all nines",
        "list with a huge integer", "long string",
        "nested list", "long list", "short tuple"])
def test_show_summarises_what_cannot_or_should_not_be_printed(value, expected):
    assert show(value) == expected


def test_a_construction_error_shows_a_long_node_name_shortened_but_keeps_it_whole():
    err = ConstructionError("bad", node=HUGE, field="name")
    assert len(str(err)) < 120 and str(err).endswith(": bad")
    assert err.node is HUGE and err.message == "bad"


def test_did_you_mean_gives_up_quickly_on_a_huge_name():
    start = time.process_time()
    assert did_you_mean(HUGE, ["B0", "B1"]) == ""
    assert closest_name(HUGE, ["B" * 20]) is None
    assert time.process_time() - start < 0.5


def test_did_you_mean_still_finds_close_names():
    assert did_you_mean("l33", ["l3", "l4"]) == "; did you mean 'l3'?"
    assert closest_name("b0", ["B0", "A1"]) == "B0"


def test_budget_errors_are_geokin_errors():
    err = BudgetError("too big", needed=10, budget=5)
    assert isinstance(err, GeokinError)
    assert (err.needed, err.budget) == (10, 5)
