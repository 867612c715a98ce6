"""Engineering measures of a linkage and of its motion.

Four-bar classification (:func:`grashof`, :func:`fourth_link_range`), the
transmission angle (:func:`transmission_angles`,
:func:`fourbar_transmission_extremes`), mobility by the Gruebler-Kutzbach
count (:func:`degrees_of_freedom`), the stroke and time ratio of an output
(:func:`stroke`, :func:`time_ratio`), link angles (:func:`link_angles`) and
coupler-curve measures (:func:`curve_measures`).

Angles are radians throughout.

Four-bar names
--------------
A four-bar has a ground link (fixed pivots ``O2`` and ``O4``), an input
link ``O2-A``, a coupler ``A-B`` and an output link ``B-O4``. With ``s``
and ``l`` the shortest and longest lengths and ``p``, ``q`` the other two,
the linkage is *Grashof* when ``s + l < p + q``: the shortest link then
turns fully relative to every other link. The Grashof class follows from
which link is shortest, the non-Grashof (triple-rocker) class from which
link is longest:

=========================  ======  =========================================
kind                       code    when
=========================  ======  =========================================
``double-crank``           GCCC    Grashof, ground shortest
``crank-rocker``           GCRR    Grashof, input shortest
``double-rocker``          GRCR    Grashof, coupler shortest
``rocker-crank``           GRRC    Grashof, output shortest
``change-point``           CP      ``s + l == p + q``
``triple-rocker RRR1``     RRR1    non-Grashof, ground longest
``triple-rocker RRR2``     RRR2    non-Grashof, input longest
``triple-rocker RRR3``     RRR3    non-Grashof, coupler longest
``triple-rocker RRR4``     RRR4    non-Grashof, output longest
``immobile``               --      ``l == s + p + q``: assembles only flat
``unassemblable``          --      ``l > s + p + q``
=========================  ======  =========================================
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import shapely
from numpy.typing import ArrayLike

from .construction import CircleCircle, Compiled, Construction, Fixed
from .errors import AnalysisError, did_you_mean
from .sweep import Sweep

__all__ = [
    "Curve",
    "Grashof",
    "KINDS",
    "Mobility",
    "Stroke",
    "TransmissionAngle",
    "curve_measures",
    "degrees_of_freedom",
    "fourbar_transmission_extremes",
    "fourth_link_range",
    "grashof",
    "link_angles",
    "stroke",
    "time_ratio",
    "transmission_angles",
    "unwrap_valid",
]

ROLES = ("ground", "input", "coupler", "output")

KINDS = {
    "double-crank": "GCCC",
    "crank-rocker": "GCRR",
    "double-rocker": "GRCR",
    "rocker-crank": "GRRC",
    "change-point": "CP",
    "triple-rocker RRR1": "RRR1",
    "triple-rocker RRR2": "RRR2",
    "triple-rocker RRR3": "RRR3",
    "triple-rocker RRR4": "RRR4",
    "immobile": "",
    "unassemblable": "",
}
"""Every four-bar kind :func:`grashof` returns, with its code."""

_GRASHOF_BY_SHORTEST = dict(zip(ROLES, ("double-crank", "crank-rocker", "double-rocker",
                                        "rocker-crank"), strict=True))
_GROUPS = {
    "grashof": tuple(_GRASHOF_BY_SHORTEST.values()),
    "non-grashof": tuple(f"triple-rocker RRR{i}" for i in range(1, 5)),
}
_GROUPS["triple-rocker"] = _GROUPS["non-grashof"]


# -- Grashof -------------------------------------------------------------------


@dataclass(frozen=True)
class Grashof:
    """The Grashof classification of a four-bar (see the module's table).

    Attributes
    ----------
    kind : str
        One of :data:`KINDS`.
    code : str
        The short code (``"GCRR"``, ``"RRR1"``, ...), ``""`` for the
        immobile and unassemblable kinds.
    grashof : bool
        Whether ``s + l <= p + q`` (the change point included): the shortest
        link turns fully relative to the others.
    s_plus_l, p_plus_q : float
        The two sides of Grashof's inequality.
    shortest, longest : tuple of str
        The roles (``"ground"``, ``"input"``, ``"coupler"``, ``"output"``)
        of the shortest and longest links (more than one on a tie).
    input_turns, output_turns : bool
        Whether the input (output) link can turn fully relative to the ground.
    input_turns_on_coupler, output_turns_on_coupler : bool
        Whether the input (output) link can turn fully relative to the coupler.
    coupler_turns : bool
        Whether the coupler can turn fully relative to the ground.
    """

    kind: str
    code: str
    grashof: bool
    s_plus_l: float
    p_plus_q: float
    shortest: tuple[str, ...]
    longest: tuple[str, ...]
    input_turns: bool
    output_turns: bool
    input_turns_on_coupler: bool
    output_turns_on_coupler: bool
    coupler_turns: bool

    @property
    def turning(self) -> tuple[str, ...]:
        """Return the links that turn fully relative to the ground."""
        turns = (self.input_turns, self.coupler_turns, self.output_turns)
        return tuple(r for r, t in zip(("input", "coupler", "output"), turns, strict=True) if t)


def _lengths(values) -> dict[str, float]:
    lengths = {}
    for role, value in zip(ROLES, values, strict=True):
        value = float(value)
        if not (np.isfinite(value) and value > 0):
            raise AnalysisError(f"the {role} length must be a positive number, got {value!r}")
        lengths[role] = value
    return lengths


def _joint_turns(x, y, u, v, tol) -> bool:
    """Whether links x and y, adjacent at a joint, turn fully relative to each other.

    The diagonal opposite the joint spans ``[|x - y|, x + y]`` over a turn; the
    other two links u, v must reach all of it.
    """
    return x + y <= u + v + tol and abs(x - y) + tol >= abs(u - v)


def grashof(ground: float, input: float, coupler: float, output: float, *,
            rtol: float = 1e-9) -> Grashof:
    """Classify a four-bar by Grashof's criterion.

    Parameters
    ----------
    ground, input, coupler, output : float
        The link lengths: the distance between the fixed pivots, the input
        link, the coupler, the output link. Positive.
    rtol : float
        Relative tolerance (of the longest length) for the equalities of a
        change point and of an immobile chain.

    Returns
    -------
    Grashof

    Examples
    --------
    Seed 000's triple rocker, and the four-bar of seed 004:

    >>> g = grashof(ground=7, input=5, coupler=6, output=5)
    >>> g.kind, g.grashof, g.s_plus_l, g.p_plus_q
    ('triple-rocker RRR1', False, 12.0, 11.0)
    >>> g = grashof(ground=24, input=10.55, coupler=25, output=14)
    >>> g.kind, g.code, g.input_turns, g.output_turns
    ('crank-rocker', 'GCRR', True, False)
    >>> grashof(2, 1, 2, 1).kind
    'change-point'
    """
    lengths = _lengths((ground, input, coupler, output))
    values = sorted(lengths.values())
    s, p, q, l_ = values
    tol = rtol * l_
    shortest = tuple(r for r in ROLES if lengths[r] <= s + tol)
    longest = tuple(r for r in ROLES if lengths[r] >= l_ - tol)
    s_plus_l, p_plus_q = s + l_, p + q
    g, i, c, o = (lengths[r] for r in ROLES)
    is_grashof = s_plus_l <= p_plus_q + tol
    if l_ > s + p + q + tol:
        kind = "unassemblable"
    elif l_ >= s + p + q - tol:
        kind = "immobile"
    elif abs(s_plus_l - p_plus_q) <= tol:
        kind = "change-point"
    elif is_grashof:
        kind = _GRASHOF_BY_SHORTEST[shortest[0]]
    else:
        kind = f"triple-rocker RRR{ROLES.index(longest[0]) + 1}"
    moving = kind not in ("unassemblable", "immobile")
    return Grashof(
        kind=kind, code=KINDS[kind], grashof=is_grashof and moving, s_plus_l=s_plus_l,
        p_plus_q=p_plus_q, shortest=shortest, longest=longest,
        input_turns=moving and _joint_turns(g, i, c, o, tol),
        output_turns=moving and _joint_turns(g, o, i, c, tol),
        input_turns_on_coupler=moving and _joint_turns(i, c, g, o, tol),
        output_turns_on_coupler=moving and _joint_turns(c, o, g, i, tol),
        coupler_turns=moving and is_grashof and ("coupler" in shortest or "ground" in shortest),
    )


def fourth_link_range(ground: float, input: float, coupler: float, kind: str, *,
                      rtol: float = 1e-9) -> list[tuple[float, float]]:
    """Return the output-link lengths that make a four-bar of a given kind.

    With the three known lengths sorted as ``a <= b <= c``, an output length
    ``x`` is Grashof (``s + l < p + q``, the roles of shortest and longest
    changing with ``x``) for ``x < a + b - c`` and for
    ``a + c - b < x < b + c - a``; it is a change point at those three
    bounds and non-Grashof between them, up to ``a + b + c`` (beyond which the
    chain cannot be assembled). The class within the Grashof and non-Grashof
    sets follows from which link is shortest or longest, so the breakpoints
    also include ``a``, ``b`` and ``c``.

    Parameters
    ----------
    ground, input, coupler : float
        The known lengths.
    kind : str
        A kind or code of :data:`KINDS` (``"crank-rocker"``, ``"GCRR"``,
        ``"triple-rocker RRR1"``, ...), or a group: ``"grashof"`` (the four
        Grashof kinds), ``"non-grashof"`` or ``"triple-rocker"`` (the four
        triple rockers).

    Returns
    -------
    list of (float, float)
        Increasing, disjoint open intervals ``(low, high)`` of output lengths
        (``high`` may be ``inf`` for ``"unassemblable"``). The change-point and
        immobile kinds hold isolated lengths, returned as ``(x, x)``.

    Examples
    --------
    Seed 000 (ground 7, crank 5, coupler 6): the output lengths that give a
    triple rocker, and those that give a crank-rocker:

    >>> fourth_link_range(7, 5, 6, "non-grashof")
    [(4.0, 6.0), (8.0, 18.0)]
    >>> fourth_link_range(7, 5, 6, "crank-rocker")
    [(6.0, 8.0)]
    >>> fourth_link_range(7, 5, 6, "change-point")
    [(4.0, 4.0), (6.0, 6.0), (8.0, 8.0)]
    """
    wanted = _kinds_matching(kind)
    known = _lengths((ground, input, coupler, 1.0))
    a, b, c = sorted((known["ground"], known["input"], known["coupler"]))
    breaks = sorted({x for x in (a + b - c, a + c - b, b + c - a, a + b + c, c - a - b, a, b, c)
                     if x > 0})
    # the line of output lengths, cut at every breakpoint: open pieces and points
    pieces = []
    edges = [0.0, *breaks, np.inf]
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        middle = 0.5 * (lo + hi) if np.isfinite(hi) else 2 * lo + 1
        pieces.append((lo, hi, _kind_of(ground, input, coupler, middle, rtol) in wanted))
        if np.isfinite(hi):
            pieces.append((hi, hi, _kind_of(ground, input, coupler, hi, rtol) in wanted))
    intervals: list[tuple[float, float]] = []
    run = None
    for lo, hi, inside in pieces:
        if inside:
            run = (lo, hi) if run is None else (run[0], hi)
        elif run is not None:
            intervals.append(run)
            run = None
    if run is not None:
        intervals.append(run)
    return [(float(lo), float(hi)) for lo, hi in intervals]


def _kind_of(ground, input, coupler, output, rtol) -> str:
    return grashof(ground, input, coupler, output, rtol=rtol).kind


def _kinds_matching(kind: str) -> frozenset[str]:
    if kind in _GROUPS:
        return frozenset(_GROUPS[kind])
    if kind in KINDS:
        return frozenset({kind})
    by_code = {code: name for name, code in KINDS.items() if code}
    if kind in by_code:
        return frozenset({by_code[kind]})
    names = [*KINDS, *by_code, *_GROUPS]
    raise AnalysisError(f"unknown four-bar kind {kind!r}{did_you_mean(str(kind), names)}")


# -- transmission angle -----------------------------------------------------------


@dataclass(frozen=True)
class TransmissionAngle:
    """The angle at a circle-circle node between its two links, over a sweep.

    Attributes
    ----------
    node : str
        The node P.
    centers : (str, str)
        Its centres C1, C2: the angle is between P->C1 and P->C2.
    angle : ndarray, shape (N,)
        The angle in ``[0, pi]`` radians; NaN at invalid samples.
    minimum, maximum : float
        Its extremes over the valid samples.
    index_min, index_max : int
        The samples where they occur.
    at_minimum, at_maximum : dict of str to float
        The input values at those samples.
    """

    node: str
    centers: tuple[str, str]
    angle: np.ndarray = field(repr=False)
    minimum: float
    maximum: float
    index_min: int
    index_max: int
    at_minimum: dict[str, float]
    at_maximum: dict[str, float]

    @property
    def worst(self) -> float:
        """Return the smallest distance of the angle from 0 or pi (0 at a toggle)."""
        distance = np.minimum(self.angle, np.pi - self.angle)
        distance = distance[np.isfinite(distance)]
        return float(distance.min()) if distance.size else float("nan")


def _angle_between(u, v):
    # each vector taken to unit size first: the angle is the same, and products of
    # tiny or huge lengths would underflow or overflow
    with np.errstate(invalid="ignore", divide="ignore"):
        u = u / np.max(np.abs(u), axis=1, keepdims=True)
        v = v / np.max(np.abs(v), axis=1, keepdims=True)
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    dot = u[:, 0] * v[:, 0] + u[:, 1] * v[:, 1]
    return np.arctan2(np.abs(cross), dot)


def transmission_angles(sweep: Sweep) -> dict[str, TransmissionAngle]:
    """Return the transmission angle at every circle-circle node of a sweep.

    At a node P found from circles about C1 and C2, the two links P-C1 and
    P-C2 meet at P; the angle between P->C1 and P->C2 is the transmission
    angle of that dyad. For a four-bar ``B = circle_circle(A, coupler; O4,
    output)`` it is the classical transmission angle between coupler and
    output: 90 degrees is ideal, 0 or 180 degrees a toggle position.

    Parameters
    ----------
    sweep : Sweep

    Returns
    -------
    dict of str to TransmissionAngle
        By node name, in evaluation order.

    Examples
    --------
    >>> from geokin import Construction, sweep
    >>> c = Construction("four-bar")
    >>> c.input("theta")
    >>> c.fixed("O2", 0, 0)
    >>> c.fixed("O4", 24, 0)
    >>> c.polar("A", "O2", 10.55, "theta")
    >>> c.circle_circle("B", ("A", "O4"), (25, 14), branch="left")
    >>> theta = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    >>> mu = transmission_angles(sweep(c, theta))["B"]
    >>> round(float(np.degrees(mu.minimum)), 4), mu.at_minimum["theta"]
    (23.8758, 0.0)
    >>> round(float(np.degrees(mu.maximum)), 4), round(float(np.degrees(mu.at_maximum["theta"])), 6)
    (122.1699, 180.0)
    """
    result = {}
    for step in sweep.construction.steps:
        node = step.node
        if not isinstance(node, CircleCircle):
            continue
        p = sweep.points[node.name]
        angle = _angle_between(sweep.points[node.centers[0]] - p,
                               sweep.points[node.centers[1]] - p)
        if np.all(np.isnan(angle)):
            lo = hi = 0
            low = high = np.nan
        else:
            lo, hi = int(np.nanargmin(angle)), int(np.nanargmax(angle))
            low, high = float(angle[lo]), float(angle[hi])
        result[node.name] = TransmissionAngle(
            node.name, node.centers, angle, low, high, lo, hi,
            {k: float(v[lo]) for k, v in sweep.inputs.items()},
            {k: float(v[hi]) for k, v in sweep.inputs.items()})
    return result


def fourbar_transmission_extremes(ground: float, input: float, coupler: float,
                                  output: float) -> tuple[float, float]:
    """Return the minimum and maximum transmission angle of a four-bar, closed form.

    The transmission angle ``mu`` between coupler and output satisfies
    ``cos mu = (coupler**2 + output**2 - e**2) / (2 coupler output)`` with ``e``
    the diagonal from the input joint to the output pivot,
    ``e**2 = ground**2 + input**2 - 2 ground input cos(theta)``. It grows
    with ``e``, which is extreme at ``theta = 0`` and ``pi`` when the linkage
    gets there; otherwise the diagonal stops where coupler and output fold
    (``mu = 0``) or stretch (``mu = pi``): the input's limits of a rocker.

    Parameters
    ----------
    ground, input, coupler, output : float

    Returns
    -------
    (float, float)
        ``(mu_min, mu_max)`` in radians, the same for both assembly circuits.

    Examples
    --------
    Seed 000's transmission example (fixed 7, crank 4, coupler 5, rocker 5):

    >>> low, high = fourbar_transmission_extremes(7, 4, 5, 5)
    >>> round(float(np.degrees(low)), 2), round(float(np.degrees(high)), 2)
    (34.92, 180.0)
    """
    g, i, c, o = _lengths((ground, input, coupler, output)).values()
    e_min = max(abs(g - i), abs(c - o))
    e_max = min(g + i, c + o)
    if e_min > e_max * (1 + 1e-12):
        raise AnalysisError(f"a four-bar with lengths {g:g}, {i:g}, {c:g}, {o:g} cannot be "
                         "assembled")

    def mu(e):
        return float(np.arccos(np.clip((c * c + o * o - e * e) / (2 * c * o), -1.0, 1.0)))

    return mu(e_min), mu(e_max)


# -- degrees of freedom -----------------------------------------------------------


@dataclass(frozen=True)
class Mobility:
    """The Gruebler-Kutzbach count of a construction's declared links.

    ``dof = 3 * moving_links - 2 * lower_pairs - higher_pairs``.

    Attributes
    ----------
    moving_links : int
        Declared links that are not the ground, plus one block per slider.
    revolute_joints : int
        At every point shared by k bodies, k - 1 joints.
    prismatic_pairs : int
        One per slider.
    lower_pairs : int
        Revolute joints plus prismatic pairs.
    higher_pairs : int
        Always 0: no node kind makes a higher pair.
    dof : int
    inputs : int
        The number of inputs the construction declares.
    bodies : tuple of str
        The moving bodies (link and slider names); the ground is ``"ground"``.
    joints : dict of str to tuple of str
        For every point joining bodies, the bodies it joins.
    guides : dict of str to str
        For every slider, the body its line belongs to (None if no declared
        body holds both of its points).
    """

    moving_links: int
    revolute_joints: int
    prismatic_pairs: int
    lower_pairs: int
    higher_pairs: int
    dof: int
    inputs: int
    bodies: tuple[str, ...] = ()
    joints: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    guides: Mapping[str, str | None] = field(default_factory=dict)

    @property
    def matches_inputs(self) -> bool:
        """Return whether the count equals the number of inputs."""
        return self.dof == self.inputs

    def __str__(self) -> str:
        return (f"DOF = 3({self.moving_links}) - 2({self.lower_pairs}) - {self.higher_pairs} "
                f"= {self.dof}; {self.inputs} input{'s' if self.inputs != 1 else ''}"
                f"{'' if self.matches_inputs else ' (mismatch)'}")


def degrees_of_freedom(construction: Construction | Compiled) -> Mobility:
    """Count the degrees of freedom of the declared links and sliders.

    The bodies are the declared links and one block per slider. A link whose
    points are all fixed belongs to the ground, and so does every fixed point:
    there is one ground body. A point shared by k bodies is k - 1 revolute
    joints. A slider ``Slider(name, point, along=(P, Q))`` is a block pinned
    at ``point`` (one more moving link and one more revolute joint there) and
    sliding on the body that holds P and Q (one prismatic pair). Points in no
    declared link are construction aids and count for nothing.

    Parameters
    ----------
    construction : Construction or Compiled

    Returns
    -------
    Mobility

    Examples
    --------
    >>> from geokin import Construction
    >>> c = Construction("four-bar")
    >>> c.input("theta")
    >>> c.fixed("O2", 0, 0)
    >>> c.fixed("O4", 4, 0)
    >>> c.polar("A", "O2", 1, "theta")
    >>> c.circle_circle("B", ("A", "O4"), (4, 3), branch="left")
    >>> c.link("crank", "O2", "A")
    >>> c.link("coupler", "A", "B")
    >>> c.link("rocker", "B", "O4")
    >>> m = degrees_of_freedom(c)
    >>> print(m)
    DOF = 3(3) - 2(4) - 0 = 1; 1 input
    >>> m.matches_inputs
    True
    """
    compiled = construction.compile() if isinstance(construction, Construction) else construction
    # a fixed point whose place depends on an input is driven, not ground
    fixed = {s.node.name for s in compiled.steps if isinstance(s.node, Fixed)
             and not any(e.names() & compiled.inputs.keys()
                         for e in s.node.value_fields().values())}
    members: dict[str, set[str]] = {}
    bodies = []
    for link in compiled.links:
        if all(p in fixed for p in link.points):
            continue
        bodies.append(link.name)
        members[link.name] = set(link.points)
    members["ground"] = set(fixed)
    guides = {}
    for slider in compiled.sliders:
        holders = [b for b in (*bodies, "ground") if set(slider.along) <= members[b]]
        guides[slider.name] = holders[0] if holders else None
        bodies.append(slider.name)
        members[slider.name] = {slider.point}
    joints = {}
    for point in compiled.point_names:
        at = tuple(b for b in ("ground", *bodies) if point in members[b])
        if len(at) > 1:
            joints[point] = at
    revolute = sum(len(at) - 1 for at in joints.values())
    prismatic = len(compiled.sliders)
    lower = revolute + prismatic
    moving = len(bodies)
    return Mobility(moving, revolute, prismatic, lower, 0, 3 * moving - 2 * lower,
                    len(compiled.inputs), tuple(bodies), joints, guides)


# -- stroke and time ratio ----------------------------------------------------------


@dataclass(frozen=True)
class Stroke:
    """Extremes of an output over one turn of a constant-speed input.

    Attributes
    ----------
    minimum, maximum : float
        The output's extremes (refined between samples).
    input_at_min, input_at_max : float
        Where they occur, within the input's first turn.
    stroke : float
        ``maximum - minimum``.
    forward, back : float
        The input travelled (increasing) from the minimum to the maximum, and
        from the maximum back to the minimum; they add up to one turn.
    time_ratio : float
        ``forward / back``: for a constant input speed, the time of the
        forward stroke (minimum to maximum) over that of the return.
    """

    minimum: float
    maximum: float
    input_at_min: float
    input_at_max: float
    stroke: float
    forward: float
    back: float
    time_ratio: float

    @property
    def quick_return_ratio(self) -> float:
        """Return the slower stroke's time over the faster one's (at least 1)."""
        return max(self.forward, self.back) / min(self.forward, self.back)


def _vertex(x, y):
    """Return the extremum (x, y) of the polynomial through the samples around x[k//2].

    A polynomial of degree len(x) - 1 (a quartic on five samples), so the
    extremum is found to a high order in the sample spacing.
    """
    mid = len(x) // 2
    x0 = x[mid]
    h = max(np.max(np.abs(np.diff(x))), np.finfo(float).tiny)
    poly = np.polynomial.Polynomial.fit((x - x0) / h, y, len(x) - 1, domain=[-1, 1],
                                        window=[-1, 1])
    roots = poly.deriv().roots()
    roots = roots[np.isreal(roots)].real
    roots = roots[np.abs(roots) <= 1.0]
    if roots.size == 0:
        return x0, y[mid]
    t = roots[np.argmin(np.abs(roots))]
    return x0 + t * h, float(poly(t))


def stroke(output: ArrayLike, input: ArrayLike, *, period: float = 2 * np.pi) -> Stroke:
    """Return the extremes, stroke and time ratio of an output over one input turn.

    Parameters
    ----------
    output : array_like, shape (N,)
        The output at each sample: a point coordinate, a link angle. The
        extremes are refined between samples by a quartic through the five
        samples around each.
    input : array_like, shape (N,)
        The input, increasing over at least one full ``period`` (the last
        sample may repeat the first one turn later). NaN outputs are left out.
    period : float
        One turn of the input.

    Returns
    -------
    Stroke

    Examples
    --------
    The sine of a crank angle: equal forward and return times.

    >>> t = np.linspace(0, 2 * np.pi, 361)
    >>> s = stroke(np.sin(t), t)
    >>> round(s.stroke, 9), round(s.time_ratio, 9)
    (2.0, 1.0)
    """
    y = np.asarray(output, dtype=float)
    x = np.asarray(input, dtype=float)
    if x.shape != y.shape or x.ndim != 1:
        raise AnalysisError("output and input must be one-dimensional arrays of one length")
    if np.any(np.diff(x) <= 0):
        raise AnalysisError("the input must increase from sample to sample")
    keep = x < x[0] + period - 1e-12 * period
    span = x[-1] - x[0]
    step = np.max(np.diff(x)) if len(x) > 1 else np.inf
    if span < period - 1.5 * step:
        raise AnalysisError(f"the input covers {span:g}, less than one turn ({period:g})")
    x, y = x[keep], y[keep]
    ok = np.isfinite(y)
    if ok.sum() < 3:
        raise AnalysisError("fewer than three finite output values")
    n = len(x)

    def extreme(index):
        around = np.arange(index - 2, index + 3)
        wrapped = around % n
        if not ok[wrapped].all():
            return x[index], y[index]
        return _vertex(x[wrapped] + period * np.floor_divide(around, n), y[wrapped])

    x_min, y_min = extreme(int(np.nanargmin(y)))
    x_max, y_max = extreme(int(np.nanargmax(y)))
    forward = float((x_max - x_min) % period)
    back = period - forward
    return Stroke(float(y_min), float(y_max), float(x_min), float(x_max),
                  float(y_max - y_min), forward, float(back), forward / back)


def time_ratio(output: ArrayLike, input: ArrayLike, *, period: float = 2 * np.pi) -> float:
    """Return the forward over return time of an output over one input turn.

    The forward stroke runs from the output's minimum to its maximum; see
    :func:`stroke`.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 721)
    >>> round(time_ratio(np.sin(t) + 0.2 * np.sin(2 * t), t), 4)
    0.6577
    """
    return stroke(output, input, period=period).time_ratio


# -- link angles -----------------------------------------------------------------------


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


# -- curve measures -----------------------------------------------------------------------


@dataclass(frozen=True)
class Curve:
    """Measures of a traced curve (see :func:`curve_measures`).

    Attributes
    ----------
    length : float
        Total length of the polyline.
    closed : bool
        Whether it ends where it starts (within the tolerance).
    signed_area : float
        For a closed curve, the shoelace area: positive counter-clockwise;
        lobes traced in opposite senses cancel. NaN for an open curve.
    area : float
        For a closed curve, the area of the regions it encloses, each region
        once (a figure-eight: both lobes). NaN for an open curve.
    bounds : (float, float, float, float)
        ``(xmin, ymin, xmax, ymax)``.
    double_points : ndarray, shape (K, 2)
        Where the curve crosses or touches itself.
    """

    length: float
    closed: bool
    signed_area: float
    area: float
    bounds: tuple[float, float, float, float]
    double_points: np.ndarray = field(repr=False)

    @property
    def simple(self) -> bool:
        """Return whether the curve has no double point."""
        return len(self.double_points) == 0


def _runs(points):
    ok = np.all(np.isfinite(points), axis=1)
    runs, start = [], None
    for i, good in enumerate(ok):
        if good and start is None:
            start = i
        if not good and start is not None:
            runs.append(points[start:i])
            start = None
    if start is not None:
        runs.append(points[start:])
    return runs


def curve_measures(points: ArrayLike, *, tol: float | None = None) -> Curve:
    """Measure a curve given as a polyline: length, area, bounds, double points.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        The curve's points in order, for example a coupler trace. Rows with
        NaN (invalid samples) split it into pieces; a split curve is open.
    tol : float, optional
        Distance below which the ends count as one point (a closed curve);
        by default ``1e-8`` times the diagonal of the bounding box.

    Returns
    -------
    Curve

    Examples
    --------
    A square, and a figure-eight with its double point at the origin:

    >>> square = [(0, 0), (2, 0), (2, 2), (0, 2), (0, 0)]
    >>> m = curve_measures(square)
    >>> m.length, m.signed_area, m.closed, m.simple
    (8.0, 4.0, True, True)
    >>> t = np.linspace(0, 2 * np.pi, 201)
    >>> eight = np.c_[np.sin(t), np.sin(t) * np.cos(t)]
    >>> m = curve_measures(eight)
    >>> np.round(m.double_points, 9) + 0.0, round(m.signed_area, 9) + 0.0
    (array([[0., 0.]]), 0.0)
    """
    xy = np.asarray(points, dtype=float)
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise AnalysisError(f"points must have shape (N, 2), got {xy.shape}")
    runs = [r for r in _runs(xy) if len(r) >= 2]
    if not runs:
        raise AnalysisError("a curve needs at least two finite points in a row")
    everything = np.concatenate(runs)
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    bounds = (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))
    # measured on the curve brought to about unit size by a power of two, which is
    # exact: lengths and areas of a tiny or huge curve would underflow or overflow
    size = float(np.max(np.abs(everything)))
    unit = 2.0 ** -math.frexp(size)[1] if 0 < size < np.inf else 1.0
    runs = [r * unit for r in runs]
    if tol is None:
        tol = 1e-8 * float(np.hypot(*(hi - lo))) * unit
    else:
        tol = tol * unit
    closed = len(runs) == 1 and len(runs[0]) >= 4 and \
        float(np.hypot(*(runs[0][-1] - runs[0][0]))) <= tol
    if closed:
        runs[0] = runs[0].copy()
        runs[0][-1] = runs[0][0]
    lines = [shapely.LineString(r) for r in runs]
    length = float(sum(line.length for line in lines))
    signed = area = np.nan
    if closed:
        ring = runs[0]
        x, y = ring[:, 0], ring[:, 1]
        signed = 0.5 * float(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))
    noded = shapely.unary_union(shapely.MultiLineString(lines))
    if closed:
        faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(noded)))
        area = float(sum(f.area for f in faces))
    least_angle = min(max(GRAZING_ANGLE, 3 * _turn_per_sample(runs)), np.radians(20))
    return Curve(length / unit, closed, _unscaled_area(signed, unit),
                 _unscaled_area(area, unit), bounds, _double_points(noded, least_angle) / unit)


def _unscaled_area(area: float, unit: float) -> float:
    """Return an area measured at ``unit`` times the size, at the true size.

    NaN where that lies beyond the normal range of floats (a curve of size
    1e-200 encloses some 1e-400): never a rounded zero or a subnormal value.
    """
    value = area / unit / unit
    if area != 0 and not (np.finfo(float).tiny <= abs(value) < np.inf):
        return np.nan
    return value


GRAZING_ANGLE = np.radians(2.0)
"""The least angle between pieces meeting at a node that makes a crossing.

Where a path runs back over itself, as a rocker's joint does, two polylines
of the same arc sampled differently cross each other at angles up to about
the turn of the path between samples; so the angle used is the larger of
this and three times the path's median turn per sample."""


def _turn_per_sample(runs) -> float:
    """Return the median angle the polyline turns through from one segment to the next."""
    turns = []
    for run in runs:
        steps = np.diff(run, axis=0)
        steps = steps[np.hypot(*steps.T) > 0]
        if len(steps) >= 2:
            a, b = steps[:-1], steps[1:]
            turns.append(np.abs(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
                                           np.einsum("ij,ij->i", a, b))))
    return float(np.median(np.concatenate(turns))) if turns else 0.0


def _double_points(noded, least_angle=GRAZING_ANGLE) -> np.ndarray:
    """Nodes where three or more pieces of the noded curve end, crossing each other.

    A crossing ends four pieces; an end of an open curve ends one, the
    joined ends of a closed curve two. Nodes where every piece runs along the
    same line (a path retraced) are not crossings.
    """
    directions: dict[tuple[float, float], list] = {}
    for part in shapely.get_parts(noded):
        coords = shapely.get_coordinates(part)
        if len(coords) < 2:  # a path that never moves has no pieces to cross
            continue
        for end, toward in ((coords[0], coords[1]), (coords[-1], coords[-2])):
            key = (float(end[0]), float(end[1]))
            step = toward - end
            directions.setdefault(key, []).append(step / max(np.hypot(*step), 1e-300))
    found = []
    for key, units in directions.items():
        if len(units) < 3:
            continue
        u = np.array(units)
        sines = np.abs(u[:, None, 0] * u[None, :, 1] - u[:, None, 1] * u[None, :, 0])
        if sines.max() > np.sin(least_angle):
            found.append(key)
    return np.array(sorted(found), dtype=float).reshape(-1, 2)
