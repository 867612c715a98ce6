"""Values of a construction: numbers, names, and arithmetic of them.

A value is an :class:`Expr`: a number, the name of a parameter or input, or
arithmetic (``+ - * / **``, unary minus, parentheses) and the functions of
:data:`FUNCTIONS` with the constant ``pi``: ``sqrt abs hypot min max``,
``sin cos tan``, ``asin acos atan atan2``, ``radians degrees``.
Strings are parsed by :func:`parse`, which reads Python's expression grammar
with :mod:`ast` and accepts only those node kinds: no ``eval``, no attribute
access, no subscripts and no calls outside that list, so parsing a script
never runs code. The trigonometric functions work in radians: ``sin cos
tan`` take radians and ``asin acos atan atan2`` return them. Every function
works elementwise on numpy arrays; ``min`` and ``max`` take two or more
values. A value outside a function's domain (``acos(2)``, ``sqrt(-1)``)
gives NaN, as numpy does: a sample where a point's value is NaN cannot be
assembled (see :func:`geokin.nodes.failure_reasons`).

An expression holds at most :data:`~geokin.budgets.MAX_EXPRESSION_LENGTH`
characters and nests operations and calls at most
:data:`~geokin.budgets.MAX_EXPRESSION_DEPTH` levels deep, so printing and
evaluating it, which recurse once per level, always have the stack they need.

Printing
--------
``str(expr)`` is the one writer of expressions: step lists, error messages
and scripts (:func:`geokin.io.dump`) all show this text, and parsing it gives
back the same tree, ``parse(str(e)) == e``. Numbers are written as the
shortest text that reads back exactly (``20``, ``0.1``, ``1e-300``, ``-0``);
parentheses appear only where the tree needs them, including around a right
operand of the same precedence (``a - (b - c)``), which the parser would
otherwise group from the left.

Names
-----
Names are read as Python reads identifiers, in Unicode normal form NFKC:
``ｌ1`` (fullwidth) and ``l1`` are one name. A name keeps to one script
(:func:`normal_name`): ``pаram`` with a Cyrillic ``а`` is refused, and a
construction refuses a name that differs from a declared one only by letters
that look alike (:func:`skeleton`), such as Cyrillic ``В0`` next to Latin ``B0``.

Examples
--------
>>> e = parse("y + l1")
>>> sorted(e.names())
['l1', 'y']
>>> float(e.evaluate({"y": 20, "l1": 10}))
30.0
>>> str(parse("2 * (a + b) ** 2"))
'2 * (a + b) ** 2'
>>> str(parse("a - (b - c)")), str(parse("(a - b) - c")), str(parse("0.1 * 3e20"))
('a - (b - c)', 'a - b - c', '0.1 * 3e+20')
"""

from __future__ import annotations

import ast
import dataclasses
import functools
import math
import unicodedata
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any, TypeAlias

import numpy as np

from .budgets import MAX_EXPRESSION_DEPTH, MAX_EXPRESSION_LENGTH, MAX_NAME_LENGTH
from .errors import ConstructionError, quote, show

__all__ = [
    "Expr",
    "FUNCTIONS",
    "ValueLike",
    "as_expr",
    "look_alike",
    "names_only_within",
    "normal_name",
    "parse",
    "script_degrees",
    "shown_in_degrees",
    "skeleton",
]



def _minimum(*values: Any) -> Any:
    """Return the elementwise minimum of two or more values (NaN if any is NaN)."""
    return functools.reduce(np.minimum, values)


def _maximum(*values: Any) -> Any:
    """Return the elementwise maximum of two or more values (NaN if any is NaN)."""
    return functools.reduce(np.maximum, values)


Arity: TypeAlias = int | tuple[int, None]
"""How many arguments a function takes: exactly ``n``, or ``(n, None)`` for n or more."""

FUNCTIONS: dict[str, tuple[Arity, Callable[..., Any]]] = {
    "sqrt": (1, np.sqrt),
    "abs": (1, np.abs),
    "hypot": (2, np.hypot),
    "min": ((2, None), _minimum),
    "max": ((2, None), _maximum),
    "sin": (1, np.sin),
    "cos": (1, np.cos),
    "tan": (1, np.tan),
    "asin": (1, np.arcsin),
    "acos": (1, np.arccos),
    "atan": (1, np.arctan),
    "atan2": (2, np.arctan2),
    "radians": (1, np.radians),
    "degrees": (1, np.degrees),
}
"""The functions expressions may call: name -> (arity, numpy function).

All are elementwise. ``hypot(x, y)`` is ``sqrt(x ** 2 + y ** 2)`` without
overflow; ``atan2(y, x)`` the angle of the vector (x, y) in radians, in the
right quadrant; ``min`` and ``max`` take two or more values.

Examples
--------
>>> parse("max(a, b, 0)").evaluate({"a": np.array([-1.0, 2.0]), "b": -3.0})
array([0., 2.])
>>> float(parse("degrees(acos(0.5))").evaluate({}))
60.00000000000001
>>> with np.errstate(invalid="ignore"):  # out of the domain: NaN, as numpy gives
...     float(parse("acos(x)").evaluate({"x": 2.0}))
nan
"""
CONSTANTS = {"pi": math.pi}

_BINARY = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
_PRECEDENCE = {"+": 1, "-": 1, "*": 2, "/": 2, "neg": 3, "**": 4}
_APPLY = {
    "+": np.add,
    "-": np.subtract,
    "*": np.multiply,
    "/": np.divide,
    "**": np.power,
}


class Expr:
    """A value of a construction, evaluated elementwise with numpy.

    Build one with :func:`parse` or :func:`as_expr`, or with arithmetic on
    other expressions: ``as_expr("l3") + 5``. ``str(expr)`` writes it as
    text that :func:`parse` reads back as the same tree (the one exception,
    a minus applied to a :class:`Number`, is read back as a negative number).

    Examples
    --------
    >>> e = (as_expr("a") - (as_expr("b") - 0.1)) ** -2
    >>> str(e)
    '(a - (b - 0.1)) ** (-2)'
    >>> parse(str(e)) == e
    True
    """

    __slots__ = ()

    @property
    def depth(self) -> int:
        """Levels of operations and calls from the whole to a number or a name."""
        return 0

    def names(self) -> frozenset[str]:
        """Return the names of parameters and inputs this value depends on."""
        raise NotImplementedError

    def evaluate(self, env: Mapping[str, object]) -> Any:
        """Return the value, with each name looked up in ``env``.

        Invalid operations give NaN or inf as numpy does; wrap the call in
        ``np.errstate`` to silence their warnings.
        """
        raise NotImplementedError

    def _precedence(self) -> int:
        return 5

    # arithmetic builds new expressions
    def __add__(self, other: ValueLike) -> BinOp:
        return BinOp("+", self, as_expr(other))

    def __radd__(self, other: ValueLike) -> BinOp:
        return BinOp("+", as_expr(other), self)

    def __sub__(self, other: ValueLike) -> BinOp:
        return BinOp("-", self, as_expr(other))

    def __rsub__(self, other: ValueLike) -> BinOp:
        return BinOp("-", as_expr(other), self)

    def __mul__(self, other: ValueLike) -> BinOp:
        return BinOp("*", self, as_expr(other))

    def __rmul__(self, other: ValueLike) -> BinOp:
        return BinOp("*", as_expr(other), self)

    def __truediv__(self, other: ValueLike) -> BinOp:
        return BinOp("/", self, as_expr(other))

    def __rtruediv__(self, other: ValueLike) -> BinOp:
        return BinOp("/", as_expr(other), self)

    def __pow__(self, other: ValueLike) -> BinOp:
        return BinOp("**", self, as_expr(other))

    def __rpow__(self, other: ValueLike) -> BinOp:
        return BinOp("**", as_expr(other), self)

    def __neg__(self) -> Neg:
        return Neg(self)

    def __repr__(self) -> str:
        return f"Expr({str(self)!r})"


@dataclass(frozen=True, slots=True, repr=False)
class Number(Expr):
    """A constant."""

    value: float

    def __eq__(self, other: object) -> bool:
        # NaN equals NaN here, so that equal texts give equal expressions whether
        # or not they share one parsed object
        if not isinstance(other, Number):
            return NotImplemented
        a, b = self.value, other.value
        return a == b or (a != a and b != b)

    def __hash__(self) -> int:
        return hash(("Number", "nan" if self.value != self.value else self.value))

    def names(self) -> frozenset[str]:
        return frozenset()

    def evaluate(self, env: Mapping[str, object]) -> Any:
        return self.value

    def __str__(self) -> str:
        value = self.value
        if math.isfinite(value) and value == int(value) and abs(value) < 1e15:
            # -0.0 keeps its sign: atan2(0, -0.0) is pi
            return "-0" if value == 0 and math.copysign(1.0, value) < 0 else str(int(value))
        return repr(value)

    def _precedence(self):
        return 3 if math.copysign(1.0, self.value) < 0 else 5


@dataclass(frozen=True, slots=True, repr=False)
class Name(Expr):
    """A parameter, an input or the constant ``pi``."""

    name: str

    def names(self) -> frozenset[str]:
        return frozenset() if self.name in CONSTANTS else frozenset([self.name])

    def evaluate(self, env: Mapping[str, object]) -> Any:
        if self.name in CONSTANTS:
            return CONSTANTS[self.name]
        return env[self.name]

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True, slots=True, repr=False)
class Neg(Expr):
    """Unary minus."""

    operand: Expr
    depth: int = dataclasses.field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "depth", 1 + self.operand.depth)

    def names(self) -> frozenset[str]:
        return self.operand.names()

    def evaluate(self, env: Mapping[str, object]) -> Any:
        return np.negative(self.operand.evaluate(env))

    def __str__(self) -> str:
        inner = str(self.operand)
        if self.operand._precedence() < _PRECEDENCE["neg"]:
            inner = f"({inner})"
        return "-" + inner

    def _precedence(self):
        return _PRECEDENCE["neg"]


@dataclass(frozen=True, slots=True, repr=False)
class BinOp(Expr):
    """A binary arithmetic operation."""

    op: str
    left: Expr
    right: Expr
    depth: int = dataclasses.field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "depth", 1 + max(self.left.depth, self.right.depth))

    def names(self) -> frozenset[str]:
        return self.left.names() | self.right.names()

    def evaluate(self, env: Mapping[str, object]) -> Any:
        return _APPLY[self.op](self.left.evaluate(env), self.right.evaluate(env))

    def _precedence(self):
        return _PRECEDENCE[self.op]

    def __str__(self) -> str:
        mine = self._precedence()
        left, right = str(self.left), str(self.right)
        # ** is right-associative, the others left-associative
        if self.left._precedence() < mine or (self.op == "**" and self.left._precedence() == mine):
            left = f"({left})"
        # the parser groups equal precedence from the left: a right operand of the
        # same precedence keeps its parentheses, so the text parses to the same tree
        if self.right._precedence() < mine or (
            self.op != "**" and self.right._precedence() == mine
        ):
            right = f"({right})"
        return f"{left} {self.op} {right}"


@dataclass(frozen=True, slots=True, repr=False)
class Call(Expr):
    """A call of one of :data:`FUNCTIONS`."""

    function: str
    args: tuple[Expr, ...]
    depth: int = dataclasses.field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "depth", 1 + max((a.depth for a in self.args), default=0))

    def names(self) -> frozenset[str]:
        return frozenset().union(*(a.names() for a in self.args))

    def evaluate(self, env: Mapping[str, object]) -> Any:
        return FUNCTIONS[self.function][1](*(a.evaluate(env) for a in self.args))

    def __str__(self) -> str:
        return f"{self.function}({', '.join(str(a) for a in self.args)})"


ValueLike: TypeAlias = Expr | float | str
"""What a construction takes as a value: a number, an expression's text or an :class:`Expr`."""


def names_only_within(exprs: Iterable[Expr], function: str) -> set[str]:
    """Return the names that appear in ``exprs`` only within calls of ``function``.

    Within through arithmetic, not through another function: in
    ``radians(asin(e / h))`` the names e and h are not within ``radians``.

    Examples
    --------
    >>> exprs = [parse("radians(beta + 2 * gamma)"), parse("radians(asin(e / h)) + gamma")]
    >>> sorted(names_only_within(exprs, "radians"))
    ['beta']
    """
    within: set[str] = set()
    elsewhere: set[str] = set()

    def walk(expr: Expr, inside: bool) -> None:
        if isinstance(expr, Name):
            (within if inside else elsewhere).add(expr.name)
        elif isinstance(expr, Neg):
            walk(expr.operand, inside)
        elif isinstance(expr, BinOp):
            walk(expr.left, inside)
            walk(expr.right, inside)
        elif isinstance(expr, Call):
            for argument in expr.args:
                walk(argument, expr.function == function)

    for expr in exprs:
        walk(expr, False)
    return within - elsewhere


# -- angles shown in degrees ----------------------------------------------------------


def script_degrees(radians: float) -> float:
    """Return the shortest degree value that reads back as exactly ``radians``.

    ``math.degrees`` may land an ulp or two off the value a script gave
    (``radians(-645.6585625622657)`` comes back as ``-645.6585625622658``),
    so its neighbours are tried too.

    Examples
    --------
    >>> script_degrees(math.radians(-645.6585625622657))
    -645.6585625622657
    >>> script_degrees(math.pi / 2)
    90.0
    """
    degrees = math.degrees(radians)
    exact, below, above = [], degrees, degrees
    for _ in range(4):
        exact += [d for d in (below, above) if math.radians(d) == radians and d not in exact]
        below, above = math.nextafter(below, -math.inf), math.nextafter(above, math.inf)
    for digits in range(1, 18):
        for candidate in exact:
            shortest = float(f"{candidate:.{digits}g}")
            if math.radians(shortest) == radians:
                return shortest
    return exact[0] if exact else degrees  # some radians have no degree value exactly


@dataclass(frozen=True, slots=True, repr=False)
class _Degrees(Number):
    """A number of radians that prints as degrees with the unit: ``30 deg``.

    For showing an angle only (:func:`shown_in_degrees`): its text does not
    parse back.
    """

    def __str__(self) -> str:
        return f"{Number(script_degrees(self.value))} deg"


def shown_in_degrees(angle: Expr) -> Expr:
    """Return an angle to be shown with its numbers in degrees: ``30 deg`` for 0.5236.

    The numbers of an angle that are angles themselves are shown in degrees
    (the shortest that reads back exactly, :func:`script_degrees`) with the
    unit: the whole value if it is a number, and every number added to,
    subtracted from or negated in it, since each term of an angle is an
    angle. Any other number (a factor, a function's argument) and every
    name are shown as they are. The value is unchanged: it is radians, as
    every angle inside geokin; only its text differs, and that text is for
    reading, not for :func:`parse`.

    Examples
    --------
    >>> str(shown_in_degrees(as_expr(math.radians(30))))
    '30 deg'
    >>> str(shown_in_degrees(parse("theta - 0.5235987755982988")))
    'theta - 30 deg'
    >>> str(shown_in_degrees(parse("2 * theta + radians(45)")))
    '2 * theta + radians(45)'
    >>> float(shown_in_degrees(as_expr(math.pi)).evaluate({})) == math.pi
    True
    """
    if isinstance(angle, Number):
        return _Degrees(angle.value)
    if isinstance(angle, Neg):
        return Neg(shown_in_degrees(angle.operand))
    if isinstance(angle, BinOp) and angle.op in "+-":
        return BinOp(angle.op, shown_in_degrees(angle.left), shown_in_degrees(angle.right))
    return angle


def as_expr(value: ValueLike, *, node: str | None = None, field: str | None = None) -> Expr:
    """Turn a number, a string or an :class:`Expr` into an :class:`Expr`.

    Raises
    ------
    ConstructionError
        For anything else, a number that is not finite (or too large for a
        float), or an expression over the limits of :mod:`geokin.budgets`.

    Examples
    --------
    >>> as_expr(3)
    Expr('3')
    >>> as_expr("l2 / 2")
    Expr('l2 / 2')
    >>> as_expr(10 ** 400)
    Traceback (most recent call last):
    ...
    geokin.errors.ConstructionError: expected a finite number, got an integer of 401 digits
    """
    if isinstance(value, Expr):
        if value.depth > MAX_EXPRESSION_DEPTH:
            raise ConstructionError(_too_deep(value.depth), node=node, field=field)
        return value
    if isinstance(value, bool):
        raise ConstructionError(f"expected a number or an expression, got {value!r}",
                                node=node, field=field)
    if isinstance(value, int | float | np.integer | np.floating):
        try:
            number = float(value)
        except OverflowError:
            number = math.inf
        if not math.isfinite(number):
            raise ConstructionError(f"expected a finite number, got {show(value)}", node=node,
                                    field=field)
        return Number(number)
    if isinstance(value, str):
        return parse(value, node=node, field=field)
    raise ConstructionError(
        f"expected a number or an expression, got {type(value).__name__} {show(value)}",
        node=node, field=field)


def _too_deep(depth: int | None = None) -> str:
    """Say that an expression is nested too deeply (``depth`` levels, when known)."""
    levels = f"{depth} levels deep" if depth is not None else "too deeply"
    return (f"nested {levels}: an expression may nest at most {MAX_EXPRESSION_DEPTH} levels "
            "of operations and calls; give parts of it names as parameters")


def _ast_depth(tree: ast.AST) -> int:
    """Return the nesting of operations and calls in a parsed expression, without recursion.

    Stops counting past :data:`~geokin.budgets.MAX_EXPRESSION_DEPTH`, so the
    answer is at most one more than the limit.
    """
    deepest = 0
    stack: list[tuple[ast.AST, int]] = [(tree, 0)]
    while stack:
        item, depth = stack.pop()
        children: tuple[ast.expr, ...]
        if isinstance(item, ast.BinOp):
            children = (item.left, item.right)
        elif isinstance(item, ast.UnaryOp):
            children = (item.operand,)
        elif isinstance(item, ast.Call):
            children = tuple(item.args)
        else:
            continue
        depth += 1
        if depth > MAX_EXPRESSION_DEPTH:
            return depth
        deepest = max(deepest, depth)
        stack.extend((child, depth) for child in children)
    return deepest


def parse(text: str, *, node: str | None = None, field: str | None = None) -> Expr:
    """Parse an arithmetic expression safely.

    Parameters
    ----------
    text : str
        The expression, in Python syntax restricted to numbers, names,
        ``+ - * / **``, parentheses and calls of :data:`FUNCTIONS`; at most
        :data:`~geokin.budgets.MAX_EXPRESSION_LENGTH` characters, nested at
        most :data:`~geokin.budgets.MAX_EXPRESSION_DEPTH` levels deep.
    node, field : str, optional
        Where the text comes from, for error messages.

    Raises
    ------
    ConstructionError
        If the text is not such an expression.

    Examples
    --------
    >>> parse("sqrt(a**2 + b**2)")
    Expr('sqrt(a ** 2 + b ** 2)')
    >>> parse("__import__('os')")
    Traceback (most recent call last):
    ...
    geokin.errors.ConstructionError: expression "__import__('os')": unknown function ...
    >>> parse("+".join(["1"] * 500))
    Traceback (most recent call last):
    ...
    geokin.errors.ConstructionError: expression '1+1+1+…1+1' [999 characters]: nested too deeply...
    """
    def fail(message):
        shown = quote(text, 60) if len(text) <= 60 else quote(text, 6)
        return ConstructionError(f"expression {shown}: {message}", node=node, field=field)

    if not isinstance(text, str):
        raise ConstructionError(f"expected an expression (a string), got {show(text)}",
                                node=node, field=field)
    if len(text) > MAX_EXPRESSION_LENGTH:
        raise fail(f"longer than the {MAX_EXPRESSION_LENGTH:,} characters an expression may "
                   "have; give parts of it names as parameters")
    parsed = _PARSED.get(text)
    if parsed is not None:
        return parsed
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:  # the first sentence: Python's advice is not for scripts
        raise fail(f"not a valid expression ({exc.msg.split(';')[0]})") from None
    except (RecursionError, MemoryError):
        raise fail(_too_deep()) from None
    except ValueError as exc:  # a NUL character, and the like
        raise fail(f"not a valid expression ({exc})") from None
    if _ast_depth(tree.body) > MAX_EXPRESSION_DEPTH:
        raise fail(_too_deep())

    def build(item: ast.AST) -> Expr:
        if isinstance(item, ast.Constant):
            if isinstance(item.value, bool) or not isinstance(item.value, int | float):
                raise fail(f"{show(item.value)} is not a number")
            try:
                number = float(item.value)
            except OverflowError:
                raise fail(f"the number {show(item.value)} is too large") from None
            if not math.isfinite(number):
                raise fail(f"{show(item.value)} is not a finite number")
            return Number(number)
        if isinstance(item, ast.Name):
            try:
                return Name(normal_name(item.id, what="name"))
            except ConstructionError as err:
                raise fail(err.message) from None
        if isinstance(item, ast.UnaryOp) and isinstance(item.op, ast.USub | ast.UAdd):
            operand = build(item.operand)
            if isinstance(item.op, ast.UAdd):
                return operand
            if isinstance(operand, Number):
                return Number(-operand.value)
            return Neg(operand)
        if isinstance(item, ast.BinOp) and type(item.op) in _BINARY:
            return BinOp(_BINARY[type(item.op)], build(item.left), build(item.right))
        if isinstance(item, ast.Call):
            if not isinstance(item.func, ast.Name):
                raise fail("only calls of plain function names are allowed")
            name = item.func.id
            if name not in FUNCTIONS:
                raise fail(f"unknown function {quote(name)}; allowed: {', '.join(FUNCTIONS)}")
            if item.keywords:
                raise fail(f"{name}() takes no keyword arguments")
            arity = FUNCTIONS[name][0]
            if isinstance(arity, int) and len(item.args) != arity:
                raise fail(f"{name}() takes {arity} argument{'s' * (arity > 1)}, "
                           f"got {len(item.args)}")
            if isinstance(arity, tuple) and len(item.args) < arity[0]:
                raise fail(f"{name}() takes at least {arity[0]} arguments, "
                           f"got {len(item.args)}")
            return Call(name, tuple(build(a) for a in item.args))
        kind = type(item).__name__
        raise fail(f"{kind} is not allowed; use numbers, names, + - * / ** and "
                   f"{', '.join(FUNCTIONS)}")

    parsed = build(tree.body)
    if len(text) <= _CACHED_LENGTH and len(_PARSED) < _CACHE_SIZE:
        _PARSED[text] = parsed
    return parsed


# scripts repeat short values ("theta", "l2 / 2"): expressions are immutable, so a
# text parsed once is shared; the cache holds at most _CACHE_SIZE short texts
_PARSED: dict[str, Expr] = {}
_CACHED_LENGTH = 64
_CACHE_SIZE = 4096


# -- names ----------------------------------------------------------------------


def _script(ch: str) -> str | None:
    """Return the script of a letter or digit, by its Unicode name; None for neutral ones."""
    if ch.isascii():
        return "Latin" if ch.isalpha() else None
    category = unicodedata.category(ch)
    if not (category[0] == "L" or category == "Nd"):
        return None  # combining marks, connector punctuation: they go with any script
    name = unicodedata.name(ch, "")
    if not name or name.startswith("MODIFIER LETTER"):
        return None
    word = name.removeprefix("EXTENDED ").split(" ")[0].split("-")[0]
    return {"CJK": "Han", "IDEOGRAPHIC": "Han"}.get(word, word.title())


# scripts that mix with Latin in one name, as in Unicode's "moderately
# restrictive" identifiers (UTS #39): Chinese, Japanese and Korean writing
_MIXES_WITH_LATIN = (
    frozenset({"Latin", "Han", "Hiragana", "Katakana"}),
    frozenset({"Latin", "Han", "Bopomofo"}),
    frozenset({"Latin", "Han", "Hangul"}),
)
_LOOK_LIKE_LATIN = frozenset({"Cyrillic", "Greek"})


def normal_name(name: str, *, what: str = "name", node: str | None = None,
                field: str | None = None) -> str:
    """Return a name in Unicode normal form NFKC, checking its length and scripts.

    Python reads identifiers in NFKC, so ``ｌ1`` (fullwidth) means ``l1``;
    names are compared in that form. A name of more than
    :data:`~geokin.budgets.MAX_NAME_LENGTH` characters is refused, and so is
    one that mixes scripts: its letters must be all of one script, or Latin
    with one other script that is neither Cyrillic nor Greek, or Latin with
    Chinese, Japanese or Korean writing (Unicode's "moderately restrictive"
    identifiers, UTS #39). Digits 0-9 and ``_`` go with any script.

    Parameters
    ----------
    name : str
    what : str
        What the name names, for the message ("parameter name").
    node, field : str, optional
        Where the name comes from, for the message.

    Raises
    ------
    ConstructionError
        For a name too long or of mixed scripts.

    Examples
    --------
    >>> normal_name("ｌ1")
    'l1'
    >>> normal_name("θ2"), normal_name("長さ_1")
    ('θ2', '長さ_1')
    >>> normal_name("pаram")  # the second letter is Cyrillic
    Traceback (most recent call last):
    ...
    geokin.errors.ConstructionError: name 'pаram' mixes Latin and Cyrillic letters ('p' and 'а' ...
    """
    article = "an" if what[:1] in tuple("aeiou") else "a"
    if not isinstance(name, str):
        raise ConstructionError(f"{article} {what} must be a string, got {show(name)}",
                                node=node, field=field)
    if len(name) > MAX_NAME_LENGTH:
        raise ConstructionError(f"{article} {what} may have at most {MAX_NAME_LENGTH} characters; "
                                f"{quote(name)} is too long", node=node, field=field)
    if name.isascii():
        return name
    name = unicodedata.normalize("NFKC", name)
    seen: dict[str, str] = {}
    for ch in name:
        script = _script(ch)
        if script is not None:
            seen.setdefault(script, ch)
    scripts = frozenset(seen)
    if len(scripts) <= 1 or any(scripts <= allowed for allowed in _MIXES_WITH_LATIN) or (
            len(scripts) == 2 and "Latin" in scripts and not scripts & _LOOK_LIKE_LATIN):
        return name
    first, second = sorted(scripts, key=lambda s: name.index(seen[s]))[:2]
    raise ConstructionError(
        f"{what} {quote(name)} mixes {first} and {second} letters ({seen[first]!r} and "
        f"{seen[second]!r} {unicodedata.name(seen[second], '').lower()}): letters of "
        "different scripts can look alike, so a name keeps to one script",
        node=node, field=field)


# Cyrillic and Greek letters that look like Latin ones, after NFKC, from the
# Unicode confusables (UTS #39); enough to tell names apart that read the same
_CONFUSABLE = str.maketrans({
    # Cyrillic
    "а": "a", "с": "c", "ԁ": "d", "е": "e", "һ": "h", "і": "i", "ј": "j", "ӏ": "l",
    "о": "o", "р": "p", "ԛ": "q", "ѕ": "s", "ԝ": "w", "х": "x", "у": "y",
    "А": "A", "В": "B", "С": "C", "Е": "E", "Н": "H", "І": "I", "Ј": "J", "К": "K",
    "М": "M", "О": "O", "Р": "P", "Ѕ": "S", "Т": "T", "Х": "X", "У": "Y", "Ӏ": "I",
    "Ԝ": "W",
    # Greek
    "α": "a", "ι": "i", "ν": "v", "ο": "o", "ρ": "p", "υ": "u", "χ": "x",
    "Α": "A", "Β": "B", "Ε": "E", "Ζ": "Z", "Η": "H", "Ι": "I", "Κ": "K", "Μ": "M",
    "Ν": "N", "Ο": "O", "Ρ": "P", "Τ": "T", "Υ": "Y", "Χ": "X",
})


def skeleton(name: str) -> str:
    """Return a name with look-alike letters replaced by the Latin letters they resemble.

    Two names with the same skeleton read the same: a construction refuses
    the second (see :func:`look_alike`). The table covers the Cyrillic and
    Greek letters that look like Latin ones.

    Examples
    --------
    >>> skeleton("В0") == skeleton("B0") == "B0"  # Cyrillic Ve, Latin B
    True
    >>> skeleton("θ2")
    'θ2'
    """
    return name if name.isascii() else name.translate(_CONFUSABLE)


def look_alike(name: str, names: Iterable[str]) -> str | None:
    """Return a name of ``names`` that reads like ``name`` but is not it, or None.

    Examples
    --------
    >>> look_alike("В0", ["A0", "B0"])
    'B0'
    >>> look_alike("B0", ["B0"]) is None
    True
    """
    key = skeleton(name)
    for other in names:
        if other != name and (other == key or skeleton(other) == key):
            return other
    return None
