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

import numpy as np

__all__ = ["MAX_ITERATIONS", "MAX_SUBSTEPS", "SINGULAR_MARGIN", "System", "continue_along",
           "margins", "newton", "stalls_singular"]

MAX_ITERATIONS = 30
"""The most Newton iterations for one solve from a guess."""

CHUNK_ITERATIONS = 8
"""The most Newton iterations for the samples of a chunk of the continuation."""

MAX_SUBSTEPS = 4096
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


def _point(z, unknowns, known, name, sl):
    """Return a point's x, y over the samples of ``sl``, and its unknown index or -1."""
    if name in unknowns:
        i = unknowns.index(name)
        return z[:, 2 * i], z[:, 2 * i + 1], i
    x, y = known[name]
    n = z.shape[0]
    return (np.broadcast_to(x, sl)[:n] if np.ndim(x) else np.full(n, float(x)),
            np.broadcast_to(y, sl)[:n] if np.ndim(y) else np.full(n, float(y)), -1)


def _residual_jacobian(system: System, unknowns, known, lengths, z):
    """Return the residuals (M, E) and Jacobians (M, E, 2k) at unknowns z (M, 2k).

    ``known`` holds each known point's (x, y) as arrays of M samples (or
    numbers), ``lengths`` the distances as an (M, D) array.
    """
    m = z.shape[0]
    f = np.empty((m, system.equations))
    jac = np.zeros((m, system.equations, 2 * system.k))
    shape = (m,)
    for e, (p, q) in enumerate(system.distances):
        px, py, i = _point(z, unknowns, known, p, shape)
        qx, qy, j = _point(z, unknowns, known, q, shape)
        d = lengths[:, e]
        dx, dy = px - qx, py - qy
        f[:, e] = (dx * dx + dy * dy - d * d) / (2 * d)
        gx, gy = dx / d, dy / d
        if i >= 0:
            jac[:, e, 2 * i] += gx
            jac[:, e, 2 * i + 1] += gy
        if j >= 0:
            jac[:, e, 2 * j] -= gx
            jac[:, e, 2 * j + 1] -= gy
    offset = len(system.distances)
    for e, (p, q, r) in enumerate(system.lines, start=offset):
        px, py, i = _point(z, unknowns, known, p, shape)
        qx, qy, j = _point(z, unknowns, known, q, shape)
        rx, ry, l_ = _point(z, unknowns, known, r, shape)
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
    z = z.copy()
    done = np.zeros(z.shape[0], dtype=bool)
    first = None
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
            f_now, _ = _residual_jacobian(system, unknowns, known, lengths, z)
            f_new, _ = _residual_jacobian(system, unknowns, known, lengths, z + step)
            polish &= (np.max(np.abs(f_new), axis=1)
                       <= np.maximum(np.max(np.abs(f_now), axis=1), tolerance))
            z = np.where(polish[:, None], z + step, z)
    assert first is not None
    return z, done, first


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
                   between: Callable | None = None, samples: np.ndarray | None = None):
    """Follow one assembly along the samples, from a sketch where it first fits.

    The first sample where Newton from ``start`` converges begins the path,
    followed from there to the last sample and back to the first.
    Each later sample starts from the last solution found: samples are
    solved a chunk at a time (up to :data:`MAX_CHUNK`, growing while all
    succeed), all from the chunk's starting solution, with at most
    :data:`CHUNK_ITERATIONS` iterations each, vectorised over the chunk.
    A sample is accepted while every sample before it in the chunk is, its
    Newton converged, and its solution lies where the previous one predicts
    (the linearised step from the previous sample, within
    :data:`JUMP_RATIO` of it): a solution of another assembly is a jump the
    step does not explain. Where the first sample of a chunk fails, the step
    to it is cut into pieces (the known points and distances as ``between``
    gives them along the step), halving each piece that fails, at
    most :data:`MAX_SUBSTEPS` pieces. A step that cannot be crossed leaves
    its sample unsolved; later samples resume where Newton from the last
    solution converges, past a sample where it does not (up to there the
    equations have solutions the path could not reach: another assembly's,
    as past a fold, where the assembly followed ends and others go on), and
    an assembly that, followed back, was there all along is another one,
    whose samples stay unsolved. ``path_starts`` are the samples where a
    new path begins (design variants, one after the other): the first
    sample of each resumes at once. ``between(a, b, t)`` gives the known
    points and lengths at fractions ``t`` of the way from sample a to b, as
    the inputs move along the straight segment (the points on arcs, as a
    crank's pin); without it they move straight between their samples.
    ``samples`` are the samples' indices as ``between`` takes them.

    Returns
    -------
    z : ndarray, shape (N, 2k)
        NaN where unsolved.
    margin : ndarray, shape (N,)
    singular : ndarray of bool, shape (N,)
        Unsolved samples where the path stopped at a singular position.
    """
    n = lengths.shape[0]
    width = 2 * system.k
    z = np.full((n, width), np.nan)
    singular = np.zeros(n, dtype=bool)
    margin = np.full(n, np.nan)
    scale = _scale(lengths, known)
    start = np.asarray(start, dtype=float).reshape(1, width)
    # the first sample that Newton from the sketch solves: those before are followed
    # back from it
    i = 0
    first_rows = np.arange(n)
    finite = np.isfinite(lengths).all(axis=1)
    for x, y in known.values():
        if np.ndim(x):
            finite &= np.isfinite(x) & np.isfinite(y)
    candidates = first_rows[finite]
    begun = False
    for lo in range(0, candidates.size, 64):
        rows = candidates[lo:lo + 64]
        data, length = _rows(known, lengths, rows)
        guess = np.repeat(start, rows.size, axis=0)
        found, ok, m = newton(system, unknowns, data, length, guess)
        ok &= m >= SINGULAR_MARGIN
        if ok.any():
            first = int(np.argmax(ok))
            i = int(rows[first])
            z[i], margin[i] = found[first], m[first]
            begun = True
            break
    if not begun:
        return z, margin, singular

    numbered = np.arange(n) if samples is None else samples

    def follow_back(solved: int, stop: int) -> None:
        """Follow the assembly from sample ``solved`` back to sample ``stop``."""
        back = np.arange(solved, stop - 1, -1)
        known_back, lengths_back = _rows(known, lengths, back)
        found, found_margin, found_singular = continue_along(
            system, unknowns, known_back, lengths_back, z[solved], between=between,
            samples=numbered[back])
        z[back[1:]], margin[back[1:]] = found[1:], found_margin[1:]
        singular[back[1:]] = found_singular[1:]

    if i > 0:  # the samples before it, on the assembly the sketch picked
        follow_back(i, 0)
    last = i
    chunk = 8
    j = i + 1
    while j < n:
        rows = np.arange(j, min(j + chunk, n))
        data, length = _rows(known, lengths, rows)
        base = np.repeat(z[last][None], rows.size, axis=0)
        found, ok, _ = _iterate(system, unknowns, data, length, base, scale, CHUNK_ITERATIONS)
        ok &= np.isfinite(found).all(axis=1)
        # each solution against the linear prediction from the previous sample
        previous = np.vstack([z[last][None], found[:-1]])
        prev_data = _rows(known, lengths, np.concatenate([[last], rows[:-1]]))
        _, jac = _residual_jacobian(system, unknowns, prev_data[0], prev_data[1], previous)
        f_next, _ = _residual_jacobian(system, unknowns, data, length, previous)
        predicted = _solve(jac, f_next)
        miss = np.max(np.abs(found - previous - predicted), axis=1)
        ok &= miss <= JUMP_RATIO * np.max(np.abs(predicted), axis=1) + 1e-9 * scale
        ok &= _comes_back(system, unknowns, prev_data, found, previous, scale)
        _, jac_found = _residual_jacobian(system, unknowns, data, length, found)
        m = margins(jac_found)
        ok &= m >= SINGULAR_MARGIN
        bad = np.flatnonzero(~ok)
        accepted = rows.size if bad.size == 0 else int(bad[0])
        if accepted:
            take = rows[:accepted]
            z[take] = found[:accepted]
            margin[take] = m[:accepted]
            last = int(take[-1])
            j = last + 1
            chunk = min(2 * chunk, MAX_CHUNK) if bad.size == 0 else max(chunk // 2, 1)
            continue
        chunk = 1
        if j == last + 1:
            # the step from the last solution to sample j, cut into pieces
            solved, stop_margin = _substeps(system, unknowns, known, lengths, last, j, z[last],
                                            scale, between, numbered)
            if solved is not None:
                z[j] = solved
                data_j, length_j = _rows(known, lengths, [j])
                _, jac_j = _residual_jacobian(system, unknowns, data_j, length_j, solved[None])
                margin[j] = margins(jac_j)[0]
                last = j
                j += 1
                continue
            singular[j] = stop_margin < NEAR_SINGULAR
            j += 1
        # a gap: the samples after it resume the assembly where Newton from the last
        # solution converges, as a two-root node resumes its branch, tried a block at a
        # time; on the same path only past a sample where it does not
        resumed = False
        apart = False
        while j < n and not resumed:
            rows = np.arange(j, min(j + MAX_CHUNK, n))
            data, length = _rows(known, lengths, rows)
            again, ok, m = newton(system, unknowns, data, length,
                                  np.repeat(z[last][None], rows.size, axis=0))
            ok &= m >= SINGULAR_MARGIN
            path = _path_start(path_starts, rows)
            same = path <= last
            if not apart:
                unsolved = np.flatnonzero(~ok & same)
                apart = unsolved.size > 0
                ok[:unsolved[0] if apart else int(same.sum())] = False
            if ok.any():
                at = int(np.argmax(ok))
                singular[rows[:at]] = singular_rows(system, unknowns, data, length, z[last],
                                                    at)
                z[rows[at]], margin[rows[at]] = again[at], m[at]
                begin = max(last + 1, int(path[at]))
                gap = np.flatnonzero(~np.isfinite(z[begin:rows[at]]).all(axis=1))
                if gap.size:  # the gap's far side, from where the assembly resumes
                    follow_back(int(rows[at]), begin + int(gap[0]))
                if same[at] and np.isfinite(z[last + 1]).all():
                    # followed back, it reaches the sample after the last solution: it
                    # was there all along, another assembly; the samples stay unsolved
                    # until a gap of its own
                    stretch = slice(last + 1, int(rows[at]) + 1)
                    z[stretch], margin[stretch], singular[stretch] = np.nan, np.nan, True
                    j, apart = int(rows[at]) + 1, False
                    continue
                last = int(rows[at])
                j = last + 1
                resumed = True
            else:
                singular[rows] = singular_rows(system, unknowns, data, length, z[last],
                                               rows.size)
                j = int(rows[-1]) + 1
    return z, margin, singular


def _path_start(path_starts: np.ndarray | None, rows: np.ndarray) -> np.ndarray:
    """Return the sample where the path of each of ``rows`` begins."""
    if path_starts is None:
        return np.zeros(rows.size, dtype=int)
    return path_starts[np.searchsorted(path_starts, rows, side="right") - 1]


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


def singular_rows(system, unknowns, known, lengths, z_last, count):
    """Say which of the first ``count`` unsolved samples lie beyond a singular position.

    Newton from the last solution there ends where the Jacobian is nearly
    singular: the equations have no real solution nearby (as two circles
    past tangency).
    """
    if count == 0:
        return np.zeros(0, dtype=bool)
    data, length = _rows(known, lengths, np.arange(count))
    z, _, _ = _iterate(system, unknowns, data, length,
                       np.repeat(np.asarray(z_last)[None], count, axis=0),
                       _scale(length, data), MAX_ITERATIONS)
    _, jac = _residual_jacobian(system, unknowns, data, length, z)
    return ~(margins(jac) >= NEAR_SINGULAR)


COME_BACK_RTOL = 1e-6
"""How close (times the group's size) Newton from a solution, at the sample before,
must come back to the solution there for the two to be one assembly."""


def _comes_back(system, unknowns, before, found, previous, scale) -> np.ndarray:
    """Say which solutions continue the solutions before them: Newton comes back.

    Newton at the sample before (``before``: its known points and lengths),
    from each solution ``found``, must converge to the solution there,
    ``previous``. Near a fold the linear prediction of a step is too long
    to tell a jump to another assembly; this tells it: from a solution of
    another assembly Newton converges to that assembly's solution at the
    sample before, not to the one followed.
    """
    back, ok, _ = _iterate(system, unknowns, before[0], before[1], found, scale,
                           CHUNK_ITERATIONS)
    return ok & (np.max(np.abs(back - previous), axis=1) <= COME_BACK_RTOL * scale)


def _substeps(system, unknowns, known, lengths, i, j, z_i, scale, between=None,
              samples=None):
    """Cross the step from sample i (solved: z_i) to sample j in pieces.

    The known points and lengths along the step are ``between``'s, at
    samples ``samples[i]`` and ``samples[j]`` (see :func:`continue_along`),
    or else blended straight between the two samples. Returns the solution
    at j (or None) and the smallest margin met on the way.
    """
    def along(fraction):
        if between is None or fraction in (0.0, 1.0):
            return _blend(known, lengths, i, j, fraction * one)
        return between(int(samples[i]), int(samples[j]), fraction * one)

    t, z, piece, pieces = 0.0, z_i.copy(), 0.5, 0
    lowest = np.inf
    one = np.ones(1)
    while pieces < MAX_SUBSTEPS:
        pieces += 1
        target = min(t + piece, 1.0)
        data, length = along(target)
        previous, prev_length = along(t)
        found, ok, _ = _iterate(system, unknowns, data, length, z[None], scale, CHUNK_ITERATIONS)
        _, jac = _residual_jacobian(system, unknowns, previous, prev_length, z[None])
        f_next, _ = _residual_jacobian(system, unknowns, data, length, z[None])
        predicted = _solve(jac, f_next)
        ok &= np.isfinite(found).all(axis=1)
        ok &= (np.max(np.abs(found - z[None] - predicted), axis=1)
               <= JUMP_RATIO * np.max(np.abs(predicted), axis=1) + 1e-9 * scale)
        ok &= _comes_back(system, unknowns, (previous, prev_length), found, z[None], scale)
        _, jac_found = _residual_jacobian(system, unknowns, data, length, found)
        m = float(margins(jac_found)[0]) if ok[0] else np.nan
        if ok[0] and m >= SINGULAR_MARGIN:
            lowest = min(lowest, m)
            t, z = target, found[0]
            if t >= 1.0:
                return z, lowest
            piece = min(2 * piece, 1.0 - t)
        else:
            m_here = float(margins(jac)[0])
            lowest = min(lowest, m_here)
            piece *= 0.5
            if piece < 1e-12:
                return None, m_here
    return None, lowest
