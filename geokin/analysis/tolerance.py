"""Tolerance analysis: how the spread of a design's dimensions spreads its motion.

:func:`tolerance` draws design variants around a construction's nominal
parameters (a Monte Carlo study), sweeps each over the same input samples,
and gives a :class:`Tolerance`: the fraction of variants that assemble at
every sample, the deviation of each traced point from its nominal path at
every sample, the spread of each moving link's and slider's stroke, and
the sensitivity of each of these to each parameter.

Variant ``i``'s values depend only on the seed, the parameter's name and
``i`` (:func:`draw_variants`): the variants are evaluated in blocks of
:data:`BLOCK_VARIANTS`, each block reduced to statistics before the next
(memory does not grow with the samples of all variants), and the blocks'
statistics are combined in the order of the blocks, so the figures are the
same whether the blocks run here or on the workers of a ``dask.distributed``
cluster, however many and in whatever order they finish.

Examples
--------
>>> import geokin
>>> c = geokin.load(f"{geokin.__path__[0]}/../constructions/fourbar_open.toml")
>>> t = tolerance(c, {"a": 0.1, "b": 0.1}, n=200, seed=1)
>>> t
<Tolerance of 'four-bar, open': 200 variants, 100.0% assemble; a ±0.1, b ±0.1 (normal)>
>>> t.paths["B"].worst.shape, t.strokes["rocker.angle"].values.shape
((361,), (200,))
>>> [name for name, _ in t.sensitivity["B.path"]]  # the largest effect first
['b', 'a']
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib
import logging
import math
import numbers
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..construction import Compiled, Construction, as_compiled
from ..engine import input_arrays, sweep
from ..errors import AnalysisError, ConstructionError, GeokinError, did_you_mean, quote
from ..frozen import Frozen
from ..results import Sweep, short_name
from .measures import closing_turns

__all__ = [
    "BLOCK_VARIANTS",
    "DISTRIBUTIONS",
    "PERCENTILE_VARIANTS",
    "SAMPLE_PATHS",
    "SENSITIVITY_STEP",
    "PathSpread",
    "StrokeSpread",
    "Tolerance",
    "dask_distributed",
    "draw_variants",
    "envelope_outline",
    "local_cluster",
    "tolerance",
]

DISTRIBUTIONS = ("normal", "uniform")
"""How a parameter is drawn within its tolerance T: ``"normal"`` with
standard deviation T / 3 (T is three standard deviations), ``"uniform"``
anywhere in the interval [nominal - T, nominal + T]."""

BLOCK_VARIANTS = 1024
"""How many variants are swept together: each block's sweep is reduced to
statistics before the next. Blocks are cut by variant index, so every
variant is always swept with the same others, whatever runs the blocks."""

CHUNK_BLOCKS = 4
"""Blocks sent to a worker at a time, by default (one task of a cluster)."""

PERCENTILE_VARIANTS = 10_000
"""The percentiles of a path's deviation are taken over the first this many
variants (by index; independent draws like any others, so a random sample
of the study): exact for a study of up to this many, and bounded in memory
for a larger one."""

SAMPLE_PATHS = 40
"""How many variants' paths are kept whole, to be drawn: the first ones by index."""

SENSITIVITY_STEP = 1e-3
"""The step of the central differences, as a fraction of each parameter's tolerance."""


# -- drawing the variants ---------------------------------------------------------------


def _check_seed(seed: object) -> int:
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise AnalysisError(f"the seed must be a non-negative integer, got {seed!r}")
    return int(seed)


def _generator(seed: int, name: str) -> np.random.Philox:
    """Return the counter-based stream of one parameter: its own for each name and seed."""
    digest = hashlib.sha256(name.encode("utf-8")).digest()
    words = [int.from_bytes(digest[i:i + 4], "little") for i in range(0, 16, 4)]
    return np.random.Philox(np.random.SeedSequence([seed, *words]))


def draw_variants(nominal: Mapping[str, float], tolerances: Mapping[str, float], seed: int,
                  start: int, stop: int, distribution: str = "normal") -> dict[str, np.ndarray]:
    """Return the parameter values of variants ``start`` to ``stop - 1`` of a study.

    Each parameter has its own counter-based stream (numpy's Philox), keyed
    by the seed and the parameter's name; variant ``i`` takes the four
    64-bit words at counter ``i`` of it. So its value depends only on the
    seed, the name and ``i``: drawing variants in pieces gives the same
    values as drawing them at once, and adding a parameter to a study leaves
    the others' draws as they were. A normal value is made from two of the
    words by the Box-Muller transform, a uniform one from one word.

    Parameters
    ----------
    nominal : mapping of str to float
        Each parameter's nominal value.
    tolerances : mapping of str to float
        Each drawn parameter's tolerance T (the ± half-width).
    seed : int
    start, stop : int
        The variants drawn: ``range(start, stop)``.
    distribution : {"normal", "uniform"}
        See :data:`DISTRIBUTIONS`.

    Returns
    -------
    dict of str to ndarray, shape (stop - start,)

    Examples
    --------
    >>> whole = draw_variants({"a": 10.0}, {"a": 0.3}, 7, 0, 6)["a"]
    >>> pieces = [draw_variants({"a": 10.0}, {"a": 0.3}, 7, i, i + 2)["a"] for i in (0, 2, 4)]
    >>> bool((np.concatenate(pieces) == whole).all())
    True
    >>> u = draw_variants({"a": 10.0}, {"a": 0.3}, 7, 0, 1000, "uniform")["a"]
    >>> bool((abs(u - 10) <= 0.3).all())
    True
    """
    count = stop - start
    values = {}
    for name, half in tolerances.items():
        stream = _generator(seed, name)
        stream.advance(start)  # one counter step, four words, a variant
        words = stream.random_raw(4 * count).reshape(count, 4)
        # 53 random bits, centred in their interval: never 0 nor 1
        u = ((words[:, :2] >> np.uint64(11)).astype(float) + 0.5) * 2.0 ** -53
        if distribution == "normal":
            z = np.sqrt(-2 * np.log(u[:, 0])) * np.cos(2 * np.pi * u[:, 1])
            values[name] = nominal[name] + half / 3 * z
        else:
            values[name] = nominal[name] + half * (2 * u[:, 0] - 1)
    return values


# -- what is measured -------------------------------------------------------------------


@dataclass(frozen=True)
class _Output:
    """A link's angle or a slider's position, whose stroke is measured."""

    name: str  # "rocker.angle", "block.position"
    kind: str  # "angle" or "length"
    points: tuple[str, ...]  # a link's two points; a slider's point and guide


def _outputs(compiled: Compiled) -> tuple[_Output, ...]:
    """Return the strokes a study measures: every link and slider that moves."""
    outputs = []
    for link in compiled.links:
        if len(link.points) >= 2 and not set(link.points) <= compiled.ground:
            outputs.append(_Output(f"{link.name}.angle", "angle", link.points[:2]))
    for slider in compiled.sliders:
        if {slider.point, *slider.along} - compiled.ground:
            outputs.append(_Output(f"{slider.name}.position", "length",
                                   (slider.point, *slider.along)))
    return tuple(outputs)


def _strokes(coords: Callable[[str], tuple[Any, Any]], output: _Output,
             reference: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None, *,
             closed: bool = False) -> np.ndarray:
    """Return the stroke of an output for each row of (V, N) coordinates.

    ``coords(point)`` gives a point's x and y. A link's angle is measured
    from ``reference``, the nominal link's direction (x, y) and unwrapped
    angle at each sample, so a variant's angle is the nominal one plus its
    small difference from it; without a reference it is followed from
    sample to sample (each step the angle between its directions, as
    unwrapping does). A full turn is 2 pi either way. ``closed``: the sweep
    ends where it began, whole turns on (see :func:`_between_samples`).
    """
    with np.errstate(all="ignore"):
        if output.kind == "angle":
            (x0, y0), (x1, y1) = coords(output.points[0]), coords(output.points[1])
            dx, dy = np.atleast_2d(x1 - x0), np.atleast_2d(y1 - y0)
            if reference is not None:
                return _stroke_from(reference, dx, dy, closed)
            cross = dx[:, :-1] * dy[:, 1:] - dy[:, :-1] * dx[:, 1:]
            dot = dx[:, :-1] * dx[:, 1:] + dy[:, :-1] * dy[:, 1:]
            turned = np.cumsum(np.arctan2(cross, dot), axis=1)
            return _range_between_samples(np.concatenate(
                [np.zeros((turned.shape[0], 1)), turned], axis=1), closed)
        (px, py), (sx, sy), (ex, ey) = (coords(p) for p in output.points)
        gx, gy = ex - sx, ey - sy
        along = np.atleast_2d(((px - sx) * gx + (py - sy) * gy) / np.hypot(gx, gy))
        stroke = _range_between_samples(along, closed)
        # a point that keeps its place on its guide moves by the rounding of its
        # coordinates: no stroke
        size = np.atleast_2d(np.abs(px) + np.abs(py) + np.abs(sx) + np.abs(sy))
        return np.where(stroke <= SLIDE_ROUNDING * np.max(size, axis=1), 0.0, stroke)


SLIDE_ROUNDING = 16 * np.finfo(float).eps
"""A slider's stroke up to this times the size of its coordinates is their
rounding, and counts as none: a block fixed on its guide is not drawn as
the slider that spreads the most."""


FROM_REFERENCE = 0.5
"""Rows whose link turns less than atan(0.5), about 26.6 degrees, from the nominal
link pick their extremes on tangents, then take one arctangent at each (see
:func:`_extreme_angles`)."""


TURN_GROUPS = tuple(FROM_REFERENCE * 2.0**k for k in range(-5, 4))
"""Upper bounds of the groups of rows whose strokes :func:`_stroke_from` takes
together, by their largest turn from the nominal (a tangent, ``|cross /
dot|``); the last group, from 4 up to a quarter turn, has none."""


STROKE_BLOCK = 2**17
"""How many samples of link angles :func:`_stroke_from` works on at a time:
their temporaries stay within the shared cache, and the work each block
does in Python is small beside its arithmetic."""


def _stroke_from(reference, dx, dy, closed: bool = False) -> np.ndarray:
    """Return each row's stroke of a link's angle, measured from the nominal link.

    The angle is the nominal one plus the angle between the two directions,
    atan2(cross, dot). A row that turns less than a quarter turn from the
    nominal at every sample differs from it by at most the arctangent of its
    largest ``|t|``, t = cross / dot: its largest and smallest angle can only
    be where the nominal angle comes within twice that of its own extremes,
    and only there are they sought, for rows in groups of like turn
    (:data:`TURN_GROUPS`). A row that cannot be assembled somewhere has no
    stroke (NaN).
    """
    ux, uy, base = reference
    rows = max(1, STROKE_BLOCK // max(dx.shape[1], 1))
    if dx.shape[0] > rows:  # a block of rows at a time: its temporaries stay in the cache
        return np.concatenate([_stroke_from(reference, dx[i:i + rows], dy[i:i + rows], closed)
                               for i in range(0, dx.shape[0], rows)])
    cross = ux * dy
    cross -= uy * dx
    dot = ux * dx
    dot += uy * dy
    least = np.minimum.reduce(dot, axis=1)  # NaN where the row is not assembled
    stroke = np.full(dx.shape[0], np.nan)
    with np.errstate(invalid="ignore"):
        tangent = np.divide(cross, dot)
        turn = np.maximum(np.maximum.reduce(tangent, axis=1), -np.minimum.reduce(tangent, axis=1))
        turn[~(least > 0)] = np.inf
    near = turn < np.inf
    group = np.searchsorted(TURN_GROUPS, turn, side="right")
    for k in np.unique(group[near]):
        members = np.flatnonzero(near & (group == k))
        largest = float(np.max(turn[members]))
        high_columns, low_columns = _near_extremes(base, largest)
        if largest < FROM_REFERENCE:
            high = _extreme_angles(reference, dx, dy, tangent, members, high_columns, np.argmax,
                                   closed)
            low = _extreme_angles(reference, dx, dy, tangent, members, low_columns, np.argmin,
                                  closed)
        else:
            high, low = (_between_samples(
                partial(_exact_at, base, cross, dot, members), columns[pick(
                    _exact(base, cross, dot, members, columns), axis=1)], dx.shape[1], sign,
                closed)
                for columns, pick, sign in ((high_columns, np.argmax, 1),
                                            (low_columns, np.argmin, -1)))
        stroke[members] = high - low
    rest = np.flatnonzero(least <= 0)
    if rest.size:
        # a link that turns a quarter turn or more from the nominal: its difference
        # from it followed along the samples, never cut at half a turn
        angle = base + np.unwrap(np.arctan2(cross[rest], dot[rest]), axis=1)
        stroke[rest] = _range_between_samples(angle, closed)
    return stroke


def _closes(compiled: Compiled, inputs: Mapping[str, np.ndarray]) -> bool:
    """Whether a sweep's inputs end where they began, an angle whole turns on (one at least).

    Only then may an output's first and last samples be one configuration,
    each the other's neighbour (:func:`_between_samples`).
    """
    turns = closing_turns(inputs, compiled.angle_inputs)
    return turns is not None and any(turns.values())


def _between_samples(values: Callable[[np.ndarray], np.ndarray], picked: np.ndarray, n: int,
                     sign: int, closed: bool = False) -> np.ndarray:
    """Return each row's largest (sign 1) or least (-1) value, placed between samples.

    ``picked`` is each row's extreme sample, ``values(columns)`` each row's
    value at one column each. The parabola through the extreme sample and
    its neighbours places the extreme where it turns within a step of the
    sample, as :func:`~geokin.analysis.measures.refine_extreme` does;
    otherwise, and at an end of the sweep, the sample is the extreme. Over a
    ``closed`` sweep (its inputs end whole turns on from where they began) a
    row whose value ends where it began has its ends as each other's
    neighbours. Measured at the samples alone, a stroke is
    short by up to the output's curvature times a step squared over 8, and
    its derivative, a sensitivity, takes the slope at the sample.

    Examples
    --------
    The tops of sin(3 t), 1, and of a parabola, 0, sampled every 0.1:

    >>> t = np.linspace(0, 1, 11)
    >>> rows = np.vstack([np.sin(3 * t), -(t - 0.42) ** 2])
    >>> top = _between_samples(lambda c: rows[np.arange(2), c], rows.argmax(axis=1), 11, 1)
    >>> np.round(rows.max(axis=1), 6).tolist(), np.round(top, 6).tolist()
    ([0.997495, -0.0004], [0.999947, 0.0])
    """
    middle = values(picked)
    last = n - 1
    if n < 3:
        return middle
    left, right = picked - 1, picked + 1
    if closed and ((picked == 0) | (picked == last)).any():
        # a row back where it began: its ends are one sample, its neighbours 1 and n - 2
        first, final = values(np.zeros_like(picked)), values(np.full_like(picked, last))
        back = np.abs(first - final) <= 1e-12 * np.fmax(np.abs(first), 1.0)
        left = np.where((picked == 0) & back, last - 1, left)
        right = np.where((picked == last) & back, 1, right)
    inside = (left >= 0) & (right <= last)  # else an end of the sweep: the sample
    before, after = values(np.clip(left, 0, last)), values(np.clip(right, 0, last))
    bend = before - 2 * middle + after  # the parabola's second difference
    with np.errstate(divide="ignore", invalid="ignore"):
        offset = (before - after) / (2 * bend)
        placed = middle - 0.25 * (before - after) * offset
    turns = (sign * bend < 0) & (np.abs(offset) <= 1) & inside
    placed = np.where(turns & (sign * placed > sign * middle), placed, middle)
    return placed


def _range_between_samples(values: np.ndarray, closed: bool = False) -> np.ndarray:
    """Return each row's largest minus least value, both placed between samples."""
    rows = np.arange(values.shape[0])

    def at(columns):
        return values[rows, columns]

    n = values.shape[1]
    return (_between_samples(at, np.argmax(values, axis=1), n, 1, closed)
            - _between_samples(at, np.argmin(values, axis=1), n, -1, closed))


def _near_extremes(base, turn: float) -> tuple[np.ndarray, np.ndarray]:
    """Return the samples where ``base`` comes within twice ``atan(turn)`` of its extremes."""
    reach = 2 * np.arctan(turn) + 1e-9
    return (np.flatnonzero(base >= np.max(base) - reach),
            np.flatnonzero(base <= np.min(base) + reach))


def _extreme_angles(reference, dx, dy, tangent, rows, columns, pick,
                    closed: bool = False) -> np.ndarray:
    """Return the largest (``pick`` np.argmax) or least (np.argmin) angle of some rows.

    Sought over ``columns``, all within twice atan(turn) of the nominal's
    extreme, for rows that turn less than :data:`FROM_REFERENCE` from the
    nominal: every angle there is within three times atan(0.5) < 90 degrees of
    the nominal link at that extreme, so its tangent from that link orders
    the columns as the angles do. That tangent is found from the link's own
    from the nominal at each column (``tangent``, cross over dot) and the
    nominal's turn from the extreme, tan(a + b) = (tan a + tan b) / (1 - tan a
    tan b). One arctangent a row, at the column picked.
    """
    ux, uy, base = reference
    at = columns[pick(base[columns])]  # the nominal's extreme
    shift = np.tan(base[columns] - base[at])
    turned = tangent[_cells(rows, columns)]
    # (shift + t) / (1 - shift t), in the memory of the gathered tangents
    denominator = shift * turned
    np.subtract(1.0, denominator, out=denominator)
    turned += shift
    turned /= denominator
    picked = columns[pick(turned, axis=1)]

    def angle(at_columns):  # the rows' angles, one column each, from the nominal's extreme
        x, y = dx[rows, at_columns], dy[rows, at_columns]
        return base[at] + np.arctan2(ux[at] * y - uy[at] * x, ux[at] * x + uy[at] * y)

    return _between_samples(angle, picked, dx.shape[1], 1 if pick is np.argmax else -1, closed)


def _cells(rows: np.ndarray, columns: np.ndarray) -> tuple:
    """Return the index of some rows at some columns, a slice where the columns run on.

    The columns near an extreme most often do, and a slice takes them
    several times faster than a second index array.
    """
    if columns.size and columns[-1] - columns[0] == columns.size - 1:
        return rows, slice(int(columns[0]), int(columns[-1]) + 1)
    return np.ix_(rows, columns)


def _exact(base, cross, dot, rows, columns) -> np.ndarray:
    """Return the link's angle at some rows and columns, by the arctangent."""
    where = _cells(rows, columns)
    return base[columns] + np.arctan2(cross[where], dot[where])


def _exact_at(base, cross, dot, rows, columns) -> np.ndarray:
    """Return the link's angle at some rows, one column each, by the arctangent."""
    return base[columns] + np.arctan2(cross[rows, columns], dot[rows, columns])


def _reference(nominal: Sweep, output: _Output) -> tuple[np.ndarray, np.ndarray,
                                                          np.ndarray] | None:
    """Return a link's nominal direction and unwrapped angle, if it assembles everywhere."""
    if output.kind != "angle" or not np.asarray(nominal.valid).all():
        return None
    d = np.asarray(nominal[output.points[1]]) - np.asarray(nominal[output.points[0]])
    return d[:, 0], d[:, 1], np.unwrap(np.arctan2(d[:, 1], d[:, 0]))


# -- the study and its blocks -----------------------------------------------------------


@dataclass(frozen=True)
class _Study:
    """Everything a block's evaluation needs; sent whole to each worker."""

    construction: Compiled
    inputs: dict[str, np.ndarray]
    tolerances: dict[str, float]
    distribution: str
    seed: int
    points: tuple[str, ...]
    nominal_paths: dict[str, np.ndarray]
    outputs: tuple[_Output, ...]
    references: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray] | None]
    percentile_variants: int
    sample_paths: int
    closed: bool  # the inputs end whole turns on from where they began


@dataclass
class _Block:
    """A block of variants reduced to what the study keeps of it."""

    start: int
    assembled: np.ndarray  # (C,)
    failures: np.ndarray  # variants failing first at each step, by step index (0: none)
    valid_count: np.ndarray  # (N,)
    count: int  # variants assembled at every sample
    mean: dict[str, np.ndarray]  # by point: (N,) over the assembled variants
    m2: dict[str, np.ndarray]
    worst: dict[str, np.ndarray]
    worst_variant: dict[str, tuple[float, int]]
    kept: dict[str, np.ndarray]  # deviations of the variants kept for percentiles
    paths: dict[str, np.ndarray]  # whole paths of the variants kept for drawing
    strokes: dict[str, np.ndarray]  # (C,), NaN where not assembled


def _evaluate_block(study: _Study, start: int, stop: int) -> _Block:
    values = draw_variants(study.construction.parameters, study.tolerances, study.seed,
                           start, stop, study.distribution)
    # only the variants that assemble everywhere are measured: the others' branches
    # are tracked only where a sample of their paths is drawn
    s = sweep(study.construction, study.inputs, parameters=values, track_incomplete=False)
    valid = np.asarray(s.valid)
    assembled: np.ndarray = np.asarray(valid.all(axis=1), dtype=bool)
    broken = np.flatnonzero(~assembled)
    first_bad = np.argmax(~valid[broken], axis=1)
    failures = np.bincount(np.asarray(s.failed_step)[broken, first_bad],
                           minlength=len(study.construction.steps) + 1)
    count = int(assembled.sum())
    mean, m2, worst, worst_variant, kept, paths = {}, {}, {}, {}, {}, {}
    keep = min(max(study.percentile_variants - start, 0), stop - start)
    draw = min(max(study.sample_paths - start, 0), stop - start)
    drawn = s
    if draw and not assembled[:draw].all():
        drawn = sweep(study.construction, study.inputs,
                      parameters={k: v[:draw] for k, v in values.items()})
    drawn_shape = np.shape(drawn.valid)
    for name in study.points:
        x, y = (np.broadcast_to(c, valid.shape) for c in s.points.coords(name))
        if draw:
            paths[name] = np.stack([np.broadcast_to(c, drawn_shape)[:draw]
                                    for c in drawn.points.coords(name)], axis=-1)
        nominal = study.nominal_paths[name]
        # not np.hypot, several times slower: deviations are far from overflow
        along = x - nominal[:, 0]
        across = y - nominal[:, 1]
        along *= along
        across *= across
        along += across
        deviation = np.sqrt(along, out=along)[assembled]
        n = nominal.shape[0]
        if count:
            mean[name] = deviation.mean(axis=0)
            m2[name] = ((deviation - mean[name]) ** 2).sum(axis=0)
            worst[name] = deviation.max(axis=0)
            with np.errstate(all="ignore"):
                largest = np.fmax.reduce(deviation, axis=1)  # NaN only where nominal fails
            row = int(np.nanargmax(largest)) if np.isfinite(largest).any() else 0
            worst_variant[name] = (float(largest[row]), start + int(np.flatnonzero(assembled)[row]))
        else:
            mean[name] = m2[name] = np.zeros(n)
            worst[name] = np.full(n, -np.inf)
            worst_variant[name] = (-np.inf, -1)
        if keep:
            kept[name] = deviation[:int(assembled[:keep].sum())]
    strokes = {}
    for output in study.outputs:
        values_ = np.full(stop - start, np.nan)
        if count:
            values_[assembled] = _strokes(s.points.coords, output,
                                          study.references[output.name],
                                          closed=study.closed)[assembled]
        strokes[output.name] = values_
    return _Block(start, assembled, failures, valid.sum(axis=0), count, mean, m2, worst,
                  worst_variant, kept, paths, strokes)


def evaluate_chunk(study: _Study, start: int, stop: int) -> list[_Block]:
    """Evaluate variants ``start`` to ``stop - 1`` block by block (one task of a cluster).

    A chunk starts at a multiple of :data:`BLOCK_VARIANTS`: its blocks are
    the blocks of the whole study.
    """
    return [_evaluate_block(study, lo, min(lo + BLOCK_VARIANTS, stop))
            for lo in range(start, stop, BLOCK_VARIANTS)]


class _Totals:
    """The blocks' statistics combined in the order of the blocks."""

    def __init__(self, study: _Study, n: int):
        self.study = study
        self.next = 0
        self.assembled: list[np.ndarray] = []
        self.failures = np.zeros(len(study.construction.steps) + 1, dtype=np.int64)
        self.valid_count = np.zeros(n, dtype=np.int64)
        self.count = 0
        self.mean = {p: np.zeros(n) for p in study.points}
        self.m2 = {p: np.zeros(n) for p in study.points}
        self.worst = {p: np.full(n, -np.inf) for p in study.points}
        self.worst_variant = {p: (-np.inf, -1) for p in study.points}
        self.kept: dict[str, list[np.ndarray]] = {p: [] for p in study.points}
        self.paths: dict[str, list[np.ndarray]] = {p: [] for p in study.points}
        self.strokes: dict[str, list[np.ndarray]] = {o.name: [] for o in study.outputs}

    def add(self, block: _Block) -> None:
        if block.start != self.next:
            raise GeokinError(f"internal: block at variant {block.start} combined out of "
                              f"order (expected {self.next})")
        self.next = block.start + block.assembled.size
        self.assembled.append(block.assembled)
        self.failures += block.failures
        self.valid_count += block.valid_count
        total = self.count + block.count
        for p in self.study.points:
            if block.count:
                # the variances of two groups joined (Chan, Golub and LeVeque), in block order
                delta = block.mean[p] - self.mean[p]
                self.mean[p] = self.mean[p] + delta * (block.count / total)
                self.m2[p] = (self.m2[p] + block.m2[p]
                              + delta ** 2 * (self.count * block.count / total))
                self.worst[p] = np.fmax(self.worst[p], block.worst[p])
                if block.worst_variant[p][0] > self.worst_variant[p][0]:
                    self.worst_variant[p] = block.worst_variant[p]
            if p in block.kept:
                self.kept[p].append(block.kept[p])
            if p in block.paths:
                self.paths[p].append(block.paths[p])
        self.count = total
        for name, values in block.strokes.items():
            self.strokes[name].append(values)


# -- the result -------------------------------------------------------------------------


def _plain(value: Any) -> Any:
    """Return a value as JSON-ready data: arrays as lists, NaN and infinities as None."""
    if isinstance(value, np.ndarray):
        return [_plain(v) for v in value.tolist()]
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value


@dataclass(frozen=True, eq=False)
class PathSpread(Frozen):
    """How far a traced point's variants stray from its nominal path, at every sample.

    The deviation of a variant at a sample is its distance from the nominal
    position at the same input value. The statistics are over the variants
    that assemble at every sample; NaN where the nominal design does not
    assemble.

    Attributes
    ----------
    point : str
    mean, std : ndarray, shape (N,)
        Mean and standard deviation of the deviation.
    median, envelope : ndarray, shape (N,)
        Its 50th and ``level``-th percentiles, over the first
        :data:`PERCENTILE_VARIANTS` variants.
    worst : ndarray, shape (N,)
        The largest deviation of any variant.
    worst_variant : int
        The variant that strays furthest at any sample (-1 if none assembles):
        :func:`draw_variants` gives its values.
    level : float
        The percentile of ``envelope``.
    """

    point: str
    mean: np.ndarray
    std: np.ndarray
    median: np.ndarray
    envelope: np.ndarray
    worst: np.ndarray
    worst_variant: int
    level: float

    _read_only = ("mean", "std", "median", "envelope", "worst")

    def __repr__(self) -> str:
        return (f"<PathSpread of {short_name(self.point)}: mean up to "
                f"{_largest(self.mean):.4g}, {self.level:g}% up to {_largest(self.envelope):.4g}, "
                f"worst {_largest(self.worst):.4g}>")

    def to_dict(self) -> dict[str, Any]:
        """Return the spread as plain data: the arrays as lists, and their largest values."""
        return _plain({
            "mean": self.mean, "std": self.std, "median": self.median,
            f"p{self.level:g}": self.envelope, "worst": self.worst,
            "worst_variant": self.worst_variant if self.worst_variant >= 0 else None,
            "largest_mean": _largest(self.mean), f"largest_p{self.level:g}":
                _largest(self.envelope), "largest_worst": _largest(self.worst)})


def _largest(values: np.ndarray) -> float:
    finite = values[np.isfinite(values)]
    return float(finite.max()) if finite.size else math.nan


@dataclass(frozen=True, eq=False)
class StrokeSpread(Frozen):
    """The spread of one output's stroke over the variants.

    The stroke is the range swept over the samples: of a link's angle
    (radians, followed through full turns; a crank's is 2 pi), or of a
    slider's position along its guide (length units). It is measured at
    the samples, not refined between them.

    Attributes
    ----------
    name : str
        ``"<link>.angle"`` or ``"<slider>.position"``.
    kind : {"angle", "length"}
    nominal : float
        The nominal design's stroke.
    values : ndarray, shape (V,)
        Each variant's stroke; NaN for one that does not assemble at every sample.
    """

    name: str
    kind: str
    nominal: float
    values: np.ndarray

    _read_only = ("values",)

    def __repr__(self) -> str:
        return (f"<StrokeSpread of {short_name(self.name)}: nominal {self.nominal:.6g}, "
                f"mean {self.mean:.6g}, std {self.std:.3g}>")

    @property
    def assembled(self) -> np.ndarray:
        """Return the strokes of the variants that assemble at every sample."""
        return self.values[np.isfinite(self.values)]

    @property
    def mean(self) -> float:
        """Return the mean stroke (NaN if no variant assembles)."""
        v = self.assembled
        return float(v.mean()) if v.size else math.nan

    @property
    def std(self) -> float:
        """Return the standard deviation of the stroke."""
        v = self.assembled
        return float(v.std()) if v.size else math.nan

    def percentile(self, q: ArrayLike) -> np.ndarray:
        """Return percentiles of the stroke (``q`` from 0 to 100), over every assembled variant."""
        v = self.assembled
        levels = np.asarray(q, dtype=float)
        return np.percentile(v, levels) if v.size else np.full(levels.shape, np.nan)

    def to_dict(self, *, degrees: bool = False, bins: int = 20) -> dict[str, Any]:
        """Return the spread as plain data, with a histogram of ``bins`` bins.

        With ``degrees``, an angle's figures are in degrees.
        """
        scale = math.degrees(1) if degrees and self.kind == "angle" else 1.0
        v = self.assembled * scale
        if not v.size:
            counts, edges = np.zeros(0, int), np.zeros(0)
        elif np.ptp(v) <= 1e-9 * max(1.0, float(np.abs(v).max())):  # the same in every variant
            counts, edges = np.array([v.size]), np.array([v.min(), v.max()])
        else:
            counts, edges = np.histogram(v, bins=bins)
        p5, p50, p95 = self.percentile([5, 50, 95]) * scale
        return _plain({
            "kind": self.kind, "unit": ("deg" if degrees else "rad") if self.kind == "angle"
            else "length", "nominal": self.nominal * scale, "mean": self.mean * scale,
            "std": self.std * scale, "min": v.min() if v.size else math.nan,
            "max": v.max() if v.size else math.nan, "p5": p5, "p50": p50, "p95": p95,
            "histogram": {"edges": edges, "counts": counts}})


@dataclass(frozen=True, eq=False)
class Tolerance(Frozen):
    """The result of a tolerance study (:func:`tolerance`).

    Attributes
    ----------
    construction : Compiled
        The nominal design.
    tolerances : mapping of str to float
        Each drawn parameter's tolerance T, in the construction's units.
    distribution : {"normal", "uniform"}
    seed : int
        The seed the variants were drawn from (:func:`draw_variants`).
    nominal : Sweep
        The nominal design's sweep.
    assembled : ndarray of bool, shape (V,)
        Whether each variant assembles at every sample.
    valid_fraction : ndarray, shape (N,)
        The fraction of variants that assemble at each sample.
    failures : mapping of str to int
        The variants that do not assemble, by the node that fails first
        along their sweep.
    paths : mapping of str to PathSpread
        Each studied point's deviation from its nominal path.
    strokes : mapping of str to StrokeSpread
        The stroke of each moving link's angle and each slider's position.
    sensitivity : mapping of str to tuple of (str, float)
        For each output (``"<point>.path"`` and each stroke), every
        parameter with the output's derivative with respect to it, from
        central differences at the nominal design, times its tolerance:
        the first-order change the tolerance alone makes. Largest first by
        size. A path's is the root mean square over the samples of the
        length of its derivative (so never negative); a stroke's is signed.
        NaN for a parameter whose small change does not assemble.
    sample_paths : mapping of str to ndarray, shape (K, N, 2)
        The whole paths of the first K variants, for drawing (NaN where
        they do not assemble).
    percentile_variants : int
        How many variants the percentiles of the paths were taken from.
    """

    construction: Compiled
    tolerances: Mapping[str, float]
    distribution: str
    seed: int
    nominal: Sweep
    assembled: np.ndarray
    valid_fraction: np.ndarray
    failures: Mapping[str, int]
    paths: Mapping[str, PathSpread]
    strokes: Mapping[str, StrokeSpread]
    sensitivity: Mapping[str, tuple[tuple[str, float], ...]]
    sample_paths: Mapping[str, np.ndarray]
    percentile_variants: int

    _read_only = ("tolerances", "assembled", "valid_fraction", "failures", "paths", "strokes",
                  "sensitivity", "sample_paths")

    def __repr__(self) -> str:
        tolerances = ", ".join(f"{k} ±{v:g}" for k, v in self.tolerances.items())
        return (f"<Tolerance of {short_name(self.construction.name)}: {self.variants:,} "
                f"variants, {100 * self.assemblable_fraction:.1f}% assemble; {tolerances} "
                f"({self.distribution})>")

    @property
    def variants(self) -> int:
        """Return the number of variants V."""
        return int(self.assembled.size)

    @property
    def assemblable_fraction(self) -> float:
        """Return the fraction of variants that assemble at every sample."""
        return float(self.assembled.mean())

    @property
    def assemblable_error(self) -> float:
        """Return the standard error of :attr:`assemblable_fraction` (binomial)."""
        f = self.assemblable_fraction
        return math.sqrt(f * (1 - f) / self.variants)

    def draws(self, start: int = 0, stop: int | None = None) -> dict[str, np.ndarray]:
        """Return the parameter values of variants ``start`` to ``stop - 1`` (all by default)."""
        stop = self.variants if stop is None else stop
        return draw_variants(self.construction.parameters, self.tolerances, self.seed,
                             start, stop, self.distribution)

    def to_dict(self, *, degrees: bool = False) -> dict[str, Any]:
        """Return the study as plain data, what ``geokin tolerance --json`` prints.

        With ``degrees``, angle inputs and the strokes of link angles (and
        their sensitivities) are in degrees; otherwise radians.
        """
        c = self.construction
        inputs = {name: np.degrees(v) if degrees and c.inputs[name].kind == "angle" else v
                  for name, v in self.nominal.inputs.items()}
        scale = {f"{p}.path": 1.0 for p in self.paths}
        for name, spread in self.strokes.items():
            scale[name] = math.degrees(1) if degrees and spread.kind == "angle" else 1.0
        return _plain({
            "construction": c.name,
            "variants": self.variants,
            "seed": self.seed,
            "distribution": self.distribution,
            "tolerances": dict(self.tolerances),
            "nominal": {name: c.parameters[name] for name in self.tolerances},
            "assemblable_fraction": self.assemblable_fraction,
            "assemblable_error": self.assemblable_error,
            "assembled_variants": int(self.assembled.sum()),
            "failures": dict(self.failures),
            "inputs": inputs,
            "valid_fraction": self.valid_fraction,
            "paths": {p: spread.to_dict() for p, spread in self.paths.items()},
            "strokes": {k: spread.to_dict(degrees=degrees) for k, spread in self.strokes.items()},
            "sensitivity": {out: [{"parameter": p, "value": v * scale[out]} for p, v in ranked]
                            for out, ranked in self.sensitivity.items()},
            "percentile_variants": self.percentile_variants,
        })


def envelope_outline(result: Tolerance, point: str, *, which: str = "envelope"):
    """Return the region within the envelope of a point's path, as a shapely geometry.

    The union, over consecutive samples, of the hull of the discs centred on
    the nominal positions with radii the deviation ``which`` (``"envelope"``,
    ``"median"``, ``"mean"`` or ``"worst"``) there: the band in which the
    variants' paths lie.

    Examples
    --------
    >>> import geokin
    >>> c = geokin.load(f"{geokin.__path__[0]}/../constructions/fourbar_open.toml")
    >>> t = tolerance(c, {"c": 0.2}, n=50, seed=0)
    >>> band = envelope_outline(t, "B")
    >>> band.geom_type, band.area > 0
    ('Polygon', True)
    """
    import shapely

    spread = result.paths[point]
    radius = np.asarray(getattr(spread, which), dtype=float)
    xy = np.asarray(result.nominal[point])
    ok = np.isfinite(radius) & np.isfinite(xy).all(axis=1)
    radius = np.maximum(np.where(ok, radius, 0.0), 1e-12)
    discs = shapely.buffer(shapely.points(np.where(ok[:, None], xy, 0.0)), radius, quad_segs=8)
    pieces = shapely.convex_hull(shapely.union(discs[:-1], discs[1:])) if len(xy) > 1 else discs
    both = ok[:-1] & ok[1:] if len(xy) > 1 else ok
    return shapely.union_all(pieces[both])


# -- the study --------------------------------------------------------------------------


def _check_tolerances(compiled: Compiled, tolerances: Mapping[str, float]) -> dict[str, float]:
    if not isinstance(tolerances, Mapping) or not tolerances:
        raise AnalysisError("a tolerance study needs at least one parameter with its "
                            "tolerance, such as {'a': 0.1}")
    names = list(compiled.parameters)
    checked: dict[str, float] = {}
    for name, value in tolerances.items():
        if name not in compiled.parameters:
            where = (" (it is an input)" if name in compiled.inputs
                     else " (it is a point)" if name in compiled.point_names else "")
            listed = f"parameters: {', '.join(names)}" if names else \
                "the construction has no parameters: give its lengths names in [parameters]"
            raise ConstructionError(f"cannot tolerance {quote(name)}{where}: no such parameter"
                                    f"{did_you_mean(name, names)} ({listed})", node=name,
                                    kind="parameter")
        try:
            # text and truth values convert to numbers, but are not tolerances
            if isinstance(value, str | bytes | bool | np.bool_):
                raise TypeError
            half = float(value)
        except (TypeError, ValueError):
            raise AnalysisError(f"the tolerance of {quote(name)} must be a number, got "
                                f"{value!r}") from None
        if not (math.isfinite(half) and half > 0):
            raise AnalysisError(f"the tolerance of {quote(name)} must be a positive number, "
                                f"got {half:g}")
        checked[name] = half
    return checked


def _studied_points(compiled: Compiled, points: Iterable[str] | None) -> tuple[str, ...]:
    names = compiled.point_names
    if points is None:
        chosen = compiled.traced or tuple(p for p in names if p not in compiled.ground)
    else:
        chosen = tuple(points)
    for p in chosen:
        if p not in names:
            raise ConstructionError(f"no point {quote(p)}{did_you_mean(p, names)} to study",
                                    node=p)
    return tuple(dict.fromkeys(chosen))


def _sensitivity(compiled: Compiled, inputs, tolerances: dict[str, float], points, outputs,
                 references, closed: bool = False) -> dict[str, tuple[tuple[str, float], ...]]:
    """Return each output's central differences times tolerance, ranked (one sweep of 2P)."""
    names = list(tolerances)
    steps = np.array([tolerances[p] * SENSITIVITY_STEP for p in names])
    values = {p: np.full(2 * len(names), compiled.parameters[p]) for p in names}
    for j, p in enumerate(names):
        values[p][2 * j] += steps[j]
        values[p][2 * j + 1] -= steps[j]
    s = sweep(compiled, inputs, parameters=values)
    ok: np.ndarray = np.asarray(np.asarray(s.valid).all(axis=1), dtype=bool)
    both = ok[0::2] & ok[1::2]
    result: dict[str, list[tuple[str, float]]] = {}
    for point in points:
        xy = np.asarray(s[point])
        rate = (xy[0::2] - xy[1::2]) / (2 * steps[:, None, None])
        with np.errstate(all="ignore"):
            # NaN, not a warning, for a design that assembles nowhere (never ranked)
            square = (rate ** 2).sum(axis=2)
            rms = np.sqrt(np.nansum(square, axis=1) / np.sum(~np.isnan(square), axis=1))
        result[f"{point}.path"] = [(p, float(rms[j] * tolerances[p]) if both[j] else math.nan)
                                   for j, p in enumerate(names)]
    for output in outputs:
        stroke = _strokes(s.points.coords, output, references[output.name], closed=closed)
        rate = (stroke[0::2] - stroke[1::2]) / (2 * steps)
        result[output.name] = [(p, float(rate[j] * tolerances[p]) if both[j] else math.nan)
                               for j, p in enumerate(names)]
    return {out: tuple(sorted(ranked, key=lambda item: -abs(item[1])
                              if math.isfinite(item[1]) else math.inf))
            for out, ranked in result.items()}


def _chunks(count: int, chunk_size: int) -> list[tuple[int, int]]:
    return [(lo, min(lo + chunk_size, count)) for lo in range(0, count, chunk_size)]


def _in_process(study: _Study, chunks: Sequence[tuple[int, int]]) -> Iterator[_Block]:
    for lo, hi in chunks:
        yield from evaluate_chunk(study, lo, hi)


def _on_cluster(client: Any, study: _Study,
                chunks: Sequence[tuple[int, int]]) -> Iterator[_Block]:
    """Evaluate the chunks on a dask.distributed cluster; yield their blocks in order."""
    distributed = dask_distributed()
    shared = client.scatter(study, broadcast=True, hash=False)
    futures = [client.submit(evaluate_chunk, shared, lo, hi, pure=False) for lo, hi in chunks]
    index = {future.key: i for i, future in enumerate(futures)}
    done: dict[int, list[_Block]] = {}
    following = 0
    try:
        for future in distributed.as_completed(futures):
            done[index[future.key]] = future.result()
            future.release()
            while following in done:  # combined in the order of the chunks, whoever ran them
                yield from done.pop(following)
                following += 1
    finally:
        client.cancel(futures)


def dask_distributed() -> Any:
    """Return the ``dask.distributed`` module, or say which extra installs it.

    Raises
    ------
    GeokinError
        Without dask.distributed, naming ``pip install 'geokin[dask]'``.
    """
    try:
        import dask.distributed as distributed
    except ImportError:
        raise GeokinError("running on a cluster needs dask.distributed: pip install "
                          "'geokin[dask]'") from None
    return distributed


WORKER_ENVIRONMENT = {"MALLOC_TRIM_THRESHOLD_": 2**30, "MALLOC_MMAP_THRESHOLD_": 2**25}
"""What :func:`local_cluster` sets in its workers' environment: dask's own
``MALLOC_TRIM_THRESHOLD_`` of 64 KiB gives every block's arrays back to the
system and faults them in again, which makes a block two to three times
slower; these keep arrays of up to 32 MiB on the heap, to be reused."""


QUIET_CLUSTER = {"distributed.worker.profile.enabled": False,
                 "distributed.admin.system-monitor.gil.enabled": False,
                 "distributed.admin.system-monitor.interval": "2s",
                 "distributed.admin.tick.interval": "1s"}
"""The dask settings :func:`local_cluster` runs with. It has no dashboard to
show what dask samples by default: each worker's stack every 10 ms, the
event loops' health every 20 ms, the processes' use of the machine every
0.5 s (here every 2 s, as dask still reads memory from it), and the GIL
every 1 ms where ``gilknocker`` is installed. Idle, that sampling took about
a tenth of a 2-core machine."""


def _imported() -> None:
    """Import this module, and with it geokin (run on each worker once started)."""
    importlib.import_module(__name__)


@contextlib.contextmanager
def local_cluster(workers: int) -> Iterator[Any]:
    """Start a ``dask.distributed`` cluster of worker processes here; yield its client.

    One thread a worker, no dashboard, the workers' memory allocator set by
    :data:`WORKER_ENVIRONMENT`, dask's sampling by :data:`QUIET_CLUSTER`;
    each worker has imported geokin before the client is yielded, so that
    the first study does not wait on one. The cluster is closed on leaving.

    Examples
    --------
    >>> import geokin
    >>> with local_cluster(2) as client:  # doctest: +SKIP
    ...     t = geokin.tolerance(geokin.load("fourbar.toml"), {"a": 1}, client=client)
    """
    distributed = dask_distributed()
    import dask

    environ = {**dask.config.get("distributed.nanny.pre-spawn-environ", {}),
               **WORKER_ENVIRONMENT}
    with dask.config.set({"distributed.nanny.pre-spawn-environ": environ, **QUIET_CLUSTER}):
        # no dashboard; the scheduler's own HTTP server (health, metrics) on any
        # free port, not dask's 8787, which another cluster may hold
        cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1,
                                           processes=True, dashboard_address=None,
                                           scheduler_kwargs={"dashboard_address": ":0"},
                                           silence_logs=logging.ERROR)
    try:
        with distributed.Client(cluster) as client:
            client.run(_imported)
            yield client
    finally:
        cluster.close()


def tolerance(construction: Construction | Compiled, tolerances: Mapping[str, float], *,
              n: int = 1000, seed: int = 0, distribution: str = "normal",
              values: ArrayLike | Mapping[str, ArrayLike] | None = None,
              samples: int | None = None, points: Iterable[str] | None = None,
              level: float = 95.0, client: Any = None,
              chunk_size: int = CHUNK_BLOCKS * BLOCK_VARIANTS) -> Tolerance:
    """Study how the tolerances of some parameters spread a construction's motion.

    Each named parameter is drawn around its nominal value, independently
    of the others, for each of ``n`` variants; every variant is swept over
    the same input samples (each tracked along its own samples, starting on
    the nominal design's declared branches).

    Parameters
    ----------
    construction : Construction or Compiled
        The nominal design.
    tolerances : mapping of str to float
        By parameter name, its tolerance T > 0: the half-width of the
        interval ``nominal ± T``, in the parameter's own units (a parameter
        that a script uses as an angle holds the script's degrees).
    n : int
        The number of variants.
    seed : int
        Variant ``i`` is drawn from the seed and ``i`` alone
        (:func:`draw_variants`).
    distribution : {"normal", "uniform"}
        ``"normal"``: standard deviation T / 3 (T is three standard
        deviations); ``"uniform"``: anywhere in ``nominal ± T``.
    values, samples
        The input samples, as :func:`geokin.sweep` takes them; by default
        each input's declared range.
    points : iterable of str, optional
        The points whose paths are studied: the traced points by default,
        or every moving point if none is traced.
    level : float
        The percentile of the envelope of the paths (see :class:`PathSpread`).
    client : dask.distributed.Client, optional
        Evaluate the variants on this cluster's workers instead of here, in
        chunks of ``chunk_size`` variants; the figures are the same.
    chunk_size : int
        Variants per task on a cluster, rounded up to a multiple of
        :data:`BLOCK_VARIANTS` (it does not change the figures).

    Returns
    -------
    Tolerance

    Raises
    ------
    ConstructionError
        For a name that is not a parameter (the message lists the parameters)
        or a point that does not exist.
    AnalysisError
        For a tolerance that is not a positive number, or a bad ``n``,
        ``seed``, ``distribution`` or ``level``.
    AssemblyError
        If the nominal design cannot be assembled at any sample.
    GeokinError
        For ``client`` without dask.distributed installed.

    Examples
    --------
    >>> import geokin
    >>> c = geokin.load(f"{geokin.__path__[0]}/../constructions/fourbar_open.toml")
    >>> t = tolerance(c, {"a": 3, "b": 3, "c": 3, "d": 3}, n=2000, seed=4)
    >>> t.assemblable_fraction, round(t.assemblable_error, 4)
    (0.8685, 0.0076)
    >>> t.failures                          # the variants that do not, by the node that fails
    mappingproxy({'B': 263})
    """
    compiled = as_compiled(construction)
    checked = _check_tolerances(compiled, tolerances)
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise AnalysisError(f"the number of variants must be a positive integer, got {n!r}")
    seed = _check_seed(seed)
    if distribution not in DISTRIBUTIONS:
        raise AnalysisError(f"unknown distribution {distribution!r}"
                            f"{did_you_mean(str(distribution), DISTRIBUTIONS)}; use "
                            f"{' or '.join(map(repr, DISTRIBUTIONS))}")
    if not 0 < level < 100:
        raise AnalysisError(f"the envelope's percentile must be between 0 and 100, got {level}")
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, numbers.Integral) \
            or chunk_size < 1:
        raise AnalysisError(f"the chunk size must be a positive integer, got {chunk_size!r}")
    chunk_size = -(-int(chunk_size) // BLOCK_VARIANTS) * BLOCK_VARIANTS
    inputs, _ = input_arrays(compiled, values, samples)
    studied = _studied_points(compiled, points)
    nominal = sweep(compiled, inputs).require_assembled()
    outputs = _outputs(compiled)
    references = {o.name: _reference(nominal, o) for o in outputs}
    closed = _closes(compiled, inputs)
    # a stroke of a design that does not assemble at every sample is none, as a variant's
    # is: a crank that cannot turn has no stroke of 360 degrees
    whole = bool(np.asarray(nominal.valid).all())
    nominal_strokes = {o.name: float(_strokes(nominal.points.coords, o, references[o.name],
                                              closed=closed)[0]) if whole else math.nan
                       for o in outputs}
    study = _Study(compiled, inputs, checked, distribution, seed, studied,
                   {p: np.asarray(nominal[p]) for p in studied}, outputs, references,
                   PERCENTILE_VARIANTS, SAMPLE_PATHS, closed)
    count = int(n)
    chunks = _chunks(count, chunk_size)
    blocks = _in_process(study, chunks) if client is None else _on_cluster(client, study,
                                                                            chunks)
    totals = _Totals(study, len(nominal))
    for block in blocks:
        totals.add(block)
    return _result(study, totals, nominal, nominal_strokes, count, level,
                   _sensitivity(compiled, inputs, checked, studied, outputs, references,
                                closed))


def _result(study: _Study, totals: _Totals, nominal: Sweep, nominal_strokes, count: int,
            level: float, sensitivity) -> Tolerance:
    compiled = study.construction
    paths = {}
    kept_count = 0
    for p in study.points:
        kept = (np.concatenate(totals.kept[p]) if totals.kept[p]
                else np.zeros((0, len(nominal))))
        kept_count = kept.shape[0]
        if kept.shape[0]:
            with np.errstate(all="ignore"):
                median, envelope = np.percentile(kept, [50, level], axis=0)
        else:
            median = envelope = np.full(len(nominal), np.nan)
        std = (np.sqrt(totals.m2[p] / totals.count) if totals.count
               else np.full(len(nominal), np.nan))
        mean = totals.mean[p] if totals.count else np.full(len(nominal), np.nan)
        worst = np.where(np.isneginf(totals.worst[p]), np.nan, totals.worst[p])
        paths[p] = PathSpread(p, mean, std, median, envelope, worst,
                              totals.worst_variant[p][1], float(level))
    strokes = {o.name: StrokeSpread(o.name, o.kind, nominal_strokes[o.name],
                                    np.concatenate(totals.strokes[o.name]))
               for o in study.outputs}
    names = {step.index: step.node.name for step in compiled.steps}
    failures = {names[i]: int(k) for i, k in enumerate(totals.failures) if i and k}
    sample_paths = {p: np.concatenate(totals.paths[p]) for p in study.points}
    return Tolerance(compiled, study.tolerances, study.distribution, study.seed, nominal,
                     np.concatenate(totals.assembled), totals.valid_count / count, failures,
                     paths, strokes, sensitivity, sample_paths, kept_count)
