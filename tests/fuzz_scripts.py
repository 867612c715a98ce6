"""Mutated construction scripts: geokin must succeed or raise GeokinError, nothing else.

Every script in ``constructions/`` and ``examples/`` is mutated: keys dropped,
values of the wrong type, names swapped, misspelt or made hostile, cycles,
huge and tiny numbers, hostile expressions, control characters, random
bytes. Each mutant then goes through what ``geokin check`` does: load,
compile, print the steps, write the script back and read it again, sweep a
few samples, and the ``check`` command itself, in-process. The only
outcomes allowed are success and :class:`geokin.GeokinError`; the command
must exit 0 or 2 and print only escaped lines.

The suite runs a few hundred cases (``tests/test_fuzz.py``); a longer run::

    python tests/fuzz_scripts.py --cases 10000

prints how many cases ended in each way, every exception of another kind
with a script that reproduces it, and the slowest cases; it exits 1 if any
case raised something else or took over ``--slow`` seconds (5 by default).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import pathlib
import random
import signal
import sys
import tempfile
import time
import tomllib
import traceback
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
SOURCES = sorted([*ROOT.glob("constructions/*.toml"), *ROOT.glob("examples/*.toml")])
TABLES = ("construction", "parameters", "inputs", "points", "links", "sliders")

KNOWN: dict[tuple[str, str], str] = {}
"""Faults known in the layers below the edge, as (exception, file of geokin raising
it) -> cause: only exactly these would be let through, and the long run lists them
apart. None are known."""
"""Exceptions known to come from a fault filed elsewhere, by (class name, geokin file)."""


# -- writing TOML ---------------------------------------------------------------------

def toml_key(key) -> str:
    key = str(key)
    if key and all(c.isascii() and (c.isalnum() or c in "_-") for c in key):
        return key
    return toml_string(key)


def toml_string(text: str) -> str:
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ch.isprintable() and not 0xD800 <= ord(ch) <= 0xDFFF:
            out.append(ch)
        elif ord(ch) <= 0xFFFF and not 0xD800 <= ord(ch) <= 0xDFFF:
            out.append(f"\\u{ord(ch):04x}")
        elif ord(ch) > 0xFFFF:
            out.append(f"\\U{ord(ch):08x}")
        else:  # a lone surrogate cannot be written in TOML
            out.append("?")
    return '"' + "".join(out) + '"'


def toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        if abs(value).bit_length() > 13_000:  # more digits than Python writes in decimal
            return f"0x{value:x}" if value > 0 else "-1" + "0" * 4000
        return str(value)
    if isinstance(value, float):
        if value != value:
            return "nan"
        if value in (float("inf"), float("-inf")):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return toml_string(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{toml_key(k)} = {toml_value(v)}" for k, v in value.items()) \
            + " }"
    return toml_string(str(value))


def to_toml(data: dict) -> str:
    """Write parsed TOML back: top-level tables as headers, everything below inline."""
    lines = [f"{toml_key(k)} = {toml_value(v)}" for k, v in data.items()
             if not isinstance(v, dict)]
    for name, table in data.items():
        if isinstance(table, dict):
            lines.append(f"[{toml_key(name)}]")
            lines += [f"{toml_key(k)} = {toml_value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


# -- mutations ------------------------------------------------------------------------

EXTREME_NUMBERS = [
    10**400, -(10**400), 2**1024, 16**5000, 2**63, -(2**63), 10**20, 1e308, -1e308, 1.7e308,
    1e-320, 5e-324, -5e-324, 1e-160, 1e153, 1e200, 0, -0.0, 1, -1, float("inf"),
    float("-inf"), float("nan"), 1_000_000, 1_000_001, 2, 1, 0.5,
]

EXPRESSIONS = [
    "1/0", "sqrt(-1)", "10**400", "1e308*10", "-1e308*10", "1e-320", "2**1024", "0**-1",
    "(-8)**(1/3)", "atan2(0, 0)", "1/(1-1)", "sin(1e308)", "tan(pi/2)", "degrees(1e307)",
    "radians(1e309)", "+".join(["1"] * 600), "-" * 500 + "1", "(" * 300 + "1" + ")" * 300,
    "(" * 2000 + "1" + ")" * 2000, "*".join(["2"] * 900), "**".join(["2"] * 300), "1e999",
    "__import__('os')", "a.b", "[1]", "lambda: 1", "theta if 1 else 2", "f'{1}'", "'x'",
    "sqrt(1, 2)", "sqrt()", "nosuch(1)", "pi()", "theta(1)", "1 +", "", " ", "\x00",
    "1" * 5000, "0x10", "1_000", "١٢", "½", "∞", "theta ** 1e10", "nan", "inf",
]

HOSTILE_TEXT = [
    "\x1b]0;owned\x07", "\x1b[2J", "\x1b[31m", "\u202e", "\u2066", "\x00", "\n", "\r\n",
    "\t", "\x7f", "\x9b", "\u2028", "\ufeff", "\u200b", "$\\frac$", "%s%n", "{0}", "\\",
]


def _names(data) -> list[str]:
    names = []
    for table in ("parameters", "inputs", "points", "links", "sliders"):
        value = data.get(table)
        if isinstance(value, dict):
            names += list(value)
    return names


def _places(value, path=()):
    """Every place in parsed TOML: (path, value), containers included."""
    yield path, value
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _places(v, (*path, k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _places(v, (*path, i))


def _set(data, path, value):
    target = data
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value


def _delete(data, path):
    target = data
    for key in path[:-1]:
        target = target[key]
    del target[path[-1]]


def _variant(name: str, rng: random.Random) -> str:
    """A name that is almost another one, or hostile."""
    choices = [
        name + "_", name.upper(), name.lower() + "x", name[:-1] or "x", "pi", "sin", "lambda",
        "for", "__class__", "1" + name, name.replace("A", "\u0410").replace("o", "\u043e"),
        "\uff21" + name, "\ufb01" + name, name + rng.choice(HOSTILE_TEXT), "",
        "N" * rng.choice([300, 5000, 100_000]), name + "\u0301", "theta",
    ]
    return rng.choice(choices)


def _random_value(rng: random.Random, depth=0):
    kind = rng.randrange(8 if depth < 2 else 5)
    if kind == 0:
        return rng.choice([True, False])
    if kind == 1:
        return rng.choice(EXTREME_NUMBERS)
    if kind == 2:
        return rng.uniform(-1e3, 1e3)
    if kind == 3:
        return rng.choice(EXPRESSIONS + HOSTILE_TEXT)
    if kind == 4:
        return rng.choice(["A", "B", "O", "theta", "left", "right", "first", "second"])
    if kind == 5:
        return [_random_value(rng, depth + 1) for _ in range(rng.randrange(4))]
    if kind == 6:
        return {rng.choice(["op", "at", "value", "x", "range"]): _random_value(rng, depth + 1)}
    return {}


def _drop(data, rng):
    places = [p for p, _ in _places(data) if p]
    if places:
        _delete(data, rng.choice(places))


def _wrong_type(data, rng):
    places = [p for p, _ in _places(data) if p]
    if places:
        _set(data, rng.choice(places), _random_value(rng))


def _swap_names(data, rng):
    names = set(_names(data))
    refs = [(p, v) for p, v in _places(data) if p and isinstance(v, str) and v in names]
    if len(refs) >= 2:
        (p, v), (q, w) = rng.sample(refs, 2)
        _set(data, p, w)
        _set(data, q, v)


def _unknown_name(data, rng):
    strings = [(p, v) for p, v in _places(data) if p and isinstance(v, str)]
    if strings:
        path, value = rng.choice(strings)
        _set(data, path, _variant(value, rng))


def _rename(data, rng):
    tables = [t for t in ("parameters", "inputs", "points", "links", "sliders")
              if isinstance(data.get(t), dict) and data[t]]
    if tables:
        table = data[rng.choice(tables)]
        old = rng.choice(list(table))
        items = [(_variant(old, rng) if k == old else k, v) for k, v in table.items()]
        table.clear()
        table.update(items)


def _cycle(data, rng):
    points = data.get("points")
    if not isinstance(points, dict):
        return
    refs = [(p, v) for p, v in _places(points) if len(p) >= 2 and isinstance(v, str)
            and v in points and p[1] != "op"]
    if refs:
        path, _ = rng.choice(refs)
        _set(points, path, rng.choice([path[0], rng.choice(list(points))]))


def _number(data, rng):
    numbers = [p for p, v in _places(data) if p and isinstance(v, int | float)
               and not isinstance(v, bool)]
    if numbers:
        _set(data, rng.choice(numbers), rng.choice(EXTREME_NUMBERS))


def _expression(data, rng):
    values = [p for p, v in _places(data) if len(p) >= 2 and p[0] in ("parameters", "points")
              and isinstance(v, int | float | str) and not isinstance(v, bool)
              and p[-1] != "op"]
    if values:
        _set(data, rng.choice(values), rng.choice(EXPRESSIONS))


def _control(data, rng):
    strings = [(p, v) for p, v in _places(data) if p and isinstance(v, str)]
    if strings:
        path, value = rng.choice(strings)
        i = rng.randrange(len(value) + 1)
        _set(data, path, value[:i] + rng.choice(HOSTILE_TEXT) + value[i:])


def _unknown_key(data, rng):
    tables = [v for _, v in _places(data) if isinstance(v, dict)]
    table = rng.choice(tables)
    table[rng.choice(["colour", "Op", "rang", "sample", "\x1b[2J", "near", "branch", "step"])] \
        = _random_value(rng)


def _sweep_size(data, rng):
    inputs = data.get("inputs")
    if isinstance(inputs, dict) and inputs:
        spec = inputs[rng.choice(list(inputs))]
        if isinstance(spec, dict):
            spec.pop("step", None)
            spec.pop("samples", None)
            key, value = rng.choice([("samples", 1_000_000), ("samples", 2), ("step", 1e-4),
                                     ("step", 1e9), ("samples", 1_000_001), ("step", -1)])
            spec[key] = value


def _more_points(data, rng):
    points = data.get("points")
    inputs = data.get("inputs")
    driver = next(iter(inputs), "theta") if isinstance(inputs, dict) else "theta"
    if isinstance(points, dict) and points:
        base = rng.choice(list(points))
        for k in range(rng.randrange(2, 40)):
            points[f"Z{k}"] = {"op": "polar", "origin": base if k == 0 else f"Z{k - 1}",
                               "distance": rng.choice([1, 0, -1, 1e-300, "1/3"]),
                               "angle": rng.choice([0, 90, driver, 1e300])}


def _degenerate(data, rng):
    """Make geometry degenerate: coincident pivots, a line from a point to itself, radius 0."""
    points = data.get("points")
    if not isinstance(points, dict) or not points:
        return
    fixed = [n for n, p in points.items() if isinstance(p, dict) and p.get("op") == "fixed"]
    kind = rng.randrange(3)
    if kind == 0 and len(fixed) >= 2:
        a, b = rng.sample(fixed, 2)
        points[b]["at"] = points[a].get("at")
        return
    pairs = [(p, v) for p, v in _places(points) if len(p) == 2 and isinstance(v, list)
             and len(v) == 2 and all(isinstance(x, str) for x in v)]
    if kind == 1 and pairs:
        path, value = rng.choice(pairs)
        _set(points, path, [value[0], value[0]])
        return
    sizes = [p for p, v in _places(points) if len(p) >= 2 and p[1] in ("radius", "radii",
                                                                         "distance")]
    if sizes:
        path = rng.choice(sizes)
        value = rng.choice([0, 0.0, 1e-300, -0.0])
        _set(points, path, [value, value] if path[-1] == "radii" else value)


def _scale(data, rng):
    """Multiply every length by one huge or tiny factor."""
    factor = rng.choice([1e-170, 1e-160, 1e-100, 1e100, 1e153, 1e160, 1e300])
    for path, value in list(_places(data)):
        if (len(path) >= 2 and path[0] in ("parameters", "points")
                and isinstance(value, int | float) and not isinstance(value, bool)
                and "angle" not in path):
            with contextlib.suppress(OverflowError):  # an integer beyond float range stays
                _set(data, path, value * factor)


DATA_MUTATIONS = [_drop, _wrong_type, _swap_names, _unknown_name, _rename, _cycle, _number,
                  _expression, _control, _unknown_key, _sweep_size, _more_points, _degenerate,
                  _scale]


def bytes_mutation(raw: bytes, rng: random.Random) -> bytes:
    """Return a script's bytes with one random change: bytes inserted or changed, cut, a
    line repeated or dropped, a byte-order mark, CRLF line ends, or a hostile table added."""
    kind = rng.randrange(8)
    i = rng.randrange(len(raw) + 1)
    if kind == 0:  # random bytes
        return raw[:i] + bytes(rng.randrange(256) for _ in range(rng.randrange(1, 8))) + raw[i:]
    if kind == 1:  # one byte changed
        if raw:
            j = min(i, len(raw) - 1)
            return raw[:j] + bytes([rng.randrange(256)]) + raw[j + 1:]
        return raw
    if kind == 2:  # cut short
        return raw[:i]
    if kind == 3:  # a line repeated or dropped
        lines = raw.split(b"\n")
        k = rng.randrange(len(lines))
        if rng.random() < 0.5:
            lines.insert(k, lines[k])
        else:
            del lines[k]
        return b"\n".join(lines)
    if kind == 4:
        return b"\xef\xbb\xbf" + raw
    if kind == 5:
        return raw.replace(b"\n", b"\r\n")
    if kind == 6:
        return raw + b"\n" + rng.choice([b"[points]\n", b"[[points]]\n", b"x = 1\n",
                                         b'[inputs.t]\nrange = [0, 1e400]\n',
                                         b"[links]\nx = " + b"[" * 600 + b"]" * 600 + b"\n",
                                         b"[sliders]\ns = " + b"{ a = " * 400 + b"1"
                                         + b" }" * 400 + b"\n"])
    return raw.replace(b'"', b"'", rng.randrange(1, 4))


def mutate(raw: bytes, rng: random.Random) -> bytes:
    """Return a mutant of a script: one to three mutations of its data, its text or both."""
    for _ in range(rng.choice([1, 1, 1, 2, 2, 3])):
        if rng.random() < 0.75:
            try:
                data = tomllib.loads(raw.decode("utf-8"))
            except (UnicodeDecodeError, ValueError, RecursionError):  # broken: mutate bytes
                raw = bytes_mutation(raw, rng)
                continue
            rng.choice(DATA_MUTATIONS)(data, rng)
            raw = to_toml(data).encode("utf-8", "surrogatepass")
        else:
            raw = bytes_mutation(raw, rng)
    return raw


# -- running a case -------------------------------------------------------------------


class Timeout(BaseException):
    """A case ran past the hard limit."""


@dataclass
class Outcome:
    """How one case ended."""

    ending: str  # "ok", "GeokinError at <step>", or the exception's class at its step
    seconds: float = 0.0
    error: BaseException | None = None
    where: str = ""
    known: str | None = None  # the KNOWN cause, if the error is known
    details: list[str] = field(default_factory=list)

    @property
    def unexpected(self) -> bool:
        """Whether the case ended in something else than success or a GeokinError."""
        return self.error is not None and self.known is None


def _where(exc: BaseException) -> str:
    """The innermost frame of geokin in an exception's traceback: file:line in function."""
    frames = [f for f in traceback.extract_tb(exc.__traceback__)
              if f"{os.sep}geokin{os.sep}" in f.filename]
    if not frames:
        return "?"
    f = frames[-1]
    return f"{pathlib.Path(f.filename).name}:{f.lineno} in {f.name}"


def run_case(raw: bytes, folder: pathlib.Path) -> Outcome:
    """Load, compile, print, round-trip, sweep and check one script; say how it ended."""
    import geokin
    from geokin.cli import main

    path = folder / "fuzz.toml"
    path.write_bytes(raw)
    start = time.perf_counter()
    step = "load"
    try:
        try:
            c = geokin.load(path)
            step = "compile"
            str(c.compile())
            step = "dump and load"
            if geokin.loads(geokin.dump(c), source="dumped") != c:
                return Outcome("dump and load: not the same construction",
                               time.perf_counter() - start, AssertionError("round trip"),
                               "io.py")
            step = "sweep"
            values = {name: np.linspace(*inp.range, 5) for name, inp in c.inputs.items()}
            geokin.sweep(c, values or None)
        except geokin.GeokinError:
            pass  # refused: a clean outcome; the command must refuse it the same way
        step = "check"
        out, err = io.StringIO(), io.StringIO()
        previous = os.environ.get("GEOKIN_DEBUG")
        os.environ["GEOKIN_DEBUG"] = "1"  # a fault of geokin propagates, with its traceback
        try:
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                status = main(["check", str(path)])
        finally:
            if previous is None:
                del os.environ["GEOKIN_DEBUG"]
            else:
                os.environ["GEOKIN_DEBUG"] = previous
        seconds = time.perf_counter() - start
        lines = (out.getvalue() + err.getvalue()).splitlines()
        bad = [line for line in lines if not line.isprintable()]
        # 1: a script that loads but assembles at no sample; 2: one refused
        if status not in (0, 1, 2) or bad or err.getvalue().count("\n") > 1:
            return Outcome(f"check: status {status}, {len(bad)} unescaped lines", seconds,
                           AssertionError("check output"), "cli.py", details=bad[:3])
        return Outcome({0: "ok", 1: "check: never assembles"}.get(status, "check: error"),
                       seconds)
    except Timeout as exc:
        return Outcome(f"timeout at {step}", time.perf_counter() - start, exc, step)
    except (Exception, RecursionError) as exc:  # noqa: B014 - the point is to list them
        where = _where(exc)
        name = type(exc).__name__
        known = KNOWN.get((name, where.split(":")[0]))
        return Outcome(f"{name} at {step}", time.perf_counter() - start, exc, where, known)


# -- the long run ---------------------------------------------------------------------


def _on_alarm(signum, frame):
    raise Timeout


def main(argv=None) -> int:
    """Run the long fuzz; print the tally, the unexpected exceptions and the slowest cases."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=10_000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--slow", type=float, default=5.0, help="seconds a case may take")
    parser.add_argument("--limit", type=float, default=60.0, help="seconds before giving up")
    parser.add_argument("--save", type=pathlib.Path, help="folder to save unexpected cases in")
    args = parser.parse_args(argv)

    import matplotlib

    matplotlib.use("Agg")
    signal.signal(signal.SIGALRM, _on_alarm)
    sources = [p.read_bytes() for p in SOURCES]
    tally, unexpected, known, slowest = Counter(), {}, Counter(), []
    began = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        for case in range(args.cases):
            rng = random.Random(args.seed * 1_000_003 + case)
            source = rng.randrange(len(sources))
            raw = mutate(sources[source], rng)
            signal.setitimer(signal.ITIMER_REAL, args.limit)
            cpu = time.process_time()
            try:
                outcome = run_case(raw, pathlib.Path(folder))
            finally:
                signal.setitimer(signal.ITIMER_REAL, 0)
            cpu = time.process_time() - cpu
            tally[outcome.ending.split(" at ")[0] if outcome.error else outcome.ending] += 1
            slowest = sorted([*slowest, (outcome.seconds, cpu, case, SOURCES[source].name)])[-5:]
            if outcome.known:
                known[(outcome.ending, outcome.where, outcome.known)] += 1
            elif outcome.unexpected:
                key = (outcome.ending, outcome.where)
                if key not in unexpected:
                    unexpected[key] = (case, SOURCES[source].name, outcome, raw)
                    if args.save:
                        args.save.mkdir(parents=True, exist_ok=True)
                        (args.save / f"case{case}.toml").write_bytes(raw)
            if (case + 1) % 1000 == 0:
                print(f"{case + 1} cases, {time.perf_counter() - began:.0f} s", file=sys.stderr)
    total = time.perf_counter() - began
    print(f"{args.cases} cases (seed {args.seed}) in {total:.1f} s ({time.process_time():.1f} s "
          f"of CPU), {1000 * total / max(args.cases, 1):.1f} ms each on average")
    for ending, count in tally.most_common():
        print(f"  {count:6d}  {ending}")
    print("slowest: " + ", ".join(f"{s:.2f} s ({cpu:.2f} s of CPU; case {c}, {name})"
                                  for s, cpu, c, name in reversed(slowest)))
    over = [s for s, _, _, _ in slowest if s > args.slow]
    print(f"cases over {args.slow:g} s: {len(over)}{'+' if len(over) == 5 else ''}")
    for (ending, where, cause), count in known.items():
        print(f"known, not counted: {count} x {ending} ({where}): {cause}")
    print(f"other exceptions: {len(unexpected)} kinds")
    for (ending, where), (case, name, outcome, raw) in unexpected.items():
        print(f"- {ending} ({where}): {str(outcome.error)[:200]!r}; case {case}, from {name}")
        for detail in outcome.details:
            print(f"    {detail[:200]!r}")
        print("    " + repr(raw[:600])[:700])
    return 1 if unexpected or over else 0


if __name__ == "__main__":
    sys.exit(main())
