"""Velocity and acceleration of every point and link, by finite differences.

The derivatives with respect to the input come from evaluating the
construction again at small perturbations ``q + k*h`` around each sample,
on that sample's branches, all samples of a block in one vectorized pass.
So their accuracy does not depend on how coarse the sweep is, and a
derivative never reaches across a branch change or an unassemblable
stretch. Every sample is evaluated at k = -1, 1, 2 (three evaluations a
sample); the few whose estimated truncation error is not far below the
accuracy stated (near a singular position, where the rates grow fast) again
at k = -2, -1, 1, 2; and where the perturbed construction cannot be
assembled on one side, or those cannot, a one-sided stencil is used there
(k = 1..4 or -1..-4).

Stencils (f_k = f(q + k h)):

* quick, on every sample: ``f' = (-2 f_-1 - 3 f_0 + 6 f_1 - f_2) / 6h``,
  third order, and ``f'' = (f_-1 - 2 f_0 + f_1) / h^2``, second order;
* central, fourth order, where the quick one's error is above
  1/:data:`REFINED_BELOW` of the accuracy stated: ``f' = (f_-2 - 8 f_-1 +
  8 f_1 - f_2) / 12h`` and ``f'' = (-f_-2 + 16 f_-1 - 30 f_0 + 16 f_1 -
  f_2) / 12h^2``;
* one-sided, fourth and third order, on f_0..f_4 or f_0..f_-4.

Error estimates
---------------
Every sample gets an estimate of the error of its derivatives
(:attr:`Derivatives.first_error`, :attr:`Derivatives.second_error`, the
largest over the points), plus the rounding of positions over the step.
For the central and one-sided stencils it comes from comparing each value
with a lower-order one on the same evaluations: their difference is the
lower order's error, and the higher order's is smaller by about the ratio of
the step to the distance to the nearest singular position, read from those
differences (``_Estimate``). For the quick stencil it is extrapolated from
the third difference ``f_2 - 3 f_1 + 3 f_0 - f_-1`` (about ``h**3 f'''``)
with that ratio (:meth:`_Block.quick`). Each point's ratio is read from its
own derivatives, so that a large point moving regularly does not hide a
small one near its toggle. A
sample is flagged (:attr:`Motion.flagged`) where the estimated error of
some point's velocity exceeds :data:`VELOCITY_RTOL` of the speed of the
fastest point at that sample, or of its acceleration
:data:`ACCELERATION_RTOL` of the largest acceleration there (or of that speed
squared over the mechanism's size, if larger), and likewise for the angular
rates of links against the fastest-turning link; where no stencil can be
assembled; and near a singular position (:data:`SINGULAR_MARGIN`), where the
rates grow without bound and no estimate is to be trusted.

The step
--------
``h`` is :data:`RELATIVE_STEP` radians for an angle input, and that
fraction of the mechanism's size (the largest extent of its points over the
sweep) for a length input. Along a motion in time, the step in time moves no
input by more than its own ``h``. With this step the rounding of positions
(about 1e-16 of the mechanism's size) gives errors near 1e-12 of the size in
velocities and 1e-8 in accelerations. The quick stencil's truncation is
larger, typically 1e-10 to 1e-9 of the fastest speed and 1e-8 to 2e-7 of the
largest acceleration, and never above 1/:data:`REFINED_BELOW` of the
accuracy stated: beyond, near singular positions, the central stencil takes
over, and the estimate flags the samples it cannot make accurate.

Time derivatives follow by the chain rule from the input's rate
(``speed``, radians or length units per second) and its acceleration:
``v = p' * speed`` and ``a = p'' * speed**2 + p' * acceleration``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from contextlib import nullcontext
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from . import display
from .budgets import check_sweep_memory
from .compat import renamed_attribute, renamed_keywords
from .construction import Slider
from .engine import BLOCKED_ABOVE, MEET_RTOL, assembly_guesses, evaluate, kept_memory, meeting_rtol
from .errors import ConstructionError
from .frozen import Frozen, read_only
from .primitives import nearby_rows
from .results import Sweep, short_name

__all__ = ["GUIDE_RTOL", "Derivatives", "Motion", "input_derivatives", "link_angles", "motion",
           "slider_offsets", "slider_positions", "sliders_off_guide", "unwrap_valid"]

RELATIVE_STEP = 2e-4
"""The perturbation h: this many radians for an angle input, and this
fraction of the mechanism's size for a length input."""

SINGULAR_MARGIN = 1e-5
"""Samples where a two-root node's margin (squared half-chord over squared
scale) falls below this are flagged as near a singular position."""

VELOCITY_RTOL = 1e-7
"""The accuracy stated for velocities (and first derivatives): a sample whose
estimated error exceeds this times the sweep's largest speed is flagged."""

ACCELERATION_RTOL = 1e-5
"""The accuracy stated for accelerations (and second derivatives), relative to
the sweep's largest acceleration."""

SAMPLES_PER_BLOCK = BLOCKED_ABOVE // 16
"""Samples differentiated together, 2**13: their three perturbations (four in a
frame of their own) are evaluated in one piece (below :data:`BLOCKED_ABOVE`),
few enough that a block's arrays (about 200 kB each) stay in the cache and
enough that Python's cost per block stays small. Blocks of 2**14 took 15 to
25% longer at 36,000 samples, in a fresh process as after a large sweep."""

QUICK = (-1, 1, 2)
"""The perturbations every sample is evaluated at first, in steps: with the
sample itself, a third-order first derivative and a second-order second one,
and an estimate of their error from the third difference."""

CENTRAL = (-2, -1, 1, 2)
"""The perturbations of the fourth-order central stencil, in steps: for the
samples where the error of the first is not far below the accuracy stated."""

# a block of the quick stencil (and the sample itself, in a frame of its own) must be
# evaluated in one piece for nearby_rows to apply, so that a sample's derivatives do
# not depend on how the samples were cut
assert (len(QUICK) + 1) * SAMPLES_PER_BLOCK <= BLOCKED_ABOVE

FORWARD, BACKWARD = (1, 2, 3, 4), (-1, -2, -3, -4)
"""The perturbations of the one-sided stencils, in steps."""

_EPS = np.finfo(float).eps

POSITION_ROUNDING = 4.0
"""How many units in the last place of the mechanism's size a computed position
is taken to be off by, for the rounding part of the error estimate."""

ERROR_FACTOR = 20.0
"""How much larger than the model of :class:`_Estimate` the error of a
fourth-order derivative is taken to be (the model gives 4 near a pole and
14 near a square root)."""

QUICK_ERROR_FACTORS = (5.0, 1.0)
"""The errors of the quick stencil's first and second derivatives over
``(h / d) * third / 6h`` and ``(h / d) * third / h**2`` (see
:meth:`_Block.quick`): with ``h / d`` read as there, the truncation errors
are 0.83 and 0.14 of these near a square root (a toggle), 0.67 and 0.11
near a pole, so the factors leave margins of 6 and 7."""

REFINED_BELOW = 10.0
"""A sample whose quick derivatives may be off by more than the accuracy stated
over this is differentiated again on :data:`CENTRAL`: only near a singular
position, where the derivatives grow fast."""

# the rounding of the positions, in units of eps * size / h (or / h**2): the root
# sum of squares of each stencil's weights, the rounding of each position taken
# independent
ROUNDING_QUICK = (np.sqrt(2**2 + 3**2 + 6**2 + 1) / 6, np.sqrt(6))
ROUNDING_CENTRAL = (np.hypot(np.hypot(1, 8), np.hypot(8, 1)) / 12,
                    np.sqrt(1 + 16**2 + 30**2 + 16**2 + 1) / 12)
ROUNDING_ONE_SIDED = (np.sqrt(25**2 + 48**2 + 36**2 + 16**2 + 3**2) / 12,
                      np.sqrt(35**2 + 104**2 + 114**2 + 56**2 + 11**2) / 12)


@dataclass(frozen=True)
class Derivatives(Frozen):
    """First and second derivatives of every point with respect to one input.

    Attributes
    ----------
    input_name : str
        The input differentiated by (for derivatives along a motion, the
        driving input).
    step : float
        The perturbation h used.
    first, second : dict of str to ndarray, shape (N, 2)
        dp/dq and d2p/dq2 (q the input, radians for an angle); NaN where the
        construction cannot be assembled around the sample.
    stencil : ndarray of int8, shape (N,)
        0 central (on -h, h and 2h, with -2h near a singular position),
        1 forward, -1 backward, 2 none (NaN).
    first_error, second_error : ndarray, shape (N,)
        The estimated error of the first and second derivatives at each
        sample, the largest over the points (NaN where there is no stencil).
    first_errors, second_errors : dict of str to ndarray, shape (N,)
        Each point's own estimated errors (0 for a point that does not move):
        its truncation, and the rounding of positions of the mechanism's size.
        Estimates are to be trusted only at unflagged samples.

    For design variants every array has a leading axis of variants: (V, N)
    and (V, N, 2).
    """

    input_name: str
    step: float
    first: dict
    second: dict
    stencil: np.ndarray
    first_error: np.ndarray
    second_error: np.ndarray
    first_errors: dict
    second_errors: dict

    input = renamed_attribute("input", "input_name")
    _read_only = ("first", "second", "stencil", "first_error", "second_error", "first_errors",
                  "second_errors")

    def __repr__(self) -> str:
        missing = int(np.count_nonzero(self.stencil == 2))
        return (f"<Derivatives by {short_name(self.input_name)}: {len(self.stencil)} samples, "
                f"step {self.step:.3g}, {missing} without a stencil>")


def _size(sweep: Sweep) -> float:
    """Return the mechanism's size: the largest extent of its points over the sweep."""
    return float(_variant_sizes(sweep.flat())[0])


def _variant_sizes(sweep: Sweep) -> np.ndarray:
    """Return :func:`_size` of each variant of a sweep, (V,); one value for one design.

    The largest extent of the points over the variant's samples, where
    any of them is assembled; else the largest coordinate, else 1.
    """
    if sweep.variants is None:
        return np.array([_design_size(sweep)])
    rows = sweep.variants
    low, high = np.full((rows, 2), np.inf), np.full((rows, 2), -np.inf)
    for name in sweep.construction.point_names:
        for axis, values in enumerate(sweep.points.coords(name)):
            if np.ndim(values) == 0:  # a point that does not move
                low[:, axis] = np.fmin(low[:, axis], values)
                high[:, axis] = np.fmax(high[:, axis], values)
                continue
            values = np.broadcast_to(values, sweep.valid.shape).reshape(rows, -1)
            low[:, axis] = np.fmin(low[:, axis], _leaving_nan(np.minimum, np.fmin, values))
            high[:, axis] = np.fmax(high[:, axis], _leaving_nan(np.maximum, np.fmax, values))
    unassembled = ~sweep.valid.reshape(rows, -1).any(axis=1)
    low[unassembled], high[unassembled] = np.inf, -np.inf
    with np.errstate(invalid="ignore"):
        spans = high - low
        size = np.where(np.isfinite(spans).all(axis=1), spans.max(axis=1), 0.0)
        largest = np.where(np.isfinite(low).all(axis=1),
                           np.abs(np.c_[low, high]).max(axis=1), 0.0)
    return np.where(size > 0, size, np.where(largest > 0, largest, 1.0))


def _design_size(sweep: Sweep) -> float:
    """Return :func:`_variant_sizes` of a sweep of one design, on numbers."""
    low, high = [math.inf, math.inf], [-math.inf, -math.inf]
    if sweep.valid.any():
        for name in sweep.construction.point_names:
            for axis, values in enumerate(sweep.points.coords(name)):
                if np.ndim(values):
                    least, most = np.minimum.reduce(values), np.maximum.reduce(values)
                    if least != least:  # NaN: leave it out
                        least, most = np.fmin.reduce(values), np.fmax.reduce(values)
                else:
                    least = most = values
                if least == least:  # what np.fmin and np.fmax keep
                    low[axis], high[axis] = min(low[axis], least), max(high[axis], most)
    spans = (high[0] - low[0], high[1] - low[1])
    size = max(spans) if all(map(math.isfinite, spans)) else 0.0
    largest = (max(abs(low[0]), abs(low[1]), abs(high[0]), abs(high[1]))
               if math.isfinite(low[0]) and math.isfinite(low[1]) else 0.0)
    return float(size if size > 0 else largest if largest > 0 else 1.0)


def _leaving_nan(fast: np.ufunc, careful: np.ufunc, values: np.ndarray) -> np.ndarray:
    """Reduce each row by ``careful``, which leaves NaN out, or by ``fast`` if it can.

    ``fast`` is taken where no NaN spoils it: ``np.minimum`` is several times
    faster than ``np.fmin``.
    """
    reduced = fast.reduce(values, axis=1)
    return reduced if not np.isnan(reduced).any() else careful.reduce(values, axis=1)


def _sizes(sweep: Sweep) -> np.ndarray:
    """Return each sample's mechanism size: :func:`_size` of its own variant.

    For a sweep of variants (V, N) each variant has its own size, given at
    each of its samples, (V * N,); for a sweep of one design, its size.
    """
    sizes = _variant_sizes(sweep)
    return np.array(sizes[0]) if sweep.variants is None else np.repeat(sizes, len(sweep))


def _step_for(sweep: Sweep, name: str, step: float | None) -> float:
    if step is not None:
        if not (np.isfinite(step) and step > 0):
            raise ConstructionError(f"the finite-difference step must be a positive number, "
                                    f"got {step!r}", node=name, field="step",
                                    kind="input")
        return float(step)
    if sweep.construction.inputs[name].kind == "angle":
        return RELATIVE_STEP
    return RELATIVE_STEP * _size(sweep)


@renamed_keywords(input="input_name")
def input_derivatives(sweep: Sweep, input_name: str | None = None, *,
                      step: float | None = None) -> Derivatives:
    """Differentiate every point of a sweep with respect to one input.

    Parameters
    ----------
    sweep : Sweep
    input_name : str, optional
        The input to differentiate by; the only input by default.
    step : float, optional
        The perturbation h (radians or length units); see :data:`RELATIVE_STEP`.

    Returns
    -------
    Derivatives

    Examples
    --------
    A crank tip moves at its radius times the crank rate:

    >>> import numpy as np
    >>> from geokin import Construction, sweep
    >>> c = Construction()
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta")
    >>> d = input_derivatives(sweep(c, [0.0, np.pi / 2]))
    >>> d.first["A"].round(9)
    array([[ 0., 10.],
           [-10., 0.]])
    >>> bool(d.first_error.max() < 1e-7 * 10)
    True
    """
    compiled = sweep.construction
    name = compiled.resolve_input(input_name, purpose="differentiate by")
    h = _step_for(sweep, name, step)
    return _along(sweep, {name: np.ones(len(sweep))}, h, name)


def _along(sweep: Sweep, direction: dict, h: float, label: str,
           sizes: np.ndarray | None = None,
           largest: tuple[np.ndarray, np.ndarray] | None = None,
           frame: list | None = None, length: int | None = None,
           one_way: bool = False) -> Derivatives:
    """Differentiate every point along a direction in the inputs' space.

    The construction is evaluated again at ``inputs + k * h * direction`` on
    each sample's branches, :data:`SAMPLES_PER_BLOCK` samples at a time
    (past a change point on the path, on the branch the path has there: see
    :class:`_Path`; ``length`` samples a path, design variants one after the
    other, the whole sweep by default; ``one_way`` where the first input
    of ``direction`` is known to move one way along each);
    ``direction`` holds, per input, an array of its rate at each sample
    (inputs left out are held). ``sizes`` gives the mechanism's size at each
    sample where it differs from sample to sample (design variants).
    ``largest``, two arrays of N, receives each sample's largest squared
    first and second derivative over the points (0 where there are none);
    ``frame``, a list, receives the origin of the frame the sweep was
    evaluated in (None for its own, see :func:`_frame`).
    """
    compiled = sweep.construction
    n = len(sweep)
    if largest is None:
        largest = (np.empty(n), np.empty(n))
    names = compiled.point_names
    # the results and one block's evaluations: refused up front if they would not fit
    check_sweep_memory(2 * len(names), n, what="motion")
    size = _size(sweep) if sizes is None else float(np.max(sizes))
    middle, origin = _frame(sweep, size)
    if frame is not None:
        frame.append(origin)
    # the rounding of positions: a few units in the last place of their size in the
    # frame they are evaluated in
    distance = 0.0 if origin is not None else float(np.hypot(*middle))
    noise = POSITION_ROUNDING * _EPS * ((size if sizes is None else sizes) + distance)
    # a ground point does not move: its derivatives are zero wherever it is assembled
    moving = [p for p in names if p not in compiled.ground]
    still = (np.broadcast_to(np.zeros(2), (n, 2)) if sweep.valid.all()  # no memory
             else read_only(np.where(sweep.valid, 0.0, np.nan)[:, None] * np.ones(2)))
    # the moving points' derivatives and errors as rows of one array each, every
    # coordinate contiguous: the stencils work on all points at once
    firsts, seconds = np.empty((len(moving), 2, n)), np.empty((len(moving), 2, n))
    errors1, errors2 = np.empty((len(moving), n)), np.empty((len(moving), n))
    row = {p: i for i, p in enumerate(moving)}
    first = {p: (firsts[row[p]].T if p in row else still) for p in names}
    second = {p: (seconds[row[p]].T if p in row else still) for p in names}
    resting = still[:, 0]
    first_errors = {p: (errors1[row[p]] if p in row else resting) for p in names}
    second_errors = {p: (errors2[row[p]] if p in row else resting) for p in names}
    stencil = np.full(n, 2, dtype=np.int8)
    first_error, second_error = np.empty(n), np.empty(n)
    rates = {k: np.broadcast_to(np.asarray(r, dtype=float), (n,)) for k, r in direction.items()}
    # in another frame the sample itself is evaluated again: the sweep's own
    # positions carry the rounding of the far frame
    extra = () if origin is None else (0,)
    path = _Path(sweep, next(iter(direction)), n if length is None else length,
                 float(meeting_rtol(np.hypot(*middle) / size)) if size > 0 else MEET_RTOL,
                 one_way)
    work = None
    for lo in range(0, n, SAMPLES_PER_BLOCK):
        hi = min(lo + SAMPLES_PER_BLOCK, n)
        block = _Block(sweep, slice(lo, hi), rates, h, origin, noise, QUICK + extra, quick=True,
                       path=path)
        if work is None:
            # the quick stencil's differences, in memory kept from motion to motion
            shape = (4, len(moving), 2, min(n, SAMPLES_PER_BLOCK))
            work = kept_memory(math.prod(shape), "stencil").reshape(shape)
        ok = block.valid(QUICK + extra) & sweep.valid[lo:hi]
        into = _Into(firsts[:, :, lo:hi], seconds[:, :, lo:hi], first_error[lo:hi],
                     second_error[lo:hi], errors1[:, lo:hi], errors2[:, lo:hi],
                     (largest[0][lo:hi], largest[1][lo:hi]))
        again = block.quick(moving, into, _at(noise, slice(lo, hi)), work)
        stencil[lo:hi][ok] = 0
        # one-sided stencils where no central one can be assembled: few samples
        rest = lo + np.flatnonzero(~ok)
        # near a singular position: fourth order, where it can be assembled, else one-sided
        again = lo + np.flatnonzero(again & ok)
        if again.size:
            fine = _Block(sweep, again, rates, h, origin, noise, CENTRAL + extra, path=path)
            central = fine.valid(CENTRAL + extra)
            estimate = _Estimate(again[central], h)
            fine.central(central, moving, first, second, estimate)
            estimate.finish(first_error, second_error, _at(noise, estimate.at), ROUNDING_CENTRAL,
                            largest, first_errors, second_errors)
            rest = np.union1d(rest, again[~central])
        firsts[:, :, rest] = seconds[:, :, rest] = np.nan
        errors1[:, rest] = errors2[:, rest] = np.nan
        first_error[rest] = second_error[rest] = np.nan
        largest[0][rest] = largest[1][rest] = 0.0
        rest = rest[sweep.valid[rest]]
        if rest.size:
            side = _Block(sweep, rest, rates, h, origin, noise, FORWARD + BACKWARD + extra,
                          path=path)
            forward = side.valid(FORWARD + extra)
            backward = side.valid(BACKWARD + extra) & ~forward
            for sign, mask in ((1, forward), (-1, backward)):
                if mask.any():
                    estimate = _Estimate(rest[mask], sign * h)
                    side.one_sided(mask, sign, moving, first, second, estimate)
                    estimate.finish(first_error, second_error, _at(noise, estimate.at),
                                    ROUNDING_ONE_SIDED, largest, first_errors, second_errors)
            stencil[rest[forward]], stencil[rest[backward]] = 1, -1
    return Derivatives(label, h, first, second, stencil, first_error, second_error,
                       first_errors, second_errors)


def _frame(sweep: Sweep, size: float) -> tuple[np.ndarray, tuple[float, float] | None]:
    """Return a sweep's middle, and the origin of the frame it is differentiated in.

    The middle is the mean of its points at the first sample assembled. Where
    the mechanism lies more than four sizes from (0, 0), the frame's origin
    is its middle: differences of positions far from (0, 0) would lose the
    digits the rates need. Else there is no other frame (None).
    """
    middle = np.zeros(2)
    if sweep.valid.any():
        first_valid = int(np.argmax(sweep.valid))
        total = [0.0, 0.0]  # summed in order, as np.mean sums rows
        names = sweep.construction.point_names
        for p in names:
            for axis, c in enumerate(sweep.points.coords(p)):
                total[axis] += float(np.asarray(c).flat[first_valid] if np.ndim(c) else c)
        middle = np.array(total) / len(names)
    origin = (float(middle[0]), float(middle[1])) if np.hypot(*middle) > 4 * size else None
    return middle, origin


def _held(sweep: Sweep, at: slice | np.ndarray, times: int) -> dict:
    """Return a sweep's branches at some samples, repeated, to hold in an evaluation.

    A branch that never changes (a broadcast view) stays one number; a
    closure group, untracked there, starts at each sample from its own
    solution.
    """
    held: dict = {name: (int(b[0]) if b.strides == (0,) else np.tile(b[at], times))
                  for name, b in sweep.branches.items()}
    held.update(assembly_guesses(sweep, at, times))
    return held


class _Path:
    """Where along a sweep's path each two-root node changes branch, for its perturbations.

    A perturbation of a sample lies on the path's steps near it, or beyond
    the path (past its end, or past a sample where it turns back). On the
    path it takes the branch the path has there: the sample's own, changed
    at each change of branch (an event of the sweep, at its fraction of its
    step) between the sample and it, a few steps away for a dense sweep
    (the path taken to run one way that near). Beyond the path it takes the
    sample's branch, changed where the node's roots meet at the sample
    itself (within ``tolerance`` of its scale): the smooth motion through a
    change point. So a sample on a change point is differentiated on the
    motion, not across onto its other branch. ``length`` samples make a
    path; the input ``driver`` measures the steps, ``one_way`` where it
    is known to move one way along each path. What it looks at is found
    once: the events, sorted, so that a block of samples looks at those
    within its reach only, and the samples where a node's roots meet that a
    perturbation can pass the path's end at (its ends, and where it turns
    back or stands still).
    """

    def __init__(self, sweep: Sweep, driver: str, length: int, tolerance: float,
                 one_way: bool = False):
        self.driver = driver
        self.values = values = sweep.inputs[driver]
        n = len(values)
        length = max(int(length), 1)
        # each change of branch: its node, the step it is on (the sample after it), and
        # where along the input its roots meet; sorted by step
        kept = [e for e in sweep.events if e.node in sweep.branches and 0 < e.index < n]
        kept.sort(key=lambda e: e.index)
        self.nodes = list(sweep.branches)
        code = {name: i for i, name in enumerate(self.nodes)}
        self.event_codes = np.array([code[e.node] for e in kept], dtype=np.intp)
        self.event_steps = np.array([e.index for e in kept], dtype=np.intp)
        self.event_at = np.array([values[e.index - 1]
                                  + e.fraction * (values[e.index] - values[e.index - 1])
                                  for e in kept], dtype=float)
        self.event_on_sample = np.array([e.fraction == 0 for e in kept], dtype=bool)
        self.length = length
        # the shortest step the input takes: how many samples a perturbation can reach
        self.shortest = math.inf
        if kept:
            steps = np.abs(np.diff(values))
            moving = steps[steps > 0]
            self.shortest = float(moving.min()) if moving.size else math.inf
        # the samples a perturbation can pass the path's end at: the ends of each path,
        # and where it turns back or stands still (none along a path run one way)
        starts = np.arange(0, n, length)
        ends = [starts, np.minimum(starts + length - 1, n - 1)]
        if not one_way:
            way = np.sign(np.diff(values))
            way[length - 1::length] = 0  # no step from one path to the next
            ends.append(1 + np.flatnonzero(way[:-1] * way[1:] <= 0))
        candidates = np.unique(np.concatenate(ends))
        # of them, those where a node's roots meet, with the way from each to the next
        # sample elsewhere on its path, and to the last one elsewhere before it (0 where
        # there is none): repeated samples skipped
        meetings = []
        for node, margin in sweep.margins.items():
            if node not in sweep.branches:
                continue
            apart = np.sqrt(np.maximum(np.asarray(margin)[candidates], 0.0))
            for sample in candidates[apart <= tolerance]:
                place = sample % length
                meetings.append((int(sample), node,
                                 _way_to(values, sample, sample + length - place, 1),
                                 _way_to(values, sample, sample - place - 1, -1)))
        meetings.sort(key=lambda meeting: meeting[0])
        self.meeting_samples = np.array([mt[0] for mt in meetings], dtype=np.intp)
        self.meeting_codes = np.array([code[mt[1]] for mt in meetings], dtype=np.intp)
        self.meeting_ahead = np.array([mt[2] for mt in meetings], dtype=float)
        self.meeting_behind = np.array([mt[3] for mt in meetings], dtype=float)

    def branch_where(self, held: dict, at: slice | np.ndarray, perturbed: np.ndarray) -> None:
        """Give each perturbation, (K, M) values of the driver, its node's branch there.

        ``held`` holds each node's branch at the samples ``at``, repeated
        for the K perturbations (offset after offset); it is changed in place.
        """
        if not (self.event_steps.size or self.meeting_samples.size):
            return
        values = self.values
        k, m = perturbed.shape
        samples = (np.arange(*at.indices(len(values))) if isinstance(at, slice)
                   else np.asarray(at))
        # how many times each perturbation passes a change of branch, by node
        passes: dict[str, np.ndarray] = {}

        def count(nodes: np.ndarray, columns: np.ndarray, passed: np.ndarray) -> None:
            """Count ``passed`` (K, P), the perturbations at ``columns`` (P,), by node."""
            for code in np.unique(nodes):
                name = self.nodes[code]
                if name not in held:
                    continue
                mine = nodes == code
                if name not in passes:
                    passes[name] = np.zeros((k, m), dtype=np.int32)
                rows, which = np.nonzero(passed[:, mine])
                np.add.at(passes[name], (rows, columns[mine][which]), 1)

        # a change of branch between a sample and its perturbation along the path: the
        # events on the steps within their reach, a few samples for a dense sweep
        if self.event_steps.size:
            reach = float(np.max(np.abs(perturbed - values[samples]), initial=0.0))
            around = 1 + (int(math.ceil(reach / self.shortest)) if reach < math.inf else 0)
            first = np.searchsorted(self.event_steps, samples[0] - around + 1)
            last = np.searchsorted(self.event_steps, samples[-1] + around, side="right")
            steps = self.event_steps[first:last]
            # each event's samples within reach on its own path, as columns here
            starts = (steps - 1) // self.length * self.length
            los = np.searchsorted(samples, np.maximum(steps - around, starts))
            his = np.searchsorted(samples, np.minimum(steps - 1 + around,
                                                      starts + self.length - 1), side="right")
            many = np.maximum(his - los, 0)
            if many.any():
                # one pair per event and column it reaches
                event = first + np.repeat(np.arange(steps.size), many)
                offset = np.arange(int(many.sum())) - np.repeat(np.cumsum(many) - many, many)
                columns = np.repeat(los, many) + offset
                here = values[samples[columns]]
                t = perturbed[:, columns]
                meets = self.event_at[event]
                # roots meeting between the sample and the perturbation; at the sample
                # itself, for the perturbations the way the path goes on from it
                passed = (here - meets) * (t - meets) < 0
                way = np.sign(values[self.event_steps[event]] - meets)
                passed |= (self.event_on_sample[event] & (here == meets)
                           & (samples[columns] < self.event_steps[event])
                           & (np.sign(t - meets) == way))
                count(self.event_codes[event], columns, passed)
        # beyond the path where a node's roots meet: past its ends, and where it turns
        # back or stands still
        first = np.searchsorted(self.meeting_samples, samples[0])
        last = np.searchsorted(self.meeting_samples, samples[-1], side="right")
        if last > first:
            at_samples = self.meeting_samples[first:last]
            place = np.minimum(np.searchsorted(samples, at_samples), m - 1)
            here = samples[place] == at_samples
            chosen = first + np.flatnonzero(here)
            columns = place[here]
            side = np.sign(perturbed[:, columns] - values[self.meeting_samples[chosen]])
            beyond = ((side != 0) & (side != self.meeting_ahead[chosen])
                      & (side != self.meeting_behind[chosen]))
            count(self.meeting_codes[chosen], columns, beyond)
        for node, passed in passes.items():
            flipped = (passed % 2).astype(bool)
            if not flipped.any():
                continue
            branch = held[node]
            if np.ndim(branch) == 0:
                branch = np.full(k * m, int(branch), dtype=np.int8)
            branch = branch.reshape(k, m)
            branch[flipped] = 1 - branch[flipped]
            held[node] = branch.reshape(-1)


def _way_to(values: np.ndarray, sample: int, stop: int, step: int) -> float:
    """Return the sign of the way from ``sample`` to the next value elsewhere, 0 if none.

    The next values are looked at ``step`` by ``step`` (1 ahead, -1 behind)
    up to ``stop`` (excluded), the end of the sample's path.

    Examples
    --------
    >>> values = np.array([0.0, 1.0, 1.0, 0.5])
    >>> _way_to(values, 1, 4, 1), _way_to(values, 1, -1, -1), _way_to(values, 0, -1, -1)
    (-1.0, -1.0, 0.0)
    """
    for other in range(sample + step, stop, step):
        if values[other] != values[sample]:
            return float(np.sign(values[other] - values[sample]))
    return 0.0


def _in_frame(sweep: Sweep, origin: tuple[float, float]) -> Sweep:
    """Return a sweep evaluated again in the frame of ``origin``, on its own branches.

    Its positions are relative to ``origin``. Where the sweep is on the edge
    of assembling, rounding in the other frame may not assemble it: such a
    sample's rates are not found in either frame (see :func:`_along`).
    """
    # the motion's results and this sweep of them all
    compiled = sweep.construction
    check_sweep_memory(2 * len(compiled.point_names) + len(compiled.steps), len(sweep.valid),
                       what="motion")
    held = _held(sweep, slice(None), 1)
    return evaluate(sweep.construction, dict(sweep.inputs), len(sweep.valid), held, track=False,
                    origin=origin, parameters=dict(sweep.parameters))


def _at(value, at):
    """Return a number, or an array's values at some samples."""
    return value if np.ndim(value) == 0 else value[at]


@dataclass(frozen=True)
class _Into:
    """Where the stencils of some samples write: views of the results over them.

    ``first`` and ``second`` hold the moving points' derivatives, (P, 2, M),
    in the order of the points given to :meth:`_Block.quick`;
    ``first_error`` and ``second_error`` their estimated errors, the largest
    over the points, (M,); ``first_errors`` and ``second_errors`` each
    point's, (P, M); and ``largest`` the largest squared first and second
    derivative over the points, (M,) each.
    """

    first: np.ndarray
    second: np.ndarray
    first_error: np.ndarray
    second_error: np.ndarray
    first_errors: np.ndarray
    second_errors: np.ndarray
    largest: tuple[np.ndarray, np.ndarray]


class _Block:
    """The perturbed evaluations of some samples, and the stencils on them.

    ``at`` is a slice of the sweep's samples, or an array of their indices.
    """

    def __init__(self, sweep: Sweep, at: slice | np.ndarray, rates: dict, h: float,
                 origin: tuple[float, float] | None, noise: float | np.ndarray,
                 offsets: tuple[int, ...] = CENTRAL, quick: bool = False,
                 path: _Path | None = None):
        self.sweep, self.at, self.h, self.noise = sweep, at, h, noise
        self.offsets = offsets
        m, k = len(sweep.valid[at]), len(offsets)
        self.m = m
        # offset-major layout: sample i at the j-th offset sits at j * m + i
        steps = h * np.asarray(offsets, dtype=float)[:, None]
        inputs = {}
        for name, values in sweep.inputs.items():
            inputs[name] = ((values[at] + steps * rates[name][at]).reshape(-1) if name in rates
                            else np.tile(values[at], k))
        held = _held(sweep, at, k)
        if path is not None:
            path.branch_where(held, at, inputs[path.driver].reshape(k, m))
        varied = {name: np.tile(values[at], k) for name, values in sweep.parameters.items()}
        # the quick stencil's perturbations are rows of nearby inputs, evaluated in one
        # piece (SAMPLES_PER_BLOCK): their angles' cosines follow from the first row's
        with nearby_rows(k, m) if quick else nullcontext():
            self.evaluated = evaluate(sweep.construction, inputs, m * k, held, track=False,
                                      origin=origin, parameters=varied)
        self.okay = self.evaluated.valid.reshape(k, m)

    def valid(self, offsets: tuple[int, ...]) -> np.ndarray:
        """Return where every evaluation at ``offsets`` can be assembled."""
        rows = [self.offsets.index(k) for k in offsets]
        return np.asarray(self.okay[rows].all(axis=0))

    def values(self, name: str, offsets: tuple[int, ...], mask: np.ndarray) -> list:
        """Return a point's (M, 2) positions at the sample itself and at ``offsets``, f_0 first."""
        rows = self.evaluated.points[name].reshape(len(self.offsets), self.m, 2)
        if 0 in self.offsets:
            base = rows[self.offsets.index(0)]
        else:
            base = self.sweep.points[name][self.at]
        picked = [base, *(rows[self.offsets.index(k)] for k in offsets)]
        return picked if mask.all() else [p[mask] for p in picked]

    def quick(self, moving: list[str], into: _Into, noise: float | np.ndarray,
              work: np.ndarray) -> np.ndarray:
        r"""Differentiate every sample of the block on :data:`QUICK`; return where to refine.

        Parameters
        ----------
        moving : list of str
            The points to differentiate.
        into : _Into
            Where the block's derivatives, their errors and its largest squared
            derivatives are written (garbage where the block cannot be
            assembled: the caller overwrites those samples).
        noise : float or ndarray
            The rounding of positions, for all samples or each.
        work : ndarray, shape (4, P, 2, at least M)
            Memory for the differences, reused from block to block: a fresh
            array each block would cost page faults on every one.

        Returns
        -------
        ndarray of bool
            The samples whose truncation error is not :data:`REFINED_BELOW`
            times below the accuracy stated, against their own fastest speed
            and largest acceleration: to be differentiated on :data:`CENTRAL`.
            Neither the rounding nor the sweep's size enters, so that a
            sample's derivatives do not depend on the samples around it.

        Notes
        -----
        With ``forward = f_1 - f_0`` and ``backward = f_0 - f_-1``,
        ``f'' = (forward - backward) / h**2`` and
        ``f' = (3 (forward + backward) - third) / 6h``, where the third
        difference ``third = f_2 - 3 f_1 + 3 f_0 - f_-1`` is about
        ``h**3 f'''``. Their truncation errors are about ``h**2 f'''' / 12``
        and ``h**3 f'''' / 12``. Near a singular position at a distance ``d``
        in the input each derivative grows on the one before by about
        ``1 / d``: for each point ``h / d`` is read as ``h f''' / f''`` (at
        most 1; not from ``f'``, which passes through zero where a point
        stops without anything singular), the errors follow from it and
        ``third``, and the largest over the points is kept. Each point is
        read on its own, so that a large point moving regularly does not hide
        a small one near its toggle.
        """
        h = self.h
        speed2, accel2 = into.largest  # the largest over the points, squared
        first_error, second_error = into.first_error, into.second_error
        if not moving:  # only rounding
            first_error[...] = ROUNDING_QUICK[0] * noise / h
            second_error[...] = ROUNDING_QUICK[1] * noise / (h * h)
            speed2[...] = accel2[...] = 0.0
            return np.zeros(self.m, dtype=bool)
        m = self.m
        before, after, farther = (self.offsets.index(k) for k in QUICK)
        # forward = f_1 - f_0, backward = f_0 - f_-1 and third = f_2 - f_1 (made the
        # third difference below), every point's x and y, (P, 2, M): taken straight
        # from the evaluations, into memory reused from block to block
        forward, backward, third, across = (part[..., :m] for part in work)
        for i, name in enumerate(moving):
            # the sample itself: evaluated again in another frame, else the sweep's
            at_sample = None if 0 in self.offsets else self.sweep.points.xy(name)
            for axis, v in enumerate(self.evaluated.points.coords(name)):
                rows = np.reshape(v, (-1, m)) if np.ndim(v) else np.full((len(self.offsets), m), v)
                f0 = (rows[self.offsets.index(0)] if at_sample is None
                      else at_sample[axis][self.at])
                np.subtract(rows[after], f0, out=forward[i, axis])
                np.subtract(f0, rows[before], out=backward[i, axis])
                np.subtract(rows[farther], rows[after], out=third[i, axis])
        np.add(forward, backward, out=across)  # f_1 - f_-1
        forward -= backward  # now f_1 - 2 f_0 + f_-1, about h**2 f''
        third -= backward
        third -= forward
        third -= forward  # f_2 - 3 f_1 + 3 f_0 - f_-1
        across *= 3
        across -= third
        d1 = np.multiply(across, 1 / (6 * h), out=into.first)
        d2 = np.multiply(forward, 1 / (h * h), out=into.second)
        # each point's squares, (P, M), x's plus y's as for one point, into rows freed
        squares = [np.multiply(d, d, out=spare) for d, spare in
                   ((d1, across), (d2, backward), (third, forward))]
        rate, curvature, third2 = (np.add(q[:, 0], q[:, 1], out=q[:, 0]) for q in squares)
        with np.errstate(divide="ignore", invalid="ignore"):
            # (h / d)**2, at most 1 (where the point does not move, 0 / 0 is NaN and
            # the cap makes it 1, times a third difference of 0)
            ratio2 = np.multiply(curvature, h**4, out=squares[1][:, 1])
            np.divide(third2, ratio2, out=ratio2)
            np.fmin(ratio2, 1.0, out=ratio2)
            ratio2 *= third2  # (h / d * third)**2, the errors but for constants
        # each point's own errors, for the rates of the links it ends
        own = np.sqrt(ratio2, out=squares[0][:, 1])
        error = np.multiply(own, QUICK_ERROR_FACTORS[0] / (6 * h), out=into.first_errors)
        error += ROUNDING_QUICK[0] * noise / h
        error = np.multiply(own, QUICK_ERROR_FACTORS[1] / (h * h), out=into.second_errors)
        error += ROUNDING_QUICK[1] * noise / (h * h)
        np.fmax.reduce(rate, axis=0, out=speed2)
        np.fmax.reduce(curvature, axis=0, out=accel2)
        worst = np.fmax.reduce(ratio2, axis=0)
        worst = np.sqrt(worst, out=worst)
        truncation1 = np.multiply(worst, QUICK_ERROR_FACTORS[0] / (6 * h), out=first_error)
        truncation2 = np.multiply(worst, QUICK_ERROR_FACTORS[1] / (h * h), out=second_error)
        again = truncation1 > (VELOCITY_RTOL / REFINED_BELOW) * np.sqrt(speed2)
        again |= truncation2 > (ACCELERATION_RTOL / REFINED_BELOW) * np.sqrt(accel2)
        first_error += ROUNDING_QUICK[0] * noise / h
        second_error += ROUNDING_QUICK[1] * noise / (h * h)
        return again

    def central(self, ok, moving, first, second, estimate):
        if not ok.any():
            return
        h = self.h
        a, b, c, e = 1 / (12 * h), 1 / (12 * h * h), 1 / (2 * h), 1 / (h * h)
        for name in moving:
            f0, fm2, fm1, f1, f2 = self.values(name, CENTRAL, ok)
            odd1 = f1 - fm1
            twice = f0 + f0
            even1 = f1 + fm1
            even1 -= twice
            d1 = 8 * odd1
            d1 -= f2
            d1 += fm2
            d1 *= a
            d2 = 16 * even1
            d2 -= f2
            d2 -= fm2
            d2 += twice
            d2 *= b
            odd1 *= c
            even1 *= e
            estimate.add(name, first[name], second[name], d1, d2, d1 - odd1, d2 - even1)

    def one_sided(self, mask, sign, moving, first, second, estimate):
        h = sign * self.h
        offsets = tuple(sign * k for k in (1, 2, 3, 4))
        for name in moving:
            f0, f1, f2, f3, f4 = self.values(name, offsets, mask)
            d1 = (-25 * f0 + 48 * f1 - 36 * f2 + 16 * f3 - 3 * f4) / (12 * h)
            d2 = (35 * f0 - 104 * f1 + 114 * f2 - 56 * f3 + 11 * f4) / (12 * h * h)
            low1 = (-3 * f0 + 4 * f1 - f2) / (2 * h)
            low2 = (2 * f0 - 5 * f1 + 4 * f2 - f3) / (h * h)
            estimate.add(name, first[name], second[name], d1, d2, d1 - low1, d2 - low2)


def _squared(vectors: np.ndarray) -> np.ndarray:
    """Return the squared length of each row of an (M, 2) array."""
    # squared whole, then the columns added: arithmetic on the columns themselves,
    # strided, is several times slower (and einsum slower still on rows of two)
    squares = vectors * vectors
    return squares[:, 0] + squares[:, 1]


class _Estimate:
    """The derivatives of some samples, and the estimate of their error.

    ``add`` takes each point's derivatives and their differences from
    lower-order ones (the truncation error of the lower order). The higher
    order's error is smaller by about the same factor again: near a singular
    position at a distance d in the input, the derivatives grow like
    ``1 / d**k`` and the errors of second and fourth order like
    ``(h / d)**2`` and ``(h / d)**4``; the ratio ``(h / d)**2`` is read from
    each point's difference over its second derivative (at most 1), each point
    on its own so that a large point moving regularly does not hide a small one
    near its toggle, and :data:`ERROR_FACTOR` covers the constants of both
    kinds of singularity (a square root, a pole). The largest error over the
    points is kept; the rounding of the positions over the step comes on top.
    """

    def __init__(self, at: slice | np.ndarray, h: float):
        self.at, self.h = at, abs(h)
        # the largest over the points: squared derivatives, and truncation errors
        self.rate = self.curvature = self.error1 = self.error2 = None
        self.own: dict[str, tuple[np.ndarray, np.ndarray]] = {}  # each point's truncation

    def add(self, name, first, second, d1, d2, gap1, gap2):
        """Take one point's derivatives and gaps, each (M, 2)."""
        first[self.at], second[self.at] = d1, d2
        rate, curvature = _squared(d1), _squared(d2)
        gap1, gap2 = np.sqrt(_squared(gap1)), np.sqrt(_squared(gap2))
        with np.errstate(divide="ignore", invalid="ignore"):
            # (h / d)**2, at most 1: from the second derivative, as the first of a
            # point that stops (a rocker at the end of its swing) passes through zero
            # where nothing is singular; where the point does not move its gaps are 0
            ratio = np.fmin(gap2 / np.sqrt(curvature), 1.0)
        found = (rate, curvature, ratio * gap1, ratio * gap2)
        self.own[name] = found[2:]
        if self.rate is None:
            self.rate, self.curvature, self.error1, self.error2 = found
        else:
            for total, value in zip((self.rate, self.curvature, self.error1, self.error2),
                                    found, strict=True):
                np.fmax(total, value, out=total)

    def finish(self, first_error, second_error, noise, rounding, largest, first_errors,
               second_errors):
        """Write the errors at the samples, each point's too, and the largest squares."""
        for into, square in zip(largest, (self.rate, self.curvature), strict=True):
            into[self.at] = 0.0 if square is None else square
        rounded = (rounding[0] * noise / self.h, rounding[1] * noise / (self.h * self.h))
        first_error[self.at], second_error[self.at] = rounded
        if self.error1 is not None:
            first_error[self.at] += ERROR_FACTOR * self.error1
            second_error[self.at] += ERROR_FACTOR * self.error2
        for name, (error1, error2) in self.own.items():
            first_errors[name][self.at] = ERROR_FACTOR * error1 + rounded[0]
            second_errors[name][self.at] = ERROR_FACTOR * error2 + rounded[1]


@dataclass(frozen=True)
class Motion(Frozen):
    """Velocities and accelerations over a sweep, with respect to time.

    Attributes
    ----------
    sweep : Sweep
    input_name : str
        The driving input.
    time : ndarray, shape (N,)
        Seconds from the first sample, for the input's speed.
    speed, input_acceleration : ndarray, shape (N,)
        The input's signed rate and its rate of change (per second, per
        second squared): negative where the sweep runs the input backwards.
    velocity, acceleration : dict of str to ndarray, shape (N, 2)
        Each point's velocity and acceleration (length units per second and per
        second squared).
    angle, angular_velocity, angular_acceleration : dict of str to ndarray, shape (N,)
        For every declared link, the angle of the line from its first point
        to its second (unwrapped, radians) and its time derivatives.
    flagged : ndarray of bool, shape (N,)
        Assembled samples whose velocities or accelerations may be less
        accurate than stated: the estimated error of some point's velocity,
        or of a slider's rate along its guide, exceeds :data:`VELOCITY_RTOL`
        of the fastest point's speed at that sample, or of its acceleration
        :data:`ACCELERATION_RTOL` of the largest acceleration there (or of
        that speed squared over the mechanism's size, if larger); likewise
        for link angular rates against the fastest-turning link; or no
        stencil could be assembled; or the sample is near a singular
        position.
    velocity_error, acceleration_error : ndarray, shape (N,)
        The estimated error of the velocities and accelerations at each
        sample, the largest over the points (NaN where unassembled).
    derivatives : Derivatives
        The derivatives along the motion, with respect to time, that the
        velocities and accelerations come from.
    slider_position, slider_velocity, slider_acceleration : dict of str to ndarray, shape (N,)
        For every declared slider, the position of its block along its
        guide (:func:`slider_positions`) and its time derivatives: the rate
        at which the block slides along the guide, seen from the guide
        (which may itself turn), in length units per second and per second
        squared.
    """

    sweep: Sweep
    input_name: str
    time: np.ndarray
    speed: np.ndarray
    input_acceleration: np.ndarray
    velocity: dict
    acceleration: dict
    angle: dict
    angular_velocity: dict
    angular_acceleration: dict
    flagged: np.ndarray
    velocity_error: np.ndarray
    acceleration_error: np.ndarray
    derivatives: Derivatives
    slider_position: dict
    slider_velocity: dict
    slider_acceleration: dict

    input = renamed_attribute("input", "input_name")
    _read_only = ("time", "speed", "input_acceleration", "velocity", "acceleration", "angle",
                  "angular_velocity", "angular_acceleration", "flagged", "velocity_error",
                  "acceleration_error", "slider_position", "slider_velocity",
                  "slider_acceleration")

    def __repr__(self) -> str:
        count = self.sweep.variants
        samples = (f"{len(self.time)} samples" if count is None
                   else f"{count} variants x {len(self.time)} samples")
        return (f"<Motion of {short_name(self.sweep.construction.name)} driven by "
                f"{short_name(self.input_name)}: {samples}, "
                f"{int(np.count_nonzero(self.flagged))} flagged>")

    def _repr_html_(self) -> str:
        """Return a table of the motion for a notebook.

        It gives the samples, how many are flagged and where the first is,
        the input's speed and the time the motion takes, and the largest
        speed and acceleration of the traced points (every moving point if
        none is traced) and of the moving links' angles over the unflagged samples,
        in the construction's length unit and in degrees. At most
        :data:`~geokin.display.MAX_LISTED` of each are listed; everything
        from the script is escaped.

        Examples
        --------
        >>> from geokin import Construction, sweep
        >>> c = Construction("crank", units="mm")
        >>> c.input("theta")
        >>> c.fixed("O", 0, 0)
        >>> c.polar("A", "O", 10, "theta")
        >>> c.link("crank", "O", "A")
        >>> page = motion(sweep(c, np.linspace(0, np.pi, 7)), speed=np.pi)._repr_html_()
        >>> "speed up to 31.4159 mm/s, acceleration up to 98.696 mm/s²" in page
        True
        >>> "angular velocity up to 180 deg/s" in page
        True
        """
        if self.sweep.variants is not None:
            flagged = int(np.count_nonzero(self.flagged))
            rows = [("variants", f"{self.sweep.variants:,} of {len(self.time):,} samples each"),
                    ("flagged", f"{flagged:,} samples in all"),
                    ("variant 0", "motion(sweep.variant(i)) is variant i's motion alone")]
            return display.table(f"Motion of {self.sweep.construction.name!r} driven by "
                                 f"{self.input_name}, {self.sweep.variants:,} variants", rows)
        s = self.sweep
        compiled, n = s.construction, len(self.time)
        units = compiled.units or "units"
        angle = compiled.inputs[self.input_name].kind == "angle"
        valid, flagged = int(np.count_nonzero(s.valid)), int(np.count_nonzero(self.flagged))
        rows = [("samples", f"{n:,}: {valid:,} valid, {flagged:,} flagged" + (
            f" (the first at sample {int(np.argmax(self.flagged))})" if flagged else ""))]
        rate = np.abs(self.speed)
        unit = "deg/s" if angle else f"{units}/s"

        def rate_of(x: float) -> str:
            return display.angle(x, unit) if angle else display.number(x, unit)

        low, high = (float(rate.min()), float(rate.max())) if n else (np.nan, np.nan)
        rows.append((f"input {self.input_name}", rate_of(low) if low == high
                     else f"{rate_of(low).split()[0]} to {rate_of(high)}"))
        rows.append(("time", display.number(float(self.time[-1]) if n else 0.0, "s")))
        good = s.valid & ~self.flagged

        def largest(values: np.ndarray) -> float:
            values = values[good]
            return float(np.nanmax(values)) if values.size and np.isfinite(values).any() \
                else float("nan")

        moving = [p for p in compiled.point_names if p not in compiled.ground]
        shown = list(compiled.traced or moving)
        for name in shown[:display.MAX_LISTED]:
            v, a = self.velocity[name], self.acceleration[name]
            rows.append((name, f"speed up to {display.number(largest(np.hypot(*v.T)), units)}/s"
                               f", acceleration up to "
                               f"{display.number(largest(np.hypot(*a.T)), units)}/s²"))
        # the frame's links do not turn
        links = [link.name for link in compiled.links
                 if not set(link.points) <= compiled.ground and link.name in self.angle]
        for name in links[:display.MAX_LISTED]:
            omega = largest(np.abs(self.angular_velocity[name]))
            alpha = largest(np.abs(self.angular_acceleration[name]))
            rows.append((f"link {name}", f"angular velocity up to "
                         f"{display.angle(omega, 'deg/s')}, angular acceleration up to "
                         f"{display.angle(alpha, 'deg/s²')}"))
        left_out = max(len(shown) - display.MAX_LISTED, 0) + max(
            len(links) - display.MAX_LISTED, 0)
        if left_out:
            rows.append(("not listed", f"{left_out:,} more points and links"))
        caption = f"Motion of {compiled.name!r} driven by {self.input_name}"
        return display.table(caption, rows)


def _time_step(sweep: Sweep, rates: dict, step: float | None) -> float:
    """Return a step in time that moves no input by more than its own step."""
    return min((_step_for(sweep, name, step) / max(np.max(np.abs(r)), 1e-300)
                for name, r in rates.items()), default=RELATIVE_STEP)


def _direction_of_travel(values: np.ndarray) -> np.ndarray:
    """Return +1 or -1 at each sample: whether the input arrived there increasing.

    The first sample takes the direction of the step after it; a sample
    repeating the one before keeps the direction it had.
    """
    step = np.diff(values)
    if step.size == 0:
        return np.ones_like(values)
    if step.min() > 0 or step.max() < 0:  # one way all along (NaN fails both)
        return np.full(values.shape, np.sign(step[0]))
    step = np.sign(step)
    direction = np.concatenate([step[:1], step])
    known = np.flatnonzero(direction)
    if known.size == 0:
        return np.ones_like(values)
    # carry the last known direction over repeated samples (the first known one backwards)
    last = np.maximum.accumulate(np.where(direction != 0, np.arange(len(direction)), known[0]))
    return direction[last]


def _sampled_rate_unsure(values: np.ndarray, time: np.ndarray, rate: np.ndarray,
                         change: np.ndarray) -> np.ndarray:
    """Say where an input's rate and its change, read off its samples, may miss the accuracy.

    They are differences of the samples over ``time`` (or over the driving
    input's values), of second order: their truncation is
    about a third of a step squared times the input's third (for the rate)
    and fourth (for its change) derivatives, told by the samples'
    third and fourth differences (the change's, two samples from either
    end, a step times the third derivative); against :data:`VELOCITY_RTOL` of the
    fastest rate and :data:`ACCELERATION_RTOL` of the largest change (or of
    that rate squared over the input's travel). An input swept in
    proportion to the driving one has none.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> bool(_sampled_rate_unsure(3 * t, t, np.full(101, 3.0), np.zeros(101)).any())
    False
    >>> wavy = np.sin(2 * np.pi * t)
    >>> bool(_sampled_rate_unsure(wavy, t, np.gradient(wavy, t), np.zeros(101)).all())
    True
    """
    n = len(values)
    if n < 5:
        return np.ones(n, dtype=bool)
    step = np.abs(np.gradient(time))  # over a driving input's values, which may fall
    with np.errstate(all="ignore"):
        # the differences about each sample (the nearest ones at the ends)
        third = np.pad(np.abs(np.diff(values, 3)), (1, 2), mode="edge")
        fourth = np.pad(np.abs(np.diff(values, 4)), (2, 2), mode="edge")
        rate_error = third / (3 * step)
        change_error = fourth / (3 * step * step)
        # the change at two samples from either end is a one-sided difference of a
        # one-sided difference: of first order there, a step times the third derivative
        for ends in (slice(0, 2), slice(-2, None)):
            change_error[ends] = np.fmax(change_error[ends],
                                         third[ends] / (step[ends] * step[ends]))
        fastest = float(np.nanmax(np.abs(rate)))
        travel = float(np.ptp(values))
        largest = max(float(np.nanmax(np.abs(change))), fastest * fastest / travel)
        return ((rate_error > VELOCITY_RTOL * fastest)
                | (change_error > ACCELERATION_RTOL * largest))


@renamed_keywords(input="input_name")
def motion(sweep: Sweep, input_name: str | None = None, *, speed: ArrayLike | None = None,
           acceleration: ArrayLike = 0.0, step: float | None = None) -> Motion:
    """Velocity and acceleration of every point and declared link over a sweep.

    Parameters
    ----------
    sweep : Sweep
    input_name : str, optional
        The driving input, whose speed sets the clock; by default the first
        input that moves in the sweep. Other inputs move as the sweep moves
        them, in step with it (their rates follow from their values against
        the driving input's, by the chain rule, or over time where it turns
        back), and an input that stays put is held.
    speed : float or array_like, optional
        How fast the input moves, per second (radians per second for an
        angle), constant or one per sample; by default the input's declared
        speed. The input moves the way the sweep goes: where its values
        decrease (a sweep run backwards, the return pass of a circuit) its
        rate is ``-speed``, and time still runs forwards.
    acceleration : float or array_like
        The rate of change of that speed, per second squared.
    step : float, optional
        The finite-difference perturbation; see :func:`input_derivatives`.

    Returns
    -------
    Motion

    Examples
    --------
    A crank of 10 turning at 2 rad/s: its tip moves at 20 and accelerates at
    40 towards the pivot.

    >>> import numpy as np
    >>> from geokin import Construction, sweep
    >>> c = Construction()
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta")
    >>> c.link("crank", "O", "A")
    >>> m = motion(sweep(c, [0.0]), speed=2.0)
    >>> np.hypot(*m.velocity["A"][0]).round(6), np.hypot(*m.acceleration["A"][0]).round(4)
    (np.float64(20.0), np.float64(40.0))
    >>> m.angular_velocity["crank"].round(9)
    array([2.])
    """
    compiled = sweep.construction
    # variants share the inputs and their clock, and are differentiated all at once as
    # one sweep of their samples one after the other
    whole, count = sweep, sweep.variants
    sweep = sweep.flat()
    n = len(whole)
    driver = input_name
    if driver is None:
        moving = [k for k, v in whole.inputs.items() if np.ptp(v) > 0]
        driver = moving[0] if moving else None
    driver = compiled.resolve_input(driver, purpose="drive the motion")
    declared = compiled.inputs[driver]
    values = whole.inputs[driver]
    direction = _direction_of_travel(values)
    size = np.broadcast_to(np.asarray(declared.speed if speed is None else speed, float), (n,))
    if not (np.isfinite(size) & (size > 0)).all():
        raise ConstructionError("the input's speed must be a positive number (how fast it "
                                "moves; the sweep's direction sets its sign), got "
                                f"{speed!r}", node=driver, field="speed", kind="input")
    rate = size * direction
    rate_change = np.broadcast_to(np.asarray(acceleration, dtype=float), (n,)) * direction
    with np.errstate(divide="ignore", invalid="ignore"):
        moved = np.diff(values)
        if n >= 2 and (size == size[0]).all() and ((moved >= 0).all() or (moved <= 0).all()):
            # one way at one speed: the distance travelled, without a sum's rounding
            time = np.abs(values - values[0]) / size[0]
        else:
            # time to travel between samples at the mean rate of the two
            dt = np.abs(moved) / np.abs(0.5 * (size[1:] + size[:-1]))
            time = np.concatenate([[0.0], np.cumsum(dt)])
    # the other inputs move as the sweep moves them, in step with the driving one
    rates, changes = {driver: rate}, {driver: rate_change}
    unsure = np.zeros(n, dtype=bool)  # where their rates may miss the accuracy stated
    one_way = n >= 3 and (np.all(np.diff(values) > 0) or np.all(np.diff(values) < 0))
    for name, other in whole.inputs.items():
        if name == driver or not np.ptp(other) > 0:
            continue
        if one_way:
            # a function of the driving input: differences over its values, evenly
            # sampled as a rule (over time they are not where the speed varies), and
            # the chain rule; an input in proportion to the driving one is exact
            slope = np.gradient(other, values, edge_order=2)
            bend = np.gradient(slope, values, edge_order=2)
            rates[name] = slope * rate
            changes[name] = bend * rate * rate + slope * rate_change
            unsure |= _sampled_rate_unsure(other, values, slope, bend)
        elif n >= 3 and (np.diff(time) > 0).all():  # of second order at the ends too
            rates[name] = np.gradient(other, time, edge_order=2)
            changes[name] = np.gradient(rates[name], time, edge_order=2)
            unsure |= _sampled_rate_unsure(other, time, rates[name], changes[name])
        elif n == 2 and time[1] > time[0]:  # one step: its slope, flagged
            rates[name], changes[name] = np.gradient(other, time), np.zeros(n)
            unsure[:] = True
        else:  # it moves while the clock stands still, or too few samples to tell
            unsure[:] = True
    if count is not None:
        rate, rate_change = np.tile(rate, count), np.tile(rate_change, count)
        rates = {k: np.tile(v, count) for k, v in rates.items()}
        changes = {k: np.tile(v, count) for k, v in changes.items()}
        n *= count
    # one step in time that moves no input by more than its own finite-difference step
    sizes = _sizes(whole)  # once: each sample's scale, for its step, noise and flags
    largest = (np.empty(n), np.empty(n))
    frame: list = []
    d = _along(sweep, rates, _time_step(sweep, rates, step), driver, sizes, largest, frame,
               length=n // (count or 1), one_way=bool(one_way))
    velocity = d.first
    accel = d.second
    velocity_error, acceleration_error = d.first_error, d.second_error
    velocity_errors, acceleration_errors = d.first_errors, d.second_errors
    accelerating = {name: c for name, c in changes.items() if np.any(c != 0)}
    if accelerating.keys() == {driver} and rates.keys() == {driver} and np.all(rate != 0):
        # one input moves: its own acceleration adds the first derivative scaled
        ratio = rate_change / rate
        accel = {p: accel[p] + velocity[p] * ratio[:, None] for p in accel}
        acceleration_error = acceleration_error + velocity_error * np.abs(ratio)
        acceleration_errors = {p: acceleration_errors[p] + velocity_errors[p] * np.abs(ratio)
                               for p in accel}
    elif accelerating:
        # the inputs' own accelerations add a first derivative along them
        extra = _along(sweep, accelerating, _time_step(sweep, accelerating, step), driver, sizes,
                       length=n // (count or 1))
        accel = {p: accel[p] + extra.first[p] for p in accel}
        acceleration_error = acceleration_error + extra.first_error
        acceleration_errors = {p: acceleration_errors[p] + extra.first_errors[p] for p in accel}
    angle = link_angles(whole)
    # a mechanism far from (0, 0): its links' and guides' directions are taken in the
    # frame its rates were found in, where the differences of positions keep their digits
    origin = frame[0]
    near = sweep if origin is None else _in_frame(sweep, origin)
    angular_velocity, angular_acceleration = {}, {}
    flagged = sweep.valid & ((d.stencil == 2) | np.tile(unsure, n // len(unsure)))
    with np.errstate(divide="ignore", invalid="ignore"):
        # errors are measured against each sample's own scales: its fastest point's
        # speed, and its largest acceleration or that speed turned over the size
        extent = sizes
        speed_scale = np.sqrt(largest[0])
        accel_scale = np.fmax(np.sqrt(largest[1]) if accel is d.second
                              else _largest_at_each(accel.values(), n), speed_scale**2 / extent)
        flagged |= velocity_error > VELOCITY_RTOL * speed_scale
        flagged |= acceleration_error > ACCELERATION_RTOL * accel_scale
        turn_scale, turn_accel_scale = speed_scale / extent, np.zeros(n)
        link_errors = []
        for link in sweep.construction.links:
            start, end = link.points[0], link.points[1]
            (x0, y0), (x1, y1) = near.points.xy(start), near.points.xy(end)
            x, y = x1 - x0, y1 - y0
            vx, vy = velocity[end][:, 0] - velocity[start][:, 0], \
                velocity[end][:, 1] - velocity[start][:, 1]
            ax, ay = accel[end][:, 0] - accel[start][:, 0], accel[end][:, 1] - accel[start][:, 1]
            r2 = x * x + y * y
            omega = (x * vy - y * vx) / r2
            alpha = (x * ay - y * ax) / r2 - 2 * omega * (x * vx + y * vy) / r2
            angular_velocity[link.name], angular_acceleration[link.name] = omega, alpha
            turn_scale = np.fmax(turn_scale, np.abs(omega))
            turn_accel_scale = np.fmax(turn_accel_scale, np.abs(alpha))
            # both ends' errors over the link's length, and through omega into alpha
            r = np.sqrt(r2)
            ends_v = velocity_errors[start] + velocity_errors[end]
            ends_a = acceleration_errors[start] + acceleration_errors[end]
            link_errors.append((ends_v / r, ends_a / r + 3 * np.abs(omega) * ends_v / r))
        turn_accel_scale = np.fmax(turn_accel_scale, turn_scale**2)
        for error_w, error_al in link_errors:
            flagged |= error_w > VELOCITY_RTOL * turn_scale
            flagged |= error_al > ACCELERATION_RTOL * turn_accel_scale
        slides = _slider_rates(sweep, near, velocity, accel, velocity_error,
                               acceleration_error)
        for _, _, _, error_v, error_a in slides.values():
            flagged |= error_v > VELOCITY_RTOL * speed_scale
            flagged |= error_a > ACCELERATION_RTOL * accel_scale
        for margin in sweep.margins.values():
            flagged |= sweep.valid & (margin < SINGULAR_MARGIN)
    if count is None:
        return Motion(sweep, driver, time, rate, rate_change, velocity, accel, angle,
                      angular_velocity, angular_acceleration, flagged & sweep.valid,
                      velocity_error, acceleration_error, d,
                      {name: rates[0] for name, rates in slides.items()},
                      {name: rates[1] for name, rates in slides.items()},
                      {name: rates[2] for name, rates in slides.items()})

    def rows(value):
        if isinstance(value, Mapping):
            return {k: rows(v) for k, v in value.items()}
        return np.reshape(value, (count, -1, *np.shape(value)[1:]))

    derivatives = Derivatives(d.input_name, d.step, rows(d.first), rows(d.second),
                              rows(d.stencil), rows(d.first_error), rows(d.second_error),
                              rows(d.first_errors), rows(d.second_errors))
    return Motion(whole, driver, time, rate[:len(time)], rate_change[:len(time)],
                  rows(velocity), rows(accel), angle, rows(angular_velocity),
                  rows(angular_acceleration), rows(flagged & sweep.valid),
                  rows(velocity_error), rows(acceleration_error), derivatives,
                  {name: rows(rates[0]) for name, rates in slides.items()},
                  {name: rows(rates[1]) for name, rates in slides.items()},
                  {name: rows(rates[2]) for name, rates in slides.items()})


def _dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Return the dot product of each row of two (..., 2) arrays."""
    return u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1]


def _slider_rates(sweep: Sweep, near: Sweep, velocity: dict, accel: dict,
                  velocity_error: np.ndarray,
                  acceleration_error: np.ndarray) -> dict[str, tuple[np.ndarray, ...]]:
    """Return each slider's position along its guide, its two rates and their errors.

    With ``q`` the block's point from the guide's first point, ``u`` the
    guide's unit direction and ``n`` that turned a quarter turn
    counter-clockwise, the guide turning at ``w`` with ``al``: the position
    is ``s = q.u``, so ``s' = q'.u + w q.n`` and ``s'' = q''.u + 2 w q'.n +
    al q.n - w**2 q.u``. The errors follow from the points' (none for a
    ground point) through the guide's rates, as for a link's. The positions
    along the guides are the sweep's; the directions are taken from ``near``,
    the sweep in the frame its rates were found in.
    """
    ground = sweep.construction.ground
    rates: dict[str, tuple[np.ndarray, ...]] = {}
    positions = slider_positions(sweep)
    points = near.points
    for block in sweep.construction.sliders:
        first, second = block.along
        d = points[second] - points[first]
        vd, ad = velocity[second] - velocity[first], accel[second] - accel[first]
        q = points[block.point] - points[first]
        vq, aq = velocity[block.point] - velocity[first], accel[block.point] - accel[first]
        r2 = _dot(d, d)
        r = np.sqrt(r2)
        u = d / r[:, None]
        n = np.c_[-u[:, 1], u[:, 0]]
        w = (d[:, 0] * vd[:, 1] - d[:, 1] * vd[:, 0]) / r2
        al = (d[:, 0] * ad[:, 1] - d[:, 1] * ad[:, 0]) / r2 - 2 * w * _dot(d, vd) / r2
        along, across = positions[block.name], _dot(q, n)
        speed = _dot(vq, u) + w * across
        acceleration = _dot(aq, u) + 2 * w * _dot(vq, n) + al * across - w * w * along

        def moving(*points: str) -> int:
            return sum(p not in ground for p in points)

        # errors: the points' own, and through the guide's turning (as for a link)
        guide_v = moving(first, second) * velocity_error / r
        guide_a = (moving(first, second) * acceleration_error / r
                   + 6 * np.abs(w) * guide_v)
        distance = np.hypot(along, across)
        error_v = moving(block.point, first) * velocity_error + distance * guide_v
        error_a = (moving(block.point, first) * (acceleration_error + 2 * np.abs(w)
                                                 * velocity_error)
                   + 2 * np.hypot(*vq.T) * guide_v
                   + distance * (guide_a + 2 * np.abs(w) * guide_v))
        rates[block.name] = (along, speed, acceleration, error_v, error_a)
    return rates


def _largest_at_each(vectors, n: int) -> np.ndarray:
    """Return, at each sample, the largest length of the (N, 2) arrays (NaN left out)."""
    largest = np.zeros(n)
    for v in vectors:
        np.fmax(largest, _squared(v), out=largest)
    return np.sqrt(largest)


def unwrap_valid(angle: np.ndarray) -> np.ndarray:
    """Unwrap angles across the finite samples, keeping NaN where they are not.

    Along the last axis: each row of a (V, N) array (design variants) on its own.

    Examples
    --------
    >>> unwrap_valid(np.array([3.0, np.nan, -3.0])).round(4)
    array([3.    ,    nan, 3.2832])
    >>> unwrap_valid(np.array([[3.0, -3.0], [-3.0, 3.0]])).round(4)
    array([[ 3.    ,  3.2832],
           [-3.    , -3.2832]])
    """
    ok = np.isfinite(angle)
    if ok.all():
        return np.unwrap(angle, axis=-1)
    # each gap filled with the angle before it (the first finite one before the
    # first): no step across it, and the same steps between finite samples
    at = np.arange(angle.shape[-1])
    first = np.argmax(ok, axis=-1)[..., None]
    filled = np.take_along_axis(angle, np.maximum.accumulate(np.where(ok, at, first), axis=-1),
                                axis=-1)
    out = np.unwrap(filled, axis=-1)
    out[~ok] = np.nan
    return out


def slider_positions(sweep: Sweep) -> dict[str, np.ndarray]:
    """Return the position of every declared slider's block along its guide, over a sweep.

    A slider ``Slider(name, point, along=(P, Q))`` is a block at ``point``
    sliding on the line through P and Q. Its position is the signed distance
    from P to the point's projection on that line, positive towards Q: the
    distance along the guide from its first point (the block's point lies
    on the guide wherever the construction keeps it there). Its rates along
    the guide are :attr:`Motion.slider_velocity` and
    :attr:`Motion.slider_acceleration`.

    Returns
    -------
    dict of str to ndarray, shape (N,)
        By slider name, in length units; NaN at invalid samples and where
        the guide's two points coincide.

    Examples
    --------
    A block on a crank's line, 3 out from the pivot along the guide O->A:

    >>> from geokin import Construction, sweep
    >>> c = Construction("block on a crank")
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 1, "theta")
    >>> c.along("B", ("O", "A"), 3)
    >>> c.slider("block", "B", ("O", "A"))
    >>> slider_positions(sweep(c, [0.0, 1.0]))["block"].round(12)
    array([3., 3.])
    """
    result = {}
    for slider in sweep.construction.sliders:
        relative, guide, length = _from_guide(sweep, slider)
        with np.errstate(all="ignore"):
            result[slider.name] = _dot(relative, guide) / length
    return result


def _from_guide(sweep: Sweep, slider: Slider) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return a slider's point from its guide's first point, the guide, and its length."""
    first, second = slider.along
    guide = sweep.points[second] - sweep.points[first]
    return (sweep.points[slider.point] - sweep.points[first], guide,
            np.hypot(guide[..., 0], guide[..., 1]))


GUIDE_RTOL = 1e-9
"""How far a slider's point may lie off its guide line, as a fraction of the
mechanism's size (beside 1e-12 of the coordinates' own size, for a
mechanism far from the origin): a point put on the line by the construction
lies on it to rounding, far below this."""


def slider_offsets(sweep: Sweep) -> dict[str, np.ndarray]:
    """Return how far every declared slider's point lies off its guide line, over a sweep.

    A slider ``Slider(name, point, along=(P, Q))`` is a block at ``point``
    on the line through P and Q: the point lies on that line wherever the
    construction puts it there (an ``along``, ``line_circle`` or
    ``line_line`` point on it). The offset is the signed distance from the
    line to the point, positive on the left of P->Q.

    Returns
    -------
    dict of str to ndarray, shape (N,)
        By slider name, in length units; NaN at invalid samples and where
        the guide's two points coincide.

    See Also
    --------
    sliders_off_guide, slider_positions

    Examples
    --------
    A block meant for a horizontal guide, but put on a vertical one:

    >>> from geokin import Construction, sweep
    >>> c = Construction("block off its guide")
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.fixed("G", 0, 5)
    >>> c.polar("A", "O", 1, "theta")
    >>> c.along("B", ("O", "A"), 3)
    >>> c.slider("on", "B", ("O", "A"))
    >>> c.slider("off", "B", ("G", "O"))
    >>> offsets = slider_offsets(sweep(c, [0.0, 1.0]))
    >>> bool(abs(offsets["on"]).max() < 1e-12), offsets["off"].round(6).tolist()
    (True, [3.0, 1.620907])
    """
    result = {}
    for slider in sweep.construction.sliders:
        relative, guide, length = _from_guide(sweep, slider)
        with np.errstate(all="ignore"):
            result[slider.name] = (guide[..., 0] * relative[..., 1]
                                   - guide[..., 1] * relative[..., 0]) / length
    return result


def sliders_off_guide(sweep: Sweep) -> dict[str, tuple[int, float]]:
    """Return the sliders whose point leaves its guide line, where it is farthest and how far.

    A slider's point that lies off the line of its guide by more than
    :data:`GUIDE_RTOL` of the mechanism's size is a construction that
    does not put the block on its guide: its position along the guide, the
    projection of the point, and a drawing of the block mean nothing.

    Returns
    -------
    dict of str to (int, float)
        By slider name, for the sliders off their guide only: the sample
        where the point is farthest from the line (of :meth:`Sweep.flat`
        for a sweep of variants) and its signed offset there (see
        :func:`slider_offsets`).

    Examples
    --------
    >>> from geokin import Construction, sweep
    >>> c = Construction("block off its guide")
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.fixed("G", 0, 5)
    >>> c.polar("A", "O", 1, "theta")
    >>> c.along("B", ("O", "A"), 3)
    >>> c.slider("on", "B", ("O", "A"))
    >>> c.slider("off", "B", ("G", "O"))
    >>> sliders_off_guide(sweep(c, [0.0, 1.0]))
    {'off': (0, 3.0)}
    """
    sizes = _sizes(sweep)
    flat = sweep.flat()
    offsets = slider_offsets(flat)
    found = {}
    for slider in sweep.construction.sliders:
        offset = offsets[slider.name]
        points = [flat.points[p] for p in (slider.point, *slider.along)]
        with np.errstate(invalid="ignore"):
            largest = np.max([np.abs(xy).max(axis=-1) for xy in points], axis=0)
            off = np.abs(offset) > GUIDE_RTOL * sizes + 1e-12 * largest
        if off.any():
            i = int(np.nanargmax(np.where(off, np.abs(offset), np.nan)))
            found[slider.name] = (i, float(offset[i]))
    return found


CRANK_RTOL = 1e-9
"""A link whose angle stays this close to an angle input plus a constant
(relative to that constant, or absolute below one radian) turns with it: see
:func:`link_angles`."""


INPUT_MOVES = 1e-6
"""An angle input that moves less than this (radians) over a link's samples is
taken to hold still, and turns no link (see :func:`link_angles`)."""


def _in_turn_of(angle: np.ndarray, driving: np.ndarray, free: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray]:
    """Turn an angle by whole turns where it keeps a constant angle from ``driving``.

    Along the last axis, in each row still ``free`` where ``driving`` moves
    over the angle's finite samples: at every sample, also
    across a gap that the angle could not be unwrapped across, the angle is
    then ``driving`` plus one constant in (-pi, pi]. Returns the angle and
    the rows it was turned in.
    """
    # an input that does not move (one sample, or held) leaves every link at a
    # constant angle from it: it turns none
    found = np.isfinite(angle)
    moving = np.where(found, driving, np.nan)
    free = free & (np.fmax.reduce(moving, axis=-1, keepdims=True)
                   - np.fmin.reduce(moving, axis=-1, keepdims=True) > INPUT_MOVES)
    between = angle - driving
    # whole turns apart from an element of its row (one of them: the least)
    apart = np.round((between - np.fmin.reduce(between, axis=-1, keepdims=True)) / (2 * np.pi))
    between -= 2 * np.pi * apart
    low = np.fmin.reduce(between, axis=-1, keepdims=True)
    high = np.fmax.reduce(between, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore"):  # a row of NaN keeps no angle from anything
        constant = free & (high - low <= CRANK_RTOL * np.fmax(1.0, np.fmax(-low, high)))
    # the constant in (-pi, pi]: a half turn, to rounding, is +pi
    middle = 0.5 * (low + high)
    turns = np.where(constant, apart + np.floor((middle + np.pi - CRANK_RTOL) / (2 * np.pi)),
                     0.0)
    return angle - 2 * np.pi * turns, constant


def link_angles(sweep: Sweep) -> dict[str, np.ndarray]:
    """Return the angle of every declared link over a sweep.

    The angle of a link is that of the line from its first point to its
    second, counter-clockwise from the x axis, unwrapped over the valid
    samples so that it runs on continuously through full turns. A link
    that keeps a constant angle from an angle input (a crank) reads in that
    input's turn, within half a turn of it; any other link starts in
    (-pi, pi].

    Returns
    -------
    dict of str to ndarray, shape (N,)
        Radians; NaN at invalid samples.

    Examples
    --------
    >>> from geokin import Construction, sweep
    >>> c = Construction("crank")
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 1, "theta")
    >>> c.link("crank", "O", "A")
    >>> angles = link_angles(sweep(c, np.linspace(0, 4 * np.pi, 9)))
    >>> np.round(angles["crank"] / np.pi, 9)
    array([0. , 0.5, 1. , 1.5, 2. , 2.5, 3. , 3.5, 4. ])

    A crank swept from 300 degrees reads 300, not -60:

    >>> angles = link_angles(sweep(c, np.radians([300.0, 330.0])))
    >>> np.degrees(angles["crank"]).round(9)
    array([300., 330.])
    """
    compiled = sweep.construction
    driving = [values for name, values in sweep.inputs.items() if name in compiled.angle_inputs]
    result = {}
    for link in compiled.links:
        d = sweep.points[link.points[1]] - sweep.points[link.points[0]]
        angle = unwrap_valid(np.arctan2(d[..., 1], d[..., 0]))
        free = np.ones((*angle.shape[:-1], 1), dtype=bool)
        for values in driving:
            angle, turned = _in_turn_of(angle, values, free)
            free &= ~turned
        result[link.name] = angle
    return result
