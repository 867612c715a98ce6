"""Four-bars: Grashof classification and transmission angles.

The Grashof class of a four-bar (:func:`grashof`), the range of a fourth
link that gives a wanted class (:func:`fourth_link_range`), and the
transmission angle, over a sweep (:func:`transmission_angles`) or in closed
form (:func:`fourbar_transmission_extremes`). Angles are radians.

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
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..compat import renamed_keywords
from ..errors import AnalysisError, did_you_mean
from ..nodes import CircleCircle
from ..results import Sweep

__all__ = [
    "KINDS",
    "ROLES",
    "Grashof",
    "TransmissionAngle",
    "fourbar_transmission_extremes",
    "fourth_link_range",
    "grashof",
    "transmission_angles",
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


@renamed_keywords(input="input_link", output="output_link")
def grashof(ground: float, input_link: float, coupler: float, output_link: float, *,
            rtol: float = 1e-9) -> Grashof:
    """Classify a four-bar by Grashof's criterion.

    Parameters
    ----------
    ground, input_link, coupler, output_link : float
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
    A triple rocker (ground 7, crank 5, coupler 6, follower 5), and a crank-rocker:

    >>> g = grashof(ground=7, input_link=5, coupler=6, output_link=5)
    >>> g.kind, g.grashof, g.s_plus_l, g.p_plus_q
    ('triple-rocker RRR1', False, 12.0, 11.0)
    >>> g = grashof(ground=24, input_link=10.55, coupler=25, output_link=14)
    >>> g.kind, g.code, g.input_turns, g.output_turns
    ('crank-rocker', 'GCRR', True, False)
    >>> grashof(2, 1, 2, 1).kind
    'change-point'
    """
    lengths = _lengths((ground, input_link, coupler, output_link))
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


@renamed_keywords(input="input_link")
def fourth_link_range(ground: float, input_link: float, coupler: float, kind: str, *,
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
    ground, input_link, coupler : float
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
    Ground 7, crank 5, coupler 6: the output lengths that give a
    triple rocker, and those that give a crank-rocker:

    >>> fourth_link_range(7, 5, 6, "non-grashof")
    [(4.0, 6.0), (8.0, 18.0)]
    >>> fourth_link_range(7, 5, 6, "crank-rocker")
    [(6.0, 8.0)]
    >>> fourth_link_range(7, 5, 6, "change-point")
    [(4.0, 4.0), (6.0, 6.0), (8.0, 8.0)]
    """
    wanted = _kinds_matching(kind)
    known = _lengths((ground, input_link, coupler, 1.0))
    a, b, c = sorted((known["ground"], known["input"], known["coupler"]))
    breaks = sorted({x for x in (a + b - c, a + c - b, b + c - a, a + b + c, c - a - b, a, b, c)
                     if x > 0})
    # the line of output lengths, cut at every breakpoint: open pieces and points
    pieces = []
    edges = [0.0, *breaks, np.inf]
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        middle = 0.5 * (lo + hi) if np.isfinite(hi) else 2 * lo + 1
        pieces.append((lo, hi, _kind_of(ground, input_link, coupler, middle, rtol) in wanted))
        if np.isfinite(hi):
            pieces.append((hi, hi, _kind_of(ground, input_link, coupler, hi, rtol) in wanted))
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


def _kind_of(ground, input_link, coupler, output_link, rtol) -> str:
    return grashof(ground, input_link, coupler, output_link, rtol=rtol).kind


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


@renamed_keywords(input="input_link", output="output_link")
def fourbar_transmission_extremes(ground: float, input_link: float, coupler: float,
                                  output_link: float) -> tuple[float, float]:
    """Return the minimum and maximum transmission angle of a four-bar, closed form.

    The transmission angle ``mu`` between coupler and output satisfies
    ``cos mu = (coupler**2 + output_link**2 - e**2) / (2 coupler output_link)``
    with ``e`` the diagonal from the input joint to the output pivot,
    ``e**2 = ground**2 + input_link**2 - 2 ground input_link cos(theta)``. It grows
    with ``e``, which is extreme at ``theta = 0`` and ``pi`` when the linkage
    gets there; otherwise the diagonal stops where coupler and output fold
    (``mu = 0``) or stretch (``mu = pi``): the input's limits of a rocker.

    Parameters
    ----------
    ground, input_link, coupler, output_link : float

    Returns
    -------
    (float, float)
        ``(mu_min, mu_max)`` in radians, the same for both assembly circuits.

    Examples
    --------
    A four-bar with ground 7, crank 4, coupler 5 and rocker 5:

    >>> low, high = fourbar_transmission_extremes(7, 4, 5, 5)
    >>> round(float(np.degrees(low)), 2), round(float(np.degrees(high)), 2)
    (34.92, 180.0)
    """
    g, i, c, o = _lengths((ground, input_link, coupler, output_link)).values()
    e_min = max(abs(g - i), abs(c - o))
    e_max = min(g + i, c + o)
    if e_min > e_max * (1 + 1e-12):
        raise AnalysisError(f"a four-bar with lengths {g:g}, {i:g}, {c:g}, {o:g} cannot be "
                         "assembled")

    def mu(e):
        return float(np.arccos(np.clip((c * c + o * o - e * e) / (2 * c * o), -1.0, 1.0)))

    return mu(e_min), mu(e_max)
