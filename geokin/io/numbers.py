"""Floats written as the shortest decimal text that reads back exactly, an array at a time.

Python's ``repr(float)`` writes the shortest decimal that reads back as the
same float, and of two such decimals the closer; formatting a million values
with it costs a Python call each. :func:`text_fields` writes the same text
for a whole array with numpy operations; :func:`shortest_texts` gives it as
strings. Whole numbers lose their ``.0`` (``20``, not ``20.0``) unless asked
to keep it.

How
---
A float ``x`` with ``1e-4 <= |x| < 1e16`` (repr's fixed notation) is written
by numpy:

- The decimals of ``p`` significant digits are the multiples of ``10**k``
  for ``k = e - p + 1`` (``e`` the decimal exponent of ``x``), and the
  shortest decimal is a multiple of the largest ``10**k`` of which a
  multiple reads back as ``x``; whether some multiple does is monotonic in
  ``k``, so a binary search over ``k`` finds it, for every element at once.
- At a given ``k``, the multiples nearest ``x`` are ``N * 10**k`` with
  ``N`` within one of ``rint(x / 10**k)``. For an integer ``N <= 2**53``
  and ``|k| <= 22`` both ``N`` and ``10**|k|`` are exact floats, so
  ``N * 10**k`` (or ``N / 10**-k``) is one correctly rounded operation on
  exact operands: exactly what reading the decimal gives. Comparing it with
  ``x`` says exactly whether the decimal reads back.
- Where ``x / 10**k >= 2**53`` the spacing of the multiples is below the
  spacing of floats around ``x``, so the nearest multiple always reads back
  (17 significant digits always suffice); it is found exactly from
  ``x * 10**-k`` computed without rounding error (Dekker's product).
- Of two decimals that read back, repr writes the closer, the even one on a
  tie; they occur only where ``x / 10**k`` is above ``2**52``, where its
  rounded value is that very integer.

Zeros, infinities and NaN are written as repr writes them; the few other
values (below ``1e-4``, from ``1e16``, subnormal) are written by ``repr``
itself, one at a time.

Examples
--------
>>> shortest_texts([0.1, 20.0, -0.0, 1e-5, 2.0 ** 70, 0.1 + 0.2, float("nan")])
['0.1', '20', '-0', '1e-05', '1.1805916207174113e+21', '0.30000000000000004', 'nan']
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["FIELD_WIDTH", "shortest_texts", "text_fields"]

FIELD_WIDTH = 24
"""The bytes :func:`text_fields` gives a value: the longest repr, ``-1.2345678901234567e-300``."""

_TWO53 = 2.0 ** 53
_SMALLEST, _LARGEST = 1e-4, 1e16  # repr's fixed notation, and the range written here
_INT_POW10 = np.array([10 ** i for i in range(19)], dtype=np.int64)
# 10**-k as up / down with one of them 1, for levels k from _LOWEST up, so that a * up / down
# rounds once. 10**i for i <= 22 is an exact float: for an exact integer N below 2**53,
# N * down / up is one correctly rounded operation, as reading the decimal is. The search
# looks at levels up to 14 above any a decimal can have, where the powers need not be
# exact (no multiple reads back there)
_LOWEST = -22
_UP = np.array([float(10 ** -k) if k <= 0 else 1.0 for k in range(_LOWEST, 31)])
_DOWN = np.array([float(10 ** k) if k > 0 else 1.0 for k in range(_LOWEST, 31)])
_SPLIT = 134217729.0  # 2**27 + 1, which splits a float into two halves of 26 bits
_LOG10_2 = 0.30102999566398120


def _split(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return high and low halves of floats whose products with one another are exact."""
    c = _SPLIT * x
    high = c - (c - x)
    return high, x - high


_UP_HIGH, _UP_LOW = _split(_UP)


def _reads_back(a: np.ndarray, level: np.ndarray) -> np.ndarray:
    """Return where some multiple of ``10**k`` reads back as ``a`` (``level`` is k - _LOWEST)."""
    up, down = _UP[level], _DOWN[level]
    q = a * up / down  # a * 10**-k, correctly rounded: one of the operations is by 1
    n = np.rint(q)
    ok = q >= _TWO53
    for candidate in (n, n - 1, n + 1):
        ok |= candidate * down / up == a
    return ok


def _nearest(a: np.ndarray, level: np.ndarray) -> np.ndarray:
    """Return ``N``: ``N * 10**k`` is the closest to ``a`` of the multiples reading back as it.

    Some multiple of ``10**k`` must read back as ``a`` (:func:`_reads_back`);
    ``level`` is ``k - _LOWEST``.
    """
    up, down = _UP[level], _DOWN[level]
    q = a * up / down
    n = np.rint(q)
    found = n + 1
    # the nearest last: where two read back (q above 2**52) q is the closer one itself
    for candidate in (n - 1, n):
        np.copyto(found, candidate, where=candidate * down / up == a)
    # from 2**53 on, the nearest integer to a * 10**-k is q plus the error of its rounding,
    # found exactly by Dekker's product (there k <= 0: for k > 0, a < 1e16 keeps q below
    # 1e15 and down is not 1, where this error means nothing and is not used)
    a_high, a_low = _split(a)
    up_high, up_low = _UP_HIGH[level], _UP_LOW[level]
    error = ((a_high * up_high - q) + a_high * up_low + a_low * up_high) + a_low * up_low
    np.copyto(found, np.rint(error), where=q >= _TWO53)
    result = found.astype(np.int64)
    # q is an even integer there, exact in int64; the error is added apart from it
    np.add(result, q.astype(np.int64), out=result, where=q >= _TWO53)
    return result


def _shortest_digits(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return ``(N, k)`` with ``N * 10**k`` the shortest decimal reading back as ``a``.

    ``a`` holds positive floats with ``1e-4 <= a < 1e16``; ``N`` has no
    trailing zero.
    """
    # the decimal exponent e of a is this or one more (2**b <= a < 2**(b + 1))
    binary = (a.view(np.int64) >> 52) - 1023
    e = np.floor(binary * _LOG10_2).astype(np.int64)
    # a multiple of 10**(e - 17) always reads back (17 digits or more), and none of
    # 10**(e + 3) or above: find the largest level that does in 20 steps of 16, 8, 4, 2, 1
    level = e - 17 - _LOWEST
    for step in (16, 8, 4, 2, 1):
        np.add(level, step, out=level, where=_reads_back(a, level + step))
    return _nearest(a, level), level + _LOWEST


# a float's text is built in three 64-bit words, 24 bytes, little-endian: byte i of the
# text is bits 8i to 8i + 7 of word i // 8, so moving text right is a left shift
_U64 = np.uint64
_BYTES = 0x0101010101010101
# _BELOW[w][i]: the bytes of word w that are before byte i of the text, for i in 0..24
_BELOW = np.array([[(1 << 8 * min(max(i - 8 * w, 0), 8)) - 1 for i in range(25)]
                   for w in range(3)], dtype=_U64)
# what goes before the digits, by sign and zeros: "-", "0", "-000", ...
_PREFIX = np.array([[int.from_bytes(b"-" * sign + b"0" * zeros, "little") for zeros in range(5)]
                    for sign in range(2)], dtype=_U64)


def _ascii8(g: np.ndarray) -> np.ndarray:
    """Return numbers below 1e8 as their 8 ASCII digits, zero-padded, in a 64-bit word."""
    # split in 4 + 4 digits, 2 + 2, 1 + 1, in lanes of 32, 16 and 8 bits, dividing every
    # lane at once by multiplying and shifting (exact for 0..9999 and 0..99)
    high = g // _U64(10_000)
    v = high | ((g - high * _U64(10_000)) << _U64(32))
    q = ((v * _U64(10486)) >> _U64(20)) & _U64(0x0000007F0000007F)
    v = q | ((v - q * _U64(100)) << _U64(16))
    q = ((v * _U64(103)) >> _U64(10)) & _U64(0x000F000F000F000F)
    v = q | ((v - q * _U64(10)) << _U64(8))
    return v + _U64(0x30 * _BYTES)


def _fixed_words(values: np.ndarray, point_zero: bool) -> np.ndarray:
    """Write floats with ``1e-4 <= |x| < 1e16`` as repr does, left-aligned in ``(n, 3)`` words."""
    n, k = _shortest_digits(np.abs(values))
    digits = np.searchsorted(_INT_POW10, n, side="right")  # how many N has
    exponent = k + digits - 1  # of the leading digit: -4 to 15
    # the 17 digits of N, left-aligned and padded with zeros, 8 + 8 + 1
    left = (n * _INT_POW10[17 - digits]).view(_U64)
    first = left // _U64(10 ** 9)
    rest = left - first * _U64(10 ** 9)
    second = rest // _U64(10)
    words = [_ascii8(first), _ascii8(second), rest - second * _U64(10) + _U64(0x30)]
    # then the sign and, below 1, as many zeros as the point takes places ("0.000123"
    # is "-"? "0000" "123" with a point after the first zero)
    sign = np.signbit(values)
    zeros = np.maximum(-exponent, 0)
    shift = (sign + zeros).astype(_U64) * _U64(8)
    back = _U64(63) - shift  # the bytes moving into the next word, in two shifts
    words[2] = (words[2] << shift) | ((words[1] >> back) >> _U64(1))
    words[1] = (words[1] << shift) | ((words[0] >> back) >> _U64(1))
    words[0] = (words[0] << shift) | _PREFIX[sign.view(np.int8), zeros]
    # the point goes in at byte `at`, the bytes from there move one right
    at = sign + np.maximum(exponent, 0) + 1
    whole = digits <= exponent + 1
    length = np.where(whole, at + (2 if point_zero else 0), sign + zeros + digits + 1)
    out = np.empty((len(values), 3), dtype="<u8")  # its bytes are the text on any machine
    carry = _U64(0)
    for w, word in enumerate(words):
        before, upto = _BELOW[w][at], _BELOW[w][at + 1]
        moved = (word << _U64(8)) | carry
        carry = word >> _U64(56)
        out[:, w] = ((word & before) | (moved & ~upto) | (upto & ~before & _U64(0x2E * _BYTES))
                     ) & _BELOW[w][length]
    return out


def text_fields(values: ArrayLike, *, point_zero: bool = False) -> np.ndarray:
    """Write floats as the shortest text that reads back exactly, one row of bytes each.

    Parameters
    ----------
    values : array_like
        Numbers, converted to float64; flattened.
    point_zero : bool, optional
        Keep repr's ``.0`` on whole numbers below 1e16 (``20.0``); without
        it they are written ``20``.

    Returns
    -------
    ndarray of uint8, shape (n, FIELD_WIDTH)
        Row ``i`` holds the ASCII text of ``values[i]``, left-aligned,
        padded with NUL bytes.

    Examples
    --------
    >>> fields = text_fields([2.5, -1e-7])
    >>> fields.shape
    (2, 24)
    >>> fields.view("S24").ravel().tolist()
    [b'2.5', b'-1e-07']
    """
    flat = np.asarray(values, dtype=np.float64).ravel()
    magnitude = np.abs(flat)
    with np.errstate(invalid="ignore"):
        fixed = (magnitude >= _SMALLEST) & (magnitude < _LARGEST)
    if fixed.all():
        return _fixed_words(flat, point_zero).view(np.uint8)
    fields = np.zeros((flat.size, FIELD_WIDTH), dtype=np.uint8)
    if fixed.any():
        fields[fixed] = _fixed_words(flat[fixed], point_zero).view(np.uint8)
    others = np.flatnonzero(~fixed)
    finite = np.isfinite(magnitude[others])
    special = {b"0.0" if point_zero else b"0": magnitude[others] == 0,
               b"inf": np.isinf(magnitude[others])}
    negative = np.signbit(flat[others])
    for text, chosen in special.items():
        for sign, prefix in ((False, b""), (True, b"-")):
            rows = others[chosen & (negative == sign)]
            fields[rows, :len(prefix + text)] = np.frombuffer(prefix + text, dtype=np.uint8)
    fields[others[np.isnan(magnitude[others])], :3] = np.frombuffer(b"nan", dtype=np.uint8)
    rest = others[finite & (magnitude[others] != 0)]
    if rest.size:
        # below 1e-4 or from 1e16, in scientific notation: rare enough for repr
        texts = [repr(v) for v in flat[rest].tolist()]
        if not point_zero:
            texts = [t[:-2] if t.endswith(".0") else t for t in texts]
        fields[rest] = np.array(texts, dtype=f"S{FIELD_WIDTH}").view(np.uint8).reshape(
            rest.size, FIELD_WIDTH)
    return fields


def shortest_texts(values: ArrayLike, *, point_zero: bool = False) -> list[str]:
    """Return the shortest text that reads back exactly of each number, as repr writes it.

    The same as ``repr(float(v))`` for every value ``v`` (``1e-05``,
    ``1e+16``, ``nan``, ``-inf``), without the ``.0`` of whole numbers
    unless ``point_zero``; computed with numpy for the whole array at once.

    Parameters
    ----------
    values : array_like
        Numbers, converted to float64; flattened.
    point_zero : bool, optional
        Keep the ``.0`` of whole numbers below 1e16, as repr does.

    Returns
    -------
    list of str

    Examples
    --------
    >>> shortest_texts([1.0, 0.0001, 123.5, 1e15, 1e16, -2.0 ** -1074])
    ['1', '0.0001', '123.5', '1000000000000000', '1e+16', '-5e-324']
    >>> shortest_texts([1.0, 600000000000000.25], point_zero=True)
    ['1.0', '600000000000000.2']
    """
    fields = text_fields(values, point_zero=point_zero)
    lines = np.empty((len(fields), FIELD_WIDTH + 1), dtype=np.uint8)
    lines[:, :-1] = fields
    lines[:, -1] = ord("\n")
    return lines[lines != 0].tobytes().decode("ascii").split("\n")[:-1]
