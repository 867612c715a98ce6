"""Constructions: parameters, inputs and points built on earlier points.

A :class:`Construction` is declared step by step, the way a mechanism is
drawn with ruler and compass: fixed pivots, a driven input, and every other
point found from points already known. Declaring checks each node on its
own (names, arity, branch); :meth:`Construction.compile` checks the whole
graph (unknown names, cycles) and orders it into :class:`Step` objects.

Every angle inside geokin is radians: input ranges, steps and speeds, input
values and angle fields. A script's degrees are converted when it is read
(:func:`geokin.io.load`) and back when one is written.

Examples
--------
A four-bar with a coupler point, ground pivots 40 apart:

>>> c = Construction("four-bar")
>>> c.parameter("crank", 10)
>>> c.input("theta", kind="angle", range=(0, 2 * np.pi))
>>> c.fixed("O2", 0, 0)
>>> c.fixed("O4", 40, 0)
>>> c.polar("A", "O2", "crank", "theta")
>>> c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
>>> c.polar("P", "A", 20, "radians(30)", reference=("A", "B"))
>>> print(c.compile())
construction 'four-bar': 5 steps
  1  O2 = fixed(0, 0)
  2  O4 = fixed(40, 0)
  3  A  = polar(O2, crank, theta)
  4  B  = circle_circle(A, 35; O4, 30)  [left]
  5  P  = polar(A, 20, radians(30) from A->B)
"""

from __future__ import annotations

import dataclasses
import heapq
import keyword
import math
import unicodedata
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import ClassVar, TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from . import primitives as prim
from .errors import ConstructionError, did_you_mean, quote, show
from .expressions import (
    CONSTANTS,
    FUNCTIONS,
    Expr,
    Number,
    ValueLike,
    as_expr,
    look_alike,
    normal_name,
    skeleton,
)

__all__ = [
    "BRANCHES",
    "Candidates",
    "CircleCircle",
    "Compiled",
    "Construction",
    "Fixed",
    "Input",
    "LineCircle",
    "LineLine",
    "Link",
    "Node",
    "Parameter",
    "Polar",
    "RayCircle",
    "SegmentCircle",
    "Slider",
    "Step",
    "Along",
]

BRANCHES = {
    "circle_circle": ("left", "right"),
    "line_circle": ("first", "second"),
    "segment_circle": ("first", "second"),
    "ray_circle": ("first", "second"),
}
"""Branch names of each two-root node kind, in the primitives' root order."""

INPUT_KINDS = ("angle", "length")

# Why a sample could not be assembled at a node; codes stored per sample.
REASONS = (
    "",
    "no intersection: the curves do not meet",
    "degenerate input: coincident centres, zero-length line or parallel lines",
    "the chosen root lies off the ray or segment",
    "a value is not finite, or a radius is negative",
)
NO_INTERSECTION, DEGENERATE, OFF_LINE, NOT_FINITE = 1, 2, 3, 4


@dataclass(frozen=True)
class Parameter:
    """A named constant of a construction (a link length, an offset)."""

    name: str
    value: float
    description: str = ""


@dataclass(frozen=True)
class Input:
    """A driving variable: an angle (radians) or a length.

    Attributes
    ----------
    name : str
    kind : {"angle", "length"}
    range : (float, float)
        Default range of a sweep, radians for an angle.
    samples : int
        Default number of samples over the range, both ends included.
    step : float or None
        Instead of ``samples``: the spacing of samples from the start of the
        range, the last one not beyond its end (like MATLAB's ``0:16:1800``).
    speed : float
        Constant rate of the input in radians (or length units) per second,
        for time-based output.
    """

    name: str
    kind: str = "angle"
    range: tuple[float, float] = (0.0, 2 * np.pi)
    samples: int = 361
    speed: float = 2 * np.pi
    step: float | None = None

    def values(self, samples: int | None = None) -> np.ndarray:
        """Return the default sweep of this input.

        Examples
        --------
        >>> Input("theta", range=(0.0, 1.0), samples=3).values()
        array([0. , 0.5, 1. ])
        >>> Input("s", kind="length", range=(0.0, 1.0), step=0.4).values()
        array([0. , 0.4, 0.8])
        """
        lo, hi = self.range
        if samples is not None:
            _check_samples(samples, node=self.name, field="samples")
        if samples is None and self.step is not None:
            count = int(np.floor((hi - lo) / self.step * (1 + 1e-12) + 1e-9)) + 1
            return lo + self.step * np.arange(count)
        return np.linspace(lo, hi, samples or self.samples)


@dataclass(frozen=True)
class Link:
    """A rigid link joining two or more points, for drawing and analysis."""

    name: str
    points: tuple[str, ...]


@dataclass(frozen=True)
class Slider:
    """A slider block at ``point`` sliding along the line ``along[0] -> along[1]``."""

    name: str
    point: str
    along: tuple[str, str]


Coords: TypeAlias = Mapping[str, tuple[np.ndarray, np.ndarray]]
"""The x and y arrays of the points already found, by name."""
Values: TypeAlias = Mapping[str, np.ndarray | float]
"""A node's evaluated value fields, angles in radians."""


@dataclass(frozen=True, slots=True)
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
    """

    x: tuple
    y: tuple
    margin: np.ndarray | None = None
    on_line: tuple | None = None
    t: tuple | None = None


def failure_reasons(cand: Candidates, values: Mapping[str, ArrayLike],
                    root: int | np.ndarray) -> np.ndarray:
    """Say why the chosen roots do not exist, as codes into ``REASONS``.

    Parameters
    ----------
    cand : Candidates
        The node's candidates at the failing samples only.
    values : mapping
        The node's values at those samples.
    root : int or ndarray
        The chosen root at each of those samples.
    """
    shape = np.shape(cand.x[0] if np.ndim(root) == 0 else root)
    finite = np.ones(shape, dtype=bool)
    for field_name, value in values.items():
        finite &= np.isfinite(value)
        if "radius" in field_name or "radii" in field_name:
            with np.errstate(invalid="ignore"):
                finite &= ~(np.asarray(value) < 0)
    reason = np.full(shape, DEGENERATE, dtype=np.int8)
    if cand.margin is not None:
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
    """A point of a construction. Subclasses say how it is found."""

    name: str
    kind: ClassVar[str] = ""
    roots: ClassVar[int] = 1
    low: ClassVar[float] = -np.inf
    """Where along its line a root counts, as the line's parameter: ``low <= t <= high``."""
    high: ClassVar[float] = np.inf

    def branch_names(self) -> tuple[str, ...]:
        """Return the names of the roots, in the primitive's order (none for one root)."""
        return ()

    def point_fields(self) -> dict[str, tuple[str, ...]]:
        """Return the points this node is built on, by field."""
        return {}

    def value_fields(self) -> dict[str, Expr]:
        """Return the values (numbers, names, arithmetic) by field."""
        return {}

    def angle_fields(self) -> frozenset[str]:
        """Return the value fields that are angles."""
        return frozenset()

    def depends_on(self) -> tuple[str, ...]:
        """Return every point this node is built on, in order, without repeats."""
        seen: dict[str, None] = {}
        for names in self.point_fields().values():
            seen.update(dict.fromkeys(names))
        return tuple(seen)

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
    """A fixed point (a ground pivot) at ``(x, y)``."""

    x: Expr
    y: Expr
    kind: ClassVar[str] = "fixed"

    def value_fields(self) -> dict[str, Expr]:
        return {"x": self.x, "y": self.y}

    def describe(self) -> str:
        return f"fixed({self.x}, {self.y})"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        return Candidates((values["x"],), (values["y"],))


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

    def point_fields(self) -> dict[str, tuple[str, ...]]:
        fields: dict[str, tuple[str, ...]] = {"origin": (self.origin,)}
        if self.reference is not None:
            fields["reference"] = self.reference
        return fields

    def value_fields(self) -> dict[str, Expr]:
        return {"distance": self.distance, "angle": self.angle}

    def angle_fields(self) -> frozenset[str]:
        return frozenset({"angle"})

    def describe(self) -> str:
        ref = "" if self.reference is None else f" from {self.reference[0]}->{self.reference[1]}"
        return f"polar({self.origin}, {self.distance}, {self.angle}{ref})"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        ox, oy = coords[self.origin]
        distance, angle = values["distance"], values["angle"]
        if self.reference is None:
            x = ox + distance * np.cos(angle)
            y = oy + distance * np.sin(angle)
        else:
            (x1, y1), (x2, y2) = coords[self.reference[0]], coords[self.reference[1]]
            x, y = prim.relative_point_xy(ox, oy, x1, y1, x2, y2, distance, angle)
        return Candidates((x,), (y,))


@dataclass(frozen=True)
class Along(Node):
    """The point at a signed ``distance`` from ``line[0]`` towards ``line[1]``."""

    line: tuple[str, str]
    distance: Expr
    kind: ClassVar[str] = "along"

    def point_fields(self) -> dict[str, tuple[str, ...]]:
        return {"line": self.line}

    def value_fields(self) -> dict[str, Expr]:
        return {"distance": self.distance}

    def describe(self) -> str:
        return f"along({self.line[0]}->{self.line[1]}, {self.distance})"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        (x1, y1), (x2, y2) = coords[self.line[0]], coords[self.line[1]]
        x, y = prim.relative_point_xy(x1, y1, x1, y1, x2, y2, values["distance"], 0.0)
        return Candidates((x,), (y,))


@dataclass(frozen=True)
class LineLine(Node):
    """The intersection of the lines ``first[0]-first[1]`` and ``second[0]-second[1]``."""

    first: tuple[str, str]
    second: tuple[str, str]
    kind: ClassVar[str] = "line_line"

    def point_fields(self) -> dict[str, tuple[str, ...]]:
        return {"first": self.first, "second": self.second}

    def describe(self) -> str:
        return f"line_line({self.first[0]}-{self.first[1]}; {self.second[0]}-{self.second[1]})"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        args = [c for name in (*self.first, *self.second) for c in coords[name]]
        x, y, _, _, _ = prim.line_line_xy(*args)
        return Candidates((x,), (y,))


@dataclass(frozen=True)
class _TwoRoot(Node):
    """A node with two candidate roots, chosen by ``branch`` or ``near``."""

    branch: str | None = None
    near: tuple[float, float] | None = None
    roots: ClassVar[int] = 2

    def branch_names(self) -> tuple[str, str]:
        """Return the names of the two roots, in the primitive's order."""
        return BRANCHES[self.kind]

    def choice(self) -> str | None:
        """Return how the initial branch is chosen, as text (None if neither is given)."""
        if self.near is not None:
            return f"near ({self.near[0]:g}, {self.near[1]:g})"
        return self.branch


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

    def point_fields(self) -> dict[str, tuple[str, ...]]:
        return {"centers": self.centers}

    def value_fields(self) -> dict[str, Expr]:
        return {"radii[0]": self.radii[0], "radii[1]": self.radii[1]}

    def describe(self) -> str:
        (a, b), (ra, rb) = self.centers, self.radii
        return f"circle_circle({a}, {ra}; {b}, {rb})  [{self.choice()}]"

    def candidates(self, coords: Coords, values: Values) -> Candidates:
        (x1, y1), (x2, y2) = coords[self.centers[0]], coords[self.centers[1]]
        r1, r2 = values["radii[0]"], values["radii[1]"]
        xl, yl, xr, yr, margin = prim.circle_circle_xy(x1, y1, r1, x2, y2, r2)
        return Candidates((xl, xr), (yl, yr), margin)


@dataclass(frozen=True)
class _LineCircle(_TwoRoot):
    """An intersection of the line ``line[0] -> line[1]`` with a circle.

    Branch ``first`` comes first along the line's direction, ``second`` after it.
    """

    # after the optional branch and near: given by keyword
    line: tuple[str, str] = field(kw_only=True)
    center: str = field(kw_only=True)
    radius: Expr = field(kw_only=True)

    def point_fields(self) -> dict[str, tuple[str, ...]]:
        return {"line": self.line, "center": (self.center,)}

    def value_fields(self) -> dict[str, Expr]:
        return {"radius": self.radius}

    def describe(self) -> str:
        joint = {"line_circle": "-", "segment_circle": "..", "ray_circle": "->"}[self.kind]
        return (f"{self.kind}({self.line[0]}{joint}{self.line[1]}; {self.center}, {self.radius})"
                f"  [{self.choice()}]")

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


@dataclass(frozen=True)
class LineCircle(_LineCircle):
    """An intersection of the whole line through ``line`` with a circle."""

    kind: ClassVar[str] = "line_circle"


@dataclass(frozen=True)
class RayCircle(_LineCircle):
    """An intersection of the ray from ``line[0]`` through ``line[1]`` with a circle."""

    kind: ClassVar[str] = "ray_circle"
    low: ClassVar[float] = 0.0


@dataclass(frozen=True)
class SegmentCircle(_LineCircle):
    """An intersection of the segment ``line[0]..line[1]`` with a circle."""

    kind: ClassVar[str] = "segment_circle"
    low: ClassVar[float] = 0.0
    high: ClassVar[float] = 1.0


NODE_KINDS: dict[str, type[Node]] = {
    cls.kind: cls
    for cls in (Fixed, Polar, Along, LineLine, LineCircle, SegmentCircle, RayCircle, CircleCircle)
}
"""Every point node kind by its name in scripts."""


@dataclass(frozen=True)
class Step:
    """One step of a compiled construction: a node and its place in the order."""

    index: int
    node: Node

    def __repr__(self) -> str:
        return f"<Step {self.index}: {self.node.name} = {self.node.describe()}>"


@dataclass(frozen=True)
class Compiled:
    """A validated construction in evaluation order.

    Attributes
    ----------
    name : str
    steps : tuple of Step
        Every point node, each after the points it is built on.
    parameters : dict of str to float
    inputs : dict of str to Input
    """

    name: str
    steps: tuple[Step, ...]
    parameters: Mapping[str, float]
    inputs: Mapping[str, Input]
    links: tuple[Link, ...] = ()
    sliders: tuple[Slider, ...] = ()
    _values: Mapping[str, Mapping[str, Expr]] = field(default_factory=dict, repr=False)
    traced: tuple[str, ...] = ()
    cache: dict = field(default_factory=dict, repr=False, compare=False)
    """Whatever later layers derive once from this construction (evaluation plans)."""

    def __len__(self) -> int:
        return len(self.steps)

    def __iter__(self) -> Iterator[Step]:
        return iter(self.steps)

    @property
    def point_names(self) -> tuple[str, ...]:
        """Return the point names in evaluation order."""
        return tuple(step.node.name for step in self.steps)

    def as_list(self) -> list[tuple]:
        """Return the steps as plain tuples ``(name, kind, points..., branch)``.

        Examples
        --------
        >>> c = Construction()
        >>> c.fixed("O", 0, 0)
        >>> c.input("t")
        >>> c.polar("A", "O", 1, "t")
        >>> c.compile().as_list()
        [('O', 'fixed'), ('A', 'polar', 'O')]
        """
        rows = []
        for step in self.steps:
            node = step.node
            row: tuple[str | None, ...] = (node.name, node.kind, *node.depends_on())
            if isinstance(node, _TwoRoot):
                row += (node.choice(),)
            rows.append(row)
        return rows

    def __str__(self) -> str:
        width = max((len(s.node.name) for s in self.steps), default=0)
        lines = [f"construction {self.name!r}: {len(self.steps)} steps"]
        for step in self.steps:
            lines.append(f"  {step.index:>{len(str(len(self.steps)))}}  "
                         f"{step.node.name:<{width}} = {step.node.describe()}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"<Compiled {self.name!r}: {len(self.steps)} steps>"


class Construction:
    """A planar linkage declared as a geometric construction.

    Declare parameters, inputs and points in any order that refers only to
    declared names by the time :meth:`compile` runs. Each declaring method
    checks its own arguments and raises :class:`~geokin.errors.ConstructionError`
    naming the node and field.

    Parameters
    ----------
    name : str
        A name for messages and pictures.
    description, units : str
        Free text, and the label of the length unit.

    Every angle is radians, whether the construction is built in Python or
    loaded from a script (whose degrees are converted as it is read).
    """

    def __init__(self, name: str = "construction", *, description: str = "",
                 units: str = ""):
        self.name = name
        self.description = description
        self.units = units
        self.parameters: dict[str, Parameter] = {}
        self.inputs: dict[str, Input] = {}
        self.nodes: dict[str, Node] = {}
        self.links: dict[str, Link] = {}
        self.sliders: dict[str, Slider] = {}
        self.traced: tuple[str, ...] = ()
        self._compiled: Compiled | None = None
        # names that are not plain ASCII, by their skeleton (see expressions.skeleton)
        self._skeletons: dict[str, str] = {}

    def __repr__(self) -> str:
        return (f"<Construction {self.name!r}: {len(self.parameters)} parameters, "
                f"{len(self.inputs)} inputs, {len(self.nodes)} points>")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Construction):
            return NotImplemented
        mine = (self.name, self.parameters, self.inputs, self.nodes, self.links,
                self.sliders, self.traced)
        theirs = (other.name, other.parameters, other.inputs, other.nodes, other.links,
                  other.sliders, other.traced)
        return mine == theirs

    # unhashable, as it is mutable; typeshed types object.__hash__ as a method only
    __hash__: ClassVar[None] = None  # type: ignore[assignment]

    # -- names -------------------------------------------------------------

    def _all_names(self) -> dict[str, str]:
        names = {}
        for kind, table in self._tables():
            names.update(dict.fromkeys(table, kind))
        return names

    def _tables(self):
        return (("parameter", self.parameters), ("input", self.inputs), ("point", self.nodes),
                ("link", self.links), ("slider", self.sliders))

    def _kind_of(self, name: str) -> str | None:
        """Return what ``name`` is declared as ("parameter", "point", ...), or None."""
        for kind, table in self._tables():
            if name in table:
                return kind
        return None

    def _claim(self, name, what: str) -> str:
        """Check a new name and return it in normal form (NFKC): the name to declare.

        The checks take a constant time per name, so declaring n names is linear.
        """
        given = name
        name = normal_name(name, what=f"{what} name", node=show(name) if not isinstance(
            name, str) else name, field="name")
        if not name.isidentifier():
            raise ConstructionError(
                f"{'an' if what[0] in 'aeiou' else 'a'} {what} name must be an identifier "
                f"(letters, digits, _), got {quote(given)}",
                node=given, field="name")
        if keyword.iskeyword(name):
            raise ConstructionError(f"{quote(name)} is a reserved word of expressions; choose "
                                    "another name", node=name, field="name")
        if name in CONSTANTS or name in FUNCTIONS:
            raise ConstructionError(f"{quote(name)} is reserved for the built-in "
                                    f"{'constant' if name in CONSTANTS else 'function'}",
                                    node=name, field="name")
        folded = f" ({quote(given)} reads as {quote(name)})" if given != name else ""
        existing = self._kind_of(name)
        if existing is not None:
            article = "an" if existing[0] in "aeiou" else "a"
            raise ConstructionError(f"duplicate name{folded}: {article} {existing} {quote(name)} "
                                    "is already declared", node=name, field="name")
        key = skeleton(name)
        other = self._skeletons.get(key)
        if other is None or other == name or self._kind_of(other) is None:
            other = key if key != name and self._kind_of(key) is not None else None
        if other is not None:
            raise ConstructionError(
                f"{quote(name)} looks like the {self._kind_of(other)} {quote(other)} but is "
                f"another name: {_differences(name, other)}; use one spelling",
                node=name, field="name")
        if key != name:
            self._skeletons[key] = name
        self._compiled = None
        return name

    # -- declarations ------------------------------------------------------

    def parameter(self, name: str, value: float, description: str = "") -> None:
        """Declare a named constant, usable in any value by its name.

        Parameters
        ----------
        name : str
            An identifier, unique in the construction.
        value : float or str
            A finite number, or arithmetic of numbers (``"sqrt(2) * 10"``).
        description : str
            Free text shown with the parameter.

        Examples
        --------
        >>> c = Construction()
        >>> c.parameter("l3", 100, "coupler")
        >>> c.parameters["l3"].value
        100.0
        """
        name = self._claim(name, "parameter")
        number = as_expr(value, node=name, field="value")
        if number.names():
            raise ConstructionError("a parameter's value must be a number", node=name,
                                    field="value")
        with np.errstate(all="ignore"):
            value = float(number.evaluate({}))
        if not np.isfinite(value):
            raise ConstructionError(f"a parameter's value must be a finite number; "
                                    f"{quote(str(number), 60)} is {value}", node=name,
                                    field="value")
        self.parameters[name] = Parameter(name, value, description)

    def input(self, name: str, kind: str = "angle", range: Sequence[float] | None = None,
              samples: int = 361, speed: float | None = None,
              step: float | None = None) -> None:
        """Declare a driving variable.

        Parameters
        ----------
        name : str
        kind : {"angle", "length"}
        range : (float, float), optional
            Default sweep range; radians for an angle. Defaults to one turn
            for an angle; required for a length.
        samples : int
            Default number of samples, both ends of the range included.
        step : float, optional
            Instead of ``samples``: the spacing of the samples from the start
            of the range (radians for an angle).
        speed : float, optional
            Rate in radians (or lengths) per second; one turn per second by default.
        """
        name = self._claim(name, "input")
        if kind not in INPUT_KINDS:
            raise ConstructionError(f"unknown input kind {show(kind)}; use one of "
                                    f"{', '.join(INPUT_KINDS)}{did_you_mean(kind, INPUT_KINDS)}",
                                    node=name, field="kind")
        if range is None:
            if kind == "length":
                raise ConstructionError("a length input needs a range", node=name,
                                        field="range")
            range = (0.0, 2 * np.pi)
        lo_hi = _pair_of_numbers(range, node=name, field="range")
        if lo_hi[0] == lo_hi[1]:
            raise ConstructionError("the range's two ends are equal: nothing to sweep",
                                    node=name, field="range")
        width = lo_hi[1] - lo_hi[0]
        if not np.isfinite(width):
            raise ConstructionError(f"the range from {lo_hi[0]:g} to {lo_hi[1]:g} is wider "
                                    "than floating-point numbers reach", node=name, field="range")
        if kind == "length":
            for end in lo_hi:
                _check_length(end, node=name, field="range")
        _check_samples(samples, node=name, field="samples")
        if step is not None:
            step = _number(step, node=name, field="step")
            if step == 0 or (step > 0) != (width > 0):
                raise ConstructionError("step must be a non-zero number that goes from "
                                        "range[0] towards range[1]", node=name, field="step")
            count = abs(width / step) + 1  # inf for a step too small to divide by
            if not count <= MAX_SAMPLES:
                raise ConstructionError(f"a step of {step:g} makes {count:.3g} samples over "
                                        f"the range, more than the {MAX_SAMPLES:,} a default "
                                        "sweep may have", node=name, field="step")
        if speed is None:
            speed = 2 * np.pi if kind == "angle" else 1.0
        speed = _number(speed, node=name, field="speed")
        low, high = prim.SCALE_RANGE
        if not low <= speed <= high:
            raise ConstructionError(
                f"speed must be a positive number from {low:g} to {high:g} (how fast the "
                f"input moves; a sweep's direction sets its sign), got {speed:g}"
                + (f" ({np.degrees(speed):g} degrees per second)" if kind == "angle" else ""),
                node=name, field="speed")
        self.inputs[name] = Input(name, kind, lo_hi, int(samples), speed, step)

    def fixed(self, name: str, x: ValueLike, y: ValueLike) -> None:
        """Declare a fixed point (a ground pivot).

        Parameters
        ----------
        name : str
        x, y : value
            Numbers, names or arithmetic. A coordinate that uses an input
            makes a point driven along a line (a slider moved directly).

        Examples
        --------
        >>> c = Construction()
        >>> c.parameter("y", 20)
        >>> c.fixed("A0", 0, "y + 10")
        >>> c.compile().steps[0]
        <Step 1: A0 = fixed(0, y + 10)>
        """
        self._add(Fixed(name, self._value(x, name, "x"), self._value(y, name, "y")))

    def polar(self, name: str, origin: str, distance: ValueLike, angle: ValueLike,
              reference: Sequence[str] | None = None) -> None:
        """Declare the point at ``distance`` and ``angle`` from ``origin``.

        Parameters
        ----------
        name, origin : str
        distance : value
        angle : value
            Counter-clockwise, in the construction's angle unit (radians in
            Python): from the x axis, or with ``reference`` from the
            direction of the line ``reference[0] -> reference[1]``.
        reference : (str, str), optional

        Examples
        --------
        A crank pin, and a coupler point 20 from it at 30 degrees off the
        coupler line:

        >>> c = Construction()
        >>> c.input("theta")
        >>> c.fixed("O", 0, 0)
        >>> c.fixed("Q", 40, 0)
        >>> c.polar("A", "O", 10, "theta")
        >>> c.polar("P", "A", 20, "radians(30)", reference=("A", "Q"))
        """
        ref = None if reference is None else self._point_pair(reference, name, "reference")
        self._add(Polar(name, self._point(origin, name, "origin"),
                        self._value(distance, name, "distance"),
                        self._value(angle, name, "angle"), ref))

    def along(self, name: str, line: Sequence[str], distance: ValueLike) -> None:
        """Declare the point at a signed ``distance`` from ``line[0]`` towards ``line[1]``.

        Examples
        --------
        >>> c = Construction()
        >>> c.fixed("A", 0, 0)
        >>> c.fixed("B", 3, 4)
        >>> c.along("M", ("A", "B"), 2.5)
        >>> print(c.compile().steps[-1].node.describe())
        along(A->B, 2.5)
        """
        self._add(Along(name, self._point_pair(line, name, "line"),
                        self._value(distance, name, "distance")))

    def line_line(self, name: str, first: Sequence[str], second: Sequence[str]) -> None:
        """Declare the intersection of two lines, each through two points.

        Samples where the lines are parallel cannot be assembled.

        Examples
        --------
        >>> c = Construction()
        >>> for name, x, y in [("P", 0, 0), ("Q", 2, 2), ("R", 0, 2), ("S", 2, 0)]:
        ...     c.fixed(name, x, y)
        >>> c.line_line("X", ("P", "Q"), ("R", "S"))
        """
        self._add(LineLine(name, self._point_pair(first, name, "first"),
                           self._point_pair(second, name, "second")))

    def circle_circle(self, name: str, centers: Sequence[str], radii: Sequence[ValueLike],
                      branch: str | None = None, near: Sequence[float] | None = None) -> None:
        """Declare an intersection of two circles.

        Parameters
        ----------
        centers : (str, str)
            The two centres.
        radii : (value, value)
            Their radii.
        branch : {"left", "right"}, optional
            The root left or right of the directed line ``centers[0] -> centers[1]``.
        near : (float, float), optional
            Instead of ``branch``: a sketch position; the root nearer to it at
            the first assemblable sample is taken.
        """
        radii = self._value_pair(radii, name, "radii")
        self._add(CircleCircle(name, *self._branch("circle_circle", name, branch, near),
                               centers=self._point_pair(centers, name, "centers"), radii=radii))

    def line_circle(self, name: str, line: Sequence[str], center: str, radius: ValueLike,
                    branch: str | None = None, near: Sequence[float] | None = None) -> None:
        """Declare an intersection of the line through ``line`` with a circle.

        ``branch`` is ``"first"`` or ``"second"`` along ``line[0] -> line[1]``,
        or give ``near`` instead.
        """
        self._line_circle(LineCircle, name, line, center, radius, branch, near)

    def ray_circle(self, name: str, line: Sequence[str], center: str, radius: ValueLike,
                   branch: str | None = None, near: Sequence[float] | None = None) -> None:
        """Declare an intersection of the ray ``line[0]`` through ``line[1]`` with a circle."""
        self._line_circle(RayCircle, name, line, center, radius, branch, near)

    def segment_circle(self, name: str, line: Sequence[str], center: str, radius: ValueLike,
                       branch: str | None = None, near: Sequence[float] | None = None) -> None:
        """Declare an intersection of the segment ``line[0]..line[1]`` with a circle."""
        self._line_circle(SegmentCircle, name, line, center, radius, branch, near)

    def link(self, name: str, *points: str) -> None:
        """Declare a rigid link joining two or more points (for drawing and analysis).

        A link's angle is the direction from its first point to its second;
        a link of fixed points is the ground. Links feed the drawings, the
        link angles and rates, and the degrees-of-freedom count; they do not
        change the motion.

        Examples
        --------
        >>> c = Construction()
        >>> c.fixed("O", 0, 0)
        >>> c.fixed("A", 1, 0)
        >>> c.link("crank", "O", "A")
        """
        name = self._claim(name, "link")
        self.links[name] = Link(name, self._points(points, name, "points", None))

    def slider(self, name: str, point: str, along: Sequence[str]) -> None:
        """Declare a slider block at ``point`` sliding on the line ``along``.

        The block is a link pinned at ``point`` that slides on the link
        holding both points of ``along`` (the ground if both are fixed): one
        more moving link, a revolute joint and a prismatic pair for the
        degrees-of-freedom count, and a block in drawings.
        """
        name = self._claim(name, "slider")
        self.sliders[name] = Slider(name, self._point(point, name, "point"),
                                    self._point_pair(along, name, "along"))

    def trace(self, *points: str) -> None:
        """Name the points whose paths are traced (coupler points) in plots and reports."""
        self.traced = tuple(self._point(p, "trace", f"points[{i}]") for i, p in enumerate(points))
        self._compiled = None

    # -- checks of one declaration -------------------------------------------

    def _add(self, node: Node) -> None:
        name = self._claim(node.name, "point")
        if name != node.name:
            node = dataclasses.replace(node, name=name)
        self.nodes[name] = node

    def _line_circle(self, cls, name, line, center, radius, branch, near):
        self._add(cls(name, *self._branch(cls.kind, name, branch, near),
                      line=self._point_pair(line, name, "line"),
                      center=self._point(center, name, "center"),
                      radius=self._value(radius, name, "radius")))

    @staticmethod
    def _value(value, node, field_name) -> Expr:
        return as_expr(value, node=node, field=field_name)

    def _values(self, values, node, field_name, count) -> tuple[Expr, ...]:
        if isinstance(values, str | bytes) or not isinstance(values, Sequence):
            raise ConstructionError(f"expected {count} values, got {show(values)}", node=node,
                                    field=field_name)
        if len(values) != count:
            raise ConstructionError(f"expected {count} values, got {len(values)}", node=node,
                                    field=field_name)
        return tuple(self._value(v, node, f"{field_name}[{i}]") for i, v in enumerate(values))

    def _value_pair(self, values, node, field_name) -> tuple[Expr, Expr]:
        first, second = self._values(values, node, field_name, 2)
        return first, second

    def _point_pair(self, points, node, field_name) -> tuple[str, str]:
        first, second = self._points(points, node, field_name, 2)
        return first, second

    @staticmethod
    def _point(point, node, field_name) -> str:
        if not isinstance(point, str):
            raise ConstructionError(f"expected a point name, got {show(point)}", node=node,
                                    field=field_name)
        return normal_name(point, what="point name", node=node, field=field_name)

    def _points(self, points, node, field_name, count) -> tuple[str, ...]:
        if isinstance(points, str) or not isinstance(points, Iterable):
            raise ConstructionError(f"expected a list of point names, got {show(points)}",
                                    node=node, field=field_name)
        points = tuple(points)  # the count is checked before the names
        if count is not None and len(points) != count:
            raise ConstructionError(f"expected {count} point names, got {len(points)}",
                                    node=node, field=field_name)
        if count is None and len(points) < 2:
            raise ConstructionError(f"a link joins at least 2 points, got {len(points)}",
                                    node=node, field=field_name)
        return tuple(self._point(p, node, f"{field_name}[{i}]") for i, p in enumerate(points))

    @staticmethod
    def _branch(kind, node, branch, near):
        names = BRANCHES[kind]
        if branch is not None and near is not None:
            raise ConstructionError("give either branch or near, not both", node=node,
                                    field="branch")
        if branch is None and near is None:
            raise ConstructionError(f"a {kind} node has two roots: choose one with branch "
                                    f"({' or '.join(map(repr, names))}) or near=(x, y)",
                                    node=node, field="branch")
        if branch is not None and branch not in names:
            raise ConstructionError(f"unknown branch {show(branch)} for {kind}; use "
                                    f"{' or '.join(map(repr, names))}"
                                    f"{did_you_mean(branch, names)}",
                                    node=node, field="branch")
        if near is not None:
            near = _pair_of_numbers(near, node=node, field="near")
        return branch, near

    # -- the whole graph -----------------------------------------------------

    def compile(self) -> Compiled:
        """Validate the whole construction and order it into steps.

        Raises
        ------
        ConstructionError
            For an unknown point or value name (with the closest existing
            name), a cycle (naming its points), or a link, slider or input
            that refers to nothing.
        """
        if self._compiled is not None:
            return self._compiled
        value_names = {**dict.fromkeys(self.parameters, "parameter"),
                       **dict.fromkeys(self.inputs, "input")}
        for node in self.nodes.values():
            for field_name, points in node.point_fields().items():
                for i, p in enumerate(points):
                    where = f"{field_name}[{i}]" if len(points) > 1 else field_name
                    self._check_point_name(p, node.name, where)
            for field_name, expr in node.value_fields().items():
                for name in sorted(expr.names()):
                    if name not in value_names:
                        hint = _hint(name, value_names)
                        if name in self.nodes:
                            hint = f"; {quote(name)} is a point, not a parameter or input"
                        raise ConstructionError(
                            f"unknown parameter or input {quote(name)}{hint}",
                            node=node.name, field=field_name)
        for link in self.links.values():
            for i, p in enumerate(link.points):
                self._check_point_name(p, link.name, f"points[{i}]")
        for i, p in enumerate(self.traced):
            self._check_point_name(p, "trace", f"points[{i}]")
        for slider in self.sliders.values():
            self._check_point_name(slider.point, slider.name, "point")
            for i, p in enumerate(slider.along):
                self._check_point_name(p, slider.name, f"along[{i}]")
        self._check_constant_values()
        order = self._ordered()
        steps = tuple(Step(i + 1, self.nodes[name]) for i, name in enumerate(order))
        self._compiled = Compiled(
            self.name, steps, {k: p.value for k, p in self.parameters.items()},
            dict(self.inputs), tuple(self.links.values()),
            tuple(self.sliders.values()),
            {n: node.value_fields() for n, node in self.nodes.items()}, self.traced)
        return self._compiled

    def _check_constant_values(self):
        """Refuse values that depend on no input and are not finite (``1 / 0``).

        Also refuse lengths beyond :data:`~geokin.primitives.SCALE_RANGE`,
        and a mechanism whose size (its largest constant length) is below it.
        """
        constants = {k: p.value for k, p in self.parameters.items()}
        size, largest = 0.0, None
        for inp in self.inputs.values():
            if inp.kind == "length" and max(map(abs, inp.range)) > size:
                size, largest = max(map(abs, inp.range)), (inp.name, "range")
        high = prim.SCALE_RANGE[1]
        with np.errstate(all="ignore"):
            for node in self.nodes.values():
                angles = node.angle_fields()
                for field_name, expr in node.value_fields().items():
                    if type(expr) is Number:  # most values: no evaluation, nothing to refuse
                        value = expr.value
                    elif expr.names() & self.inputs.keys():
                        continue
                    else:
                        value = float(expr.evaluate(constants))
                    if not math.isfinite(value):
                        raise ConstructionError(f"{quote(str(expr), 60)} is {value}: a value "
                                                "must be a finite number", node=node.name,
                                                field=field_name)
                    if value < 0 and ("radius" in field_name or "radii" in field_name):
                        raise ConstructionError(f"a radius cannot be negative; "
                                                f"{quote(str(expr), 60)} is {value:g}",
                                                node=node.name, field=field_name)
                    if field_name not in angles and abs(value) > size:
                        if abs(value) > high:
                            _check_length(value, node=node.name, field=field_name)
                        size, largest = abs(value), (node.name, field_name)
        low = prim.SCALE_RANGE[0]
        if 0 < size < low:
            raise ConstructionError(
                f"the mechanism's largest length is {size:g}, smaller than the {low:g} geokin "
                "computes with; express the mechanism in another unit of length",
                node=largest[0], field=largest[1])

    def _check_point_name(self, point, node, field_name):
        if point in self.nodes:
            return
        hint = _hint(point, self.nodes)
        other = self._kind_of(point)
        if other is not None:
            hint = f"; {quote(point)} is a {other}, not a point" + hint
        raise ConstructionError(f"unknown point {quote(point)}{hint}", node=node,
                                field=field_name)

    def _ordered(self) -> list[str]:
        """Topological order, declaration order breaking ties."""
        position = {name: i for i, name in enumerate(self.nodes)}
        waiting = {name: set(node.depends_on()) for name, node in self.nodes.items()}
        for name, deps in waiting.items():
            if name in deps:
                raise ConstructionError("the point is built on itself", node=name,
                                        field=_field_naming(self.nodes[name], name))
        users: dict[str, list[str]] = {name: [] for name in self.nodes}
        for name, deps in waiting.items():
            for d in deps:
                users[d].append(name)
        ready = [(position[n], n) for n, deps in waiting.items() if not deps]
        heapq.heapify(ready)
        order = []
        while ready:
            _, name = heapq.heappop(ready)
            order.append(name)
            for user in users[name]:
                waiting[user].discard(name)
                if not waiting[user]:
                    heapq.heappush(ready, (position[user], user))
        if len(order) < len(self.nodes):
            cycle = _find_cycle({n: d for n, d in waiting.items() if d})
            first = cycle[0]
            raise ConstructionError(
                "cycle: " + " -> ".join([*cycle, first]) + " (each is built on the next)",
                node=first, field=_field_naming(self.nodes[first], cycle[1 % len(cycle)]))
        return order


def _differences(name: str, other: str) -> str:
    """Say where two names of the same skeleton differ: 'В' (Cyrillic) for 'B' (Latin)."""
    for a, b in zip(name, other, strict=False):
        if a != b:
            return (f"{a!r} ({unicodedata.name(a, '?').lower()}) stands for "
                    f"{b!r} ({unicodedata.name(b, '?').lower()})")
    return "they differ in letters that look alike"


def _hint(name: str, candidates) -> str:
    """Return a hint for an unknown name: a look-alike of a declared one, or the closest."""
    other = look_alike(name, candidates)
    if other is not None:
        return (f"; it looks like {quote(other)} but is another name: "
                f"{_differences(name, other)}")
    return did_you_mean(name, candidates)


def _field_naming(node: Node, point: str) -> str:
    for field_name, points in node.point_fields().items():
        if point in points:
            return field_name
    return "name"


def _find_cycle(waiting: Mapping[str, set[str]]) -> list[str]:
    """Return one cycle among nodes that all wait on each other."""
    start = min(waiting)
    path, seen = [start], {start: 0}
    while True:
        nxt = min(d for d in waiting[path[-1]] if d in waiting)
        if nxt in seen:
            return path[seen[nxt]:]
        seen[nxt] = len(path)
        path.append(nxt)


MAX_SAMPLES = 1_000_000
"""The most samples an input's default sweep may have."""


def _number(value, *, node, field) -> float:
    """Return ``value`` as a finite float, or raise naming the node and field."""
    if isinstance(value, bool):
        raise ConstructionError(f"expected a number, got {value!r}", node=node, field=field)
    try:
        number = float(value)
    except OverflowError:
        raise ConstructionError(f"expected a finite number, got {show(value)}: beyond the "
                                "range of floating-point numbers", node=node,
                                field=field) from None
    except (TypeError, ValueError):
        raise ConstructionError(f"expected a number, got {show(value)}", node=node,
                                field=field) from None
    if not np.isfinite(number):
        raise ConstructionError(f"expected a finite number, got {show(value)}", node=node,
                                field=field)
    return number


def _check_samples(samples, *, node, field):
    if isinstance(samples, bool) or not isinstance(samples, int | np.integer) or samples < 2:
        raise ConstructionError(f"samples must be an integer of at least 2, got {show(samples)}",
                                node=node, field=field)
    if samples > MAX_SAMPLES:
        raise ConstructionError(f"a default sweep may have at most {MAX_SAMPLES:,} samples, "
                                f"got {show(samples)}", node=node, field=field)


def _pair_of_numbers(value, *, node, field) -> tuple[float, float]:
    try:
        a, b = value
        pair = (float(a), float(b))
    except OverflowError:
        raise ConstructionError(f"expected two finite numbers, got {show(value)}: beyond the "
                                "range of floating-point numbers", node=node,
                                field=field) from None
    except (TypeError, ValueError):
        raise ConstructionError(f"expected two numbers, got {show(value)}", node=node,
                                field=field) from None
    if not all(np.isfinite(pair)):
        raise ConstructionError(f"expected two finite numbers, got {show(value)}", node=node,
                                field=field)
    return pair


def _check_length(value: float, *, node, field) -> None:
    """Refuse a length larger than the scales the primitives compute with."""
    high = prim.SCALE_RANGE[1]
    if abs(value) > high:
        raise ConstructionError(
            f"{value:g} is larger than the lengths geokin computes with (magnitudes up to "
            f"{high:g}); express the mechanism in another unit of length",
            node=node, field=field)
