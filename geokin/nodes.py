"""Node kinds: how each point of a construction is found, declared once.

Every kind of point is one class here. The class says everything geokin
needs to know about the kind, and nothing about it is repeated elsewhere:

- its fields (the dataclass fields) and its script keys (:attr:`Node.keys`),
  from which the builder (:meth:`~geokin.construction.Construction.add`),
  the script reader and the script writer are made;
- which of its values are angles (``Key.angle``);
- its roots and their branch names (:attr:`Node.branch_names`; none for a
  node with one root);
- whether it stands on no other point (:attr:`Node.ground_kind`);
- how its roots are computed (:meth:`Node.candidates`), and why a chosen
  root may not exist (:func:`failure_reasons`).

The engine evaluates nodes through :meth:`Node.candidates` only; it never
asks which kind a node is.

Examples
--------
>>> CircleCircle.branch_names
('left', 'right')
>>> [key.name for key in Polar.keys]
['origin', 'distance', 'angle', 'reference']
>>> sorted(NODE_KINDS)[:3]
['along', 'circle_circle', 'fixed']
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import ClassVar, TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from . import closure as solver  # the module: Newton and continuation
from . import primitives as prim
from .expressions import Expr

__all__ = [
    "BRANCHES",
    "HOLDS",
    "NODE_KINDS",
    "REASONS",
    "Along",
    "Candidates",
    "CircleCircle",
    "Closure",
    "Fixed",
    "Key",
    "LineCircle",
    "LineLine",
    "Local",
    "Node",
    "Polar",
    "RayCircle",
    "SegmentCircle",
    "failure_reasons",
]

# Why a sample could not be assembled at a node; codes stored per sample.
REASONS = (
    "",
    "no intersection: the curves do not meet",
    "degenerate input: coincident centres, zero-length line or parallel lines",
    "the chosen root lies off the ray or segment",
    "a value is not finite, or a radius is negative",
    "the group reaches a singular position",
    "Newton did not converge",
)
NO_INTERSECTION, DEGENERATE, OFF_LINE, NOT_FINITE, SINGULAR, NOT_CONVERGED = 1, 2, 3, 4, 5, 6

HOLDS = ("point", "point pair", "value", "value pair", "branch", "sketch")
"""What a script key may hold: a point name, two point names, a value
(number or arithmetic), two values, a branch name, or a sketch position
``[x, y]`` (plain numbers)."""


@dataclass(frozen=True)
class Key:
    """One key of a node kind, as scripts and the builder take it.

    Attributes
    ----------
    name : str
        The key in scripts, and the keyword of
        :meth:`~geokin.construction.Construction.add`.
    holds : str
        One of :data:`HOLDS`.
    attributes : tuple of str
        The node fields it fills: by default the one named like the key;
        two for a pair spread over two fields (a fixed point's ``at`` fills
        ``x`` and ``y``).
    required : bool
    angle : bool
        Whether its values are angles (radians inside, degrees in scripts).
    nonnegative : bool
        Whether its values cannot be negative (a radius): a negative one is
        refused when it is constant, and makes its samples unassemblable.
    """

    name: str
    holds: str
    attributes: tuple[str, ...] = ()
    required: bool = True
    angle: bool = False
    nonnegative: bool = False

    def __post_init__(self) -> None:
        if self.holds not in HOLDS:
            raise ValueError(f"unknown holds {self.holds!r}")
        if not self.attributes:
            object.__setattr__(self, "attributes", (self.name,))

    def fields(self) -> tuple[str, ...]:
        """Return the field names this key's errors and values are known by.

        One per value: ``("x", "y")`` for ``at``, ``("radii[0]", "radii[1]")``
        for ``radii``, ``("distance",)`` for ``distance``.
        """
        if len(self.attributes) > 1:
            return self.attributes
        if self.holds in ("point pair", "value pair", "sketch"):
            return (f"{self.name}[0]", f"{self.name}[1]")
        return self.attributes


Coords: TypeAlias = Mapping[str, tuple[np.ndarray, np.ndarray]]
"""The x and y arrays of the points already found, by name."""
Values: TypeAlias = Mapping[str, np.ndarray | float]
"""A node's evaluated value fields, angles in radians."""


# not frozen: a frozen dataclass takes four times as long to make, and every node of
# every sweep makes one; nothing changes one once made
@dataclass(slots=True)
class Candidates:
    """What a node computes for every sample, before a branch is chosen.

    Attributes
    ----------
    x, y : tuple of ndarray
        One entry per root (one for a single-root node, two for a two-root
        node), each broadcastable to the N samples; NaN where the root does
        not exist.
    margin : ndarray or None
        Distance from tangency of a two-root node (positive: two roots,
        zero: tangent, negative: none), smooth in the inputs.
    on_line : tuple of ndarray or None
        For a ray or a segment: whether each root lies on it (with the
        tolerance of :data:`~geokin.primitives.PARAMETER_RTOL`).
    t : tuple of ndarray or None
        For a ray or a segment: each root's parameter along it, which lies
        within the node's ``low``..``high`` exactly on it.
    also : mapping of str to (x, y), or None
        Further points the node found at once (the other points of a
        closure group), known to the steps after it.
    reason : ndarray or None
        Why the root does not exist where it is NaN, as codes into
        :data:`REASONS`, for a node that knows it itself (a closure group).
    """

    x: tuple
    y: tuple
    margin: np.ndarray | None = None
    on_line: tuple | None = None
    t: tuple | None = None
    also: Mapping[str, tuple[np.ndarray, np.ndarray]] | None = None
    reason: np.ndarray | None = None


def failure_reasons(cand: Candidates, values: Mapping[str, ArrayLike],
                    root: int | np.ndarray,
                    nonnegative: frozenset[str] = frozenset()) -> np.ndarray:
    """Say why the chosen roots do not exist, as codes into ``REASONS``.

    Parameters
    ----------
    cand : Candidates
        The node's candidates at the failing samples only.
    values : mapping
        The node's values at those samples.
    root : int or ndarray
        The chosen root at each of those samples.
    nonnegative : frozenset of str
        The value fields that cannot be negative (:meth:`Node.nonnegative_fields`).
    """
    shape = np.shape(cand.x[0] if np.ndim(root) == 0 else root)
    finite = np.ones(shape, dtype=bool)
    for field_name, value in values.items():
        finite &= np.isfinite(value)
        if field_name in nonnegative:
            with np.errstate(invalid="ignore"):
                finite &= ~(np.asarray(value) < 0)
    reason = np.full(shape, DEGENERATE, dtype=np.int8)
    if cand.reason is not None:
        reason[...] = np.broadcast_to(cand.reason, shape)
    elif cand.margin is not None:
        with np.errstate(invalid="ignore"):
            reason[np.broadcast_to(cand.margin < 0, shape)] = NO_INTERSECTION
        if cand.on_line is not None:
            exists = np.broadcast_to(np.isfinite(cand.margin) & (cand.margin >= 0), shape)
            on_line = np.where(root, cand.on_line[1], cand.on_line[0])
            reason[exists & ~np.broadcast_to(on_line, shape)] = OFF_LINE
    reason[~finite] = NOT_FINITE
    return reason


@dataclass(frozen=True)
class Node:
    """A point of a construction. Subclasses say how it is found.

    Class attributes
    ----------------
    kind : str
        The kind's name, the ``op`` of scripts.
    keys : tuple of Key
        Its script keys, in the order a script is written.
    branch_names : tuple of str
        The names of its roots in the primitive's order; empty for a node
        with one root.
    ground_kind : bool
        Whether a point of this kind is ground when none of its values
        uses an input, whatever it is built on (a fixed point is built on
        nothing); a point of another kind is ground when, besides, every
        point it is built on is ground (see :meth:`is_ground`).
    low, high : float
        Where along its line a root counts, as the line's parameter:
        ``low <= t <= high``.
    """

    name: str
    kind: ClassVar[str] = ""
    keys: ClassVar[tuple[Key, ...]] = ()
    branch_names: ClassVar[tuple[str, ...]] = ()
    ground_kind: ClassVar[bool] = False
    low: ClassVar[float] = -np.inf
    high: ClassVar[float] = np.inf

    @property
    def continued(self) -> bool:
        """Whether the node follows its solution along the samples (a closure group).

        Such a node takes a ``guess`` and an ``origin`` in
        :meth:`candidates`: without a guess it continues from sample to
        sample, so it needs the samples of a path all at once; with one (an
        (N, 2k) array of positions, as held from a sweep) it solves each
        sample from its own guess.
        """
        return False

    @property
    def defines(self) -> tuple[str, ...]:
        """Return the points this node's evaluation finds: itself, or its whole group."""
        return (self.name,)

    @property
    def roots(self) -> int:
        """Return the number of roots: 1, or 2 for a node with branches."""
        return len(self.branch_names) or 1

    @property
    def missing_by_position(self) -> bool:
        """Whether where the points it is built on are can make this point missing.

        So an intersection, which can miss, and a point in the frame of two
        points, which has none where they coincide. Not a fixed point, built
        on none, nor one at a distance and absolute angle from another: such
        a point is missing only where one of its values, or its origin, is.
        """
        return True

    @property
    def missing_where_coincide(self) -> tuple[str, str] | None:
        """Return the two points this point is missing only where they coincide, if any.

        The points of a frame or direction it is built in; None for a kind
        that can be missing otherwise, or not at all.
        """
        return None

    def radius_about(self, center: str) -> Expr | None:
        """Return how far every root of this node is from ``center``, if it is a circle's centre.

        The evaluation plan gives a node built in the frame of two points
        (:attr:`missing_where_coincide`), one on a circle about the other,
        that radius as the value ``frame_length``: the distance between them,
        known without measuring it.
        """
        return None

    @property
    def equidistant_from(self) -> tuple[str, ...]:
        """Return the points every root of this node is equally far from: a circle's centre."""
        return ()

    @property
    def missing_by_branch(self) -> bool:
        """Whether one root can be missing where the other is found (off a ray or segment)."""
        return False

    def point_fields(self) -> dict[str, tuple[str, ...]]:
        """Return the points this node is built on, by field."""
        fields = {}
        for key in self.keys:
            if key.holds in ("point", "point pair"):
                value = getattr(self, key.attributes[0])
                if value is not None:
                    fields[key.name] = (value,) if key.holds == "point" else tuple(value)
        return fields

    def value_fields(self) -> dict[str, Expr]:
        """Return the values (numbers, names, arithmetic) by field."""
        fields: dict[str, Expr] = {}
        for key in self.keys:
            if key.holds in ("value", "value pair"):
                values = [getattr(self, a) for a in key.attributes]
                if key.holds == "value pair" and len(values) == 1:
                    values = list(values[0])
                fields.update(zip(key.fields(), values, strict=True))
        return fields

    def angle_fields(self) -> frozenset[str]:
        """Return the value fields that are angles."""
        return frozenset(f for key in self.keys if key.angle for f in key.fields())

    def nonnegative_fields(self) -> frozenset[str]:
        """Return the value fields that cannot be negative (radii)."""
        return frozenset(f for key in self.keys if key.nonnegative for f in key.fields())

    def initial_root(self, cand: Candidates, n: int, paths: int = 1) -> int | np.ndarray:
        """Return the root this node starts on: 0 for a node with one root."""
        return 0

    @property
    def chosen_by_position(self) -> bool:
        """Whether the initial root depends on where the roots are, over all samples."""
        return False

    def scale(self, coords: Coords, values: Values) -> np.ndarray | None:
        """Return the scale a two-root node's margin is measured against, at every sample.

        The distance between its roots is known to the rounding of the
        coordinates it is found from, relative to this scale (None, as for a
        node with one root: to the rounding of the scale itself).
        """
        return None

    def depends_on(self) -> tuple[str, ...]:
        """Return every point this node is built on, in order, without repeats."""
        seen: dict[str, None] = {}
        for names in self.point_fields().values():
            seen.update(dict.fromkeys(names))
        return tuple(seen)

    def is_ground(self, inputs: frozenset[str] | set[str],
                  ground: frozenset[str] | set[str] = frozenset()) -> bool:
        """Whether the point never moves.

        It never moves when its values use none of ``inputs`` and it is of
        a ground kind (a fixed point), or is built only on points that never
        move: a second point of a fixed slider guide, at a constant angle
        from a fixed point, is ground as the fixed point is.

        Parameters
        ----------
        inputs : set of str
            The construction's inputs.
        ground : set of str
            The points already known to be ground.

        Examples
        --------
        >>> from geokin.expressions import as_expr
        >>> Fixed("A", as_expr(0), as_expr("s")).is_ground({"s"})
        False
        >>> Fixed("A", as_expr(0), as_expr(1)).is_ground({"s"})
        True
        >>> guide = Polar("H", "G", as_expr(1), as_expr(0.5))
        >>> guide.is_ground({"s"}, {"G"}), guide.is_ground({"s"}, set())
        (True, False)
        """
        if any(expr.names() & inputs for expr in self.value_fields().values()):
            return False
        if self.ground_kind:
            return True
        built_on = self.depends_on()
        return bool(built_on) and all(p in ground for p in built_on)

    def choice(self) -> str | None:
        """Return how the initial branch is chosen, as text (None for one root)."""
        return None

    def describe(self) -> str:
        """Return the node's right-hand side, as a step list shows it."""
        raise NotImplementedError

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        """Compute every root for all samples.

        Parameters
        ----------
        coords : mapping of str to (x, y)
            Coordinate arrays of the points already known.
        values : mapping of str to ndarray or float
            The evaluated value fields, angles in radians.
        """
        raise NotImplementedError


@dataclass(frozen=True)
class Fixed(Node):
    """A fixed point (a ground pivot) at ``(x, y)``.

    A coordinate that uses an input makes a point driven along a line (a
    slider moved directly); such a point is not ground.
    """

    x: Expr
    y: Expr
    kind: ClassVar[str] = "fixed"
    keys: ClassVar[tuple[Key, ...]] = (Key("at", "value pair", ("x", "y")),)
    ground_kind: ClassVar[bool] = True

    @property
    def missing_by_position(self) -> bool:
        return False

    def describe(self) -> str:
        return f"fixed({self.x}, {self.y})"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        return Candidates((values["x"],), (values["y"],))


def _scaled_and_shifted(values, factor, offset):
    """Return ``offset + factor * values``, in the memory of ``values`` where it can.

    ``values`` is a fresh array; its memory is used where ``factor`` and
    ``offset`` are numbers or of its shape.
    """
    if type(values) is np.ndarray and (
            type(factor) is float or np.ndim(factor) == 0) and (
            type(offset) is float or np.ndim(offset) == 0 or np.shape(offset) == values.shape):
        values *= factor
        if not (type(offset) is float and offset == 0.0):  # a crank on the origin
            values += offset
        return values
    return offset + factor * values


@dataclass(frozen=True)
class Polar(Node):
    """The point at ``distance`` from ``origin`` at ``angle``.

    The angle is absolute (counter-clockwise from the x axis), or, with
    ``reference=(P, Q)``, measured from the direction of the line P -> Q.
    """

    origin: str
    distance: Expr
    angle: Expr
    reference: tuple[str, str] | None = None
    kind: ClassVar[str] = "polar"
    keys: ClassVar[tuple[Key, ...]] = (
        Key("origin", "point"), Key("distance", "value"), Key("angle", "value", angle=True),
        Key("reference", "point pair", required=False))

    @property
    def missing_by_position(self) -> bool:
        return self.reference is not None  # no direction where the reference's points meet

    @property
    def missing_where_coincide(self) -> tuple[str, str] | None:
        return self.reference

    def describe(self) -> str:
        ref = "" if self.reference is None else f" from {self.reference[0]}->{self.reference[1]}"
        return f"polar({self.origin}, {self.distance}, {self.angle}{ref})"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        ox, oy = coords[self.origin]
        distance, angle = values["distance"], values["angle"]
        if self.reference is None:
            cos, sin = prim.cos_sin(angle)
            x = _scaled_and_shifted(cos, distance, ox)
            y = _scaled_and_shifted(sin, distance, oy)
        else:
            (x1, y1), (x2, y2) = coords[self.reference[0]], coords[self.reference[1]]
            x, y = prim.relative_point_xy(ox, oy, x1, y1, x2, y2, distance, angle,
                                          values.get("frame_length"))
        return Candidates((x,), (y,))


@dataclass(frozen=True)
class Local(Node):
    """The point at coordinates ``(u, v)`` in the frame of ``origin`` and ``toward``.

    The frame's x axis points from ``origin`` towards ``toward``, its y axis
    a quarter turn counter-clockwise from it: a coupler or leg point is given
    once by its coordinates on the link, ``at = [u, v]``. No root where the
    two points coincide (degenerate input).

    Examples
    --------
    >>> from geokin.expressions import as_expr
    >>> node = Local("P", "A", "B", as_expr(12), as_expr(5))
    >>> node.describe()
    'local(A->B, 12, 5)'
    >>> cand = node.candidates({"A": (1.0, 1.0), "B": (1.0, 9.0)}, {"u": 12.0, "v": 5.0})
    >>> float(cand.x[0]), float(cand.y[0])
    (-4.0, 13.0)
    """

    origin: str
    toward: str
    u: Expr
    v: Expr
    kind: ClassVar[str] = "local"
    keys: ClassVar[tuple[Key, ...]] = (Key("origin", "point"), Key("toward", "point"),
                                       Key("at", "value pair", ("u", "v")))

    @property
    def missing_where_coincide(self) -> tuple[str, str] | None:
        return (self.origin, self.toward)

    def describe(self) -> str:
        return f"local({self.origin}->{self.toward}, {self.u}, {self.v})"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        (ox, oy), (tx, ty) = coords[self.origin], coords[self.toward]
        x, y = prim.local_point_xy(ox, oy, tx, ty, values["u"], values["v"],
                                   values.get("frame_length"))
        return Candidates((x,), (y,))


@dataclass(frozen=True)
class Along(Node):
    """The point at a signed ``distance`` from ``line[0]`` towards ``line[1]``."""

    line: tuple[str, str]
    distance: Expr
    kind: ClassVar[str] = "along"
    keys: ClassVar[tuple[Key, ...]] = (Key("line", "point pair"), Key("distance", "value"))

    @property
    def missing_where_coincide(self) -> tuple[str, str] | None:
        return self.line

    def describe(self) -> str:
        return f"along({self.line[0]}->{self.line[1]}, {self.distance})"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        (x1, y1), (x2, y2) = coords[self.line[0]], coords[self.line[1]]
        x, y = prim.relative_point_xy(x1, y1, x1, y1, x2, y2, values["distance"], 0.0,
                                      values.get("frame_length"))
        return Candidates((x,), (y,))


@dataclass(frozen=True)
class LineLine(Node):
    """The intersection of the lines ``first[0]-first[1]`` and ``second[0]-second[1]``."""

    first: tuple[str, str]
    second: tuple[str, str]
    kind: ClassVar[str] = "line_line"
    keys: ClassVar[tuple[Key, ...]] = (Key("first", "point pair"), Key("second", "point pair"))

    def describe(self) -> str:
        return f"line_line({self.first[0]}-{self.first[1]}; {self.second[0]}-{self.second[1]})"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        args = [c for name in (*self.first, *self.second) for c in coords[name]]
        x, y, _, _, _ = prim.line_line_xy(*args)
        return Candidates((x,), (y,))


_CHOICE = (Key("branch", "branch", required=False), Key("near", "sketch", required=False))


@dataclass(frozen=True)
class _TwoRoot(Node):
    """A node with two candidate roots, chosen by ``branch`` or ``near``."""

    branch: str | None = None
    near: tuple[float, float] | None = None

    def choice(self) -> str | None:
        """Return how the initial branch is chosen, as text (None if neither is given)."""
        if self.near is not None:
            return f"near ({self.near[0]:g}, {self.near[1]:g})"
        return self.branch

    def initial_root(self, cand: Candidates, n: int, paths: int = 1) -> int | np.ndarray:
        """Return the root this node starts on.

        That is its declared branch, or the root nearer its sketch position
        ``near`` at the first sample where one can be assembled. The N
        samples may be ``paths`` paths of N / paths samples one after the
        other (variants of a design): the root is then chosen on each, and
        returned per path where it depends on the roots' positions.
        """
        if self.near is None:
            return self.branch_names.index(self.branch or self.branch_names[0])
        x0, x1, y0, y1 = (np.broadcast_to(a, (n,)).reshape(paths, -1)
                          for a in (*cand.x, *cand.y))
        usable = [np.isfinite(x0) & np.isfinite(y0), np.isfinite(x1) & np.isfinite(y1)]
        if cand.on_line is not None:  # a root off its ray or segment cannot be assembled
            usable = [u & np.broadcast_to(on, (n,)).reshape(paths, -1)
                      for u, on in zip(usable, cand.on_line, strict=True)]
        exists = usable[0] | usable[1]
        rows = np.arange(paths)
        i = np.argmax(exists, axis=1)  # the first sample of each path where a root exists
        near_x, near_y = self.near
        with np.errstate(invalid="ignore"):
            distance = [np.where(usable[k][rows, i], np.hypot(x[rows, i] - near_x,
                                                              y[rows, i] - near_y), np.inf)
                        for k, (x, y) in enumerate(((x0, y0), (x1, y1)))]
        root = (distance[1] < distance[0]) & exists[rows, i]
        return int(root[0]) if paths == 1 else root.astype(np.int8)

    @property
    def chosen_by_position(self) -> bool:
        """Whether the initial root depends on where the roots are (``near``)."""
        return self.near is not None


@dataclass(frozen=True)
class CircleCircle(_TwoRoot):
    """An intersection of two circles: centres ``centers``, radii ``radii``.

    Branch ``left`` is left of the directed line from the first centre to the
    second, ``right`` right of it.
    """

    # after the optional branch and near: given by keyword
    centers: tuple[str, str] = field(kw_only=True)
    radii: tuple[Expr, Expr] = field(kw_only=True)
    kind: ClassVar[str] = "circle_circle"
    keys: ClassVar[tuple[Key, ...]] = (Key("centers", "point pair"),
                                       Key("radii", "value pair", nonnegative=True), *_CHOICE)
    branch_names: ClassVar[tuple[str, ...]] = ("left", "right")

    @property
    def equidistant_from(self) -> tuple[str, ...]:
        return self.centers

    def radius_about(self, center: str) -> Expr | None:
        return next((r for c, r in zip(self.centers, self.radii, strict=True) if c == center),
                    None)

    def describe(self) -> str:
        (a, b), (ra, rb) = self.centers, self.radii
        return f"circle_circle({a}, {ra}; {b}, {rb})  [{self.choice()}]"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        (x1, y1), (x2, y2) = coords[self.centers[0]], coords[self.centers[1]]
        r1, r2 = values["radii[0]"], values["radii[1]"]
        xl, yl, xr, yr, margin = prim.circle_circle_xy(x1, y1, r1, x2, y2, r2)
        return Candidates((xl, xr), (yl, yr), margin)

    def scale(self, coords: Coords, values: Values) -> np.ndarray:
        (x1, y1), (x2, y2) = coords[self.centers[0]], coords[self.centers[1]]
        return prim.circle_circle_scale(x1, y1, values["radii[0]"], x2, y2, values["radii[1]"])


@dataclass(frozen=True)
class _LineCircle(_TwoRoot):
    """An intersection of the line ``line[0] -> line[1]`` with a circle.

    Branch ``first`` comes first along the line's direction, ``second`` after it.
    """

    # after the optional branch and near: given by keyword
    line: tuple[str, str] = field(kw_only=True)
    center: str = field(kw_only=True)
    radius: Expr = field(kw_only=True)
    keys: ClassVar[tuple[Key, ...]] = (Key("line", "point pair"), Key("center", "point"),
                                       Key("radius", "value", nonnegative=True), *_CHOICE)
    branch_names: ClassVar[tuple[str, ...]] = ("first", "second")
    joint: ClassVar[str] = "-"
    """How a step list joins the line's two points."""

    @property
    def equidistant_from(self) -> tuple[str, ...]:
        return (self.center,)

    def radius_about(self, center: str) -> Expr | None:
        return self.radius if center == self.center else None

    @property
    def missing_by_branch(self) -> bool:
        return self.low != -np.inf or self.high != np.inf

    def describe(self) -> str:
        return (f"{self.kind}({self.line[0]}{self.joint}{self.line[1]}; {self.center}, "
                f"{self.radius})  [{self.choice()}]")

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        (x1, y1), (x2, y2) = coords[self.line[0]], coords[self.line[1]]
        cx, cy = coords[self.center]
        r = values["radius"]
        xa, ya, xb, yb, ta, tb, margin = prim.line_circle_xy(x1, y1, x2, y2, cx, cy, r)
        on_line = None
        if self.low != -np.inf or self.high != np.inf:
            # off-line roots keep their positions: branch tracking follows them
            low, high = self.low - prim.PARAMETER_RTOL, self.high + prim.PARAMETER_RTOL
            on_line = ((ta >= low) & (ta <= high), (tb >= low) & (tb <= high))
            return Candidates((xa, xb), (ya, yb), margin, on_line, (ta, tb))
        return Candidates((xa, xb), (ya, yb), margin)

    def scale(self, coords: Coords, values: Values) -> np.ndarray:
        (x1, y1), (x2, y2) = coords[self.line[0]], coords[self.line[1]]
        cx, cy = coords[self.center]
        return prim.line_circle_scale(x1, y1, x2, y2, cx, cy, values["radius"])


@dataclass(frozen=True)
class LineCircle(_LineCircle):
    """An intersection of the whole line through ``line`` with a circle."""

    kind: ClassVar[str] = "line_circle"


@dataclass(frozen=True)
class RayCircle(_LineCircle):
    """An intersection of the ray from ``line[0]`` through ``line[1]`` with a circle."""

    kind: ClassVar[str] = "ray_circle"
    joint: ClassVar[str] = "->"
    low: ClassVar[float] = 0.0


@dataclass(frozen=True)
class SegmentCircle(_LineCircle):
    """An intersection of the segment ``line[0]..line[1]`` with a circle."""

    kind: ClassVar[str] = "segment_circle"
    joint: ClassVar[str] = ".."
    low: ClassVar[float] = 0.0
    high: ClassVar[float] = 1.0


@dataclass(frozen=True)
class Closure(Node):
    """A point of a closure group: unknown points found together by Newton's method.

    The group's ``points`` (k of them) are tied to each other and to known
    points by ``distances`` (``(P, Q, length)``) and ``lines`` (``(P, Q,
    R)``: P on the line through Q and R), 2k equations in all. Every point
    of the group is a node of this kind holding the whole group; the first
    solves it (see :mod:`geokin.closure`) and hands the others their
    positions. The assembly is the one nearest the sketch positions
    ``near`` (one per point, in the order of ``points``) at the first
    sample where Newton converges from them, followed along the samples by
    continuation. Samples where the group's Jacobian is singular cannot be
    assembled ("the group reaches a singular position"): the limits of the
    motion, as a toggle is for two circles.

    Examples
    --------
    >>> from geokin.expressions import as_expr
    >>> node = Closure("B", group="g", points=("B",), near=((3.0, 3.0),),
    ...                distances=(("A", "B", as_expr(5)), ("C", "B", as_expr(5))))
    >>> node.depends_on(), node.describe()
    (('A', 'C'), 'closure g(B): |A-B| = 5, |C-B| = 5  [near B (3, 3)]')
    >>> cand = node.candidates({"A": (0.0, 0.0), "C": (6.0, 0.0)},
    ...                        {"distances[0]": 5.0, "distances[1]": 5.0})
    >>> cand.x[0].round(12).tolist(), cand.y[0].round(12).tolist()
    ([3.0], [4.0])
    """

    group: str = field(kw_only=True)
    points: tuple[str, ...] = field(kw_only=True)
    near: tuple[tuple[float, float], ...] = field(kw_only=True)
    distances: tuple[tuple[str, str, Expr], ...] = field(kw_only=True)
    lines: tuple[tuple[str, str, str], ...] = field(kw_only=True, default=())
    kind: ClassVar[str] = "closure"

    @property
    def solves(self) -> bool:
        """Whether this point solves the group (its first point)."""
        return self.name == self.points[0]

    @property
    def continued(self) -> bool:
        return self.solves

    @property
    def defines(self) -> tuple[str, ...]:
        return self.points if self.solves else (self.name,)

    def point_fields(self) -> dict[str, tuple[str, ...]]:
        fields = {"points": self.points}
        fields.update({f"distances[{i}]": (p, q) for i, (p, q, _) in enumerate(self.distances)})
        fields.update({f"lines[{i}]": line for i, line in enumerate(self.lines)})
        return fields

    def known_points(self) -> tuple[str, ...]:
        """Return the points the group is built on: those of its equations not in it."""
        seen: dict[str, None] = {}
        for p, q, _ in self.distances:
            seen.update(dict.fromkeys(x for x in (p, q) if x not in self.points))
        for line in self.lines:
            seen.update(dict.fromkeys(x for x in line if x not in self.points))
        return tuple(seen)

    def depends_on(self) -> tuple[str, ...]:
        """Return the group's known points; after the first point, that point too."""
        first = () if self.solves else (self.points[0],)
        return (*self.known_points(), *first)

    def value_fields(self) -> dict[str, Expr]:
        return {f"distances[{i}]": d for i, (_, _, d) in enumerate(self.distances)}

    def nonnegative_fields(self) -> frozenset[str]:
        return frozenset(self.value_fields())

    def equations(self) -> str:
        """Return the group's equations as text: ``|F-D| = FD, ..., D on E-B``."""
        terms = [f"|{p}-{q}| = {d}" for p, q, d in self.distances]
        terms += [f"{p} on {q}-{r}" for p, q, r in self.lines]
        return ", ".join(terms)

    def choice(self) -> str | None:
        return "near " + ", ".join(f"{p} ({x:g}, {y:g})"
                                   for p, (x, y) in zip(self.points, self.near, strict=True))

    def describe(self) -> str:
        if not self.solves:
            return f"closure {self.group}: found with {self.points[0]}"
        return (f"closure {self.group}({', '.join(self.points)}): {self.equations()}  "
                f"[{self.choice()}]")

    def system(self) -> solver.System:
        """Return the group's equations for the solver."""
        return solver.System(len(self.points), tuple((p, q) for p, q, _ in self.distances),
                             self.lines)

    def _between(self, between: Callable) -> Callable:
        """Return ``between`` giving the known points and the table of lengths."""
        def at(a: int, b: int, t: np.ndarray):
            coords, values = between(a, b, t)
            known = {p: coords[p] for p in self.known_points()}
            table = np.column_stack([
                np.broadcast_to(np.asarray(values[f"distances[{i}]"], dtype=float), t.shape)
                for i in range(len(self.distances))])
            return known, table

        return at

    def candidates(self, coords: Coords, values: Values, guess: np.ndarray | None = None,
                   origin: tuple[float, float] | None = None,
                   sketch: np.ndarray | None = None, paths: int = 1,
                   between: Callable | None = None,
                   positions: np.ndarray | None = None) -> Candidates:
        """Return the point's position; the first point solves the whole group.

        Without ``guess`` the group is followed along the samples from its
        sketch ``near`` (or from ``sketch``: absolute positions, x and y of
        every point of the group, as a circuit passes them), the samples
        being ``paths`` paths of equal length one after the other, and
        ``between(a, b, t)`` giving its known points and lengths between
        samples and ``positions`` the samples' places in the space of the
        inputs (:func:`geokin.closure.continue_along`); with ``guess``
        (N, 2k) each sample is solved from its own.
        """
        if not self.solves:
            x, y = coords[self.name]
            return Candidates((x,), (y,))
        known = {p: coords[p] for p in self.known_points()}
        lengths = [values[f"distances[{i}]"] for i in range(len(self.distances))]
        sizes = [np.size(a) for a in (*lengths, *(c for xy in known.values() for c in xy))]
        if guess is not None:
            sizes.append(len(guess))
        n = max(sizes, default=1)
        table = np.column_stack([np.broadcast_to(np.asarray(v, dtype=float), (n,))
                                 for v in lengths])
        system = self.system()
        with np.errstate(all="ignore"):
            if guess is None:
                sketch = np.asarray(self.near if sketch is None else sketch, dtype=float).ravel()
                if origin is not None:
                    sketch = sketch - np.tile(origin, len(self.points))
                z, margin, singular = solver.continue_along(
                    system, self.points, known, table, sketch,
                    np.arange(0, n, max(n // paths, 1)) if paths > 1 else None,
                    None if between is None else self._between(between),
                    positions=positions)
            else:
                guess = np.asarray(guess, dtype=float)
                z, _, margin = solver.newton(system, self.points, known, table, guess)
                singular = np.zeros(n, dtype=bool)
                # a guess beside a fold that the sample lies beyond: a singular position
                failed = np.flatnonzero(~np.isfinite(z).all(axis=1)
                                        & np.isfinite(guess).all(axis=1))
                if failed.size:
                    picked = {p: tuple(c[failed] if np.ndim(c) else c for c in xy)
                              for p, xy in known.items()}
                    singular[failed] = solver.stalls_singular(system, self.points, picked,
                                                              table[failed], guess[failed])
        solved = np.isfinite(z).all(axis=1)
        reason = np.where(singular, SINGULAR, NOT_CONVERGED).astype(np.int8)
        reason[solved] = 0
        also = {p: (z[:, 2 * i], z[:, 2 * i + 1]) for i, p in enumerate(self.points)}
        x, y = also.pop(self.name)
        return Candidates((x,), (y,), margin, also=also, reason=reason)


NODE_KINDS: Mapping[str, type[Node]] = MappingProxyType({
    cls.kind: cls
    for cls in (Fixed, Polar, Local, Along, LineLine, LineCircle, SegmentCircle, RayCircle,
                CircleCircle)
})
"""Every point node kind a script's ``[points]`` table takes, by its ``op`` (read-only).

A :class:`Closure` point is declared with its group, in a script's
``[groups]`` table or with :meth:`~geokin.construction.Construction.closure`."""

BRANCHES: Mapping[str, tuple[str, ...]] = MappingProxyType({
    kind: cls.branch_names for kind, cls in NODE_KINDS.items() if cls.branch_names})
"""Branch names of each two-root node kind, in the primitives' root order."""
