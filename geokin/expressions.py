"""Values of a construction: numbers, names, and arithmetic of them.

A value is an :class:`Expr`: a number, the name of a parameter or input, or
arithmetic (``+ - * / **``, unary minus, parentheses) and the functions
``sqrt sin cos tan atan2 radians degrees`` with the constant ``pi``.
Strings are parsed by :func:`parse`, which reads Python's expression grammar
with :mod:`ast` and accepts only those node kinds: no ``eval``, no attribute
access, no subscripts and no calls outside that list, so parsing a script
never runs code. The trigonometric functions work in radians.

Examples
--------
>>> e = parse("y + l1")
>>> sorted(e.names())
['l1', 'y']
>>> float(e.evaluate({"y": 20, "l1": 10}))
30.0
>>> str(parse("2 * (a + b) ** 2"))
'2 * (a + b) ** 2'
"""

from __future__ import annotations

import ast
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .errors import ConstructionError

__all__ = ["Expr", "FUNCTIONS", "as_expr", "parse"]

FUNCTIONS = {
    "sqrt": (1, np.sqrt),
    "sin": (1, np.sin),
    "cos": (1, np.cos),
    "tan": (1, np.tan),
    "atan2": (2, np.arctan2),
    "radians": (1, np.radians),
    "degrees": (1, np.degrees),
}
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
    other expressions: ``as_expr("l3") + 5``.
    """

    __slots__ = ()

    def names(self) -> frozenset[str]:
        """Return the names of parameters and inputs this value depends on."""
        raise NotImplementedError

    def evaluate(self, env: Mapping[str, object]):
        """Return the value, with each name looked up in ``env``.

        Invalid operations give NaN or inf as numpy does; wrap the call in
        ``np.errstate`` to silence their warnings.
        """
        raise NotImplementedError

    def _precedence(self) -> int:
        return 5

    # arithmetic builds new expressions
    def __add__(self, other):
        return BinOp("+", self, as_expr(other))

    def __radd__(self, other):
        return BinOp("+", as_expr(other), self)

    def __sub__(self, other):
        return BinOp("-", self, as_expr(other))

    def __rsub__(self, other):
        return BinOp("-", as_expr(other), self)

    def __mul__(self, other):
        return BinOp("*", self, as_expr(other))

    def __rmul__(self, other):
        return BinOp("*", as_expr(other), self)

    def __truediv__(self, other):
        return BinOp("/", self, as_expr(other))

    def __rtruediv__(self, other):
        return BinOp("/", as_expr(other), self)

    def __pow__(self, other):
        return BinOp("**", self, as_expr(other))

    def __rpow__(self, other):
        return BinOp("**", as_expr(other), self)

    def __neg__(self):
        return Neg(self)

    def __repr__(self):
        return f"Expr({str(self)!r})"


@dataclass(frozen=True, slots=True, repr=False)
class Number(Expr):
    """A constant."""

    value: float

    def names(self):
        return frozenset()

    def evaluate(self, env):
        return self.value

    def __str__(self):
        value = self.value
        if math.isfinite(value) and value == int(value) and abs(value) < 1e15:
            return str(int(value))
        return repr(value)

    def _precedence(self):
        return 3 if self.value < 0 else 5


@dataclass(frozen=True, slots=True, repr=False)
class Name(Expr):
    """A parameter, an input or the constant ``pi``."""

    name: str

    def names(self):
        return frozenset() if self.name in CONSTANTS else frozenset([self.name])

    def evaluate(self, env):
        if self.name in CONSTANTS:
            return CONSTANTS[self.name]
        return env[self.name]

    def __str__(self):
        return self.name


@dataclass(frozen=True, slots=True, repr=False)
class Neg(Expr):
    """Unary minus."""

    operand: Expr

    def names(self):
        return self.operand.names()

    def evaluate(self, env):
        return np.negative(self.operand.evaluate(env))

    def __str__(self):
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

    def names(self):
        return self.left.names() | self.right.names()

    def evaluate(self, env):
        return _APPLY[self.op](self.left.evaluate(env), self.right.evaluate(env))

    def _precedence(self):
        return _PRECEDENCE[self.op]

    def __str__(self):
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

    def names(self):
        return frozenset().union(*(a.names() for a in self.args))

    def evaluate(self, env):
        return FUNCTIONS[self.function][1](*(a.evaluate(env) for a in self.args))

    def __str__(self):
        return f"{self.function}({', '.join(str(a) for a in self.args)})"


def as_expr(value, *, node: str | None = None, field: str | None = None) -> Expr:
    """Turn a number, a string or an :class:`Expr` into an :class:`Expr`.

    Examples
    --------
    >>> as_expr(3)
    Expr('3')
    >>> as_expr("l2 / 2")
    Expr('l2 / 2')
    """
    if isinstance(value, Expr):
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
            raise ConstructionError(f"expected a finite number, got {value!r}", node=node,
                                    field=field)
        return Number(number)
    if isinstance(value, str):
        return parse(value, node=node, field=field)
    raise ConstructionError(
        f"expected a number or an expression, got {type(value).__name__} {value!r}",
        node=node, field=field)


def parse(text: str, *, node: str | None = None, field: str | None = None) -> Expr:
    """Parse an arithmetic expression safely.

    Parameters
    ----------
    text : str
        The expression, in Python syntax restricted to numbers, names,
        ``+ - * / **``, parentheses and calls of :data:`FUNCTIONS`.
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
    """
    def fail(message):
        shown = text if len(text) <= 80 else text[:77] + "..."
        return ConstructionError(f"expression {shown!r}: {message}", node=node, field=field)

    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise fail(f"not a valid expression ({exc.msg})") from None
    except (RecursionError, MemoryError):
        raise fail("too deeply nested") from None
    def build(item: ast.AST) -> Expr:
        if isinstance(item, ast.Constant):
            if isinstance(item.value, bool) or not isinstance(item.value, int | float):
                raise fail(f"{item.value!r} is not a number")
            try:
                number = float(item.value)
            except OverflowError:
                raise fail(f"the number {str(item.value)[:20]}... is too large") from None
            if not math.isfinite(number):
                raise fail(f"{item.value!r} is not a finite number")
            return Number(number)
        if isinstance(item, ast.Name):
            return Name(item.id)
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
                raise fail(f"unknown function {name!r}; allowed: {', '.join(FUNCTIONS)}")
            if item.keywords:
                raise fail(f"{name}() takes no keyword arguments")
            arity = FUNCTIONS[name][0]
            if len(item.args) != arity:
                raise fail(f"{name}() takes {arity} argument{'s' * (arity > 1)}, "
                           f"got {len(item.args)}")
            return Call(name, tuple(build(a) for a in item.args))
        kind = type(item).__name__
        raise fail(f"{kind} is not allowed; use numbers, names, + - * / ** and "
                   f"{', '.join(FUNCTIONS)}")

    try:
        return build(tree.body)
    except RecursionError:
        raise fail("too deeply nested") from None
