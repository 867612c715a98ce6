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
>>> c.polar("P", "A", 20, np.radians(30), reference=("A", "B"))
>>> print(c.compile())
construction 'four-bar': 5 steps
  1  O2 = fixed(0, 0)
  2  O4 = fixed(40, 0)
  3  A  = polar(O2, crank, theta)
  4  B  = circle_circle(A, 35; O4, 30)  [left]
  5  P  = polar(A, 20, 30 deg from A->B)

The step list shows an angle's numbers in degrees, with the unit; the
construction holds radians (``repr`` of a step, the values):

>>> c.compile().steps[-1]
<Step 5: P = polar(A, 20, 0.5235987755982988 from A->B)>
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import heapq
import keyword
import math
import unicodedata
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import ClassVar, Concatenate, ParamSpec, TypeVar

import numpy as np

from . import display
from . import primitives as prim
from .errors import (
    ConstructionError,
    degrees_hint,
    did_you_mean,
    looks_like_degrees,
    quote,
    range_looks_like_degrees,
    show,
    warn_of_degrees,
)
from .expressions import (
    CONSTANTS,
    FUNCTIONS,
    Expr,
    Number,
    ValueLike,
    as_expr,
    look_alike,
    normal_name,
    shown_in_degrees,
    skeleton,
)
from .frozen import Frozen
from .nodes import NODE_KINDS, Closure, Key, Node

__all__ = [
    "MAX_SAMPLES",
    "MAX_STEPS_SHOWN",
    "describe_input",
    "whole_steps",
    "as_compiled",
    "Compiled",
    "Construction",
    "Input",
    "Link",
    "Parameter",
    "Slider",
    "Step",
]

INPUT_KINDS = ("angle", "length")

MAX_STEPS_SHOWN = 40
"""The most steps a notebook shows of a construction."""


@dataclass(frozen=True)
class Parameter:
    """A named constant of a construction (a link length, an offset)."""

    name: str
    value: float
    description: str = ""


def default_speed(kind: str) -> float:
    """Return an input's speed where none is given: a turn, or one length unit, a second."""
    return 2 * np.pi if kind == "angle" else 1.0


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
            return lo + self.step * np.arange(self.sample_count())
        return np.linspace(lo, hi, samples or self.samples)

    def sample_count(self) -> int:
        """Return how many samples the default sweep has, by ``samples`` or by ``step``.

        Examples
        --------
        >>> Input("s", kind="length", range=(0.0, 1.0), step=0.4).sample_count()
        3
        """
        if self.step is None:
            return self.samples
        return math.floor(whole_steps(self.range[0], self.range[1], self.step)) + 1


def describe_input(inp: Input, units: str = "") -> str:
    """Return an input's declared sweep in words, angles in degrees.

    Examples
    --------
    >>> describe_input(Input("theta", range=(0, 10 * np.pi), step=np.radians(16)))
    'angle, 0 to 1800 deg, every 16 deg, 360 deg/s'
    >>> describe_input(Input("s", kind="length", range=(0, 5), speed=2), "mm")
    'length, 0 to 5 mm, 361 samples, 2 mm/s'
    """
    unit = "deg" if inp.kind == "angle" else units
    rate = "deg/s" if inp.kind == "angle" else f"{units or 'units'}/s"

    def value(x: float, what: str = unit) -> str:
        return display.angle(x, what) if inp.kind == "angle" else display.number(x, what)

    spacing = f"{inp.samples:,} samples" if inp.step is None else f"every {value(inp.step)}"
    return (f"{inp.kind}, {value(inp.range[0], '')} to {value(inp.range[1])}, {spacing}, "
            f"{value(inp.speed, rate)}")


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




@dataclass(frozen=True)
class Step:
    """One step of a compiled construction: a node and its place in the order."""

    index: int
    node: Node

    def __repr__(self) -> str:
        return f"<Step {self.index}: {self.node.name} = {self.node.describe()}>"


@dataclass(frozen=True)
class Compiled(Frozen):
    """A validated construction in evaluation order.

    Attributes
    ----------
    name : str
    steps : tuple of Step
        Every point node, each after the points it is built on.
    parameters : mapping of str to float
        Every parameter's value.
    inputs : mapping of str to Input
    links, sliders : tuple
        The declared links and sliders, for drawing and analysis.
    traced : tuple of str
        The points whose paths are traced.
    units, description : str
        The label of the length unit, and free text, as the construction has them.
    ground : frozenset of str
        The points that never move: fixed points that use no input, and
        points built only on those with values that use no input (see
        :meth:`~geokin.nodes.Node.is_ground`), found from the steps. The one
        place that decides what is ground, for the analysis and the drawing
        alike.

    A compiled construction is not changed after it is made; the mappings it
    holds are its own copies. ``str(compiled)`` is the step list of
    :meth:`listing`, angles shown in degrees.
    """

    name: str
    steps: tuple[Step, ...]
    parameters: Mapping[str, float]
    inputs: Mapping[str, Input]
    links: tuple[Link, ...] = ()
    sliders: tuple[Slider, ...] = ()
    traced: tuple[str, ...] = ()
    units: str = ""
    description: str = ""
    ground: frozenset[str] = field(init=False, default=frozenset())

    # read-only views of its own copies: a compiled construction is shared by every
    # sweep of it, and must not change under them
    _read_only = ("parameters", "inputs")

    def __post_init__(self) -> None:
        super().__post_init__()
        inputs = frozenset(self.inputs)
        ground: set[str] = set()
        for step in self.steps:  # in order: each point after the points it is built on
            if step.node.is_ground(inputs, ground):
                ground.add(step.node.name)
        object.__setattr__(self, "ground", frozenset(ground))

    def __len__(self) -> int:
        return len(self.steps)

    def __iter__(self) -> Iterator[Step]:
        return iter(self.steps)

    @property
    def point_names(self) -> tuple[str, ...]:
        """Return the point names in evaluation order."""
        return tuple(step.node.name for step in self.steps)

    @property
    def angle_inputs(self) -> frozenset[str]:
        """Return the names of the angle inputs (the others are lengths).

        Examples
        --------
        >>> c = Construction()
        >>> c.input("t")
        >>> c.input("s", kind="length", range=(0, 1))
        >>> sorted(c.compile().angle_inputs)
        ['t']
        """
        return frozenset(name for name, declared in self.inputs.items()
                         if declared.kind == "angle")

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
            if node.branch_names:
                row += (node.choice(),)
            rows.append(row)
        return rows

    def __str__(self) -> str:
        return self.listing()

    def listing(self, *, degrees: bool = True) -> str:
        """Return the steps as text, one a line, readable like a textbook construction.

        Parameters
        ----------
        degrees : bool, optional
            Show each angle's numbers in degrees with the unit, ``30 deg``
            (see :func:`~geokin.expressions.shown_in_degrees`): the number a
            script gave, or ``np.radians(30)`` given in Python. With False,
            the numbers as the nodes hold them: radians, or the units of a
            caller that rewrote them (:func:`geokin.io.script_steps` shows a
            script's own text this way).

        Examples
        --------
        >>> c = Construction("crank")
        >>> c.input("theta")
        >>> c.fixed("O", 0, 0)
        >>> c.polar("A", "O", 10, -np.pi / 2)
        >>> c.polar("B", "A", 5, "theta + pi / 6")
        >>> print(c.compile().listing())
        construction 'crank': 3 steps
          1  O = fixed(0, 0)
          2  A = polar(O, 10, -90 deg)
          3  B = polar(A, 5, theta + pi / 6)
        >>> print(c.compile().listing(degrees=False).splitlines()[2])
          2  A = polar(O, 10, -1.5707963267948966)
        """
        width = max((len(s.node.name) for s in self.steps), default=0)
        lines = [f"construction {self.name!r}: {len(self.steps)} steps"]
        for step in self.steps:
            node = _angles_in_degrees(step.node) if degrees else step.node
            lines.append(f"  {step.index:>{len(str(len(self.steps)))}}  "
                         f"{node.name:<{width}} = {node.describe()}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"<Compiled {self.name!r}: {len(self.steps)} steps>"

    def _repr_html_(self) -> str:
        """Return a table of the construction, and its steps, for a notebook.

        Angles are shown in degrees, lengths in :attr:`units`; everything
        from the script is escaped.

        Examples
        --------
        >>> c = Construction("crank <1>", units="mm")
        >>> c.input("theta", range=(0, np.pi), samples=19)
        >>> c.fixed("O", 0, 0)
        >>> c.polar("A", "O", 10, "theta")
        >>> page = c.compile()._repr_html_()
        >>> "crank &lt;1&gt;" in page, "0 to 180 deg, 19 samples, 360 deg/s" in page
        (True, True)
        """
        ground = [name for name in self.point_names if name in self.ground]
        moving = [name for name in self.point_names if name not in self.ground]
        rows = []
        if self.description:
            rows.append(("description", self.description))
        if self.units:
            rows.append(("lengths in", self.units))
        rows.append(("ground points", display.names(ground)))
        rows.append(("moving points", display.names(moving)))
        if self.parameters:
            rows.append(("parameters", display.names(
                f"{name} = {value:.6g}" for name, value in self.parameters.items())))
        for name, inp in list(self.inputs.items())[:display.MAX_LISTED]:
            rows.append((f"input {name}", describe_input(inp, self.units)))
        if len(self.inputs) > display.MAX_LISTED:
            rows.append(("inputs", f"{len(self.inputs):,} in all"))
        rows.append(("links", display.names(link.name for link in self.links)))
        if self.sliders:
            rows.append(("sliders", display.names(slider.name for slider in self.sliders)))
        rows.append(("traced", display.names(self.traced)))
        shown = str(self).splitlines()[1:1 + MAX_STEPS_SHOWN]
        if len(self.steps) > MAX_STEPS_SHOWN:
            shown.append(f"  ... and {len(self.steps) - MAX_STEPS_SHOWN:,} more")
        steps = "\n".join(display.text(line, 400) for line in shown)
        return (display.table(f"Construction {self.name!r}: {len(self.steps)} steps", rows)
                + f"\n<details><summary>steps</summary><pre>{steps}</pre></details>")

    def resolve_input(self, name: str | None = None, *, purpose: str = "move") -> str:
        """Return the input called ``name``, or the only input when ``name`` is None.

        Raises
        ------
        ConstructionError
            For an unknown name (with the closest one), or for None when the
            construction has several inputs or none; ``purpose`` completes
            the message ("name the one to move").

        Examples
        --------
        >>> c = Construction()
        >>> c.input("theta")
        >>> c.fixed("O", 0, 0)
        >>> c.compile().resolve_input()
        'theta'
        """
        names = list(self.inputs)
        if name is None:
            if len(names) != 1:
                raise ConstructionError(f"this construction has {len(names)} inputs "
                                        f"({', '.join(names) or 'none'}); name the one to "
                                        f"{purpose}")
            return names[0]
        if not isinstance(name, str):
            # a value passed where the name goes: circuit(c, np.radians(150))
            raise ConstructionError(f"expected the name of an input to {purpose} (a str, or "
                                    f"none for the only input), got {type(name).__name__} "
                                    f"{name!r}; values are given by keyword")
        if name not in self.inputs:
            raise ConstructionError(f"unknown input {name!r}{did_you_mean(name, names)}",
                                    node=name, kind="input")
        return name

    def with_parameters(self, values: Mapping[str, float]) -> Compiled:
        """Return this construction with some parameters given other values.

        The steps are shared; only the parameters' values change, in the
        construction's own units (a parameter that a script uses as an
        angle holds the script's degrees).

        Parameters
        ----------
        values : mapping of str to float
            New values of some declared parameters, by name.

        Raises
        ------
        ConstructionError
            For a name that is not a parameter (with the closest one, and
            the parameters there are), a value that is not a finite number,
            or one that makes a constant radius negative.

        Examples
        --------
        >>> c = Construction("crank")
        >>> c.parameter("r", 10)
        >>> c.input("theta")
        >>> c.fixed("O", 0, 0)
        >>> c.polar("A", "O", "r", "theta")
        >>> longer = c.compile().with_parameters({"r": 12})
        >>> longer.parameters["r"], c.compile().parameters["r"]
        (12.0, 10.0)
        >>> c.compile().with_parameters({"R": 12})  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        geokin.errors.ConstructionError: parameter 'R': no parameter 'R'; did you mean 'r'? ...
        """
        names = list(self.parameters)
        new = dict(self.parameters)
        for name, value in values.items():
            if name not in self.parameters:
                listed = f"parameters: {', '.join(names)}" if names else "it has no parameters"
                if name in self.inputs:  # an input is swept, not set
                    listed = f"{quote(name)} is an input, swept over its range; {listed}"
                raise ConstructionError(f"no parameter {quote(name)}{did_you_mean(name, names)} "
                                        f"({listed})", node=name, kind="parameter")
            try:
                number = float(value)
            except (TypeError, ValueError):
                raise ConstructionError(f"the value of parameter {quote(name)} must be a "
                                        f"number, got {show(value)}", node=name,
                                        kind="parameter") from None
            if not math.isfinite(number):
                raise ConstructionError(f"the value of parameter {quote(name)} must be a "
                                        f"finite number, got {number}", node=name,
                                        kind="parameter")
            new[name] = number
        with np.errstate(all="ignore"):
            for step in self.steps:
                node = step.node
                for field_name in node.nonnegative_fields():
                    expr = node.value_fields().get(field_name)
                    if expr is None or not expr.names() <= new.keys():
                        continue
                    radius = float(expr.evaluate(new))
                    if radius < 0:
                        raise ConstructionError(f"a radius cannot be negative; "
                                                f"{quote(str(expr), 60)} is {radius:g}",
                                                node=node.name, field=field_name)
        return dataclasses.replace(self, parameters=new)

    def step_named(self, name: str) -> Step:
        """Return the step of the point called ``name``.

        Raises
        ------
        KeyError
            For no such point, with the closest name.
        """
        if not name.isascii():
            name = unicodedata.normalize("NFKC", name)  # names are declared in NFKC
        for step in self.steps:
            if step.node.name == name:
                return step
        raise KeyError(f"no point {name!r}{did_you_mean(name, self.point_names)}")


def _angles_in_degrees(node: Node) -> Node:
    """Return ``node`` with its angle fields shown in degrees (its step list text only)."""
    changes: dict[str, Expr | tuple[Expr, ...]] = {}
    for key in node.keys:
        if key.angle:
            for attribute in key.attributes:
                value = getattr(node, attribute)
                changes[attribute] = (shown_in_degrees(value) if isinstance(value, Expr)
                                      else tuple(map(shown_in_degrees, value)))
    # mypy checks replace() against Node, whose only field is the name
    return dataclasses.replace(node, **changes) if changes else node  # type: ignore[arg-type]


def as_compiled(construction: Construction | Compiled) -> Compiled:
    """Return a construction compiled, or a compiled one as it is.

    Raises
    ------
    TypeError
        For anything else.
    """
    if isinstance(construction, Construction):
        return construction.compile()
    if isinstance(construction, Compiled):
        return construction
    raise TypeError(f"expected a Construction, got {type(construction).__name__}")


_P = ParamSpec("_P")
_R = TypeVar("_R")


@contextlib.contextmanager
def _declaring(kind: str) -> Iterator[None]:
    """Call the node of a ConstructionError raised in the block a ``kind`` ("link", ...).

    Every check of a declaration names what is declared as its node; this
    says what that is, so that an error about a link says "link 'rocker'".
    """
    try:
        yield
    except ConstructionError as err:
        if type(err) is not ConstructionError or err.node is None or err.kind != "node":
            raise
        raise err.naming(kind).with_traceback(err.__traceback__) from None


def _declares(kind: str) -> Callable[[Callable[Concatenate[Construction, _P], _R]],
                                     Callable[Concatenate[Construction, _P], _R]]:
    """Decorate a method that declares a ``kind``: its errors call the name a ``kind``."""
    def decorate(method: Callable[Concatenate[Construction, _P], _R]
                 ) -> Callable[Concatenate[Construction, _P], _R]:
        @functools.wraps(method)
        def declare(self: Construction, *args: _P.args, **kwargs: _P.kwargs) -> _R:
            with _declaring(kind):
                return method(self, *args, **kwargs)
        return declare
    return decorate


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
        self.groups: dict[str, tuple[str, ...]] = {}
        self.traced: tuple[str, ...] = ()
        self._compiled: Compiled | None = None
        # names that are not plain ASCII, by their skeleton (see expressions.skeleton)
        self._skeletons: dict[str, str] = {}

    def __repr__(self) -> str:
        return (f"<Construction {self.name!r}: {len(self.parameters)} parameters, "
                f"{len(self.inputs)} inputs, {len(self.nodes)} points>")

    def _repr_html_(self) -> str:
        """Return the compiled construction as a table for a notebook, or why it cannot compile.

        Examples
        --------
        >>> c = Construction("unfinished")
        >>> c.fixed("O", 0, 0)
        >>> c.polar("A", "O", 10, "theta")
        >>> print(c._repr_html_())  # doctest: +ELLIPSIS
        <table class="geokin">
        ...<td style="text-align:left">node &#x27;A&#x27;, field &#x27;angle&#x27;: unknown...
        """
        try:
            compiled = self.compile()
        except ConstructionError as err:
            return display.table(f"Construction {self.name!r}: {len(self.nodes)} points", [
                ("parameters", str(len(self.parameters))), ("inputs", str(len(self.inputs))),
                ("cannot compile", str(err))])
        return compiled._repr_html_()

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
                ("link", self.links), ("slider", self.sliders), ("group", self.groups))

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

    @_declares("parameter")
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
            names = ", ".join(map(quote, sorted(number.names())))
            raise ConstructionError(
                f"a parameter's value must be a number or arithmetic of numbers, not of "
                f"names ({names} in {quote(str(number), 60)}): give each parameter its own "
                "value, and write the arithmetic where the parameter is used", node=name,
                field="value")
        with np.errstate(all="ignore"):
            value = float(number.evaluate({}))
        if not np.isfinite(value):
            raise ConstructionError(f"a parameter's value must be a finite number; "
                                    f"{quote(str(number), 60)} is {value}", node=name,
                                    field="value")
        self.parameters[name] = Parameter(name, value, description)

    # ``range`` is the script's key and the Input's field; the builtin is not used here
    @_declares("input")
    def input(self, name: str, kind: str = "angle",
              range: Sequence[float] | None = None,  # noqa: A002
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
        if range is None and kind == "length":
            raise ConstructionError("a length input needs a range", node=name, field="range")
        lo_hi = _pair_of_numbers((0.0, 2 * np.pi) if range is None else range, node=name,
                                 field="range")
        if lo_hi[0] == lo_hi[1]:
            raise ConstructionError("the range's two ends are equal: nothing to sweep",
                                    node=name, field="range")
        width = lo_hi[1] - lo_hi[0]
        if kind == "angle" and range_looks_like_degrees(*lo_hi):
            warn_of_degrees(f"input {quote(name)}: a range of {lo_hi[0]:g} to {lo_hi[1]:g} "
                            f"{degrees_hint(abs(width))}")
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
            steps = whole_steps(lo_hi[0], lo_hi[1], step)  # inf for a tiny step
            if not steps < MAX_SAMPLES:
                raise ConstructionError(f"a step of {step:g} makes {steps + 1:.3g} samples over "
                                        f"the range, more than the {MAX_SAMPLES:,} a default "
                                        "sweep may have", node=name, field="step")
        if speed is None:
            speed = default_speed(kind)
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
        self.add("fixed", name, at=(x, y))

    def polar(self, name: str, origin: str, distance: ValueLike, angle: ValueLike,
              reference: Sequence[str] | None = None) -> None:
        """Declare the point at ``distance`` and ``angle`` from ``origin``.

        Parameters
        ----------
        name, origin : str
        distance : value
        angle : value
            Counter-clockwise, in radians (a script's degrees are converted
            when it is read): from the x axis, or with ``reference`` from the
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
        self.add("polar", name, origin=origin, distance=distance, angle=angle,
                 reference=reference)

    def local(self, name: str, origin: str, toward: str, at: Sequence[ValueLike]) -> None:
        """Declare the point at coordinates ``at = (u, v)`` in a frame on two points.

        The frame has its origin at ``origin`` and its x axis pointing towards
        ``toward``; v is measured a quarter turn counter-clockwise from it.
        A point of a rigid link (a coupler point, a leg's foot) is so given by
        its coordinates on the link, however the link moves. Samples where
        the two points coincide cannot be assembled.

        Parameters
        ----------
        name, origin, toward : str
        at : (value, value)
            The coordinates u and v, lengths.

        Examples
        --------
        A coupler point 12 along the coupler A->B and 5 to its left:

        >>> c = Construction()
        >>> c.input("theta")
        >>> c.fixed("O", 0, 0)
        >>> c.fixed("Q", 40, 0)
        >>> c.polar("A", "O", 10, "theta")
        >>> c.circle_circle("B", ("A", "Q"), (35, 30), branch="left")
        >>> c.local("P", "A", "B", (12, 5))
        >>> print(c.compile().steps[-1].node.describe())
        local(A->B, 12, 5)
        """
        self.add("local", name, origin=origin, toward=toward, at=at)

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
        self.add("along", name, line=line, distance=distance)

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
        self.add("line_line", name, first=first, second=second)

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
        self.add("circle_circle", name, centers=centers, radii=radii, branch=branch, near=near)

    def line_circle(self, name: str, line: Sequence[str], center: str, radius: ValueLike,
                    branch: str | None = None, near: Sequence[float] | None = None) -> None:
        """Declare an intersection of the line through ``line`` with a circle.

        ``branch`` is ``"first"`` or ``"second"`` along ``line[0] -> line[1]``,
        or give ``near`` instead.
        """
        self.add("line_circle", name, line=line, center=center, radius=radius, branch=branch,
                 near=near)

    def ray_circle(self, name: str, line: Sequence[str], center: str, radius: ValueLike,
                   branch: str | None = None, near: Sequence[float] | None = None) -> None:
        """Declare an intersection of the ray ``line[0]`` through ``line[1]`` with a circle."""
        self.add("ray_circle", name, line=line, center=center, radius=radius, branch=branch,
                 near=near)

    def segment_circle(self, name: str, line: Sequence[str], center: str, radius: ValueLike,
                       branch: str | None = None, near: Sequence[float] | None = None) -> None:
        """Declare an intersection of the segment ``line[0]..line[1]`` with a circle."""
        self.add("segment_circle", name, line=line, center=center, radius=radius,
                 branch=branch, near=near)

    def add(self, kind: str, name: str, **keys: object) -> None:
        """Declare a point of any kind, by the keys a script gives it.

        The methods named after each kind (:meth:`fixed`, :meth:`polar`, ...)
        call this; scripts are read through it. A key given as None counts
        as not given.

        Parameters
        ----------
        kind : str
            One of :data:`~geokin.nodes.NODE_KINDS`, the ``op`` of scripts.
        name : str
        **keys
            The kind's keys (:attr:`~geokin.nodes.Node.keys`), angles in
            radians.

        Examples
        --------
        >>> c = Construction()
        >>> c.input("t")
        >>> c.add("fixed", "O", at=(0, 0))
        >>> c.add("polar", "A", origin="O", distance=10, angle="t")
        >>> c.compile().steps[1]
        <Step 2: A = polar(O, 10, t)>
        """
        cls = NODE_KINDS.get(kind) if isinstance(kind, str) else None
        if cls is None:
            raise ConstructionError(f"unknown point kind {show(kind)}"
                                    f"{did_you_mean(str(kind), NODE_KINDS)} (kinds: "
                                    f"{', '.join(NODE_KINDS)})", node=name, field="op")
        declared = {key.name: key for key in cls.keys}
        for key_name in keys:
            if key_name not in declared:
                raise ConstructionError(
                    f"a {kind} point has no key {quote(key_name)}"
                    f"{did_you_mean(key_name, declared)} (keys: {', '.join(declared)})",
                    node=name, field=key_name)
        fields: dict[str, object] = {}
        for key in cls.keys:
            given = keys.get(key.name)
            if given is None:
                if key.required:
                    raise ConstructionError(f"a {kind} point needs {quote(key.name)}",
                                            node=name, field=key.name)
                continue
            fields.update(self._key_fields(key, given, name))
        if cls.branch_names:
            fields["branch"], fields["near"] = self._branch(
                cls, name, fields.pop("branch", None), fields.pop("near", None))
        self._add(cls(name, **fields))

    def closure(self, group: str, points: Sequence[str],
                distances: Sequence[Sequence[object]],
                near: Mapping[str, Sequence[float]] | Sequence[Sequence[float]],
                lines: Sequence[Sequence[str]] = ()) -> None:
        """Declare a closure group: points found together from equations between them.

        Use it where no construction reaches a point from points already
        known, as in the triad of a Stephenson III six-bar, whose four
        joints each depend on the others. Each point of the group becomes a
        point of the construction; the group is solved by Newton's method
        on its equations and followed along the sweep by continuation (see
        :mod:`geokin.closure`).

        Parameters
        ----------
        group : str
            The group's name, for messages and the step list.
        points : sequence of str
            The k unknown points, new names.
        distances : sequence of (str, str, value)
            Each a distance between two points, at least one of the group.
        near : mapping of str to (float, float), or sequence of (x, y)
            A sketch position for every point of the group (in the order of
            ``points`` for a sequence): the assembly nearest them, found by
            Newton's method from them at the first sample, is followed.
        lines : sequence of (str, str, str), optional
            Each a point (of the group) on the line through two others.

        Raises
        ------
        ConstructionError
            Naming the group, when the equations are not 2k (under- or
            over-constrained), a sketch position is missing, or an equation
            ties no point of the group.

        Examples
        --------
        A four-bar's coupler-rocker joint B as a group of one point:

        >>> c = Construction()
        >>> c.input("theta")
        >>> c.fixed("O2", 0, 0)
        >>> c.fixed("O4", 40, 0)
        >>> c.polar("A", "O2", 10, "theta")
        >>> c.closure("dyad", ["B"], [("A", "B", 35), ("O4", "B", 30)], near={"B": (30, 30)})
        >>> print(c.compile().steps[3].node.describe())
        closure dyad(B): |A-B| = 35, |O4-B| = 30  [near B (30, 30)]
        """
        with _declaring("group"):
            group, names, found, on_lines, sketch = self._group(group, points, distances, near,
                                                                lines)
        for p in names:
            self._claim(p, "point")
        for p in names:
            self.nodes[p] = Closure(p, group=group, points=names, near=sketch,
                                    distances=tuple(found), lines=tuple(on_lines))
        self.groups[group] = names
        self._compiled = None

    def _group(self, group, points, distances, near, lines):
        """Check a closure group's declaration; return its name, points, equations, sketch."""
        group = self._claim(group, "group")
        if isinstance(points, str) or not isinstance(points, Iterable):
            raise ConstructionError(f"expected a list of point names, got {show(points)}",
                                    node=group, field="points")
        names = tuple(self._point(p, group, f"points[{i}]") for i, p in enumerate(points))
        if not names:
            raise ConstructionError("a group needs at least one point", node=group,
                                    field="points")
        if len(set(names)) != len(names):
            raise ConstructionError("a point is listed twice", node=group, field="points")
        k = len(names)
        found: list[tuple[str, str, Expr]] = []
        if isinstance(distances, str) or not isinstance(distances, Iterable):
            raise ConstructionError(f"expected a list of [P, Q, length], got {show(distances)}",
                                    node=group, field="distances")
        for i, entry in enumerate(distances):
            where = f"distances[{i}]"
            if isinstance(entry, str) or not isinstance(entry, Sequence) or len(entry) != 3:
                raise ConstructionError(f"expected [P, Q, length], got {show(entry)}",
                                        node=group, field=where)
            p, q = (self._point(x, group, where) for x in entry[:2])
            if p == q:
                raise ConstructionError(f"a distance from {quote(p)} to itself", node=group,
                                        field=where)
            if p not in names and q not in names:
                raise ConstructionError(f"|{p}-{q}| ties no point of the group", node=group,
                                        field=where)
            found.append((p, q, self._value(entry[2], group, where)))
        on_lines: list[tuple[str, str, str]] = []
        if isinstance(lines, str) or not isinstance(lines, Iterable):
            raise ConstructionError(f"expected a list of [P, Q, R], got {show(lines)}",
                                    node=group, field="lines")
        for i, entry in enumerate(lines):
            where = f"lines[{i}]"
            if isinstance(entry, str) or not isinstance(entry, Sequence) or len(entry) != 3:
                raise ConstructionError(f"expected [P, Q, R] (P on the line Q-R), got "
                                        f"{show(entry)}", node=group, field=where)
            p, q, r = (self._point(x, group, where) for x in entry)
            if not {p, q, r} & set(names):
                raise ConstructionError(f"{p} on {q}-{r} ties no point of the group",
                                        node=group, field=where)
            on_lines.append((p, q, r))
        equations = len(found) + len(on_lines)
        if equations != 2 * k:
            what = "under-constrained" if equations < 2 * k else "over-constrained"
            points = "1 point needs" if k == 1 else f"{k} points need"
            raise ConstructionError(
                f"group {quote(group)} is {what}: {points} {2 * k} equations "
                f"(two each), got {equations} ({len(found)} distances, {len(on_lines)} "
                f"on lines)", node=group, field="distances")
        if isinstance(near, Mapping):
            for p in near:
                if p not in names:
                    raise ConstructionError(f"{quote(str(p))} is not a point of the group"
                                            f"{did_you_mean(str(p), names)}", node=group,
                                            field="near")
            missing = [p for p in names if p not in near]
            if missing:
                raise ConstructionError(f"no sketch position for {', '.join(map(quote, missing))}"
                                        ": every point of the group needs one", node=group,
                                        field="near")
            sketches = [near[p] for p in names]
        else:
            sketches = list(near)
            if len(sketches) != k:
                raise ConstructionError(f"expected {k} sketch positions, got {len(sketches)}",
                                        node=group, field="near")
        sketch = tuple(_pair_of_numbers(v, node=group, field=f"near.{p}")
                       for p, v in zip(names, sketches, strict=True))
        return group, names, found, on_lines, sketch

    def _key_fields(self, key: Key, given: object, node: str) -> dict[str, object]:
        """Check one key's value and return the node fields it fills."""
        (attribute, *others) = key.attributes
        if key.holds == "point":
            return {attribute: self._point(given, node, key.name)}
        if key.holds == "point pair":
            return {attribute: self._point_pair(given, node, key.name)}
        if key.holds == "value":
            return {attribute: self._value(given, node, key.name)}
        if key.holds == "value pair":
            pair = self._value_pair(given, node, key.fields(), key.name)
            return dict(zip(key.attributes, pair, strict=True)) if others else {attribute: pair}
        return {attribute: given}  # a branch or sketch: checked with the node's choice

    @_declares("link")
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

    @_declares("slider")
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
        values = node.value_fields()
        for field_name in sorted(node.angle_fields()):
            value = values[field_name]
            if isinstance(value, Number) and looks_like_degrees(value.value):
                warn_of_degrees(f"point {quote(name)}: an angle of {value.value:g} "
                                f"{degrees_hint(value.value)}")
        self.nodes[name] = node

    @staticmethod
    def _value(value, node, field_name) -> Expr:
        return as_expr(value, node=node, field=field_name)

    @staticmethod
    def _value_pair(values, node, field_names: Sequence[str], key: str) -> tuple[Expr, Expr]:
        if isinstance(values, str | bytes) or not isinstance(values, Sequence):
            raise ConstructionError(f"expected 2 values, got {show(values)}", node=node,
                                    field=key)
        if len(values) != 2:
            raise ConstructionError(f"expected 2 values, got {len(values)}", node=node,
                                    field=key)
        first, second = (as_expr(v, node=node, field=f)
                         for v, f in zip(values, field_names, strict=True))
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
    def _branch(kind: type[Node], node, branch, near):
        names, kind_name = kind.branch_names, kind.kind
        if branch is not None and near is not None:
            raise ConstructionError("give either branch or near, not both", node=node,
                                    field="branch")
        if branch is None and near is None:
            raise ConstructionError(f"a {kind_name} node has two roots: choose one with branch "
                                    f"({' or '.join(map(repr, names))}) or near=(x, y)",
                                    node=node, field="branch")
        if branch is not None and branch not in names:
            raise ConstructionError(f"unknown branch {show(branch)} for {kind_name}; use "
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
        if self._compiled is not None and (
                (self._compiled.name, self._compiled.units, self._compiled.description)
                == (self.name, self.units, self.description)):
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
                self._check_point_name(p, link.name, f"points[{i}]", "link")
        for i, p in enumerate(self.traced):
            self._check_point_name(p, "trace", f"points[{i}]")
        for slider in self.sliders.values():
            self._check_point_name(slider.point, slider.name, "point", "slider")
            for i, p in enumerate(slider.along):
                self._check_point_name(p, slider.name, f"along[{i}]", "slider")
        self._check_constant_values()
        order = self._ordered()
        steps = tuple(Step(i + 1, self.nodes[name]) for i, name in enumerate(order))
        self._compiled = Compiled(
            self.name, steps, {k: p.value for k, p in self.parameters.items()},
            dict(self.inputs), tuple(self.links.values()), tuple(self.sliders.values()),
            self.traced, self.units, self.description)
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
                size, largest = max(map(abs, inp.range)), (inp.name, "range", "input")
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
                    if value < 0 and field_name in node.nonnegative_fields():
                        raise ConstructionError(f"a radius cannot be negative; "
                                                f"{quote(str(expr), 60)} is {value:g}",
                                                node=node.name, field=field_name)
                    if field_name not in angles and abs(value) > size:
                        if abs(value) > high:
                            _check_length(value, node=node.name, field=field_name)
                        size, largest = abs(value), (node.name, field_name, "node")
        low = prim.SCALE_RANGE[0]
        if 0 < size < low:
            raise ConstructionError(
                f"the mechanism's largest length is {size:g}, smaller than the {low:g} geokin "
                "computes with; express the mechanism in another unit of length",
                node=largest[0], field=largest[1], kind=largest[2])

    def _check_point_name(self, point, node, field_name, kind="node"):
        if point in self.nodes:
            return
        hint = _hint(point, self.nodes)
        other = self._kind_of(point)
        if other is not None:
            hint = f"; {quote(point)} is a {other}, not a point" + hint
        raise ConstructionError(f"unknown point {quote(point)}{hint}", node=node,
                                field=field_name, kind=kind)

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


def whole_steps(start: float, stop: float, step: float) -> float:
    """Return how many steps of ``step`` fit from ``start`` to ``stop``, not rounded down.

    A sampling by steps (like MATLAB's ``start:step:stop``) has
    ``floor(whole_steps(...)) + 1`` samples, the last not beyond ``stop``;
    a stop that the steps reach to rounding counts as reached. Infinite for a
    step too small to divide by.

    Examples
    --------
    >>> math.floor(whole_steps(0, 1800, 16))
    112
    >>> math.floor(whole_steps(0.0, 0.3, 0.1))  # 0.3 / 0.1 is 2.9999999999999996
    3
    """
    return (stop - start) / step * (1 + 1e-12) + 1e-9


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
