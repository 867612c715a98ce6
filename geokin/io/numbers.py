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
  ``k``. Most computed floats need 16 or 17 digits, so whether 16 and 15
  digits read back is checked first, 8192 values at a time; the floats
  with fewer digits are then found by a binary search over ``k``, all at
  once.
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
- The text is then built in three 64-bit words per value: the digits from a
  table of all groups of four, shifted right past the sign and the zeros
  of a number below 1, the point put in, the bytes past the end cleared.

Zeros, infinities and NaN are written as repr writes them; the few other
values (below ``1e-4``, from ``1e16``, subnormal) are written by ``repr``
itself, one at a time.

Examples
--------
>>> shortest_texts([0.1, 20.0, -0.0, 1e-5, 2.0 ** 70, 0.1 + 0.2, float("nan")])
['0.1', '20', '-0', '1e-05', '1.1805916207174113e+21', '0.30000000000000004', 'nan']
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["FIELD_WIDTH", "shortest_texts", "text_fields"]

FIELD_WIDTH = 24
"""The bytes :func:`text_fields` gives a value: the longest repr, ``-1.2345678901234567e-300``."""

# values worked on at a time: their temporary arrays stay in the cache, which makes a
# chunk twice as fast as a long array
_CHUNK = 8192
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
# the least float from 10**j on, for j from _POW10_FROM: a >= 10**j exactly when a >= it
_POW10_FROM = -5
_AT_LEAST_POW10 = np.array([float(10 ** j) if j >= 0 else
                            math.nextafter(float(Fraction(1, 10 ** -j)), math.inf)
                            if Fraction(float(Fraction(1, 10 ** -j))) < Fraction(1, 10 ** -j)
                            else float(Fraction(1, 10 ** -j)) for j in range(_POW10_FROM, 18)])
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


def _rounded(a: np.ndarray, q: np.ndarray, a_high: np.ndarray, a_low: np.ndarray,
             level: np.ndarray) -> np.ndarray:
    """Return the integer nearest ``a * 10**-k``, the even one on a tie.

    ``q``, its rounded value, is from 2**53 on, so an even integer;
    ``a_high, a_low`` split ``a``; ``level`` is ``k - _LOWEST``.
    """
    # q plus the error of its rounding, found exactly by Dekker's product
    up_high, up_low = _UP_HIGH[level], _UP_LOW[level]
    error = ((a_high * up_high - q) + a_high * up_low + a_low * up_high) + a_low * up_low
    return q.astype(np.int64) + np.rint(error).astype(np.int64)


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
    result = found.astype(np.int64)
    # from 2**53 on the nearest reads back (there k <= 0: for k > 0, a < 1e16 keeps q
    # below 1e15)
    sure = q >= _TWO53
    if sure.any():
        a_high, a_low = _split(a[sure])
        result[sure] = _rounded(a[sure], q[sure], a_high, a_low, level[sure])
    return result


def _searched_digits(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


def _sixteen_or_seventeen(a: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return ``(N, e, fewer)``: the shortest decimal of ``a`` if of 16 or 17 digits.

    Where not ``fewer``, ``N * 10**(e - 16 + (N < 10**16))`` is the
    shortest decimal reading back as ``a``. ``a`` holds positive floats
    with ``1e-4 <= a < 1e16``; ``e`` is the decimal exponent of ``a``, and
    ``fewer`` where 15 digits or fewer do.
    """
    # most floats computed need 16 or 17 digits: those are told apart first, by whether
    # 16 and 15 digits read back; the others are searched for
    binary = (a.view(np.int64) >> 52) - 1023
    e = np.floor(binary * _LOG10_2).astype(np.int64)
    e += a >= _AT_LEAST_POW10[e + 1 - _POW10_FROM]  # now the decimal exponent of a
    level = e - _LOWEST
    a_high, a_low = _split(a)
    # 17 digits always read back, and the nearest 17-digit decimal is from 2**53 on
    result = _rounded(a, a * _UP[level - 16], a_high, a_low, level - 16)
    # 16 digits: the nearest of the multiples of 10**(e - 15) near a that read back,
    # always the nearest from 2**53 on
    up = _UP[level - 15]
    q = a * up
    n = np.rint(q)
    sure = q >= _TWO53
    middle = n / up == a
    below = (n - 1) / up == a
    above = (n + 1) / up == a
    sixteen = sure | middle | below | above
    # n where it reads back (the nearest), else n - 1 or n + 1, whichever does
    nearest = n.astype(np.int64)
    nearest += above & ~middle
    nearest -= below & ~middle
    np.copyto(result, nearest, where=sixteen)
    if sure.any():
        at = np.flatnonzero(sure)
        result[at] = _rounded(a[at], q[at], a_high[at], a_low[at], level[at] - 15)
    # 15 digits (for e below 15, where 10**(e - 14) is below 1)
    up = _UP[level - 14]
    n = np.rint(a * up)
    fewer = (e >= 15) | (n / up == a) | ((n - 1) / up == a) | ((n + 1) / up == a)
    return result, e, fewer


def _shortest_digits(a: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return ``(N, k, d)``: ``N * 10**k`` is the shortest decimal reading back as ``a``.

    ``a`` holds positive floats with ``1e-4 <= a < 1e16``; ``N`` has ``d``
    digits, the last not zero.
    """
    n = np.empty(a.shape, dtype=np.int64)
    e = np.empty(a.shape, dtype=np.int64)
    fewer = np.empty(a.shape, dtype=bool)
    for i in range(0, a.size, _CHUNK):
        n[i:i + _CHUNK], e[i:i + _CHUNK], fewer[i:i + _CHUNK] = _sixteen_or_seventeen(
            a[i:i + _CHUNK])
    digits = 16 + (n >= 10 ** 16)
    # the floats of 15 digits or fewer searched for all at once: they are few, or a whole
    # column of values typed with few digits
    shorter = np.flatnonzero(fewer)
    if shorter.size:
        n[shorter], k = _searched_digits(a[shorter])
        digits[shorter] = np.searchsorted(_INT_POW10, n[shorter], side="right")
        e[shorter] = k + digits[shorter] - 1
    return n, e - digits + 1, digits


# a float's text is built in three 64-bit words, 24 bytes, little-endian: byte i of the
# text is bits 8i to 8i + 7 of word i // 8, so moving text right is a left shift
_U64 = np.uint64
_BYTES = 0x0101010101010101
# _BELOW[w][i]: the bytes of word w that are before byte i of the text, for i in 0..24
_BELOW = np.array([[(1 << 8 * min(max(i - 8 * w, 0), 8)) - 1 for i in range(25)]
                   for w in range(3)], dtype=_U64)
# what goes before the digits, by zeros + 5 * sign: "", "0", ..., "-", "-0", ..., "-0000"
_PREFIX = np.array([int.from_bytes(b"-" * sign + b"0" * zeros, "little")
                    for sign in range(2) for zeros in range(5)], dtype=_U64)
# the text of 0 to 9999 in four ASCII digits, as the low and the high half of a word
_DIGITS4 = np.array([int.from_bytes(b"%04d" % i, "little") for i in range(10_000)], dtype=_U64)
_DIGITS4_HIGH = _DIGITS4 << _U64(32)


def _fixed_words(values: np.ndarray, point_zero: bool) -> np.ndarray:
    """Write floats with ``1e-4 <= |x| < 1e16`` as repr does, left-aligned in ``(n, 3)`` words."""
    n, k, digits = _shortest_digits(np.abs(values))
    out = np.empty((len(values), 3), dtype="<u8")  # its bytes are the text on any machine
    for i in range(0, len(values), _CHUNK):
        part = slice(i, i + _CHUNK)
        out[part] = _written(values[part], n[part], k[part], digits[part], point_zero)
    return out


def _written(values: np.ndarray, n: np.ndarray, k: np.ndarray, digits: np.ndarray,
             point_zero: bool) -> np.ndarray:
    """Write ``values``, ``+-N * 10**k`` with ``N`` of ``digits`` digits, as in words."""
    exponent = k + digits - 1  # of the leading digit: -4 to 15
    # the 17 digits of N, left-aligned and padded with zeros, 4 + 4 + 4 + 4 + 1
    left = n * _INT_POW10[17 - digits]
    first = left // 10 ** 9
    rest = left - first * 10 ** 9
    second = rest // 10
    words = []
    for eight in (first, second):
        high = eight // 10_000
        word = _DIGITS4[high]
        word |= _DIGITS4_HIGH[eight - high * 10_000]
        words.append(word)
    words.append((rest - second * 10 + 0x30).view(_U64))
    # then the sign and, below 1, as many zeros as the point takes places ("0.000123"
    # is "-"? "0000" "123" with a point after the first zero)
    sign = np.signbit(values)
    zeros = np.maximum(-exponent, 0)
    prefix = sign + zeros
    shift = prefix.astype(_U64) << _U64(3)
    back = _U64(63) - shift  # the bytes moving into the next word, in two shifts
    for w in (2, 1):
        words[w] <<= shift
        words[w] |= (words[w - 1] >> back) >> _U64(1)
    words[0] <<= shift
    words[0] |= _PREFIX[zeros + 5 * sign]
    # the point goes in at byte `at`, the bytes from there move one right
    at = sign + np.maximum(exponent, 0) + 1
    whole = digits <= exponent + 1
    # whole numbers end at the point (after ".0" with point_zero), the others after
    # their digits
    length = prefix + digits + 1
    length += whole * (at + (2 if point_zero else 0) - length)
    out = np.empty((len(values), 3), dtype="<u8")  # its bytes are the text on any machine
    carry: np.ndarray | np.uint64 = _U64(0)
    for w, word in enumerate(words):
        before, upto = _BELOW[w][at], _BELOW[w][at + 1]
        moved = (word << _U64(8)) | carry
        carry = word >> _U64(56)
        moved &= ~upto
        upto &= ~before
        upto &= _U64(0x2E * _BYTES)
        word &= before
        word |= moved
        word |= upto
        word &= _BELOW[w][length]
        out[:, w] = word
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
