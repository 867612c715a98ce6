"""Vector-loop closure: an independent check of the construction engine.

The classical way to analyse a linkage writes one vector equation per loop
(the links as vectors adding up to zero), splits it into x and y parts and
solves them for the unknown angles and lengths. This module does that for
the four-bar and for the crank and slotted-lever quick-return mechanism,
in closed form and by Newton-Raphson with an analytic Jacobian,
continuing from sample to sample. It shares no code with the construction
engine, so agreement between the two is a real test of both.

Four-bar loop, with ground angle ``theta1``::

    r2 e(theta2) + r3 e(theta3) - r4 e(theta4) - r1 e(theta1) = 0

where ``e(t) = (cos t, sin t)``, ``r1`` the ground (``O2 -> O4``), ``r2``
the input (``O2 -> A``), ``r3`` the coupler (``A -> B``) and ``r4`` the
output (``O4 -> B``). *Open* is the circuit where B lies left of the line
``A -> O4`` (the quadrilateral ``O2 A B O4`` is convex when A is just above
the ground line), *crossed* the other one; in construction terms
``circle_circle(A, r3; O4, r4)`` on branch ``left`` or ``right``.

Quick-return loops: the slotted lever turns about ``O1`` at the
origin, the crank ``r2`` about ``O2 = (0, r1)``; the crank pin A slides in
the lever at distance ``r3`` from ``O1``; the lever drives a slider B on the
horizontal line ``y = r1 + r6`` at distance ``r4`` from ``O1`` and ``r5``
from the foot ``C = (0, r1 + r6)``::

    r1 + r2 sin(theta2) = r3 sin(theta3)      r2 cos(theta2) = r3 cos(theta3)
    r1 + r6 = r4 sin(theta3)                  r5 = r4 cos(theta3)

Failures
--------
Newton's method can fail near a toggle (singular Jacobian) or where the
linkage cannot be assembled. With ``on_failure="raise"`` (the default) the
solvers raise :class:`~geokin.errors.AssemblyError` naming the sample, its
input value and the residual; with ``on_failure="mask"`` they return NaN
there with ``valid`` False, and continue from the last good solution.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .compat import renamed_keywords
from .errors import AnalysisError, AssemblyError

__all__ = [
    "LoopSolution",
    "fourbar_closed_form",
    "fourbar_loop",
    "newton_continuation",
    "quick_return_closed_form",
    "quick_return_loop",
]


def _wrap(angle):
    """Wrap angles to ``(-pi, pi]``."""
    return np.pi - np.mod(np.pi - np.asarray(angle, dtype=float), 2 * np.pi)


@dataclass(frozen=True)
class LoopSolution:
    """The solution of loop equations over a sweep of the input.

    Attributes
    ----------
    names : tuple of str
        The unknowns, in the order of the columns of ``x``.
    x : ndarray, shape (N, len(names))
        The solution at each sample (NaN where ``valid`` is False).
    valid : ndarray of bool, shape (N,)
    residual : ndarray, shape (N,)
        The largest absolute residual of the loop equations at the solution.
    iterations : ndarray of int, shape (N,)
        Newton steps taken at each sample.
    """

    names: tuple[str, ...]
    x: np.ndarray = field(repr=False)
    valid: np.ndarray = field(repr=False)
    residual: np.ndarray = field(repr=False)
    iterations: np.ndarray = field(repr=False)

    def __getitem__(self, name: str) -> np.ndarray:
        """Return the column of one unknown."""
        return self.x[:, self.names.index(name)]


def newton_continuation(residual: Callable, jacobian: Callable, inputs, guess, *,
                        names: tuple[str, ...], tol: float = 1e-12, maxiter: int = 50,
                        on_failure: str = "raise", input_name: str = "input") -> LoopSolution:
    """Solve ``residual(x, u) = 0`` for every input ``u`` by Newton-Raphson.

    The first sample starts from ``guess``; every later one from a linear
    extrapolation of the two previous solutions (continuation), so the
    solution stays on the circuit the guess chose.

    Parameters
    ----------
    residual : callable ``(x, u) -> ndarray (m,)``
    jacobian : callable ``(x, u) -> ndarray (m, m)``
        The analytic derivative of ``residual`` with respect to ``x``.
    inputs : array_like, shape (N,)
    guess : array_like, shape (m,)
    names : tuple of str
        The names of the unknowns.
    tol : float
        Convergence when the Newton step and the residual are both below
        ``tol`` times the scale of the solution.
    maxiter : int
    on_failure : {"raise", "mask"}
    input_name : str
        The input's name in messages.

    Returns
    -------
    LoopSolution

    Examples
    --------
    The square root of u, continued along u:

    >>> sol = newton_continuation(lambda x, u: x ** 2 - u, lambda x, u: np.diag(2 * x),
    ...                           [1.0, 4.0, 9.0], [1.0], names=("root",))
    >>> sol["root"]
    array([1., 2., 3.])
    """
    if on_failure not in ("raise", "mask"):
        raise AnalysisError(f"on_failure must be 'raise' or 'mask', got {on_failure!r}")
    u = np.atleast_1d(np.asarray(inputs, dtype=float))
    x = np.array(guess, dtype=float).reshape(-1)
    m = len(x)
    out = np.full((len(u), m), np.nan)
    valid = np.zeros(len(u), dtype=bool)
    res = np.full(len(u), np.nan)
    its = np.zeros(len(u), dtype=int)
    good: list[int] = []
    for k, uk in enumerate(u):
        if len(good) >= 2 and good[-1] == k - 1 and good[-2] == k - 2:
            start = 2 * out[k - 1] - out[k - 2]
        elif good:
            start = out[good[-1]].copy()
        else:
            start = x.copy()
        x, r, it, why = _newton(residual, jacobian, start, uk, tol, maxiter)
        if why and good and not np.array_equal(start, out[good[-1]]):
            # the extrapolated start may overshoot: retry from the last solution
            x, r, it, why = _newton(residual, jacobian, out[good[-1]].copy(), uk, tol, maxiter)
        its[k] = it
        res[k] = r
        if why:
            if on_failure == "raise":
                raise AssemblyError(f"loop equations not solved at sample {k} "
                                    f"({input_name} = {uk:g}): {why}; residual {r:.3g}")
            continue
        out[k] = x
        valid[k] = True
        good.append(k)
    return LoopSolution(tuple(names), out, valid, res, its)


def _newton(residual, jacobian, x, u, tol, maxiter):
    """Return (x, max residual, iterations, failure text or '')."""
    for it in range(1, maxiter + 1):
        f = np.asarray(residual(x, u), dtype=float)
        j = np.asarray(jacobian(x, u), dtype=float)
        try:
            step = np.linalg.solve(j, -f)
        except np.linalg.LinAlgError:
            return x, float(np.max(np.abs(f))), it, "singular Jacobian (a toggle position?)"
        if not np.all(np.isfinite(step)):
            return x, float(np.max(np.abs(f))), it, "singular Jacobian (a toggle position?)"
        x = x + step
        scale = max(1.0, float(np.max(np.abs(x))))
        if np.max(np.abs(step)) <= tol * scale:
            r = float(np.max(np.abs(residual(x, u))))
            if r <= 1e3 * tol * scale:
                return x, r, it, ""
    r = float(np.max(np.abs(residual(x, u))))
    return x, r, maxiter, f"no convergence in {maxiter} iterations"


# -- four-bar -------------------------------------------------------------------------


@renamed_keywords(input="input_link", output="output_link")
def fourbar_closed_form(ground: float, input_link: float, coupler: float, output_link: float,
                        theta2, open: bool | None = None, *,  # noqa: A002 - the old name
                        crossed: bool = False, theta1: float = 0.0):
    """Solve the four-bar loop in closed form (the half-angle formula).

    The loop gives ``A cos(theta4) + B sin(theta4) + C = 0`` with
    ``A = 2 r1 r4 cos(theta1) - 2 r2 r4 cos(theta2)``,
    ``B = 2 r1 r4 sin(theta1) - 2 r2 r4 sin(theta2)`` and
    ``C = r1**2 + r2**2 + r4**2 - r3**2 - 2 r1 r2 cos(theta1 - theta2)``;
    with ``t = tan(theta4 / 2)`` it is the quadratic
    ``(C - A) t**2 + 2 B t + (A + C) = 0``, so
    ``theta4 = 2 atan2(-B -+ sqrt(A**2 + B**2 - C**2), C - A)``, the minus
    sign for the open circuit. The coupler angle follows from the loop's two
    components with ``atan2``, which keeps its quadrant.

    Parameters
    ----------
    ground, input_link, coupler, output_link : float
        ``r1``, ``r2``, ``r3``, ``r4``.
    theta2 : float or array_like
        Input angle, radians.
    open : bool, optional
        Deprecated, the old way to choose the circuit: ``open=False`` is
        ``crossed=True``.
    crossed : bool
        The crossed circuit, or (by default) the open one (B left of ``A -> O4``).
    theta1 : float
        Angle of the ground line ``O2 -> O4``.

    Returns
    -------
    theta3, theta4 : ndarray
        Coupler and output angles in ``(-pi, pi]``; NaN where the linkage
        cannot be assembled.

    Examples
    --------
    A crank-rocker (ground 24, crank 10.55, coupler 25, rocker 14) at
    theta2 = 0, open and crossed:

    >>> t3, t4 = fourbar_closed_form(24, 10.55, 25, 14, 0.0)
    >>> round(float(np.degrees(t3)), 6), round(float(np.degrees(t4)), 6)
    (24.917114, 48.792913)
    >>> t3, t4 = fourbar_closed_form(24, 10.55, 25, 14, 0.0, crossed=True)
    >>> round(float(np.degrees(t3)), 6), round(float(np.degrees(t4)), 6)
    (-24.917114, -48.792913)
    """
    if open is not None:
        warnings.warn("fourbar_closed_form(..., open) is now fourbar_closed_form(..., "
                      "crossed=not open); the old argument will be removed",
                      DeprecationWarning, stacklevel=2)
        crossed = not open
    r1, r2, r3, r4 = (float(v) for v in (ground, input_link, coupler, output_link))
    t2 = np.asarray(theta2, dtype=float)
    a = 2 * r1 * r4 * np.cos(theta1) - 2 * r2 * r4 * np.cos(t2)
    b = 2 * r1 * r4 * np.sin(theta1) - 2 * r2 * r4 * np.sin(t2)
    c = r1 * r1 + r2 * r2 + r4 * r4 - r3 * r3 - 2 * r1 * r2 * np.cos(theta1 - t2)
    disc = a * a + b * b - c * c
    scale = (r1 + r2 + r3 + r4) ** 4
    disc = np.where((disc < 0) & (disc > -1e-13 * scale), 0.0, disc)
    with np.errstate(invalid="ignore"):
        root = np.sqrt(disc)
    # tan(theta4 / 2) = (-b -+ root) / (c - a) = (a + c) / (-b +- root): of the two
    # forms take the one without cancellation (c - a vanishes for a rhombus)
    sign = np.where(b >= 0, 1.0, -1.0)
    q = -b - sign * root
    minus_is_q = sign > 0
    stable_first = ~minus_is_q if crossed else minus_is_q
    t4 = np.where(stable_first, 2 * np.arctan2(q, c - a), 2 * np.arctan2(a + c, q))
    x = r1 * np.cos(theta1) + r4 * np.cos(t4) - r2 * np.cos(t2)
    y = r1 * np.sin(theta1) + r4 * np.sin(t4) - r2 * np.sin(t2)
    t3 = np.arctan2(y, x)
    return _wrap(t3), _wrap(t4)


@renamed_keywords(input="input_link", output="output_link")
def fourbar_loop(ground: float, input_link: float, coupler: float, output_link: float,
                 theta2, *,
                 guess, theta1: float = 0.0, tol: float = 1e-12, maxiter: int = 50,
                 on_failure: str = "raise") -> LoopSolution:
    """Solve the four-bar loop for ``theta3`` and ``theta4`` by Newton-Raphson.

    The residual is the loop ``r2 e(theta2) + r3 e(theta3) - r4 e(theta4) -
    r1 e(theta1)``; its Jacobian with respect to ``(theta3, theta4)`` is
    ``[[-r3 sin theta3, r4 sin theta4], [r3 cos theta3, -r4 cos theta4]]``,
    singular where coupler and output are aligned (a toggle).

    Parameters
    ----------
    ground, input_link, coupler, output_link : float
    theta2 : array_like, shape (N,)
        Input angles in radians, in the order of the motion.
    guess : (float, float)
        ``(theta3, theta4)`` near the solution at the first sample: it picks
        the circuit, which continuation then follows.
    theta1 : float
        Angle of the ground line.
    tol, maxiter, on_failure
        See :func:`newton_continuation`.

    Returns
    -------
    LoopSolution
        Unknowns ``"theta3"``, ``"theta4"``, wrapped to ``(-pi, pi]``.

    Examples
    --------
    >>> sol = fourbar_loop(24, 10.55, 25, 14, [0.0, 0.1], guess=(0.5, 1.2))
    >>> np.round(np.degrees(sol.x[0]), 6)
    array([24.917114, 48.792913])
    """
    r1, r2, r3, r4 = (float(v) for v in (ground, input_link, coupler, output_link))
    g = (r1 * np.cos(theta1), r1 * np.sin(theta1))

    def residual(x, t2):
        t3, t4 = x
        return np.array([r2 * np.cos(t2) + r3 * np.cos(t3) - r4 * np.cos(t4) - g[0],
                         r2 * np.sin(t2) + r3 * np.sin(t3) - r4 * np.sin(t4) - g[1]])

    def jacobian(x, t2):
        t3, t4 = x
        return np.array([[-r3 * np.sin(t3), r4 * np.sin(t4)],
                         [r3 * np.cos(t3), -r4 * np.cos(t4)]])

    sol = newton_continuation(residual, jacobian, theta2, guess, names=("theta3", "theta4"),
                              tol=tol, maxiter=maxiter, on_failure=on_failure,
                              input_name="theta2")
    return LoopSolution(sol.names, _wrap(sol.x), sol.valid, sol.residual, sol.iterations)


# -- quick return -----------------------------------------------------------------------


def quick_return_closed_form(r1: float, r2: float, r6: float, theta2) -> dict[str, np.ndarray]:
    """Solve the quick-return loops analytically.

    ``r3 = sqrt(r1**2 + r2**2 + 2 r1 r2 sin theta2)``,
    ``theta3 = atan2(r1 + r2 sin theta2, r2 cos theta2)``,
    ``r4 = (r1 + r6) / sin theta3`` and ``r5 = r4 cos theta3``.

    Parameters
    ----------
    r1 : float
        Distance from the lever pivot O1 up to the crank pivot O2 (``r2 < r1``).
    r2 : float
        Crank length.
    r6 : float
        Height of the slider's line above O2.
    theta2 : float or array_like
        Crank angle, radians.

    Returns
    -------
    dict of str to ndarray
        ``"r3"``, ``"theta3"`` (radians, in ``(0, pi)``), ``"r4"``, ``"r5"``.

    Examples
    --------
    With r1 = 60, r2 = 40, r6 = 60 (the crank 40 on a pivot 60 above the
    lever's, the slider's line 60 above that) at theta2 = 30 degrees:

    >>> q = quick_return_closed_form(60, 40, 60, np.radians(30))
    >>> [round(float(q[k]), 3) for k in ("r3", "r4", "r5")]
    [87.178, 130.767, 51.962]
    >>> round(float(np.degrees(q["theta3"])), 3)
    66.587
    """
    t2 = np.asarray(theta2, dtype=float)
    y = r1 + r2 * np.sin(t2)
    x = r2 * np.cos(t2)
    r3 = np.hypot(x, y)
    t3 = np.arctan2(y, x)
    r4 = (r1 + r6) / np.sin(t3)
    return {"r3": r3, "theta3": t3, "r4": r4, "r5": r4 * np.cos(t3)}


def quick_return_loop(r1: float, r2: float, r6: float, theta2, *, guess, tol: float = 1e-12,
                      maxiter: int = 50, on_failure: str = "raise") -> LoopSolution:
    """Solve the four quick-return loop equations for ``r3, r4, r5, theta3`` by Newton-Raphson.

    The unknowns are ``x = (r3, r4, r5, theta3)``; the Jacobian of the
    residuals (module docstring) with respect to them is::

        [[-sin t3,       0, 0, -r3 cos t3],
         [-cos t3,       0, 0,  r3 sin t3],
         [      0, -sin t3, 0, -r4 cos t3],
         [      0, -cos t3, 1,  r4 sin t3]]

    Parameters
    ----------
    r1, r2, r6 : float
        As in :func:`quick_return_closed_form`.
    theta2 : array_like, shape (N,)
        Crank angles in radians, in the order of the motion.
    guess : (float, float, float, float)
        ``(r3, r4, r5, theta3)`` near the solution at the first sample.
    tol, maxiter, on_failure
        See :func:`newton_continuation`.

    Returns
    -------
    LoopSolution
        Unknowns ``"r3"``, ``"r4"``, ``"r5"``, ``"theta3"`` (wrapped to
        ``(-pi, pi]``).

    Examples
    --------
    The same mechanism at theta2 = 30 degrees, from a rough guess:

    >>> sol = quick_return_loop(60, 40, 60, [np.radians(30)], guess=(80, 120, 50, 1.0))
    >>> np.round(sol.x[0, :3], 3), round(float(np.degrees(sol["theta3"][0])), 3)
    (array([ 87.178, 130.767,  51.962]), 66.587)
    """
    def residual(x, t2):
        r3, r4, r5, t3 = x
        return np.array([r1 + r2 * np.sin(t2) - r3 * np.sin(t3),
                         r2 * np.cos(t2) - r3 * np.cos(t3),
                         r1 + r6 - r4 * np.sin(t3),
                         r5 - r4 * np.cos(t3)])

    def jacobian(x, t2):
        r3, r4, r5, t3 = x
        s, c = np.sin(t3), np.cos(t3)
        return np.array([[-s, 0.0, 0.0, -r3 * c],
                         [-c, 0.0, 0.0, r3 * s],
                         [0.0, -s, 0.0, -r4 * c],
                         [0.0, -c, 1.0, r4 * s]])

    sol = newton_continuation(residual, jacobian, theta2, guess,
                              names=("r3", "r4", "r5", "theta3"), tol=tol, maxiter=maxiter,
                              on_failure=on_failure, input_name="theta2")
    x = sol.x.copy()
    x[:, 3] = _wrap(x[:, 3])
    return LoopSolution(sol.names, x, sol.valid, sol.residual, sol.iterations)
