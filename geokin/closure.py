"""Groups of points found together: Newton's method on their constraint equations.

A closure group has k unknown points tied to each other and to known points
by constraints, two equations per unknown point (an Assur group: the triad
of a Stephenson III six-bar has 4 unknown points and 8 distances). Two kinds
of constraint are known here:

- a **distance** between two points P and Q, either of which may be known:
  ``(|P - Q|**2 - d**2) / (2 d) = 0``, which is ``|P - Q| - d`` to first
  order, so every equation is a length and the Jacobian is dimensionless;
- a point P **on the line** through Q and R: the signed distance
  ``cross(R - Q, P - Q) / |R - Q| = 0``.

Everything is vectorised over samples: the unknowns are an (N, 2k) array,
the Jacobians an (N, 2k, 2k) stack solved at once with :func:`numpy.linalg.solve`.

:func:`continue_along` follows one assembly along a path of samples by
continuation (see its docstring); :func:`newton` solves samples from guesses
of their own. Every loop is bounded: :data:`MAX_ITERATIONS` Newton
iterations, :data:`MAX_SUBSTEPS` pieces of a step.

Examples
--------
One unknown point B at distance 5 from A = (0, 0) and 5 from C = (6, 0),
starting near (3, 3): B = (3, 4).

>>> import numpy as np
>>> system = System(1, (("B", "A"), ("B", "C")), ())
>>> known = {"A": (np.zeros(1), np.zeros(1)), "C": (np.full(1, 6.0), np.zeros(1))}
>>> z, ok, margin = newton(system, ["B"], known, np.array([[5.0, 5.0]]), np.array([[3.0, 3.0]]))
>>> z.round(12).tolist(), ok.tolist()
([[3.0, 4.0]], [True])
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np

__all__ = ["MAX_ITERATIONS", "MAX_SUBSTEPS", "SINGULAR_MARGIN", "System", "continue_along",
           "margins", "newton", "stalls_singular"]

MAX_ITERATIONS = 30
"""The most Newton iterations for one solve from a guess."""

CHUNK_ITERATIONS = 8
"""The most Newton iterations for the samples of a chunk of the continuation."""

MAX_SUBSTEPS = 1024
"""The most pieces one step between samples is cut into by the continuation."""

RESIDUAL_RTOL = 1e-13
"""Converged: every equation's residual within this times the group's size
(plus the rounding of the coordinates, :data:`RESIDUAL_ROUNDING`)."""

RESIDUAL_ROUNDING = 8 * np.finfo(float).eps
"""Converged also within this times the largest coordinate of the row: far from
(0, 0) a difference of coordinates is rounded to their size, not the group's."""

POLISH_RTOL = 1e-6
"""The longest last step taken after convergence, times the group's size."""

SINGULAR_MARGIN = 1e-14
"""A solution whose margin (:func:`margins`) is below this is a singular position."""

NEAR_SINGULAR = 1e-6
"""A continuation that stops where the margin is below this stops at a
singular position (a fold of the assembly, as a toggle is for two circles)."""

JUMP_RATIO = 0.5
"""A solution more than this fraction of the predicted step (plus rounding)
away from the prediction has jumped to another assembly."""

MAX_CHUNK = 512
"""The most samples the continuation solves together."""


@dataclass(frozen=True)
class System:
    """The constraint equations of a group, by point name.

    Attributes
    ----------
    k : int
        The number of unknown points.
    distances : tuple of (str, str)
        The two points of each distance constraint, in the order of the
        values given to the solvers.
    lines : tuple of (str, str, str)
        Each point-on-line constraint: the point, and two points of the line.
    """

    k: int
    distances: tuple[tuple[str, str], ...]
    lines: tuple[tuple[str, str, str], ...] = ()

    @property
    def equations(self) -> int:
        """Return the number of equations."""
        return len(self.distances) + len(self.lines)


def _point(z, unknowns, known, name, n):
    """Return a point's x, y over the N rows of z (arrays or numbers), and its index.

    The index is the point's among the unknowns, or -1 for a known point.
    """
    if name in unknowns:
        i = unknowns.index(name)
        return z[:, 2 * i], z[:, 2 * i + 1], i
    x, y = known[name]
    if np.ndim(x) and np.shape(x) != (n,):
        x, y = np.broadcast_to(x, (n,)), np.broadcast_to(y, (n,))
    return x, y, -1


@dataclass(frozen=True)
class _Layout:
    """Where the points of a group's distance equations are: columns of one array."""

    names: tuple[str, ...]  # the unknown points, then the known ones
    p: np.ndarray  # each equation's two points' columns
    q: np.ndarray
    p_rows: np.ndarray  # the equations whose p (or q) is unknown
    q_rows: np.ndarray
    bend: np.ndarray  # each equation's largest second derivative, times its distance


@lru_cache(maxsize=64)
def _layout(system: System, unknowns: tuple[str, ...]) -> _Layout:
    """Return the columns of the points of ``system``'s distance equations."""
    names = list(unknowns)
    for pair in system.distances:
        names.extend(name for name in pair if name not in names)
    column = {name: i for i, name in enumerate(names)}
    p = np.array([column[a] for a, _ in system.distances])
    q = np.array([column[b] for _, b in system.distances])
    k = len(unknowns)
    # |P - Q|**2 changes by at most twice |D|**2 along a unit D where both move
    bend = np.where((p < k) & (q < k), 2.0, 1.0)
    return _Layout(tuple(names), p, q, np.flatnonzero(p < k), np.flatnonzero(q < k), bend)


def _residual_jacobian(system: System, unknowns, known, lengths, z):
    """Return the residuals (M, E) and Jacobians (M, E, 2k) at unknowns z (M, 2k).

    ``known`` holds each known point's (x, y) as arrays of M samples (or
    numbers), ``lengths`` the distances as an (M, D) array.
    """
    m = z.shape[0]
    f = np.empty((m, system.equations))
    jac = np.zeros((m, system.equations, 2 * system.k))
    if system.distances:
        layout = _layout(system, tuple(unknowns))
        # every point's x and y, the unknowns first: (M, points)
        xs = np.empty((m, len(layout.names)))
        ys = np.empty((m, len(layout.names)))
        xs[:, :system.k], ys[:, :system.k] = z[:, 0::2], z[:, 1::2]
        for column, name in enumerate(layout.names[system.k:], start=system.k):
            xs[:, column], ys[:, column] = known[name]
        d = lengths[:, :len(system.distances)]
        dx = xs[:, layout.p] - xs[:, layout.q]
        dy = ys[:, layout.p] - ys[:, layout.q]
        f[:, :d.shape[1]] = (dx * dx + dy * dy - d * d) / (2 * d)
        gx, gy = dx / d, dy / d
        rows, cols = layout.p_rows, 2 * layout.p[layout.p_rows]
        jac[:, rows, cols], jac[:, rows, cols + 1] = gx[:, rows], gy[:, rows]
        rows, cols = layout.q_rows, 2 * layout.q[layout.q_rows]
        jac[:, rows, cols], jac[:, rows, cols + 1] = -gx[:, rows], -gy[:, rows]
    offset = len(system.distances)
    for e, (p, q, r) in enumerate(system.lines, start=offset):
        px, py, i = _point(z, unknowns, known, p, m)
        qx, qy, j = _point(z, unknowns, known, q, m)
        rx, ry, l_ = _point(z, unknowns, known, r, m)
        ux, uy = rx - qx, ry - qy
        length = np.hypot(ux, uy)
        wx, wy = px - qx, py - qy
        cross = ux * wy - uy * wx
        f[:, e] = cross / length
        # d(cross)/dP = (-uy, ux); d/dR = (wy, -wx) - cross * u / |u|**2 ... on the unit
        if i >= 0:
            jac[:, e, 2 * i] += -uy / length
            jac[:, e, 2 * i + 1] += ux / length
        dcr = (wy / length - cross * ux / length**3, -wx / length - cross * uy / length**3)
        if l_ >= 0:
            jac[:, e, 2 * l_] += dcr[0]
            jac[:, e, 2 * l_ + 1] += dcr[1]
        if j >= 0:
            jac[:, e, 2 * j] += (uy - wy) / length + cross * ux / length**3
            jac[:, e, 2 * j + 1] += (wx - ux) / length + cross * uy / length**3
    return f, jac


def margins(jac: np.ndarray) -> np.ndarray:
    """Return each Jacobian's margin: its normalised determinant, squared.

    That is ``(|det J| / (product of the row lengths)) ** 2``, between 0
    (singular) and 1 (orthogonal rows); like a two-root node's margin it
    falls to zero linearly in the input at a fold of the assembly (where the
    smallest singular value goes as the square root of the distance).

    Examples
    --------
    >>> margins(np.array([[[1.0, 0.0], [0.0, 0.5]], [[1.0, 1.0], [1.0, 1.0]]])).round(12)
    array([1., 0.])
    """
    out = np.full(jac.shape[0], np.nan)
    finite = np.isfinite(jac).all(axis=(1, 2))
    if finite.any():
        j = jac[finite]
        rows = np.prod(np.sqrt(np.einsum("nij,nij->ni", j, j)), axis=1)
        with np.errstate(all="ignore"):
            out[finite] = np.where(rows > 0, (np.linalg.det(j) / rows) ** 2, 0.0)
    return out


def _solve(jac, f):
    """Return the Newton steps -J^-1 f, NaN where a Jacobian is singular."""
    out = np.full(f.shape, np.nan)
    finite = np.isfinite(jac).all(axis=(1, 2)) & np.isfinite(f).all(axis=1)
    if not finite.any():
        return out
    j, r = jac[finite], f[finite]
    try:
        out[finite] = -np.linalg.solve(j, r[..., None])[..., 0]
    except np.linalg.LinAlgError:  # one singular matrix: solve each with lstsq guard
        steps = np.full(r.shape, np.nan)
        for a in range(j.shape[0]):
            try:
                steps[a] = -np.linalg.solve(j[a], r[a])
            except np.linalg.LinAlgError:
                pass
        out[finite] = steps
    return out


def _iterate(system, unknowns, known, lengths, z, scale, iterations):
    """Run up to ``iterations`` Newton steps on every row; return z, converged, first step."""
    z, done, first, _, _ = _run(system, unknowns, known, lengths, z, scale, iterations)
    return z, done, first


def _run(system, unknowns, known, lengths, z, scale, iterations):
    """Run Newton as :func:`_iterate` does, and return more.

    Also the residuals at the start, and the Jacobians at the end (before the
    last, polishing step).
    """
    z = z.copy()
    done = np.zeros(z.shape[0], dtype=bool)
    first = start = None
    # each row's: the group's size, and the rounding of its coordinates where they are
    # far larger
    tolerance = RESIDUAL_RTOL * scale + RESIDUAL_ROUNDING * np.max(
        np.abs(np.where(np.isfinite(z), z, 0.0)), axis=1, initial=0.0)
    for _ in range(iterations):
        f, jac = _residual_jacobian(system, unknowns, known, lengths, z)
        small = np.all(np.abs(f) <= tolerance[:, None], axis=1)
        done = small
        step = _solve(jac, f)
        if first is None:
            first = np.where(np.isfinite(step), step, np.nan)
            start = f
        if done.all():
            break
        # a step longer than the group's size is cut to it: a guess far off cannot fly off
        size = np.max(np.abs(step), axis=1, initial=0.0)
        cut = np.where(size > scale, scale / np.where(size > 0, size, 1.0), 1.0)
        z = np.where(done[:, None], z, z + cut[:, None] * step)
    else:
        f, jac = _residual_jacobian(system, unknowns, known, lengths, z)
        done = np.all(np.abs(f) <= tolerance[:, None], axis=1)
        step = _solve(jac, f)
    # one more step where converged: Newton's last step takes the solution to rounding,
    # which finite differences of the positions need. Where the Jacobian is (nearly)
    # singular that step is rounding divided by nearly zero, and may fly to another
    # solution: it is kept only if it is short and leaves the residual as small
    if done.any():
        polish = (done & np.isfinite(step).all(axis=1)
                  & (np.max(np.abs(step), axis=1, initial=0.0) <= POLISH_RTOL * scale))
        if polish.any():
            f_new, _ = _residual_jacobian(system, unknowns, known, lengths, z + step)
            polish &= (np.max(np.abs(f_new), axis=1)
                       <= np.maximum(np.max(np.abs(f), axis=1), tolerance))
            z = np.where(polish[:, None], z + step, z)
    assert first is not None
    return z, done, first, start, jac


def _scale(lengths, known_xy) -> float:
    """Return the group's size: its longest distance."""
    finite = lengths[np.isfinite(lengths)]
    return float(max(np.max(np.abs(finite), initial=0.0), 1e-300))


def newton(system: System, unknowns: Sequence[str], known: Mapping, lengths: np.ndarray,
           guess: np.ndarray, iterations: int = MAX_ITERATIONS):
    """Solve every sample from its own guess.

    Parameters
    ----------
    system : System
    unknowns : sequence of str
        The unknown points, in the order of ``guess``'s columns (x, y each).
    known : mapping of str to (x, y)
        The known points, arrays of N samples or numbers.
    lengths : ndarray, shape (N, D)
        The distances, one column per distance constraint.
    guess : ndarray, shape (N, 2k)

    Returns
    -------
    z : ndarray, shape (N, 2k)
        The solutions, NaN where Newton did not converge.
    converged : ndarray of bool, shape (N,)
    margin : ndarray, shape (N,)
        Of each solution's Jacobian (:func:`margins`).
    """
    scale = _scale(lengths, known)
    z, ok, _ = _iterate(system, unknowns, known, lengths, np.asarray(guess, dtype=float), scale,
                        iterations)
    _, jac = _residual_jacobian(system, unknowns, known, lengths, z)
    margin = margins(jac)
    ok &= np.isfinite(z).all(axis=1)
    z = np.where(ok[:, None], z, np.nan)
    return z, ok, np.where(ok, margin, np.nan)


def _rows(known, lengths, rows):
    """Return the known points and lengths at some samples."""
    picked = {}
    for name, (x, y) in known.items():
        picked[name] = (x[rows] if np.ndim(x) else x, y[rows] if np.ndim(y) else y)
    return picked, lengths[rows]


def _blend(known, lengths, i, j, t):
    """Return the data linearly between samples i and j at fractions t (arrays)."""
    picked = {}
    for name, (x, y) in known.items():
        picked[name] = ((x[i] + t * (x[j] - x[i])) if np.ndim(x) else x,
                        (y[i] + t * (y[j] - y[i])) if np.ndim(y) else y)
    return picked, lengths[i] + t[:, None] * (lengths[j] - lengths[i])


def continue_along(system: System, unknowns: Sequence[str], known: Mapping,
                   lengths: np.ndarray, start: np.ndarray,
                   path_starts: np.ndarray | None = None,
                   between: Callable | None = None, samples: np.ndarray | None = None,
                   positions: np.ndarray | None = None):
    """Follow one assembly along the samples, from a sketch where it first fits.

    The first sample where Newton from ``start`` converges begins the path,
    followed from there to the last sample and back to the first.
    Each later sample starts from the last solution found: samples are
    solved a chunk at a time (up to :data:`MAX_CHUNK`, growing while all
    succeed), all from the chunk's starting solution, with at most
    :data:`CHUNK_ITERATIONS` iterations each, vectorised over the chunk.
    A sample is accepted while every sample before it in the chunk is, its
    Newton converged, and it continues the solution before it
    (:func:`_continues`: within :data:`TRUST` of the distance to that
    solution's nearest other solution, and where the linearised step
    predicts). Where the first sample of a chunk fails, the step to it is
    cut into pieces (the known points and distances as ``between`` gives
    them along the step), each as long as the step allowed, at most
    :data:`MAX_SUBSTEPS` pieces; at a singular position where the assembly
    goes on (two assemblies cross), a piece steps over it along the last
    rate (:func:`_substeps`).

    A step that cannot be crossed leaves its sample unsolved: a gap. A
    later sample resumes the path only where its assembly is reached again
    (:meth:`_Path._resume`): from the last solution, moving the inputs
    straight to the sample's, or at the inputs of the path's first solved
    sample (a crank that turns fully comes back to where it began). The
    samples between the gap and a resumed one are followed back from it.

    ``path_starts`` are the samples where a new path begins (design
    variants, one after the other): each path is followed on its own, from
    the sketch. ``between(a, b, t)`` gives the known points and lengths at
    fractions ``t`` of the way from sample a to b, as the inputs move along
    the straight segment (the points on arcs, as a crank's pin); without it
    they move straight between their samples. ``samples`` are the samples'
    indices as ``between`` takes them, ``positions`` (N, m) their places in
    the space of the inputs: a step that cannot be crossed stops at an
    obstacle there, and a segment through it is not tried again.

    Returns
    -------
    z : ndarray, shape (N, 2k)
        NaN where unsolved.
    margin : ndarray, shape (N,)
    singular : ndarray of bool, shape (N,)
        Unsolved samples where the path stopped at a singular position.
    """
    n = lengths.shape[0]
    numbered = np.arange(n) if samples is None else np.asarray(samples)
    if path_starts is None or len(path_starts) < 2:
        path = _Path(system, unknowns, known, lengths, between, numbered, positions)
        path.follow(np.asarray(start, dtype=float).reshape(-1))
        return path.z, path.margin, path.singular
    z = np.full((n, 2 * system.k), np.nan)
    margin = np.full(n, np.nan)
    singular = np.zeros(n, dtype=bool)
    ends = np.append(np.asarray(path_starts)[1:], n)
    for begin, end in zip(path_starts, ends, strict=True):
        rows = np.arange(begin, end)
        data, length = _rows(known, lengths, rows)
        part = _Path(system, unknowns, data, length, between, numbered[rows],
                     None if positions is None else positions[rows])
        part.follow(np.asarray(start, dtype=float).reshape(-1))
        z[rows], margin[rows], singular[rows] = part.z, part.margin, part.singular
    return z, margin, singular


TRUST = 0.25
"""A step is taken only while the solution moves less than this fraction of the
distance from it to the group's nearest other solution (:func:`_separation`): Newton
cannot then land on another assembly, however coarse the samples."""

MAX_ATTEMPTS = 8
"""The most samples past one gap tried by crossing the straight segment to them."""

CROSSING_PIECE = 1e-9
"""A piece of a step this small (a fraction of the step) that still fails stops at a
singular position: the step over it along the last rate is tried."""

ANCHOR_MARGIN = 1e-6
"""The least margin of a solution the step over a singular position is predicted from."""

TANGENT_MARGIN = 1e-10
"""Below this margin a solution's tangent is not told by its Jacobian: a step from
it starts from a sample before (see :meth:`_Path._step`)."""

DIP = 100.0
"""How many times larger the margin at the sample a step starts from instead must be
than at the sample on the singular position (see :meth:`_Path._step`)."""

MAX_BACK = 64
"""The most samples back a step from a sample at a singular position starts (see
:meth:`_Path._step`)."""

CROSSING_MOVE = 1e-4
"""How far (times the group's size) the step over a singular position moves the
solution along its last rate."""


class _Path:
    """The continuation of one assembly along the samples of one path."""

    def __init__(self, system, unknowns, known, lengths, between, numbered, positions=None):
        self.system, self.unknowns = system, unknowns
        self.known, self.lengths = known, lengths
        self.between, self.numbered, self.positions = between, numbered, positions
        n = lengths.shape[0]
        self.n = n
        self.z = np.full((n, 2 * system.k), np.nan)
        self.margin = np.full(n, np.nan)
        self.singular = np.zeros(n, dtype=bool)
        self.scale = _scale(lengths, known)
        # where in the space of the inputs a step stopped: a fold of the assembly
        self.obstacles: list[np.ndarray | None] = []

    def follow(self, start: np.ndarray, resume: bool = True) -> None:
        """Solve the first sample that Newton from ``start`` solves, and follow on.

        The samples after it are followed forwards, those before it back
        from it. Without ``resume`` the path ends at its first gap.
        """
        first = self._first(start)
        if first is None:
            return
        self._from(first, resume)
        if (self.margin[first] < ANCHOR_MARGIN and first + 1 < self.n
                and not np.isfinite(self.z[first + 1]).all()):
            self._from_regular(start, first, resume)
        self.singular &= ~np.isfinite(self.z).all(axis=1)

    def _from(self, first: int, resume: bool) -> None:
        """Follow the path from its solved sample ``first``, back and forwards."""
        if first > 0:
            self._follow_back(first, 0, resume)
        self._forwards(first, resume)

    def _from_regular(self, start: np.ndarray, first: int, resume: bool) -> None:
        """Follow the path again from a regular sample, where its first lies on a crossing.

        At a sample where two assemblies cross, the sketch fits both, and
        no rate is known there to step over the crossing along. The first
        sample after it that the sketch solves away from singular positions
        begins the path instead, where the path followed from it comes back
        to sample ``first`` through the solution found there (both
        assemblies pass through it); else the path stays as it was.
        """
        kept = (self.z.copy(), self.margin.copy(), self.singular.copy(), list(self.obstacles))
        self.z[:], self.margin[:], self.singular[:], self.obstacles = np.nan, np.nan, False, []
        regular = self._first(start, first + 1, ANCHOR_MARGIN)
        if regular is not None:
            self._from(regular, resume)
        # at a crossing both assemblies pass through the first solution, to about the
        # square root of the tolerance: a path through another point is another assembly
        back = self.z[first] - kept[0][first]
        if not np.max(np.abs(back)) <= 10 * np.sqrt(RESIDUAL_RTOL) * self.scale:
            self.z, self.margin, self.singular, self.obstacles = kept

    def _first(self, start: np.ndarray, since: int = 0,
               least: float = SINGULAR_MARGIN) -> int | None:
        """Solve the first sample from ``since`` on that Newton from the sketch solves.

        Its solution's margin must be at least ``least``. Returns the sample.
        """
        finite = np.isfinite(self.lengths).all(axis=1)
        for x, y in self.known.values():
            if np.ndim(x):
                finite &= np.isfinite(x) & np.isfinite(y)
        candidates = np.flatnonzero(finite)
        candidates = candidates[candidates >= since]
        for lo in range(0, candidates.size, 64):
            rows = candidates[lo:lo + 64]
            data, length = _rows(self.known, self.lengths, rows)
            found, ok, m = newton(self.system, self.unknowns, data, length,
                                  np.repeat(start[None], rows.size, axis=0))
            ok &= m >= least
            if ok.any():
                at = int(np.argmax(ok))
                i = int(rows[at])
                self.z[i], self.margin[i] = found[at], m[at]
                return i
        return None

    def _follow_back(self, solved: int, stop: int, resume: bool) -> None:
        """Follow the assembly from sample ``solved`` back to sample ``stop``."""
        back = np.arange(solved, stop - 1, -1)
        data, length = _rows(self.known, self.lengths, back)
        path = _Path(self.system, self.unknowns, data, length, self.between,
                     self.numbered[back],
                     None if self.positions is None else self.positions[back])
        path.z[0], path.margin[0] = self.z[solved], self.margin[solved]
        path._forwards(0, resume)
        self.z[back[1:]], self.margin[back[1:]] = path.z[1:], path.margin[1:]
        self.singular[back[1:]] |= path.singular[1:]

    def _forwards(self, last: int, resume: bool) -> None:
        """Follow the assembly from solved sample ``last`` to the last sample."""
        system, unknowns, scale = self.system, self.unknowns, self.scale
        chunk = 8
        j = last + 1
        while j < self.n:
            rows = np.arange(j, min(j + chunk, self.n))
            data, length = _rows(self.known, self.lengths, rows)
            base = np.repeat(self.z[last][None], rows.size, axis=0)
            found, ok, _, _, jac_found = _run(system, unknowns, data, length, base, scale,
                                              CHUNK_ITERATIONS)
            previous = np.vstack([self.z[last][None], found[:-1]])
            before = _rows(self.known, self.lengths, np.concatenate([[last], rows[:-1]]))
            ok &= _continues(system, unknowns, before, (data, length), previous, found,
                             scale)[0]
            m = margins(jac_found)
            ok &= m >= SINGULAR_MARGIN
            bad = np.flatnonzero(~ok)
            accepted = rows.size if bad.size == 0 else int(bad[0])
            if accepted:
                take = rows[:accepted]
                self.z[take], self.margin[take] = found[:accepted], m[:accepted]
                last = int(take[-1])
                j = last + 1
                chunk = min(2 * chunk, MAX_CHUNK) if bad.size == 0 else max(chunk // 2, 1)
                continue
            chunk = 1
            # the step from the last solution to sample j, cut into pieces, unless it
            # runs through where a step stopped before
            if self._blocked(last, np.array([j]), self.obstacles)[0]:
                crossing = _Crossing(None, 0.0, 0.0, True)
            else:
                crossing = self._step(last, j)
                if crossing.stopped:
                    self.obstacles.append(self._obstacle(last, j, crossing.reached))
            if crossing.solution is not None:
                self._take(j, crossing.solution)
                last = j
                j += 1
                continue
            self.singular[j] = crossing.margin < NEAR_SINGULAR
            if not resume:
                return
            resumed = self._resume(last, j + 1)
            if resumed is None:
                return
            last = resumed
            j = last + 1

    def _along(self, i: int, j: int) -> Callable:
        """Return the known points and lengths at fractions of the step from sample i to j.

        They are ``between``'s (see :func:`continue_along`), or else blended
        straight between the two samples.
        """
        one = np.ones(1)

        def along(fraction: float):
            if self.between is None or fraction in (0.0, 1.0):
                return _blend(self.known, self.lengths, i, j, fraction * one)
            return self.between(int(self.numbered[i]), int(self.numbered[j]), fraction * one)
        return along

    def _along_samples(self, rows: list[int]) -> tuple[Callable, np.ndarray, tuple]:
        """Return the data along the steps through samples ``rows``, taken as one step.

        Each step's share of the fractions is its length in the space of
        the inputs, where they are known, or else an equal share. Also
        returns the fractions at the samples, and the bends at the samples
        between as :func:`_step_over` takes them: each one's fraction and
        how fast the inputs go on in their direction after it, for each unit
        before (negative back; None turned aside, or not known).
        """
        steps = [self._along(a, b) for a, b in zip(rows[:-1], rows[1:], strict=True)]
        shares = np.ones(len(steps))
        if self.positions is not None:
            apart = np.linalg.norm(np.diff(self.positions[rows], axis=0), axis=1)
            if (apart > 0.0).all():
                shares = apart
        cuts = np.concatenate([[0.0], np.cumsum(shares)]) / np.sum(shares)

        def along(fraction: float):
            k = min(int(np.searchsorted(cuts, fraction, side="right")) - 1, len(steps) - 1)
            return steps[k](min(max((fraction - cuts[k]) / (cuts[k + 1] - cuts[k]), 0.0), 1.0))
        bends: list[tuple[float, float | None]] = []
        for k in range(1, len(steps)):
            factor = None
            if self.positions is not None:
                before = (self.positions[rows[k]] - self.positions[rows[k - 1]]) / (
                    cuts[k] - cuts[k - 1])
                after = (self.positions[rows[k + 1]] - self.positions[rows[k]]) / (
                    cuts[k + 1] - cuts[k])
                square = float(before @ before)
                if square > 0.0:
                    factor = float(after @ before) / square
                    if np.linalg.norm(after - factor * before) > 1e-9 * np.linalg.norm(after):
                        factor = None
            bends.append((float(cuts[k]), factor))
        return along, cuts, tuple(bends)

    def _step(self, last: int, j: int) -> _Crossing:
        """Cross the step from solved sample last to sample j in pieces (:func:`_substeps`).

        A sample may lie on a singular position where two assemblies cross
        (a change point): no rate is known there to step over it along, and
        a step from it could land on either. Where its margin is below
        :data:`TANGENT_MARGIN`, or the step from it fails and its margin is
        below :data:`ANCHOR_MARGIN`, the step starts from the regular
        solution before it instead, the nearest with a margin of at least
        :data:`ANCHOR_MARGIN` (at most :data:`MAX_BACK` samples back, or
        else the furthest of those), its pieces coming up to the sample and
        stepping over the crossing as anywhere else. The samples before are
        taken back only while their margins grow, not back over a crossing
        already passed, and only where the margin dips there, :data:`DIP`
        times below theirs (a crossing); where it falls slowly (a fold
        ahead) the step is from the sample itself. The fraction reached is
        of the step from last to j.
        """
        def from_last() -> _Crossing:
            return _substeps(self.system, self.unknowns, self._along(last, j), self.z[last],
                             self.scale)

        direct = None
        if not self.margin[last] < TANGENT_MARGIN:
            direct = from_last()
            if direct.solution is not None or not self.margin[last] < ANCHOR_MARGIN:
                return direct
        rows = [last]
        h = last
        while h > 0 and last - h < MAX_BACK and self.margin[h] < ANCHOR_MARGIN:
            if self._still(h - 1, h):  # the same sample again: nothing moved
                h -= 1
                continue
            if not self.margin[h - 1] > self.margin[h]:
                break
            h -= 1
            rows.insert(0, h)
        # a crossing is a sharp dip of the margin; a slow fall is a fold ahead, or a long
        # nearly singular stretch, where the step from the sample itself is the one
        if len(rows) == 1 or not self.margin[rows[0]] >= DIP * self.margin[last]:
            return direct if direct is not None else from_last()
        along, cuts, bends = self._along_samples([*rows, j])
        crossing = _substeps(self.system, self.unknowns, along, self.z[rows[0]], self.scale,
                             bends)
        if crossing.solution is None and direct is not None:
            return direct
        return crossing._replace(
            reached=max(float(crossing.reached - cuts[-2]), 0.0) / float(1.0 - cuts[-2]))

    def _still(self, a: int, b: int) -> bool:
        """Say whether samples a and b are the same: the inputs did not move between them."""
        if self.positions is not None:
            return bool(np.array_equal(self.positions[a], self.positions[b]))
        first = _rows(self.known, self.lengths, [a])
        data, length = _rows(self.known, self.lengths, [b])
        return bool(_same_data(data, length, first, self.scale)[0])

    def _take(self, j: int, solved: np.ndarray) -> None:
        """Store the solution at sample j with its margin."""
        self.z[j] = solved
        data, length = _rows(self.known, self.lengths, [j])
        _, jac = _residual_jacobian(self.system, self.unknowns, data, length, solved[None])
        self.margin[j] = margins(jac)[0]

    def _obstacle(self, last: int, j: int, reached: float) -> np.ndarray | None:
        """Return where the inputs were when the step from sample last to j stopped."""
        if self.positions is None:
            return None
        a, b = self.positions[last], self.positions[j]
        return a + reached * (b - a)

    def _blocked(self, last: int, rows: np.ndarray, obstacles: list) -> np.ndarray:
        """Say which segments from sample last's inputs to rows' meet an obstacle.

        The segments are straight, in the space of the inputs.
        """
        out = np.zeros(rows.size, dtype=bool)
        if self.positions is None:
            return out
        a = self.positions[last]
        d = self.positions[rows] - a
        length = np.einsum("ni,ni->n", d, d)
        with np.errstate(all="ignore"):
            for point in obstacles:
                if point is None:
                    continue
                t = d @ (point - a) / length
                off = a + t[:, None] * d - point
                out |= ((length > 0) & (t >= 0.0) & (t <= 1.0 + 1e-9)
                        & (np.sqrt(np.einsum("ni,ni->n", off, off))
                           <= 1e-9 * (np.sqrt(length) + np.max(np.abs(point), initial=0.0))))
        return out

    def _resume(self, last: int, j: int) -> int | None:
        """Find the first sample from j on where the assembly is reached again.

        Past a gap the equations may have solutions close to the last one
        that the path cannot reach: another assembly's, as past a fold,
        where the assembly followed ends and others go on. A sample resumes
        the path where the inputs, moved straight from the last solved
        sample's to its own, carry the last solution to it (:func:`_substeps`),
        tried in order at the samples whose segment from the last solved
        sample meets no obstacle (:meth:`_blocked`), at most
        :data:`MAX_ATTEMPTS` of them; or where its inputs are those of the
        path's first solved sample, whose solution it takes. The samples
        from the gap to it are followed back from it (up to the sample after
        the gap's first, which stays unsolved).

        Returns the sample resumed at, or None: the rest stays unsolved.
        """
        system, unknowns, scale = self.system, self.unknowns, self.scale
        home = int(np.argmax(np.isfinite(self.z).all(axis=1)))
        home_data = _rows(self.known, self.lengths, [home])
        stopped = bool(self.singular[last + 1])  # why the path stopped: for those past it
        attempts = 0
        while j < self.n:
            rows = np.arange(j, min(j + MAX_CHUNK, self.n))
            data, length = _rows(self.known, self.lengths, rows)
            self.singular[rows] = stopped
            home_rows = _same_data(data, length, home_data, scale)
            open_ = (~self._blocked(last, rows, self.obstacles) if attempts < MAX_ATTEMPTS
                     else np.zeros(rows.size, dtype=bool))
            for at in np.flatnonzero(open_ | home_rows):
                k = int(rows[at])
                solved = None
                if home_rows[at]:
                    here, here_length = _rows(self.known, self.lengths, [k])
                    found, done, _ = _iterate(system, unknowns, here, here_length,
                                              self.z[home][None], scale, MAX_ITERATIONS)
                    solved = found[0] if done[0] else None
                elif attempts < MAX_ATTEMPTS and not self._blocked(
                        last, rows[at:at + 1], self.obstacles)[0]:
                    attempts += 1
                    crossing = self._step(last, k)
                    solved = crossing.solution
                    if crossing.stopped:
                        self.obstacles.append(self._obstacle(last, k, crossing.reached))
                if solved is None:
                    continue
                self._take(k, solved)
                self.singular[k] = False
                if k > last + 2:
                    self._follow_back(k, last + 2, resume=False)
                return k
            j = int(rows[-1]) + 1
        return None


def _same_data(data, length, reference, scale) -> np.ndarray:
    """Say which samples' known points and lengths are those of ``reference`` (one sample)."""
    tolerance = 1e-9 * scale
    same = np.all(np.abs(length - reference[1]) <= tolerance, axis=1)
    for name, (x, y) in data.items():
        rx, ry = reference[0][name]
        if np.ndim(x) or np.ndim(rx):
            same &= (np.abs(np.asarray(x) - np.asarray(rx)) <= tolerance) & (
                np.abs(np.asarray(y) - np.asarray(ry)) <= tolerance)
    return same


def _inverse(jac: np.ndarray) -> np.ndarray:
    """Return the Jacobians' inverses, NaN where one is singular or not finite."""
    out = np.full(jac.shape, np.nan)
    finite = np.isfinite(jac).all(axis=(1, 2))
    if not finite.any():
        return out
    j = jac[finite]
    try:
        out[finite] = np.linalg.inv(j)
    except np.linalg.LinAlgError:  # one singular matrix: invert each alone
        each = np.full(j.shape, np.nan)
        for a in range(j.shape[0]):
            try:
                each[a] = np.linalg.inv(j[a])
            except np.linalg.LinAlgError:
                pass
        out[finite] = each
    return out


def _separation(inverse: np.ndarray, lengths: np.ndarray, system: System,
                unknowns: Sequence[str]) -> np.ndarray:
    """Return how far a solution lies from the group's others, at the least.

    The distance equations ``(|P - Q|**2 - d**2) / (2 d)`` are quadratic:
    along a step D of the unknowns each changes by its first-order term plus
    ``|D_P - D_Q|**2 / (2 d)``, at most ``c |D|**2 / (2 d)`` (c = 2 where both
    points are unknown, else 1). Two solutions z and z + D therefore satisfy
    ``|J D| <= |D|**2 sqrt(sum (c / d)**2) / 2``, and ``|D|`` is at least
    ``2 sigma_min(J) / sqrt(sum (c / d)**2)`` (for many rows, with the
    Frobenius norm of ``J^-1`` for ``1 / sigma_min``, cheaper and as large).

    For few rows (the pieces of a step, near singular positions, where the
    bound is what limits them) the distance is estimated sharper, the
    larger of two estimates. Write the equations at a step D as
    ``J D + Q(D) = 0``, Q their quadratic part, ``|Q(D)| <= C |D|**2 / 2``
    (C the curvature above). A solution nearby lies along v, J's right
    singular vector of its smallest singular value: first, as far along v
    as Q(v) puts it, ``sigma_min / |Q(v)|``. Second, at ``D = s v + w``:
    along u, the matching left singular vector,
    ``sigma_min s = -u . Q(D)``, while ``|w|`` is at most about
    ``C s**2 / (2 sigma_2)``; so no solution is nearer than the least s
    with ``sigma_min = p s + q s**2``, ``p = |u . Q(v)|`` and
    ``q = C**2 / (2 sigma_2)``. Two circles crossing at a shallow angle,
    whose curvatures nearly match, so cross again far away. Neither is
    taken nearer than the bound; a solution off the direction v is at least
    ``2 sigma_2 / C`` away. A point on a line adds no curvature where only
    the point is unknown.
    """
    with np.errstate(all="ignore"):
        if system.distances:
            layout = _layout(system, tuple(unknowns))
            d = lengths[:, :len(layout.bend)]
            curvature = np.sqrt(np.sum((layout.bend / d) ** 2, axis=1))
        else:
            curvature = np.ones(inverse.shape[0])
        if inverse.shape[0] > 8:  # many rows: the Frobenius norm, cheaper and as large
            return 2.0 / (np.sqrt(np.einsum("nij,nij->n", inverse, inverse)) * curvature)
        out = np.full(inverse.shape[0], np.nan)
        finite = np.isfinite(inverse).all(axis=(1, 2))
        if not finite.any():
            return out
        # J's inverse's singular vectors: its left ones are J's right ones (v), its
        # right ones J's left ones (u), J's smallest singular value's first
        vectors, inverse_values, lefts = np.linalg.svd(inverse[finite])
        smallest, second = 1.0 / inverse_values[:, 0], 1.0 / inverse_values[:, 1]
        c = curvature[finite]
        apart = 2.0 * second / c
        if system.distances:
            v, u = vectors[:, :, 0], lefts[:, 0, :]
            half = 0.5 * _along_distances(layout, system.k, v, v) / d[finite]  # Q(v)
            p = np.abs(np.sum(u[:, :half.shape[1]] * half, axis=1))
            q = c ** 2 / (2.0 * second)
            along = np.fmax(smallest / np.sqrt(np.sum(half ** 2, axis=1)),
                            2.0 * smallest / (p + np.sqrt(p * p + 4.0 * q * smallest)))
        else:
            along = 2.0 * smallest
        out[finite] = np.minimum(np.fmax(along, 2.0 * smallest / c), apart)
        return out


def _along_distances(layout: _Layout, k: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Return ``(a_P - a_Q) . (b_P - b_Q)`` for each distance equation, for steps a, b (N, 2k)."""
    known = np.zeros((a.shape[0], len(layout.names) - k))
    ax, ay = np.concatenate([a[:, 0::2], known], 1), np.concatenate([a[:, 1::2], known], 1)
    bx, by = np.concatenate([b[:, 0::2], known], 1), np.concatenate([b[:, 1::2], known], 1)
    return ((ax[:, layout.p] - ax[:, layout.q]) * (bx[:, layout.p] - bx[:, layout.q])
            + (ay[:, layout.p] - ay[:, layout.q]) * (by[:, layout.p] - by[:, layout.q]))


def _continues(system, unknowns, before, after, previous, found, scale, jac=None,
               f_next=None):
    """Say which solutions ``found`` (at data ``after``) continue ``previous`` (at ``before``).

    The step must stay within :data:`TRUST` of the distance from the
    previous solution to its nearest other (:func:`_separation`), and lie
    where the linearised step predicts (within :data:`JUMP_RATIO` of it).
    Returns that, and the linearised step's length over the step allowed
    (what a step cut to fit should be shortened by). ``jac``, the Jacobians
    at the previous solutions, and ``f_next``, the residuals of the previous
    solutions with the data after, may be given where known.
    """
    if jac is None:
        _, jac = _residual_jacobian(system, unknowns, before[0], before[1], previous)
    if f_next is None:
        f_next, _ = _residual_jacobian(system, unknowns, after[0], after[1], previous)
    inverse = _inverse(jac)
    predicted = -np.einsum("nij,nj->ni", inverse, f_next)
    step = found - previous
    slack = 1e-9 * scale
    with np.errstate(all="ignore"):
        reach = TRUST * _separation(inverse, before[1], system, unknowns)
        ok = np.isfinite(found).all(axis=1)
        ok &= (np.max(np.abs(step - predicted), axis=1)
               <= JUMP_RATIO * np.max(np.abs(predicted), axis=1) + slack)
        ok &= np.sqrt(np.einsum("ni,ni->n", step, step)) <= reach + slack
        ratio = np.sqrt(np.einsum("ni,ni->n", predicted, predicted)) / reach
    return ok, ratio


def stalls_singular(system: System, unknowns: Sequence[str], known: Mapping,
                    lengths: np.ndarray, guess: np.ndarray) -> np.ndarray:
    """Say which samples, unsolved from their guesses, lie at or beyond a singular position.

    A guess there is a solution of a nearby sample (a bisection's inside
    end, a finite difference's centre): where the group folds back between
    the two, the Jacobian is nearly singular at the guess already (its
    margin falls to zero linearly as the input nears the fold), or where
    Newton from it ends (the equations have no real solution nearby, as two
    circles past tangency).

    Parameters
    ----------
    system, unknowns, known, lengths
        As for :func:`newton`.
    guess : ndarray, shape (N, 2k)

    Returns
    -------
    ndarray of bool, shape (N,)

    Examples
    --------
    Two circles of radius 5 about (0, 0) and (10 + 1e-9, 0), from their
    tangent point: no solution, at a fold.

    >>> system = System(1, (("B", "A"), ("B", "C")), ())
    >>> known = {"A": (np.zeros(1), np.zeros(1)), "C": (np.full(1, 10 + 1e-9), np.zeros(1))}
    >>> stalls_singular(system, ["B"], known, np.array([[5.0, 5.0]]),
    ...                 np.array([[5.0, 0.0]])).tolist()
    [True]
    """
    guess = np.asarray(guess, dtype=float)
    with np.errstate(all="ignore"):
        _, jac = _residual_jacobian(system, unknowns, known, lengths, guess)
        at_guess = margins(jac)
        z, _, _ = _iterate(system, unknowns, known, lengths, guess, _scale(lengths, known),
                           MAX_ITERATIONS)
        _, jac = _residual_jacobian(system, unknowns, known, lengths, z)
        at_end = margins(jac)
    return (at_guess < NEAR_SINGULAR) | (at_end < NEAR_SINGULAR)


class _Crossing(NamedTuple):
    """How far the pieces of a step got (see :func:`_substeps`)."""

    solution: np.ndarray | None  # at the step's end, None where not reached
    margin: float  # the smallest met on the way, or where the pieces stopped
    reached: float  # the fraction of the step reached
    stopped: bool  # stopped at a singular position, not merely out of pieces


def _substeps(system, unknowns, along, z_i, scale, kinks=()):
    """Cross a step from its start (solved: z_i) to its end in pieces.

    ``along(t)`` gives the known points and lengths at fraction t of the
    step (:meth:`_Path._along`); ``kinks`` are where it bends (at the
    samples of steps taken as one, :meth:`_Path._along_samples`).
    A piece is taken
    where its solution continues the one before (:func:`_continues`); the
    next is as long as the step allowed there (within halving and doubling
    the last). Where the pieces shrink below
    :data:`CROSSING_PIECE` the solution is at a singular position: where two
    assemblies cross there, a piece moving the solution
    :data:`CROSSING_MOVE` along its last rate, and Newton from there,
    passes it on the assembly's own side; at a fold Newton finds nothing
    there, and the step cannot be crossed.

    Returns a :class:`_Crossing`: the solution at the end (or None), the smallest
    margin met on the way (or the margin where the pieces ran out), the
    fraction of the step reached, and whether the step stopped at a singular
    position it could not step over.
    """
    t, z, piece = 0.0, z_i.copy(), 0.5
    # the last solution taken away from singular positions, where Newton converges to
    # the rounding (near one it leaves an error of the square root of the residual)
    anchor = (0.0, z)
    lowest = np.inf
    before = along(0.0)
    _, jac_here = _residual_jacobian(system, unknowns, *before, z[None])
    here: tuple[float, float] | None = None  # the margin and the step allowed at z
    for _ in range(MAX_SUBSTEPS):
        target = min(t + piece, 1.0)
        after = along(target)
        found, ok, _, f_next, jac_found = _run(system, unknowns, *after, z[None], scale,
                                               CHUNK_ITERATIONS)
        continues, ratio = _continues(system, unknowns, before, after, z[None], found, scale,
                                      jac_here, f_next)
        ok &= continues
        # the next piece as long as the step allowed takes, within halving and doubling
        fit = 0.9 / ratio[0] if ratio[0] > 0 else 2.0
        m = float(margins(jac_found)[0])
        if ok[0] and m >= SINGULAR_MARGIN:
            if m >= ANCHOR_MARGIN:
                anchor = (target, found[0])
            lowest = min(lowest, m)
            t, z, before, here, jac_here = target, found[0], after, None, jac_found
            if t >= 1.0:
                return _Crossing(z, lowest, t, False)
            piece = min(piece * min(max(fit, 1.0), 2.0), 1.0 - t)
            continue
        if here is None:
            reach = TRUST * _separation(_inverse(jac_here), before[1], system, unknowns)[0]
            here = float(margins(jac_here)[0]), float(reach)
        lowest = min(lowest, here[0])
        piece *= min(max(fit, 0.05), 0.5) if np.isfinite(fit) else 0.5
        # on, while neither the pieces nor the steps they may take are too short to tell
        # a singular position from a fold
        if piece >= CROSSING_PIECE and not here[1] < 0.1 * CROSSING_MOVE * scale:
            continue
        crossed = _step_over(system, unknowns, along, t, anchor, scale, kinks)
        if crossed is None:
            return _Crossing(None, here[0], t, True)
        t, z = crossed
        before, here = along(t), None
        _, jac_here = _residual_jacobian(system, unknowns, *before, z[None])
        if t >= 1.0:
            return _Crossing(z, lowest, t, False)
        piece = min(1e3 * CROSSING_PIECE, 1.0 - t)
    return _Crossing(None, float(margins(jac_here)[0]), t, False)  # out of pieces


def _step_over(system, unknowns, along, t, anchor, scale, kinks=()):
    """Step over a singular position at fraction t of a step, or return None.

    The step is predicted linearly from ``anchor`` (fraction, solution),
    the last solution taken away from singular positions, along the
    solution's rate there, to where the solution has moved
    :data:`CROSSING_MOVE` times the group's size past t (or to the step's
    end, where the solution stands still); past a bend of the step (one of
    ``kinks``: its fraction, and how fast the inputs go on in their
    direction after it for each unit before, negative where they turn
    back; None where they turn aside) along the rate for the inputs' new
    motion. Newton from there must converge within a tenth
    of the predicted travel, on a regular position unless the step ends
    there (a sample on the crossing itself). Where two assemblies cross,
    it lands on the one continuing the motion; past a fold there is
    nothing to land on.
    """
    t_a, z_a = anchor
    # the tangent at the anchor: the data's rate by a short difference (a long one
    # would carry its curvature, magnified near the singular position)
    h = min(1e-6, 1.0 - t_a)
    f_a, jac = _residual_jacobian(system, unknowns, *along(t_a), z_a[None])
    f_h, _ = _residual_jacobian(system, unknowns, *along(t_a + h), z_a[None])
    rates = [-np.einsum("nij,nj->ni", _inverse(jac), (f_h - f_a) / h)[0]]
    # past a bend the inputs move on in their old direction (or back), faster or
    # slower: the rate scales with them. Turned aside, it is not known.
    starts = [t_a]
    for k, factor in kinks:
        if t_a < k < 1.0:
            if factor is None:
                rates.append(np.full_like(z_a, np.nan))
            else:
                rates.append(factor * rates[-1])
            starts.append(k)
    bends = starts[1:]
    here = max(i for i, u in enumerate(starts) if u <= t) if t >= t_a else 0
    speed = float(np.sqrt(rates[here] @ rates[here]))
    if t <= t_a or not np.isfinite(speed):
        return None
    if speed * (1.0 - t) <= 0.1 * CROSSING_MOVE * scale:
        target = 1.0  # the solution all but stands still: on to the step's end
    else:
        target = min(t + CROSSING_MOVE * scale / speed, 1.0)
    guess, travel = z_a.copy(), 0.0
    for u, r, end in zip(starts, rates, [*bends, 1.0], strict=True):
        if u >= target:
            break
        move = r * (min(end, target) - u)
        guess += move
        travel += float(np.sqrt(move @ move))
    if not np.isfinite(guess).all():
        return None
    # next to a crossing, and on it, Newton converges only linearly
    found, ok, _, _, jac_found = _run(system, unknowns, *along(target), guess[None], scale,
                                      MAX_ITERATIONS)
    miss = float(np.sqrt(np.sum((found[0] - guess) ** 2)))
    landed = margins(jac_found)[0]
    slack = 1e-9 * scale
    if target == 1.0 and landed < TANGENT_MARGIN:
        # on the crossing itself, where the two solutions meet: Newton ends within
        # about the square root of the residual's tolerance of it
        slack = np.sqrt(RESIDUAL_RTOL) * scale
    if not (ok[0] and (target == 1.0 or landed >= SINGULAR_MARGIN)
            and miss <= 0.1 * travel + slack):
        return None
    return target, found[0]
