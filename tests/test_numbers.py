"""Floats written by numpy as the shortest text that reads back: the very text of repr."""

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from geokin.io import shortest_text
from geokin.io.numbers import FIELD_WIDTH, shortest_texts, text_fields


def assert_as_repr(values):
    """Check the texts of ``values`` against repr, with and without the ``.0``, and read back."""
    values = np.asarray(values, dtype=float)
    texts = shortest_texts(values)
    assert texts == [shortest_text(v) for v in values.tolist()]
    assert shortest_texts(values, point_zero=True) == [repr(v) for v in values.tolist()]
    back = np.array([float(t) for t in texts])
    np.testing.assert_array_equal(back, values)
    numbers = ~np.isnan(values)
    assert np.array_equal(np.signbit(back[numbers]), np.signbit(values[numbers]))


@given(hnp.arrays(np.float64, st.integers(0, 40), elements=st.floats(width=64)))
def test_any_floats_as_repr(values):
    assert_as_repr(values)


@given(st.binary(min_size=0, max_size=8 * 40).map(lambda b: b[:len(b) // 8 * 8]))
def test_any_bit_patterns_as_repr(data):
    # every double, subnormals and NaNs with payloads among them
    assert_as_repr(np.frombuffer(data, dtype=np.float64))


@given(st.lists(st.tuples(st.integers(-330, 310), st.integers(-3, 3)), max_size=30))
def test_floats_next_to_powers_of_ten_as_repr(steps):
    # where the decimal exponent changes, and where a decimal of one digit fewer may
    # read back as a float just below a power of ten
    values = []
    for exponent, ulps in steps:
        v = float(f"1e{exponent}")
        for _ in range(abs(ulps)):
            v = math.nextafter(v, math.inf if ulps > 0 else 0.0)
        values += [v, -v]
    assert_as_repr(values)


@given(st.lists(st.tuples(st.integers(0, 10 ** 17), st.integers(0, 25)), max_size=30))
def test_short_decimals_as_repr(fractions):
    # k / 10**d: values a person types, with few digits
    assert_as_repr([k / 10 ** d for k, d in fractions])


@given(hnp.arrays(np.float64, st.integers(0, 40),
                  elements=st.floats(1e-5, 2e16) | st.floats(-2e16, -1e-5)))
def test_floats_of_fixed_notation_as_repr(values):
    assert_as_repr(values)


def test_many_floats_as_repr():
    rng = np.random.default_rng(0)
    n = 20_000
    assert_as_repr(np.concatenate([
        rng.integers(0, 2 ** 64, n, dtype=np.uint64).view(np.float64),  # any bits
        rng.uniform(-1000, 1000, n),  # coordinates
        np.exp(rng.uniform(math.log(1e-5), math.log(2e16), n)),  # every scale written by numpy
        rng.integers(0, 10 ** 15, n) / 10.0 ** rng.integers(0, 20, n),  # short decimals
        rng.integers(2 ** 52, 2 ** 53, n) * 2.0 ** rng.integers(-60, 10, n),  # 53 bits used
        np.nextafter(10.0 ** rng.integers(-5, 17, n), rng.choice([0, np.inf], n)),
    ]))


def test_ties_go_to_the_even_digit_as_repr():
    # two decimals of 16 or 17 digits read back, as near as each other: repr takes the even
    values = [600000000000000.25, 600000000000000.75, 2.0 ** 50 + 0.25, 2.0 ** 50 + 0.75]
    assert shortest_texts(values) == ["600000000000000.2", "600000000000000.8",
                                      "1125899906842624.2", "1125899906842624.8"]
    assert_as_repr(values)


def test_the_notations_of_repr():
    values = [0.0001, 0.00012345678901234567, 1e-5, 123.5, 1e15, 1e16, 20.0, 0.0, -0.0,
              np.nan, np.inf, -np.inf, 5e-324, -2.2250738585072014e-308, 1.7976931348623157e308]
    assert shortest_texts(values) == [
        "0.0001", "0.00012345678901234567", "1e-05", "123.5", "1000000000000000", "1e+16", "20",
        "0", "-0", "nan", "inf", "-inf", "5e-324", "-2.2250738585072014e-308",
        "1.7976931348623157e+308"]
    assert_as_repr(values)


def test_fields_are_left_aligned_text_padded_with_nul():
    values = np.array([[-2.2250738585072014e-308, 2.5], [-0.00012345678901234567, np.nan]])
    fields = text_fields(values)
    assert fields.shape == (4, FIELD_WIDTH) and fields.dtype == np.uint8
    assert fields.view(f"S{FIELD_WIDTH}").ravel().tolist() == [
        b"-2.2250738585072014e-308", b"2.5", b"-0.00012345678901234567", b"nan"]
    for row in fields:  # no NUL inside a text
        text = row[:np.count_nonzero(row)]
        assert (text != 0).all() and (row[len(text):] == 0).all()


def test_empty():
    assert shortest_texts([]) == []
    assert text_fields(np.array([])).shape == (0, FIELD_WIDTH)
