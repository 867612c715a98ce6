"""Construction scripts: read and write the plain-data TOML files that describe a linkage.

A script is read with the standard library's :mod:`tomllib`; loading never
runs code. Every value is a number or a string holding arithmetic of
numbers, parameter names and input names, parsed by the safe parser of
:mod:`geokin.expressions`: ``+ - * / **``, parentheses, ``pi`` and the
functions ``sqrt abs hypot min max sin cos tan asin acos atan atan2
radians degrees`` (``min`` and ``max`` of two or more values). Each works
elementwise over the samples; a value outside a function's domain
(``acos(1.2)``) makes that sample unassemblable, with the reason.

Units
-----
Angles are **degrees** everywhere in a script: input ranges, steps and
speeds, and every angle field (the ``angle`` of a ``polar`` point). An angle
input is handed to expressions in degrees, so ``angle = "theta + 90"`` means
90 degrees ahead of the input. The trigonometric functions still take and
give radians: write ``sin(radians(theta))``, and
``angle = "degrees(asin(e / l))"``. Lengths are in the script's
``units`` (a label such as ``"mm"``), speeds in degrees (or length units)
per second. The construction a script gives holds radians, as every
construction does: its angle inputs, ranges and angle fields are converted
as the script is read, and back when one is written.

An annotated script
-------------------
::

    [construction]
    name = "six-bar"              # for messages and pictures (default: file name)
    description = "a six-bar"     # optional free text
    units = "mm"                  # label of the length unit (optional)
    trace = ["M"]                 # points whose paths are traced (coupler points)

    [parameters]                  # named constants: numbers or constant arithmetic
    l2 = 20
    l3 = { value = 100, description = "coupler" }   # with a description

    [inputs.theta]                # one table per driving variable
    kind = "angle"                # "angle" (default) or "length"
    range = [0, 1800]             # default sweep: degrees for an angle
    step = 16                     # spacing from range[0]; or samples = 113 (ends included)
    speed = 360                   # degrees (or length units) per second, for time output

    [points]                      # every point, built on points declared anywhere
    A0 = { op = "fixed", at = [0, "y + l1"] }
    A = { op = "polar", origin = "A0", distance = "l2", angle = "theta" }
    B = { op = "circle_circle", centers = ["A", "B0"], radii = ["l3", "l4"], branch = "left" }
    Ap = { op = "line_circle", line = ["A0", "A"], center = "A", radius = "l2p", branch = "first" }

    [links]                       # rigid links, for drawing: two or more points
    crank = ["A0", "A"]

    [sliders]                     # slider blocks: a point sliding on a line
    block = { point = "C", along = ["Ap", "M"] }

Point kinds (``op``)
--------------------
``fixed``           ``at = [x, y]``: a ground pivot.
``polar``           ``origin``, ``distance``, ``angle`` (degrees, counter-clockwise
                    from the x axis, or from the direction ``reference = [P, Q]``).
``local``           ``origin``, ``toward``, ``at = [u, v]``: u along the direction from
                    ``origin`` towards ``toward``, v to its left (a link's own frame).
``along``           ``line = [P, Q]``, ``distance``: signed distance from P towards Q.
``line_line``       ``first = [P, Q]``, ``second = [R, S]``: two lines' crossing.
``line_circle``     ``line = [P, Q]``, ``center``, ``radius``: the whole line P-Q.
``segment_circle``  the same on the segment from P to Q only.
``ray_circle``      the same on the ray from P through Q only.
``circle_circle``   ``centers = [P, Q]``, ``radii = [r, s]``.

Closure groups
--------------
Points no construction reaches one at a time (the triad of a Stephenson III
six-bar) are one group in the ``[groups]`` table, two equations per point::

    [groups.triad]
    points = ["D", "E", "A", "B"]                   # the unknown points
    distances = [["F", "D", "FD"], ["D", "A", 2.6]]  # ... [P, Q, length], 2k in all
    lines = [["B", "C", "G"]]                       # optional: B on the line C-G
    near = { D = [1, 2.9], E = [2.8, 1.5] }         # ... a sketch for every point

They are solved together by Newton's method, on the assembly nearest the
sketch (see :meth:`geokin.construction.Construction.closure`).

The two-root kinds take ``branch`` or ``near = [x, y]``: ``"left"`` or
``"right"`` of the directed line from the first centre to the second for
``circle_circle``; ``"first"`` or ``"second"`` along the direction P -> Q
for the line kinds; ``near`` picks the root nearer to a sketched position
at the first assemblable sample. The sweep then keeps the branch along the
motion (see :mod:`geokin.engine`).

Errors
------
A script that cannot be read raises :class:`~geokin.errors.ScriptError`
naming the file, the line when it can be found, the table and the key,
what is wrong and, for a misspelt name, the closest valid one::

    sixbar.toml:17: [points] B.radii[1]: unknown parameter or input 'l33'; did you mean 'l3'?

The error's attributes ``source``, ``table``, ``key`` and ``line`` hold the
same places (``line`` is None where it cannot be found). What a message
quotes from the script is escaped and shortened (see :mod:`geokin.terminal`),
so that it stays one readable line whatever the script holds.

Limits
------
A script has at most :data:`MAX_SCRIPT_BYTES` bytes; a byte-order mark at
its start is skipped. An integer beyond the range of floating-point numbers
(about ±1.8e308) is an error at its place, as is a ``step`` that would make
more samples than a default sweep may have.

Examples
--------
>>> c = loads('''
... [parameters]
... r = 10
... [inputs.theta]
... range = [0, 90]
... samples = 3
... [points]
... O = { op = "fixed", at = [0, 0] }
... A = { op = "polar", origin = "O", distance = "r", angle = "theta" }
... ''')
>>> from geokin import sweep
>>> sweep(c)["A"].round(9)
array([[10.        ,  0.        ],
       [ 7.07106781,  7.07106781],
       [ 0.        , 10.        ]])
>>> loads(dump(c)) == c
True
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import sys
import tomllib
import warnings
from collections.abc import Mapping

from ..budgets import MAX_SCRIPT_BYTES
from ..construction import MAX_SAMPLES, Construction, Input, default_speed
from ..errors import (
    ConstructionError,
    DegreesWarning,
    PairingWarning,
    RadiansWarning,
    ScriptError,
    did_you_mean,
    quote,
    range_looks_like_radians,
    warn_outside,
)
from ..expressions import BinOp, Call, Expr, Name, Neg, Number, names_only_within
from ..nodes import NODE_KINDS, Closure, Key, Node
from ..terminal import clip_message, escape, shorten
from ..units import script_degrees, to_script

__all__ = ["MAX_SCRIPT_BYTES", "OPS", "dump", "load", "loads", "script_steps"]

"""The most bytes :func:`load` reads of a script (and characters :func:`loads` takes).

A script of 20,000 points is about 1.4 MB; reading stops here, so that a
device or a file that never ends (``/dev/zero``) is refused instead of
filling the memory.
"""

OPS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    kind: (tuple(k.name for k in cls.keys if k.required),
           tuple(k.name for k in cls.keys if not k.required))
    for kind, cls in NODE_KINDS.items()}
"""Required and optional keys of each point kind, besides ``op``; made from
the node kinds' declarations (:attr:`geokin.nodes.Node.keys`)."""

TABLES = ("construction", "parameters", "inputs", "points", "groups", "links", "sliders")
GROUP_KEYS = ("points", "distances", "near", "lines")
CONSTRUCTION_KEYS = ("name", "description", "units", "trace")
INPUT_KEYS = ("kind", "range", "samples", "step", "speed")
SLIDER_KEYS = ("point", "along")

# what each script key of a point holds, by kind and key
_KEYS: dict[str, dict[str, Key]] = {
    kind: {key.name: key for key in cls.keys} for kind, cls in NODE_KINDS.items()}


def _script_field(node_kind: str | None, field: str) -> str:
    """Return a node field as a script names it (a fixed point's ``x`` is ``at[0]``)."""
    for key in _KEYS.get(node_kind or "", {}).values():
        if len(key.attributes) > 1 and field in key.attributes:
            return f"{key.name}[{key.attributes.index(field)}]"
    return field


# -- loading -------------------------------------------------------------------


def load(path: str | os.PathLike[str]) -> Construction:
    r"""Read a construction script from a file.

    Parameters
    ----------
    path : str or os.PathLike
        A TOML construction script (see the module documentation).

    Returns
    -------
    Construction
        In radians, as every construction: angle inputs and angle fields
        are converted from the script's degrees.

    Raises
    ------
    ScriptError
        If the script cannot be read; the message names the file, table and
        key. Also for a file larger than :data:`MAX_SCRIPT_BYTES`.
    OSError
        If the file cannot be opened.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "crank.toml"
    >>> _ = path.write_text('[points]\nO = { op = "fixed", at = [0, 0] }\n')
    >>> load(path)
    <Construction 'crank': 0 parameters, 0 inputs, 1 points>
    """
    path = os.fspath(path)
    with open(path, "rb") as f:
        data = f.read(MAX_SCRIPT_BYTES + 1)
    if len(data) > MAX_SCRIPT_BYTES:
        raise _error(f"{_where(path)}: more than the {MAX_SCRIPT_BYTES:,} bytes a script may "
                     "have; is it a construction script?", source=path)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise _error(f"{_where(path)}: not UTF-8 text ({exc.reason} at byte {exc.start})",
                     source=path) from None
    stem = os.path.splitext(os.path.basename(path))[0]
    return loads(text, source=path, default_name=stem)


def loads(text: str, source: str = "<string>", *, default_name: str | None = None
          ) -> Construction:
    r"""Read a construction script from a string.

    Parameters
    ----------
    text : str
        The script, at most :data:`MAX_SCRIPT_BYTES` characters. A
        byte-order mark at its start is skipped.
    source : str
        The name used for the script in error messages.
    default_name : str, optional
        The construction's name if ``[construction] name`` is not given;
        ``"construction"`` by default.

    Returns
    -------
    Construction

    Raises
    ------
    ScriptError
        If the script cannot be read.

    Examples
    --------
    >>> loads('[points]\nO = { op = "fixd", at = [0, 0] }', source="demo.toml")
    Traceback (most recent call last):
    ...
    geokin.errors.ScriptError: demo.toml:2: [points] O.op: unknown op 'fixd'; did you mean ...
    """
    if len(text) > MAX_SCRIPT_BYTES:
        raise _error(f"{_where(source)}: more than the {MAX_SCRIPT_BYTES:,} characters a "
                     "script may have", source=source)
    if text.startswith("\ufeff"):  # a byte-order mark, as some editors write
        text = text[1:]
    return _Reader(text, source, default_name or "construction").read()


def _where(source: str) -> str:
    """Return a script's name as it is shown in a message: escaped, not absurdly long."""
    return escape(shorten(str(source), 1000))


def _error(message, **attributes) -> ScriptError:
    err = ScriptError(message)
    for key, value in attributes.items():
        setattr(err, key, value)
    return err


def _kind_of(value) -> str:
    """Describe a TOML value's type for messages, quoting at most a short part of it."""
    if isinstance(value, bool):
        return f"the boolean {str(value).lower()}"
    if isinstance(value, int):
        if value.bit_length() > 256:  # printing it in full could take thousands of digits
            return f"an integer of {_digits(value)} digits"
        return f"the integer {value}"
    if isinstance(value, float):
        return f"the number {value!r}"
    if isinstance(value, str):
        return f"the string {shorten(value)!r}"
    if isinstance(value, list):
        return f"an array of {len(value)}"
    if isinstance(value, dict):
        return "a table"
    return f"a {type(value).__name__} ({value})"


def _is_number(value) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _digits(value: int) -> str:
    """Return how many decimal digits an integer has, without writing it out.

    Examples
    --------
    >>> _digits(10**400), _digits(-(10**5000))
    ('401', 'about 5,001')
    """
    bits = abs(value).bit_length()
    if bits <= 13_000:  # well within the 4,300 digits Python writes out
        return f"{len(str(abs(value))):,}"
    return f"about {int(bits * math.log10(2)) + 1:,}"


def _overflowing(data):
    """Yield the place of every integer in parsed TOML too large for a float."""
    waiting = [((), data)]  # a stack, not recursion: TOML nests as deep as tomllib allows
    while waiting:
        path, value = waiting.pop()
        if isinstance(value, dict):
            waiting += reversed([((*path, k), v) for k, v in value.items()])
        elif isinstance(value, list):
            waiting += reversed([((*path, i), v) for i, v in enumerate(value)])
        elif isinstance(value, int) and not isinstance(value, bool):
            try:
                float(value)
            except OverflowError:
                yield path, value


class _Reader:
    """Turns the parsed TOML of one script into a Construction, naming places in errors."""

    def __init__(self, text: str, source: str, default_name: str):
        self.text = text
        self.source = source
        self.default_name = default_name
        self.point_kind: str | None = None  # the kind of the point being declared

    # -- errors --

    def place(self, table: str, entry: str | None, sub: str | None = None
              ) -> tuple[str, str | None, int | None]:
        """Say where ``[table] entry.sub`` is, as messages do; also give its key and line."""
        key = entry if sub is None else f"{entry}.{sub}" if entry else sub
        line = self.locate(table, entry, sub)
        where = _where(self.source) + (f":{line}" if line else "")
        return (f"{where}: [{escape(shorten(table))}]" + (f" {escape(shorten(key))}" if key
                                                         else ""), key, line)

    def fail(self, table: str, entry: str | None, message: str, sub: str | None = None):
        """Return a ScriptError at ``[table] entry.sub``."""
        place, key, line = self.place(table, entry, sub)
        return _error(f"{place}: {clip_message(message)}", source=self.source,
                      table=table, key=key, line=line)

    def fail_on(self, pattern: str, message: str):
        """Return a ScriptError at the first line where ``pattern`` matches the text."""
        found = re.search(pattern, self.text)
        line = self.text.count("\n", 0, found.start()) + 1 if found else None
        where = _where(self.source) + (f":{line}" if line else "")
        return _error(f"{where}: {message}", source=self.source, table=None, key=None,
                      line=line)

    def fail_at(self, path: tuple, message: str):
        """Return a ScriptError at a place in the parsed TOML: (table, entry, key, index...)."""
        table, *rest = [str(p) for p in path[:1]] + list(path[1:])
        if not rest:
            return self.fail(table, None, message)
        entry, *keys = rest
        if isinstance(entry, int):  # an array right under a table: [construction] trace
            return self.fail(table, None, message)
        sub = ""
        for key in keys:
            sub += f"[{key}]" if isinstance(key, int) else f".{key}" if sub else str(key)
        if table == "parameters" and sub == "value":
            sub = ""  # the value of { value = ..., description = ... } is the parameter's
        if sub.startswith("["):  # an entry's own array: [links] crank[1]
            return self.fail(table, f"{entry}{sub}", message)
        return self.fail(table, entry, message, sub or None)

    def locate(self, table: str, entry: str | None, sub: str | None) -> int | None:
        """Find the line of ``[table] entry`` (or of its ``sub`` key), best effort."""
        lines = self.text.splitlines()
        header = re.compile(r"^\s*\[\s*([^\[\]]+?)\s*\]\s*(#.*)?$")
        table_line = entry_line = sub_line = None
        current = None
        base = (sub or "").split("[")[0].split(".")[0]
        entry = None if entry is None else entry.split("[")[0]
        for number, line in enumerate(lines, 1):
            match = header.match(line)
            if match:
                current = re.sub(r"\s*\.\s*", ".", match.group(1)).replace('"', "")
                if current == table and table_line is None:
                    table_line = number
                if entry is not None and current == f"{table}.{entry}" and entry_line is None:
                    entry_line = number
                continue
            key_match = re.match(r'^\s*"?([^"=\s]+)"?\s*=', line)
            if not key_match:
                continue
            key = key_match.group(1)
            if entry is None:
                if current is None and key == table and table_line is None:
                    table_line = number
                continue
            if current == table and key == entry and entry_line is None:
                entry_line = number
                if base and re.search(rf"\b{re.escape(base)}\s*=", line[key_match.end():]):
                    sub_line = number
            elif current == f"{table}.{entry}" and base and key == base and sub_line is None:
                sub_line = number
        return sub_line or entry_line or (table_line if entry is None else None)

    def construction_error(self, err: ConstructionError, table: str, entry: str | None,
                           construction: Construction | None = None) -> ScriptError:
        """Map an engine error to a ScriptError at its table and key."""
        message = err.message  # the place is the script's: file, line, table and key
        field = err.field
        if construction is not None and err.node is not None:
            table, entry = self.table_of(construction, err.node, field)
        if table == "construction" and entry == "trace":
            index = (field or "")[len("points"):] if (field or "").startswith("points") else ""
            return self.fail("construction", "trace" + index, message)
        sub = None
        if field not in (None, "name"):
            if table == "parameters":
                sub = None
            elif table == "links" and entry is not None:
                return self.fail(table, entry + field[len("points"):]
                                 if field.startswith("points") else entry, message)
            elif table == "points":
                node = None if construction is None else construction.nodes.get(entry or "")
                sub = _script_field(node.kind if node else self.point_kind, field)
            else:
                sub = field
        return self.fail(table, entry, message, sub)

    @staticmethod
    def table_of(c: Construction, node: str, field: str | None) -> tuple[str, str]:
        if node == "trace" and (field or "").startswith("points[") and node not in c.links:
            return "construction", "trace"
        for table, names in (("parameters", c.parameters), ("inputs", c.inputs),
                             ("groups", c.groups), ("points", c.nodes), ("links", c.links),
                             ("sliders", c.sliders)):
            if node in names:
                return table, node
        return "construction", node

    # -- reading --

    def read(self) -> Construction:
        try:
            data = tomllib.loads(self.text)
        except tomllib.TOMLDecodeError as exc:
            message = str(exc)
            match = re.search(r"\(at line (\d+), column (\d+)\)$", message)
            line = None
            if match:
                line = int(match.group(1))
                message = (message[:match.start()].rstrip()
                           + f" (column {match.group(2)})")
            elif message.endswith("(at end of document)"):
                line = len(self.text.splitlines()) or 1
                message = message.replace("(at end of document)", "(at the end)")
            if message.startswith("Cannot overwrite a value") and line:
                key = self.text.splitlines()[line - 1].split("=", 1)[0].strip()
                message += f": {shorten(key)!r} is given twice in its table"
            where = _where(self.source) + (f":{line}" if line else "")
            raise _error(f"{where}: TOML syntax error: {clip_message(message)}",
                         source=self.source, table=None, key=None, line=line) from None
        except ValueError:  # an integer longer than Python reads (4,300 digits)
            raise self.fail_on(r"\d{4000,}", "a number of more than 4,000 digits") from None
        except RecursionError:  # tomllib parses nested arrays and tables by recursion
            raise self.fail_on(r"(?:[\[{][\s\w=\"',.-]*){100,}",
                               "arrays or tables nested too deeply") from None
        for path, value in _overflowing(data):
            raise self.fail_at(path, f"{_kind_of(value)} is beyond the range of numbers "
                                     f"(±{sys.float_info.max:.1e})")
        for table in data:
            if table not in TABLES and not isinstance(data[table], dict):
                where = ("it belongs in the [construction] table" if table in CONSTRUCTION_KEYS
                         else f"tables are {', '.join(TABLES)}")
                raise self.fail(table, None, f"a key outside any table; {where}")
            if table not in TABLES:
                raise self.fail(table, None, f"unknown table{did_you_mean(table, TABLES)} "
                                f"(tables: {', '.join(TABLES)})")
            if not isinstance(data[table], dict):
                raise self.fail(table, None, f"expected a table, got {_kind_of(data[table])}")
        if not data.get("points") and not data.get("groups"):
            raise self.fail("points", None, "the script declares no points: a construction "
                            "needs at least a [points] table with one point")
        meta = data.get("construction", {})
        self.check_keys("construction", None, meta, (), CONSTRUCTION_KEYS)
        for key in ("name", "description", "units"):
            if key in meta and not isinstance(meta[key], str):
                raise self.fail("construction", key,
                                f"expected a string, got {_kind_of(meta[key])}")
        c = Construction(meta.get("name", self.default_name),
                         description=meta.get("description", ""), units=meta.get("units", ""))
        for name, value in data.get("parameters", {}).items():
            self.declare(c, "parameters", name, self.parameter, value)
        with warnings.catch_warnings():
            # a script's angles are degrees, converted as it is read: never a mistake
            warnings.simplefilter("ignore", DegreesWarning)
            for name, value in data.get("inputs", {}).items():
                self.declare(c, "inputs", name, self.input, value)
            for name, value in data.get("points", {}).items():
                self.declare(c, "points", name, self.point, value)
        self.warn_of_pairing(c, data.get("inputs", {}))
        for name, value in data.get("groups", {}).items():
            self.declare(c, "groups", name, self.group, value)
        for name, value in data.get("links", {}).items():
            self.declare(c, "links", name, self.link, value)
        for name, value in data.get("sliders", {}).items():
            self.declare(c, "sliders", name, self.slider, value)
        if "trace" in meta:
            trace = meta["trace"]
            if isinstance(trace, str):
                trace = [trace]
            if not isinstance(trace, list):
                raise self.fail("construction", "trace",
                                f"expected an array of point names, got {_kind_of(trace)}")
            for i, p in enumerate(trace):
                if not isinstance(p, str):
                    raise self.fail("construction", f"trace[{i}]",
                                    f"expected a point name (a string), got {_kind_of(p)}")
            c.trace(*trace)
        # inside geokin every angle is radians: the script's degrees end here
        to_radians = _AngleRewriter(c, to_script=False)
        for name, node in list(c.nodes.items()):
            c.nodes[name] = to_radians.node(node)
        try:
            c.compile()
        except ScriptError:
            raise
        except ConstructionError as err:
            raise self.construction_error(err, "construction", None, c) from None
        return c

    def declare(self, c, table, name, declare, value):
        try:
            declare(c, name, value)
        except ScriptError:
            raise
        except ConstructionError as err:
            raise self.construction_error(err, table, name) from None
        except OverflowError as err:  # a number too large or too small to compute with
            raise self.fail(table, name, f"a number is out of range ({err})") from None

    def check_keys(self, table, entry, value: Mapping, required, optional):
        allowed = (*required, *optional)
        for key in value:
            if key not in allowed:
                message = (f"unknown key {key!r}{did_you_mean(key, allowed)} "
                           f"(keys: {', '.join(allowed)})")
                if entry is None:
                    raise self.fail(table, key, message)
                raise self.fail(table, entry, message, sub=key)
        for key in required:
            if key not in value:
                raise self.fail(table, entry, f"missing key {key!r} "
                                f"(required: {', '.join(required)})", sub=key)

    def table_value(self, table, name, value, example):
        if not isinstance(value, dict):
            raise self.fail(table, name, f"expected a table such as {example}, "
                            f"got {_kind_of(value)}")
        return value

    def parameter(self, c, name, value):
        description = ""
        if isinstance(value, dict):
            self.check_keys("parameters", name, value, ("value",), ("description",))
            description = value.get("description", "")
            if not isinstance(description, str):
                raise self.fail("parameters", name, f"expected a string, got "
                                f"{_kind_of(description)}", sub="description")
            value = value["value"]
        if not (_is_number(value) or isinstance(value, str)):
            raise self.fail("parameters", name, f"expected a number, got {_kind_of(value)}")
        c.parameter(name, value, description)

    def input(self, c, name, spec):
        spec = self.table_value("inputs", name, spec, '{ kind = "angle", range = [0, 360] }')
        self.check_keys("inputs", name, spec, (), INPUT_KEYS)
        kind = spec.get("kind", "angle")
        if not isinstance(kind, str):
            raise self.fail("inputs", name, f"expected \"angle\" or \"length\", got "
                            f"{_kind_of(kind)}", sub="kind")
        scale = math.radians if kind == "angle" else float
        options = {}
        plain = ("; an input's range, step and speed are plain numbers, not expressions"
                 + (" (in degrees: 360 for a turn)" if kind == "angle" else ""))
        if "range" in spec:
            lo_hi = spec["range"]
            if not (isinstance(lo_hi, list) and len(lo_hi) == 2):
                raise self.fail("inputs", name, f"expected two numbers [start, end], got "
                                f"{_kind_of(lo_hi)}", sub="range")
            for i, end in enumerate(lo_hi):
                if not _is_number(end):
                    raise self.fail("inputs", name, f"expected a number, got {_kind_of(end)}"
                                    + (plain if isinstance(end, str) else ""),
                                    sub=f"range[{i}]")
            options["range"] = tuple(scale(v) for v in lo_hi)
            if kind == "angle" and range_looks_like_radians(*lo_hi):
                turns = f"{abs(lo_hi[1] - lo_hi[0]) / (2 * math.pi):.3g}"
                warn_outside(f"{self.place('inputs', name, 'range')[0]}: a range of "
                             f"{lo_hi[0]:g} to {lo_hi[1]:g} degrees is {turns} "
                             f"turn{'' if turns == '1' else 's'} in radians, but a script's "
                             "angles are degrees ([0, 360] is a full turn)", RadiansWarning)
        if "samples" in spec and "step" in spec:
            raise self.fail("inputs", name, "give either samples or step, not both", sub="step")
        if "samples" in spec:
            samples = spec["samples"]
            if not isinstance(samples, int) or isinstance(samples, bool):
                raise self.fail("inputs", name, f"expected an integer, got {_kind_of(samples)}",
                                sub="samples")
            options["samples"] = samples
        for key in ("step", "speed"):
            if key in spec:
                if not _is_number(spec[key]):
                    raise self.fail("inputs", name, f"expected a number, got "
                                    f"{_kind_of(spec[key])}"
                                    + (plain if isinstance(spec[key], str) else ""), sub=key)
                options[key] = scale(spec[key])
        speed = spec.get("speed")
        if speed is not None and not speed > 0:
            # said in the script's units: the construction would say radians
            raise self.fail("inputs", name, f"speed must be a positive number (how fast the "
                            f"input moves, {'degrees' if kind == 'angle' else 'lengths'} per "
                            f"second; a sweep's direction sets its sign), got {speed!r}",
                            sub="speed")
        step = options.get("step")
        if step and math.isfinite(step):
            lo, hi = options.get("range", (0.0, 2 * math.pi))
            count = abs(hi - lo) / abs(step)  # inf for a step too small to divide by
            if not count < MAX_SAMPLES:
                raise self.fail("inputs", name, f"step {spec['step']!r} makes more than the "
                                f"{MAX_SAMPLES:,} samples a default sweep may have",
                                sub="step")
        c.input(name, kind, **options)

    def warn_of_pairing(self, c, specs) -> None:
        """Warn of samples or a speed of an input after the first that a default sweep changes.

        Inputs are swept together (:class:`~geokin.PairingWarning`): the first
        sets how many samples there are and how long they take.
        """
        if len(c.inputs) < 2:
            return
        first, *others = c.inputs.values()
        count = first.sample_count()
        low, high = first.range
        span = high - low if first.step is None else (count - 1) * first.step
        seconds = abs(span) / first.speed
        # the inputs in the order the script declares them, with the keys it gives them
        for (key, spec), inp in list(zip(specs.items(), c.inputs.values(), strict=True))[1:]:
            if ("samples" in spec or "step" in spec) and inp.sample_count() != count:
                given = "samples" if "samples" in spec else "step"
                warn_outside(f"{self.place('inputs', key, given)[0]}: a sweep of the declared "
                             f"ranges takes input {quote(inp.name)} with the first input, "
                             f"{quote(first.name)}, over its {count:,} samples, not over "
                             f"{inp.sample_count():,}", PairingWarning)
            if "speed" in spec and seconds > 0:
                rate = to_script(inp, abs(inp.range[1] - inp.range[0]) / seconds)
                declared = to_script(inp, inp.speed)
                if not math.isclose(rate, declared, rel_tol=1e-9):
                    unit = "deg/s" if inp.kind == "angle" else f"{c.units or 'units'}/s"
                    warn_outside(f"{self.place('inputs', key, 'speed')[0]}: a sweep of the "
                                 f"declared ranges moves input {quote(inp.name)} at "
                                 f"{rate:.6g} {unit}, not its declared {declared:.6g}: "
                                 f"swept with the first input, {quote(first.name)}, it covers "
                                 f"its range in the {seconds:.6g} s that {quote(first.name)} "
                                 "takes", PairingWarning)

    def point(self, c, name, spec):
        spec = self.table_value("points", name, spec, '{ op = "fixed", at = [0, 0] }')
        if "op" not in spec:
            raise self.fail("points", name, f"missing key 'op' (ops: {', '.join(OPS)})",
                            sub="op")
        op = spec["op"]
        if not isinstance(op, str):
            raise self.fail("points", name, f"expected an op name (a string), got "
                            f"{_kind_of(op)}", sub="op")
        if op not in OPS:
            raise self.fail("points", name, f"unknown op {op!r}{did_you_mean(op, OPS)} "
                            f"(ops: {', '.join(OPS)})", sub="op")
        required, optional = OPS[op]
        fields = {k: v for k, v in spec.items() if k != "op"}
        self.check_keys("points", name, fields, required, optional)
        keys = _KEYS[op]
        for key, value in fields.items():
            self.check_type(name, keys[key], value)
        self.point_kind = op
        c.add(op, name, **fields)

    def check_type(self, name, key: Key, value):
        """Check the TOML type of one point key; the builder checks the rest."""
        def wrong(expected, sub=key.name):
            return self.fail("points", name, f"expected {expected}, got {_kind_of(value)}",
                             sub=sub)
        if key.holds == "point" and not isinstance(value, str):
            raise wrong("a point name (a string)")
        if key.holds == "point pair":
            if not (isinstance(value, list) and len(value) == 2):
                raise wrong("two point names such as [\"A\", \"B\"]")
            for i, p in enumerate(value):
                if not isinstance(p, str):
                    value = p
                    raise wrong("a point name (a string)", f"{key.name}[{i}]")
        if key.holds == "value pair" and not (isinstance(value, list) and len(value) == 2):
            raise wrong("two values such as [0, \"l1\"]")
        if key.holds == "branch" and not isinstance(value, str):
            raise wrong("a branch name (a string)")
        if key.holds == "sketch" and not (isinstance(value, list) and len(value) == 2
                                          and all(map(_is_number, value))):
            raise wrong("two numbers [x, y]")

    def link(self, c, name, points):
        if not isinstance(points, list):
            raise self.fail("links", name, f"expected an array of point names, got "
                            f"{_kind_of(points)}")
        for i, p in enumerate(points):
            if not isinstance(p, str):
                raise self.fail("links", f"{name}[{i}]",
                                f"expected a point name (a string), got {_kind_of(p)}")
        c.link(name, *points)

    def group(self, c, name, spec):
        spec = self.table_value("groups", name, spec,
                                '{ points = ["D"], distances = [["F", "D", 2.9], ...], '
                                'near = { D = [1, 2.9] } }')
        self.check_keys("groups", name, spec, GROUP_KEYS[:3], GROUP_KEYS[3:])
        near = spec["near"]
        if not isinstance(near, dict):
            raise self.fail("groups", name, "expected a table of sketch positions such as "
                            f"{{ D = [1, 2.9] }}, got {_kind_of(near)}", sub="near")
        c.closure(name, spec["points"], spec["distances"], near, spec.get("lines", ()))

    def slider(self, c, name, spec):
        spec = self.table_value("sliders", name, spec, '{ point = "C", along = ["A", "B"] }')
        self.check_keys("sliders", name, spec, SLIDER_KEYS, ())
        if not isinstance(spec["point"], str):
            raise self.fail("sliders", name, f"expected a point name (a string), got "
                            f"{_kind_of(spec['point'])}", sub="point")
        along = spec["along"]
        if not (isinstance(along, list) and len(along) == 2
                and all(isinstance(p, str) for p in along)):
            raise self.fail("sliders", name, f"expected two point names such as [\"A\", \"B\"], "
                            f"got {_kind_of(along)}", sub="along")
        c.slider(name, spec["point"], along)


# -- dumping -------------------------------------------------------------------


def dump(construction: Construction) -> str:
    """Write a construction as a script that :func:`loads` reads back.

    Every construction holds radians; the script is written in degrees:
    angle inputs appear in degrees, and each angle field is rewritten, for
    example ``theta + pi / 2`` as ``theta + 90``, or wrapped in
    ``degrees(...)`` with the angle inputs referenced as ``radians(name)``
    where no simpler form is known. A parameter that serves only as an
    angle is written in degrees too, its uses as an angle input's. A
    construction read from a script is written back as the script it was
    read from, but for such a parameter, and for the samples and speed of
    an input after the first, written only where they are not the defaults
    (the first input's set them: :class:`~geokin.PairingWarning`).

    Parameters
    ----------
    construction : Construction

    Returns
    -------
    str
        The script's text.

    Examples
    --------
    >>> import numpy as np
    >>> from geokin import Construction
    >>> c = Construction("crank")
    >>> c.input("theta", range=(0, np.pi), samples=5)
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta + pi / 2")
    >>> print(dump(c))
    [construction]
    name = "crank"
    <BLANKLINE>
    [inputs.theta]
    kind = "angle"
    range = [0, 180]
    samples = 5
    speed = 360
    <BLANKLINE>
    [points]
    O = { op = "fixed", at = [0, 0] }
    A = { op = "polar", origin = "O", distance = 10, angle = "theta + 90" }
    <BLANKLINE>
    """
    if not isinstance(construction, Construction):
        raise TypeError(f"expected a Construction, got {type(construction).__name__}")
    c = construction
    convert, in_degrees = _to_script(c)
    out = ["[construction]", f"name = {_toml_string(c.name)}"]
    if c.description:
        out.append(f"description = {_toml_string(c.description)}")
    if c.units:
        out.append(f"units = {_toml_string(c.units)}")
    if c.traced:
        out.append(f"trace = {_toml_list(c.traced)}")
    if c.parameters:
        out += ["", "[parameters]"]
        for p in c.parameters.values():
            value = _toml_number(script_degrees(p.value) if p.name in in_degrees else p.value)
            if p.description:
                out.append(f"{_toml_key(p.name)} = {{ value = {value}, "
                           f"description = {_toml_string(p.description)} }}")
            else:
                out.append(f"{_toml_key(p.name)} = {value}")
    for position, i in enumerate(c.inputs.values()):
        low, high = (_toml_number(to_script(i, v)) for v in i.range)
        out += ["", f"[inputs.{_toml_key(i.name)}]", f"kind = {_toml_string(i.kind)}",
                f"range = [{low}, {high}]"]
        # the first input's samples and speed set every input's (PairingWarning): a later
        # one's are written only where they are not the defaults, as someone gave them
        later = position > 0
        if i.step is not None:
            out.append(f"step = {_toml_number(to_script(i, i.step))}")
        elif not later or i.samples != Input.samples:
            out.append(f"samples = {i.samples}")
        if not later or i.speed != default_speed(i.kind):
            out.append(f"speed = {_toml_number(to_script(i, i.speed))}")
    points = [node for node in c.nodes.values() if not isinstance(node, Closure)]
    if points:
        out += ["", "[points]"]
        for node in points:
            out.append(f"{_toml_key(node.name)} = {_inline_table(_node_entries(node, convert))}")
    for group, names in c.groups.items():
        node = c.nodes[names[0]]
        assert isinstance(node, Closure)
        out += ["", f"[groups.{_toml_key(group)}]", f"points = {_toml_list(names)}",
                "distances = ["]
        out += [f"    [{_toml_string(p)}, {_toml_string(q)}, {_toml_expr(convert.plain(d))}],"
                for p, q, d in node.distances]
        out.append("]")
        if node.lines:
            out.append("lines = [" + ", ".join(_toml_list(line) for line in node.lines) + "]")
        out.append("near = " + _inline_table([
            (_toml_key(p), f"[{_toml_number(x)}, {_toml_number(y)}]")
            for p, (x, y) in zip(names, node.near, strict=True)]))
    if c.links:
        out += ["", "[links]"]
        for link in c.links.values():
            out.append(f"{_toml_key(link.name)} = {_toml_list(link.points)}")
    if c.sliders:
        out += ["", "[sliders]"]
        for s in c.sliders.values():
            out.append(f"{_toml_key(s.name)} = {{ point = {_toml_string(s.point)}, "
                       f"along = {_toml_list(s.along)} }}")
    return "\n".join(out) + "\n"


def _to_script(construction: Construction) -> tuple[_AngleRewriter, set[str]]:
    """Return the rewriter of a construction's values into a script, and its degree parameters.

    A parameter that stands only as an angle is written in degrees, as a
    script's angles are: beta = 40 and angle = "beta", not 0.698... and
    "degrees(beta)".
    """
    convert = _AngleRewriter(construction, to_script=True)
    in_degrees = _radian_parameters(construction, convert)
    if in_degrees:
        convert = _AngleRewriter(construction, to_script=True, angle_parameters=in_degrees)
    return convert, in_degrees


def _radian_parameters(construction: Construction, convert: _AngleRewriter) -> set[str]:
    """Return the parameters that every field written to a script takes in ``degrees(...)``.

    Such a parameter holds radians and serves only as an angle: written in
    degrees, it reads as a script's angles do.
    """
    values = [value for node in construction.nodes.values()
              for value in convert.node(node).value_fields().values()]
    # one whose value in degrees is beyond the floats stays in radians
    return {name for name in names_only_within(values, "degrees")
            if name in construction.parameters
            and math.isfinite(math.degrees(construction.parameters[name].value))}


def script_steps(construction: Construction) -> str:
    r"""Return the compiled steps as text, with angles in degrees as a script has them.

    Inside geokin every angle is radians; ``str(construction.compile())``
    shows an angle field of 30 degrees as ``30 deg`` but keeps the angle
    inputs' radians (``theta + 30 deg``); this shows every angle as the
    script writes it, the angle inputs in degrees (``theta + 30``).

    Examples
    --------
    >>> c = loads('[inputs.theta]\n[points]\nO = { op = "fixed", at = [0, 0] }\n'
    ...           'A = { op = "polar", origin = "O", distance = 10, angle = "theta + 30" }\n')
    >>> print(script_steps(c))
    construction 'construction': 2 steps
      1  O = fixed(0, 0)
      2  A = polar(O, 10, theta + 30)
    """
    compiled = construction.compile()
    to_script, _ = _to_script(construction)
    steps = tuple(dataclasses.replace(step, node=to_script.node(step.node))
                  for step in compiled.steps)
    return dataclasses.replace(compiled, steps=steps).listing(degrees=False)


def _node_entries(node: Node, convert: _AngleRewriter) -> list[tuple[str, str]]:
    """Return the ``key = value`` pairs of a node's inline table, as TOML text."""
    values = node.value_fields()
    angles = node.angle_fields()

    def value(field):
        expr = values[field]
        return _toml_expr(convert.angle(expr) if field in angles else convert.plain(expr))

    entries = [("op", _toml_string(node.kind))]
    for key in node.keys:
        given = [getattr(node, a) for a in key.attributes]
        if given[0] is None:
            continue  # an optional key not given
        if key.holds == "point":
            text = _toml_string(given[0])
        elif key.holds == "point pair":
            text = _toml_list(given[0])
        elif key.holds == "value":
            text = value(key.fields()[0])
        elif key.holds == "value pair":
            text = f"[{', '.join(value(f) for f in key.fields())}]"
        elif key.holds == "sketch":
            text = f"[{_toml_number(given[0][0])}, {_toml_number(given[0][1])}]"
        else:  # a branch
            text = _toml_string(given[0])
        entries.append((key.name, text))
    return entries


def _inline_table(entries) -> str:
    return "{ " + ", ".join(f"{k} = {v}" for k, v in entries) + " }"


def _toml_string(text: str) -> str:
    escapes = {'"': '\\"', "\\": "\\\\", "\n": "\\n", "\t": "\\t", "\r": "\\r", "\b": "\\b",
               "\f": "\\f"}
    body = "".join(escapes.get(ch, ch if ch.isprintable() or ch == " " else f"\\u{ord(ch):04x}")
                   for ch in text)
    return f'"{body}"'


def _toml_list(names) -> str:
    return "[" + ", ".join(_toml_string(n) for n in names) + "]"


def _toml_key(name: str) -> str:
    """Return a name as a TOML key: bare when it can be, quoted otherwise."""
    return name if re.fullmatch(r"[A-Za-z0-9_-]+", name) else _toml_string(name)


def _toml_number(value: float) -> str:
    value = float(value)
    if math.isnan(value):
        return "nan"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return str(Number(value))  # the shortest text that reads back exactly, as in expressions


def _toml_expr(expr: Expr) -> str:
    if isinstance(expr, Number):
        return _toml_number(expr.value)
    # str() writes the text that parses back to the same tree (see geokin.expressions)
    return _toml_string(str(expr))


class _AngleRewriter:
    """Rewrite expressions between a radians construction and a degrees script.

    Towards a script (``to_script=True``) every angle input holds degrees,
    so each use of one in an expression becomes ``radians(name)``, and an
    angle field ``e`` becomes ``degrees(e)``. From a script it is the other
    way round: ``degrees(name)`` and ``radians(e)``. Both are simplified
    where the rewriting is exact and obvious (``theta + pi / 2`` and
    ``theta + 90``), so a script read and written again is the same text.
    """

    def __init__(self, construction: Construction, *, to_script: bool,
                 angle_parameters: frozenset[str] | set[str] = frozenset()):
        # angle parameters: parameters that hold an angle in the script's unit, as inputs do
        self.angles = frozenset(n for n, i in construction.inputs.items()
                                if i.kind == "angle") | angle_parameters
        self.to_script = to_script
        # how an angle input reads on the other side, and how an angle field is wrapped
        self.read, self.wrap = ("radians", "degrees") if to_script else ("degrees", "radians")

    def number(self, value: float) -> float:
        """Return an angle's number on the other side."""
        # towards a script, the shortest degree value that reads back as exactly this
        return script_degrees(value) if self.to_script else math.radians(value)

    def angular(self, expr: Expr) -> bool:
        """Whether an expression involves an angle input, pi or a conversion.

        A conversion either way counts: ``degrees(asin(r))`` in a script is
        the angle of a product ``2 * degrees(asin(r))``, as ``theta`` is.
        """
        if isinstance(expr, Name):
            return expr.name in self.angles or expr.name == "pi"
        if isinstance(expr, Neg):
            return self.angular(expr.operand)
        if isinstance(expr, BinOp):
            return self.angular(expr.left) or self.angular(expr.right)
        if isinstance(expr, Call):
            return (expr.function in (self.wrap, self.read)
                    or any(self.angular(a) for a in expr.args))
        return False

    def plain(self, expr: Expr) -> Expr:
        """Return ``expr`` with each angle input read in the other unit."""
        if isinstance(expr, Name) and expr.name in self.angles:
            return Call(self.read, (expr,))
        if isinstance(expr, Neg):
            return Neg(self.plain(expr.operand))
        if isinstance(expr, BinOp):
            return BinOp(expr.op, self.plain(expr.left), self.plain(expr.right))
        if isinstance(expr, Call):
            (first, *_) = expr.args
            if (expr.function == self.wrap and isinstance(first, Name)
                    and first.name in self.angles):
                return first
            return Call(expr.function, tuple(self.plain(a) for a in expr.args))
        return expr

    def angle(self, expr: Expr) -> Expr:
        """Return an expression on the other side equal to the angle ``expr``."""
        if isinstance(expr, Number):
            return Number(self.number(expr.value))
        if isinstance(expr, Name):
            if expr.name in self.angles:
                return expr
            if expr.name == "pi" and self.to_script:
                return Number(180.0)
            return Call(self.wrap, (expr,))
        if isinstance(expr, Call) and expr.function == self.read:
            return self.plain(expr.args[0])
        if isinstance(expr, Neg):
            inner = self.angle(expr.operand)
            return Number(-inner.value) if isinstance(inner, Number) else Neg(inner)
        if isinstance(expr, BinOp):
            if expr.op in "+-":
                return _fold(expr.op, self.angle(expr.left), self.angle(expr.right))
            if expr.op == "*":
                # the factor that carries the angle is converted; of two that carry
                # none, the one that is not a number (2 * atan2(y, x) is written
                # 2 * degrees(atan2(y, x)), not 114.59... * atan2(y, x))
                left, right = expr.left, expr.right
                if not self.angular(left) and (self.angular(right) or (
                        isinstance(left, Number) and not isinstance(right, Number))):
                    return _fold("*", self.plain(left), self.angle(right))
                return _fold("*", self.angle(left), self.plain(right))
            if expr.op == "/":
                return _fold("/", self.angle(expr.left), self.plain(expr.right))
        return Call(self.wrap, (self.plain(expr),))

    def node(self, node: Node) -> Node:
        """Return ``node`` with every value field rewritten."""
        changes: dict[str, object] = {}
        if isinstance(node, Closure):  # a group's distances: lengths
            changes["distances"] = tuple((p, q, self.plain(d)) for p, q, d in node.distances)
        # the node's value keys say which of its fields hold values and which are angles
        for key in node.keys:
            if key.holds not in ("value", "value pair"):
                continue
            convert = self.angle if key.angle else self.plain
            for attribute in key.attributes:
                value = getattr(node, attribute)
                changes[attribute] = (convert(value) if isinstance(value, Expr)
                                      else tuple(convert(v) for v in value))
        # mypy checks replace() against Node, whose only field is the name, not the
        # node's own class
        return dataclasses.replace(node, **changes)  # type: ignore[arg-type]


def _fold(op: str, left: Expr, right: Expr) -> Expr:
    """Return ``left op right``, computed when both are numbers."""
    if isinstance(left, Number) and isinstance(right, Number):
        if op == "+":
            return Number(left.value + right.value)
        if op == "-":
            return Number(left.value - right.value)
        if op == "*":
            return Number(left.value * right.value)
        if op == "/" and right.value != 0:
            return Number(left.value / right.value)
    if op in "+-" and isinstance(right, Number) and right.value == 0:
        return left
    return BinOp(op, left, right)
