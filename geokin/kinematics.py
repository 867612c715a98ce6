"""Velocity and acceleration of every point and link, by finite differences.

The derivatives with respect to the input come from evaluating the
construction again at small perturbations ``theta + k*h`` (k = -4..4) around
each sample, on that sample's branches. So their accuracy does not depend on
how coarse the sweep is, and a derivative never reaches across a branch
change or an unassemblable stretch: where the perturbed construction cannot
be assembled on one side, a one-sided stencil is used.

Stencils (f_k = f(theta + k h)):

* central, fourth order: ``f' = (f_-2 - 8 f_-1 + 8 f_1 - f_2) / 12h`` and
  ``f'' = (-f_-2 + 16 f_-1 - 30 f_0 + 16 f_1 - f_2) / 12h^2``;
* one-sided (at the ends of a valid stretch), fourth and third order, on
  f_0..f_4 or f_0..f_-4.

Time derivatives follow by the chain rule from the input's rate
(``speed``, radians or length units per second) and its acceleration:
``v = p' * speed`` and ``a = p'' * speed**2 + p' * acceleration``.

Near a singular position (a two-root node close to tangency, where the
mechanism locks or toggles) the derivatives grow without bound; such samples
are flagged in :attr:`Motion.flagged` rather than silently reported: where a
node's margin is below :data:`SINGULAR_MARGIN`, or where the fourth- and
second-order estimates of a first derivative disagree.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .budgets import check_sweep_memory
from .engine import evaluate
from .errors import ConstructionError
from .results import Sweep

__all__ = ["Motion", "input_derivatives", "motion"]

RELATIVE_STEP = 2e-4
"""The perturbation h: this many radians for an angle input, and this
fraction of the span a sweep covers for a length input."""

SINGULAR_MARGIN = 1e-5
"""Samples where a two-root node's margin (squared half-chord over squared
scale) falls below this are flagged as near a singular position."""

CONVERGENCE_RTOL = 1e-4
"""Samples where the fourth- and second-order estimates of a first derivative
differ by more than this, relative to the largest first derivative of the
sweep, are flagged: the derivative there is not to be trusted."""

OFFSETS = np.arange(-4, 5)

_CENTRAL_1 = np.array([0, 0, 1, -8, 0, 8, -1, 0, 0]) / 12
_CENTRAL_2 = np.array([0, 0, -1, 16, -30, 16, -1, 0, 0]) / 12
_FORWARD_1 = np.array([0, 0, 0, 0, -25, 48, -36, 16, -3]) / 12
_FORWARD_2 = np.array([0, 0, 0, 0, 35, -104, 114, -56, 11]) / 12
# backward stencils mirror the forward ones: f' changes sign, f'' does not
_BACKWARD_1 = -_FORWARD_1[::-1]
_BACKWARD_2 = _FORWARD_2[::-1]
# second-order first derivatives, to estimate the error of the fourth-order ones
_CENTRAL_1_LOW = np.array([0, 0, 0, -6, 0, 6, 0, 0, 0]) / 12
_FORWARD_1_LOW = np.array([0, 0, 0, 0, -18, 24, -6, 0, 0]) / 12
_BACKWARD_1_LOW = -_FORWARD_1_LOW[::-1]


@dataclass(frozen=True)
class Derivatives:
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
        0 central, 1 forward, -1 backward, 2 none (NaN).
    unconverged : ndarray of bool, shape (N,)
        Where the fourth- and second-order first derivatives of some point
        differ by more than :data:`CONVERGENCE_RTOL` of the sweep's largest:
        near a singular position, where the derivatives grow without bound.
    """

    input_name: str
    step: float
    first: dict
    second: dict
    stencil: np.ndarray
    unconverged: np.ndarray


def _step_for(sweep: Sweep, name: str, step: float | None) -> float:
    if step is not None:
        if not (np.isfinite(step) and step > 0):
            raise ConstructionError(f"the finite-difference step must be a positive number, "
                                    f"got {step!r}", node=name, field="step")
        return float(step)
    declared = sweep.construction.inputs[name]
    if declared.kind == "angle":
        return RELATIVE_STEP
    # a length input: a fraction of the span the sweep covers (of the declared
    # range where the sweep stays put)
    span = float(np.ptp(sweep.inputs[name])) or abs(declared.range[1] - declared.range[0])
    return RELATIVE_STEP * span


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
    """
    compiled = sweep.construction
    name = compiled.resolve_input(input_name, purpose="differentiate by")
    h = _step_for(sweep, name, step)
    return _along(sweep, {name: np.ones(len(sweep))}, h, name)


def _along(sweep: Sweep, direction: dict, h: float, label: str) -> Derivatives:
    """Differentiate every point along a direction in the inputs' space.

    The construction is evaluated again at ``inputs + k * h * direction``
    (k = -4..4) on each sample's branches; ``direction`` holds, per input, an
    array of its rate at each sample (inputs left out are held).
    """
    compiled = sweep.construction
    n, k = len(sweep), len(OFFSETS)
    # the perturbed evaluation holds k sweeps' worth of arrays: refused up front if
    # they would not fit, as the sweep itself is
    check_sweep_memory(len(compiled.steps), n * k, what="motion")
    # offset-major layout: sample i at offset j sits at j * n + i
    inputs = {name: np.tile(values, k) for name, values in sweep.inputs.items()}
    for name, rate in direction.items():
        shift = h * OFFSETS[:, None] * np.broadcast_to(rate, (n,))[None, :]
        inputs[name] = (sweep.inputs[name][None, :] + shift).ravel()
    # a branch that never changes (a broadcast view) stays one number: no per-sample choice
    branches = {name: (int(label[0]) if label.strides == (0,) else np.tile(label, k))
                for name, label in sweep.branches.items()}
    # evaluated about the mechanism's own middle: differences of positions far from
    # (0, 0) would lose the digits the derivatives need
    everything = np.concatenate([sweep.points[p][sweep.valid] for p in compiled.point_names])
    origin = np.nanmean(everything, axis=0) if everything.size else None
    perturbed = evaluate(compiled, inputs, n * k, branches, track=False, origin=origin)
    ok = perturbed.valid.reshape(k, n)
    central = ok[2:7].all(axis=0)
    forward = ok[4:9].all(axis=0) & ~central
    backward = ok[0:5].all(axis=0) & ~central & ~forward
    stencil = np.full(n, 2, dtype=np.int8)
    stencil[central], stencil[forward], stencil[backward] = 0, 1, -1
    weights = np.zeros((3, k, n))
    for mask, stencils in ((central, (_CENTRAL_1, _CENTRAL_2, _CENTRAL_1_LOW)),
                           (forward, (_FORWARD_1, _FORWARD_2, _FORWARD_1_LOW)),
                           (backward, (_BACKWARD_1, _BACKWARD_2, _BACKWARD_1_LOW))):
        for row, w in zip(weights, stencils, strict=True):
            row[:, mask] = w[:, None]
    missing = (stencil == 2) | ~sweep.valid
    first, second, error = {}, {}, np.zeros(n)
    for name in compiled.point_names:
        positions = perturbed.points[name].reshape(k, n, 2)
        # relative to the sample itself, so a point far from the origin loses no
        # digits and a fixed point has no rate at all; unused offsets may be NaN:
        # zero them so they do not poison the sums
        positions = positions - np.where(np.isfinite(positions[4]), positions[4], 0.0)
        positions = np.where(ok[:, :, None], positions, 0.0)
        d1, d2, d1_low = np.einsum("skn,knc->snc", weights, positions)
        d1, d2, d1_low = d1 / h, d2 / (h * h), d1_low / h
        d1[missing] = d2[missing] = np.nan
        error = np.fmax(error, np.hypot(*(d1 - d1_low).T))
        first[name], second[name] = d1, d2
    largest = max((np.nanmax(np.hypot(*d.T), initial=0.0) for d in first.values()), default=0.0)
    unconverged = ~missing & (error > CONVERGENCE_RTOL * largest)
    return Derivatives(label, h, first, second, stencil, unconverged)


@dataclass(frozen=True)
class Motion:
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
        Samples near a singular position, or without a usable stencil, where
        the derivatives are not to be trusted.
    derivatives : Derivatives
        The derivatives along the motion, with respect to time, that the
        velocities and accelerations come from.
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
    derivatives: Derivatives


def _time_step(sweep: Sweep, rates: dict, step: float | None) -> float:
    """Return a step in time that moves no input by more than its own step."""
    return min((_step_for(sweep, name, step) / max(np.max(np.abs(r)), 1e-300)
                for name, r in rates.items()), default=RELATIVE_STEP)


def _direction_of_travel(values: np.ndarray) -> np.ndarray:
    """Return +1 or -1 at each sample: whether the input arrived there increasing.

    The first sample takes the direction of the step after it; a sample
    repeating the one before keeps the direction it had.
    """
    step = np.sign(np.diff(values))
    if step.size == 0:
        return np.ones_like(values)
    direction = np.concatenate([step[:1], step])
    known = np.flatnonzero(direction)
    if known.size == 0:
        return np.ones_like(values)
    # carry the last known direction over repeated samples (the first known one backwards)
    last = np.maximum.accumulate(np.where(direction != 0, np.arange(len(direction)), known[0]))
    return direction[last]


def motion(sweep: Sweep, input_name: str | None = None, *, speed: ArrayLike | None = None,
           acceleration: ArrayLike = 0.0, step: float | None = None) -> Motion:
    """Velocity and acceleration of every point and declared link over a sweep.

    Parameters
    ----------
    sweep : Sweep
    input_name : str, optional
        The driving input, whose speed sets the clock; by default the first
        input that moves in the sweep. Other inputs move as the sweep moves
        them, in step with it (their rates follow from their values over
        time), and an input that stays put is held.
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
    n = len(sweep)
    driver = input_name
    if driver is None:
        moving = [k for k, v in sweep.inputs.items() if np.ptp(v) > 0]
        driver = moving[0] if moving else None
    driver = compiled.resolve_input(driver, purpose="drive the motion")
    declared = compiled.inputs[driver]
    values = sweep.inputs[driver]
    direction = _direction_of_travel(values)
    size = np.broadcast_to(np.asarray(declared.speed if speed is None else speed, float), (n,))
    rate = size * direction
    rate_change = np.broadcast_to(np.asarray(acceleration, dtype=float), (n,)) * direction
    with np.errstate(divide="ignore", invalid="ignore"):
        # time to travel between samples at the mean rate of the two
        dt = np.abs(np.diff(values)) / np.abs(0.5 * (size[1:] + size[:-1]))
    time = np.concatenate([[0.0], np.cumsum(dt)])
    # the other inputs move as the sweep moves them, in step with the driving one
    rates, changes = {driver: rate}, {driver: rate_change}
    for name, other in sweep.inputs.items():
        if name != driver and np.ptp(other) > 0 and n >= 2 and (np.diff(time) > 0).all():
            rates[name] = np.gradient(other, time)
            changes[name] = np.gradient(rates[name], time) if n >= 3 else np.zeros(n)
    # one step in time that moves no input by more than its own finite-difference step
    d = _along(sweep, rates, _time_step(sweep, rates, step), driver)
    velocity = d.first
    accel = dict(d.second)
    if any(np.any(c != 0) for c in changes.values()):
        # the inputs' own accelerations add a first derivative along them
        accelerating = {name: c for name, c in changes.items() if np.any(c != 0)}
        extra = _along(sweep, accelerating, _time_step(sweep, accelerating, step), driver)
        accel = {p: accel[p] + extra.first[p] for p in accel}
    angle, angular_velocity, angular_acceleration = {}, {}, {}
    for link in sweep.construction.links:
        start, end = link.points[0], link.points[1]
        x, y = (sweep.points[end] - sweep.points[start]).T
        vx, vy = (velocity[end] - velocity[start]).T
        ax, ay = (accel[end] - accel[start]).T
        r2 = x * x + y * y
        with np.errstate(divide="ignore", invalid="ignore"):
            omega = (x * vy - y * vx) / r2
            alpha = (x * ay - y * ax) / r2 - 2 * omega * (x * vx + y * vy) / r2
        angle[link.name], angular_velocity[link.name] = unwrap_valid(np.arctan2(y, x)), omega
        angular_acceleration[link.name] = alpha
    flagged = ((d.stencil == 2) & sweep.valid) | d.unconverged
    for margin in sweep.margins.values():
        with np.errstate(invalid="ignore"):
            flagged |= sweep.valid & (margin < SINGULAR_MARGIN)
    return Motion(sweep, driver, time, rate, rate_change, velocity, accel, angle,
                  angular_velocity, angular_acceleration, flagged, d)


def unwrap_valid(angle: np.ndarray) -> np.ndarray:
    """Unwrap angles across the finite samples, keeping NaN where they are not.

    Examples
    --------
    >>> unwrap_valid(np.array([3.0, np.nan, -3.0])).round(4)
    array([3.    ,    nan, 3.2832])
    """
    out = np.full_like(angle, np.nan)
    ok = np.isfinite(angle)
    out[ok] = np.unwrap(angle[ok])
    return out


def link_angles(sweep: Sweep) -> dict[str, np.ndarray]:
    """Return the angle of every declared link over a sweep.

    The angle of a link is that of the line from its first point to its
    second, counter-clockwise from the x axis, unwrapped over the valid
    samples so that it runs on continuously through full turns.

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
    """
    result = {}
    for link in sweep.construction.links:
        d = sweep.points[link.points[1]] - sweep.points[link.points[0]]
        result[link.name] = unwrap_valid(np.arctan2(d[:, 1], d[:, 0]))
    return result
