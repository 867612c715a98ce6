"""The ``geokin`` command line: check, trace, plot, animate, analyze and tolerance scripts.

Every command takes a construction script (see :mod:`geokin.io`). Values on
the command line are in the script's units: degrees for an angle input,
the script's length unit for a length input.

Commands
--------
``geokin check SCRIPT...``
    Validate scripts; print the compiled steps, the inputs, the degrees of
    freedom (with a warning where Gruebler's count and the inputs differ)
    and whether the default sweep can be assembled.
``geokin trace SCRIPT [-o FILE] [--points M,B] [--links L,..] [--sliders S,..] [--derivatives]``
    The motion as data: the input (named as in the script, in its units),
    ``valid``, and ``<point>.x``, ``<point>.y`` for each point; with
    ``--derivatives`` also ``time`` and ``flagged`` and ``<point>.vx .vy .ax
    .ay`` per second at the input's declared speed; where branches change,
    ``<node>.branch``. ``--links`` adds ``<link>.angle`` (degrees, unwrapped)
    and with ``--derivatives`` ``.omega`` (deg/s) and ``.alpha`` (deg/s^2);
    ``--sliders`` adds ``<slider>.position`` along its guide and with
    ``--derivatives`` ``.velocity`` and ``.acceleration``. ``FILE.csv``,
    ``.json`` or ``.npz``; CSV on standard output without ``-o``.
``geokin plot SCRIPT [-o FILE.png|.svg] [--at VALUE] [--kinematics]``
    The mechanism drawn at one input value with the paths of its traced
    points; with ``--kinematics`` the link angles and their rates against time.
``geokin animate SCRIPT -o FILE.gif|.html|.mp4 [--fps F] [--frames N] [--dpi D] [--no-progress]``
    An animation of the motion with the paths growing: 60 frames at 72 dpi
    unless ``--frames`` and ``--dpi`` ask for more (or fewer).
``geokin analyze SCRIPT [--json]``
    Degrees of freedom, limits, Grashof classes, transmission angles,
    strokes and curve measures (see :func:`geokin.analyze`).
``geokin tolerance SCRIPT --tol NAME=T [--tol ...] [-n N] [--seed S] [--json] [-o FILE]``
    A Monte Carlo tolerance study (see :func:`geokin.tolerance`), in
    process or on a dask.distributed cluster (``--workers K``,
    ``--scheduler ADDRESS``).

``trace``, ``plot``, ``animate``, ``analyze`` and ``tolerance`` take
``--set NAME=VALUE`` to give a parameter another value (script units).

``trace``, ``plot`` and ``animate`` take the sweep options ``--range A B``
and ``--samples N`` or ``--step S`` for the first input (other inputs are
swept over their own ranges with as many samples), or ``--circuit`` for the
first input's whole circuit. Errors are printed on standard error without a
traceback, one line each with what came from a script escaped, and the exit
status is 2. A construction that cannot be assembled at any sample is said
so in one line, naming the node that fails and why, with exit status 1,
after ``trace``, ``plot`` and ``animate`` have written what is known: the
ground pivots (and the points found before the failing node, in a
picture); ``plot --kinematics``, ``--circuit`` and ``analyze``, which have
nothing known to show, write nothing. Every output file is written whole or not at all
(:mod:`geokin.atomic`): Ctrl-C exits with status 130 and leaves the old file.

Adding a command takes a function ``run_<name>(args) -> int`` and a
function ``add_<name>(subparsers)`` that declares its arguments and sets
``run``; list the latter in :data:`COMMANDS`.

Examples
--------
>>> main(["check", "no-such-file.toml"])
2
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import pathlib
import re
import signal
import sys
import threading
import unicodedata
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TypeAlias

import numpy as np

from . import __version__
from .analysis import analyze, degrees_of_freedom
from .analysis.report import off_guide_text
from .analysis.tolerance import (
    DISTRIBUTIONS,
    SENSITIVITY_STEP,
    Tolerance,
    dask_distributed,
    local_cluster,
    tolerance,
)
from .atomic import require_folder
from .circuits import circuit, limits, placed_in
from .construction import MAX_SAMPLES, Compiled, Construction, whole_steps
from .engine import STREAM_BLOCK_SAMPLES, evaluate, sweep_in_blocks
from .engine import sweep as run_sweep
from .errors import (
    AssemblyError,
    ConstructionError,
    GeokinError,
    ScriptError,
    closest_name,
    did_you_mean,
    quote,
)
from .expressions import names_only_within
from .io import (
    EXPORT_FORMATS,
    columns,
    export_blocks,
    export_sweep,
    load,
    script_steps,
    shortest_text,
    write_csv,
)
from .kinematics import motion, sliders_off_guide
from .results import Sweep, failure_causes, unassembled_error
from .terminal import escape, one_line, shorten
from .units import from_script, to_script, to_script_array

__all__ = ["COMMANDS", "build_parser", "main"]

Subparsers: TypeAlias = "argparse._SubParsersAction[_Parser]"
"""What ``ArgumentParser.add_subparsers`` returns, to which each command adds itself."""


class UsageError(GeokinError):
    """A command-line argument that cannot be used."""


def _print_lines(text: str, stream=None):
    """Print text of several lines, each escaped: nothing from a script acts on the terminal.

    Free text that may hold a newline of its own (a construction's name,
    description or units) is escaped before it is put in ``text``.
    """
    stream = sys.stdout if stream is None else stream
    stream.write("\n".join(escape(line) for line in text.split("\n")) + "\n")


# -- sweeping from the command line -----------------------------------------------


@dataclass
class ScriptSweep:
    """A sweep of a script's construction, with its input values in script units."""

    construction: Construction
    sweep: Sweep
    inputs: dict[str, np.ndarray]  # name -> values in script units


def _sample(lo, hi, samples=None, step=None, *, label="--range") -> np.ndarray:
    count, between = _sampling(lo, hi, samples, step, label=label)
    return between(0, count)


def _sampling(lo, hi, samples=None, step=None, *, label="--range", most=MAX_SAMPLES):
    """Return how many samples the sweep options make, and a function giving samples i to j - 1.

    The values are made as they are asked for, the same numbers as made all
    at once (those of ``numpy.linspace`` for a number of samples): a sweep
    too long to hold whole is walked block by block.
    """
    if samples == 1:  # one configuration: the start of the range
        return 1, lambda i, j: np.array([float(lo)])[i:j]
    if lo == hi:
        raise UsageError(f"{label} {lo:g} {hi:g}: the two ends are equal, nothing to sweep "
                         "(--samples 1 gives that one value)")
    if not math.isfinite(hi - lo):
        raise UsageError(f"{label} {lo:g} {hi:g}: too wide to compute with; the span must be "
                         f"below {sys.float_info.max:.1e}")
    if step is not None:
        if not (math.isfinite(step) and step != 0):
            raise UsageError(f"--step must be a non-zero number, got {step:g}")
        step = math.copysign(step, hi - lo)  # its size counts: the range gives the direction
        count = whole_steps(lo, hi, step)
        if not count + 1 <= most:
            shown = (f"{math.floor(count) + 1}" if count < 1e15
                     else f"about {count:.1e}" if math.isfinite(count) else "too many")
            raise UsageError(f"--step {shortest_text(step)} makes {shown} samples; at most "
                             f"{most}")
        return math.floor(count) + 1, lambda i, j: lo + step * np.arange(i, j)
    spacing = (hi - lo) / (samples - 1)

    def between(i, j):
        values = np.arange(i, j, dtype=float) * spacing + lo
        if j == samples and j > i:
            values[-1] = hi  # the end exactly, as numpy.linspace has it
        return values

    return samples, between


def _range_asked(first, args) -> tuple[float, float]:
    """Return the first input's range to sweep, in script units: --range or the declared one."""
    if args.range is not None:
        return tuple(args.range)
    return to_script(first, first.range[0]), to_script(first, first.range[1])


def sweep_values(construction: Construction, args: argparse.Namespace) -> dict[str, np.ndarray]:
    """Return the input values, in script units, asked for by the sweep options."""
    count, between = sweep_sampling(construction, args)
    return between(0, count)


def sweep_sampling(construction: Construction, args: argparse.Namespace, *,
                   most: int = MAX_SAMPLES, warn: bool = True):
    """Return how many samples the sweep options ask for, and a function giving some.

    ``between(i, j)`` gives the input values of samples i to j - 1, in
    script units: the values :func:`sweep_values` gives all at once. With
    ``warn``, says so where ``--range`` changes how several inputs pair up.
    """
    if getattr(args, "start", None) is not None:
        raise UsageError("--start picks where a circuit starts: use it with --circuit "
                         "(--range sets where a sweep runs)")
    inputs = list(construction.inputs.values())
    given = any(getattr(args, k, None) is not None for k in ("samples", "step", "range"))
    if not inputs:
        if given:
            raise UsageError("this construction has no input to sweep")
        return 1, lambda i, j: {}
    first, *others = inputs
    lo, hi = _range_asked(first, args)
    label = "--range" if args.range is not None else f"input {first.name}: range"
    if args.samples is not None:
        count, values = _sampling(lo, hi, samples=args.samples, label=label, most=most)
    elif args.step is not None:
        count, values = _sampling(lo, hi, step=args.step, label=label, most=most)
    elif first.step is not None:
        count, values = _sampling(lo, hi, step=to_script(first, first.step), label=label,
                                  most=most)
    else:
        count, values = _sampling(lo, hi, samples=first.samples, label=label, most=most)
    parts = {first.name: values}
    if warn:
        _warn_of_pairing(construction, args)
    for inp in others:
        parts[inp.name] = _sampling(to_script(inp, inp.range[0]), to_script(inp, inp.range[1]),
                                    samples=count, label=f"input {inp.name}: range",
                                    most=most)[1]
    return count, lambda i, j: {name: part(i, j) for name, part in parts.items()}


def _warn_of_pairing(construction: Construction, args: argparse.Namespace) -> None:
    """Warn that ``--range`` moves the first of several inputs alone, if it is given."""
    first, *others = construction.inputs.values()
    if args.range is None or not others:
        return
    kept = "; ".join(f"{quote(inp.name)} from {_format_value(inp, to_script(inp, lo))} to "
                     f"{_format_value(inp, to_script(inp, hi))}"
                     for inp in others for lo, hi in [inp.range])
    print(one_line(f"geokin: warning: --range moves input {quote(first.name)} alone; the "
                   f"other inputs keep their declared ranges ({kept}) over as many samples, "
                   "so the inputs pair up differently than in the declared sweep"),
          file=sys.stderr)


def motion_of(path: str | os.PathLike[str], args: argparse.Namespace,
              at: float | None = None, *, assembled: bool = True,
              script: tuple[Construction, Compiled] | None = None
              ) -> tuple[ScriptSweep, int | None]:
    """Load a script and sweep it; with ``at``, make sure the first input takes that value.

    Returns the motion and the index of the sample at ``at`` (None without it).
    With ``assembled``, a sweep that cannot be assembled at any sample is an
    :class:`AssemblyError`; without it, the caller writes what is known of
    it first (and then calls :meth:`Sweep.require_assembled`). ``script``
    is the script already loaded by :func:`script_of`, if it is.
    """
    construction, compiled = script_of(path, args) if script is None else script
    if getattr(args, "circuit", False):
        return _circuit_of(construction, compiled, args, at)
    values = sweep_values(construction, args)
    index = None
    if at is not None:
        if not values:
            raise UsageError("--at needs a construction with an input")
        name = next(iter(values))
        first = construction.inputs[name]
        lo, hi = _range_asked(first, args)
        if not min(lo, hi) - 1e-9 * max(1.0, abs(at)) <= at <= max(lo, hi) + 1e-9 * max(
                1.0, abs(at)):
            raise _outside(at, first, lo, hi, "the sweep")
        values, index = _insert(values, name, at)
    radians = {name: from_script(construction.inputs[name], v) for name, v in values.items()}
    result = run_sweep(compiled, radians or None)
    if assembled:  # nothing to write or draw if no sample assembles: say why instead
        result.require_assembled()
    return ScriptSweep(construction, result, values), index


def _assignments(texts: Sequence[str] | None, option: str) -> dict[str, float]:
    """Read the ``NAME=VALUE`` values of an option given once or more, as numbers."""
    values: dict[str, float] = {}
    for text in texts or ():
        name, equals, number = text.partition("=")
        name = unicodedata.normalize("NFKC", name.strip())
        if not equals or not name:
            raise UsageError(f"{option} {shorten(text)!r}: expected NAME=VALUE, such as "
                             f"{option} a=10.5")
        try:
            value = float(number)
        except ValueError:
            raise UsageError(f"{option} {shorten(text)!r}: expected a number after '=', got "
                             f"{shorten(number)!r}") from None
        if not math.isfinite(value):
            raise UsageError(f"{option} {shorten(text)!r}: expected a finite number")
        if name in values:
            raise UsageError(f"{option} gives {name!r} twice")
        values[name] = value
    return values


def script_of(path: str | os.PathLike[str],
              args: argparse.Namespace) -> tuple[Construction, Compiled]:
    """Load a script, and compile it with the parameter values ``--set`` gives."""
    construction = load(path)
    compiled = construction.compile()
    values = _assignments(getattr(args, "set", None), "--set")
    if values:
        try:
            compiled = compiled.with_parameters(values)
        except ConstructionError as err:
            raise UsageError(f"--set: {err.message}") from None
    return construction, compiled


def _add_set_option(p):
    p.add_argument("--set", action="append", metavar="NAME=VALUE",
                   help="give a parameter of the script another value, in the script's "
                        "units (degrees for a parameter the script uses as an angle); "
                        "once per parameter")


def _circuit_of(construction, compiled, args, at):
    """Sweep the whole circuit of the first input (``--circuit``)."""
    if not construction.inputs:
        raise UsageError("--circuit needs a construction with an input")
    if args.range is not None or args.step is not None:
        raise UsageError("--circuit runs between the limits of the motion: it takes "
                         "--samples (per pass) but not --range or --step")
    if args.samples == 1:
        raise UsageError("--circuit --samples counts the samples of each pass between two "
                         "limits: at least 2")
    if len(construction.inputs) > 1:
        raise UsageError(f"--circuit moves one input through its toggles; this construction "
                         f"has {len(construction.inputs)} inputs "
                         f"({', '.join(map(quote, construction.inputs))}), which a sweep "
                         "moves together: leave out --circuit")
    first = next(iter(construction.inputs))
    start = None if args.start is None else _circuit_start(construction, compiled, args.start)
    result = circuit(compiled, first, start=start, samples_per_pass=args.samples or 361)
    index = None
    if at is not None:
        inp = construction.inputs[next(iter(result.inputs))]
        path = result.input_values
        value = float(from_script(inp, at))
        slack = float(from_script(inp, START_SLACK))  # an end copied from analyze's six decimals
        if inp.kind == "angle":  # the same angle, where the circuit's motion meets it
            value = _first_passed(path, value, slack)
        if not path.min() - slack <= value <= path.max() + slack:
            raise _outside(at, inp, to_script(inp, path.min()), to_script(inp, path.max()),
                           "the circuit")
        result, index = _circuit_at(result, min(max(value, path.min()), path.max()))
    values = {name: to_script_array(construction.inputs[name], v)
              for name, v in result.inputs.items()}
    return ScriptSweep(construction, result, values), index


def _circuit_start(construction: Construction, compiled: Compiled, value: float) -> float:
    """Return --start in geokin's units, refused where the first input cannot be assembled.

    An angle is taken any whole number of turns away; a value within
    :data:`START_SLACK` of an interval (its end, copied from the six
    decimals ``analyze`` prints) is that end.
    """
    inp = next(iter(construction.inputs.values()))
    found = limits(compiled, inp.name)
    placed = placed_in(found, float(from_script(inp, value)), inp.kind == "angle",
                       float(from_script(inp, START_SLACK)))
    if placed is not None:
        return placed[1]
    unit = " deg" if inp.kind == "angle" else f" {one_line(construction.units, 100)}".rstrip()
    spans = ", ".join(f"{round(to_script(inp, lo), 6):.12g} to "
                      f"{round(to_script(inp, hi), 6):.12g}{unit}" for lo, hi in found.as_values())
    raise UsageError(f"--start {value:.12g}: input {quote(inp.name)} cannot be assembled there "
                     f"(it can from {spans or 'nowhere'})")


START_SLACK = 1e-6
"""How far (script units) a --start may lie outside an interval and still start at its end."""


def _first_passed(path: np.ndarray, angle: float, slack: float) -> float:
    """Return ``angle`` as many turns away as the circuit's ``path`` meets it in its motion.

    An angle the path reaches is meant as it is. Beyond a circuit of whole
    turns, which the mechanism repeats (two through a change point, where
    each angle has another pose in each turn), it is meant as many circuits
    away as it is: the same pose. Beyond any other circuit, as many turns
    away as the path first reaches it; where it never does, the turn
    nearest the path's middle, for the message.

    Examples
    --------
    >>> two_turns = np.radians([0.0, 360.0, 720.0])
    >>> [float(np.degrees(_first_passed(two_turns, np.radians(a), 0.0)))
    ...  for a in (420, 1120, -40, -300)]
    [420.0, 400.0, 680.0, 420.0]
    >>> float(np.degrees(_first_passed(np.radians([0.0, -360.0]), np.radians(60), 0.0)))
    -300.0
    >>> float(np.degrees(_first_passed(np.radians([-90.0, 90.0, -90.0]), np.radians(300), 0.0)))
    -60.0
    """
    turn = 2 * math.pi
    low, high = float(path.min()) - slack, float(path.max()) + slack
    if low <= angle <= high:
        return angle
    span = float(path[-1] - path[0])
    turns = round(span / turn)
    if turns and abs(span - turns * turn) <= 1e-9 * abs(span):
        return float(path[0]) + (angle - float(path[0])) % span
    middle = angle + turn * round((0.5 * (low + high) - angle) / turn)
    passed = []
    for k in range(math.ceil((low - angle) / turn), math.floor((high - angle) / turn) + 1):
        value = angle + k * turn
        at = min(max(value, path.min()), path.max())
        crossing = np.flatnonzero((path[:-1] - at) * (path[1:] - at) <= 0)
        if crossing.size:
            passed.append((int(crossing[0]), value))
    return min(passed)[1] if passed else middle


def _circuit_at(result, at):
    """Return the circuit with a sample at input value ``at`` (radians) where it first passes it."""
    name = next(iter(result.inputs))
    path = result.inputs[name]
    passing = np.flatnonzero((path[:-1] - at) * (path[1:] - at) <= 0)
    if passing.size == 0:
        raise UsageError("--at is outside the circuit's range of the input")
    i = int(passing[0])
    if np.isclose(path[i], at, rtol=0, atol=1e-12):
        return result, i
    if np.isclose(path[i + 1], at, rtol=0, atol=1e-12):
        return result, i + 1
    inputs = {k: np.insert(v, i + 1, at if k == name else v[i]) for k, v in result.inputs.items()}
    branches = {k: np.insert(b, i + 1, b[i]) for k, b in result.branches.items()}
    return evaluate(result.construction, inputs, len(path) + 1, branches, track=False), i + 1


def _outside(at, inp, start, end, what) -> UsageError:
    """Refuse an --at beyond the values swept, naming them: drawing there would extrapolate."""
    start, end = round(start, 6), round(end, 6)  # as analyze gives the limits
    swept = (f"{_format_value(inp, start)} alone" if start == end
             else f"{start:.12g} to {_format_value(inp, end)}")
    return UsageError(f"--at {at:.12g} is outside {what} of input {quote(inp.name)}: {swept}")


def _insert(values: dict, name: str, at: float):
    """Insert ``at`` into the first input's path where the path passes it."""
    path = values[name]
    close = np.flatnonzero(np.abs(path - at) <= 1e-9 * max(1.0, abs(at)))
    if close.size:
        return values, int(close[0])
    increasing = path.size < 2 or path[-1] >= path[0]
    ordered = path if increasing else path[::-1]
    k = int(np.searchsorted(ordered, at))
    if not increasing:
        k = path.size - k
    out = {}
    for key, v in values.items():
        extra = at if key == name else (v[min(k, v.size - 1)] if v.size else at)
        out[key] = np.insert(v, k, extra)
    return out, k


def _format_value(inp, value) -> str:
    if inp.kind == "angle":
        return f"{value:.12g} deg"
    return f"{value:.12g}"


# -- check -------------------------------------------------------------------------


def add_check(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "check", help="validate scripts; print steps, inputs and degrees of freedom",
        description="Validate construction scripts and print their compiled steps, inputs, "
                    "degrees of freedom and whether the default sweep can be assembled.")
    p.add_argument("scripts", nargs="+", metavar="SCRIPT", help="construction script (.toml)")
    p.set_defaults(run=run_check)


def run_check(args: argparse.Namespace) -> int:
    status = 0
    for i, path in enumerate(args.scripts):
        if i:
            print()
        try:
            _check_one(path)
        except BrokenPipeError:
            raise
        except AssemblyError as err:
            _print_error(err, path)
            status = max(status, 1)
        except (GeokinError, OSError) as err:
            # a script that reads but describes no mechanism: named by its file here
            about = isinstance(err, ConstructionError) and not isinstance(err, ScriptError)
            _print_error(err, path if about else None)
            status = 2
    return status


def _degrees_of_freedom(construction) -> str:
    mobility = degrees_of_freedom(construction)
    text = str(mobility)
    if not mobility.matches_inputs:
        text += (f"\n  warning: Gruebler's count gives {mobility.dof} degree(s) of freedom "
                 f"but the construction has {mobility.inputs} input(s): the declared links "
                 "and sliders may not describe the mechanism (a point not on any link, a "
                 "link missing, or a slider not declared)")
    return text


def _check_one(path):
    c = load(path)
    print(escape(f"{path}: {shorten(c.name, 1000)}"))
    if c.description:
        print(f"  {one_line(c.description, 1000)}")
    if c.units:
        print(f"  lengths in {one_line(c.units, 1000)}, angles in degrees")
    if c.parameters:
        _print_lines("parameters: " + ", ".join(f"{p.name} = {p.value:g}"
                                                for p in c.parameters.values()))
    print("inputs:" if c.inputs else "inputs: none")
    for inp in c.inputs.values():
        unit = " deg" if inp.kind == "angle" else f" {one_line(c.units, 1000)}" if c.units else ""
        lo, hi = (to_script(inp, v) for v in inp.range)
        if inp.step is not None:
            count = len(inp.values())
            spacing = f"step {to_script(inp, inp.step):g}{unit} ({count} samples)"
        else:
            spacing = f"{inp.samples} samples"
        rate = f"{to_script(inp, inp.speed):g}{unit or ' length units'}/s"
        _print_lines(f"  {inp.name} ({inp.kind}): {lo:g} to {hi:g}{unit}, {spacing}, {rate}")
    _print_lines(script_steps(c))
    if c.traced:
        _print_lines("traced: " + ", ".join(c.traced))
    _print_lines(f"degrees of freedom: {_degrees_of_freedom(c)}")
    defaults = argparse.Namespace(range=None, samples=None, step=None)
    values = sweep_values(c, defaults)
    s = run_sweep(c, {k: from_script(c.inputs[k], v) for k, v in values.items()} or None)
    bad = np.flatnonzero(~s.valid)
    summary = f"sweep: {len(s)} sample{'s' if len(s) != 1 else ''}, "
    if bad.size == 0:
        summary += "all assembled"
    else:
        i = int(bad[0])
        summary += (f"{len(s) - bad.size} assembled, {bad.size} cannot be: first at "
                    f"{_sample_text(c, s, i)}: node {s.failed_node[i]!r}: "
                    f"{s.failure_reason[i]}")
    summary += f"; {len(s.events)} branch change{'s' if len(s.events) != 1 else ''}"
    _print_lines(summary)
    for event in s.events:
        _print_lines(f"  at {_inputs_text(c, s.event_inputs(event), event.index)}: node "
                     f"{event.node!r} changes branch from {event.before} to {event.after}")
    s.require_assembled()
    for name, (i, offset) in sliders_off_guide(s).items():
        raise ConstructionError(_off_guide(c, s, name, i, offset), node=name, field="point",
                                kind="slider")


def _off_guide(c: Construction, s: Sweep, name: str, i: int, offset: float) -> str:
    """Say how far a slider's point is off its guide's line, and where it is farthest."""
    return off_guide_text(c.sliders[name], offset, c.units, _sample_text(c, s, i))


def _warn_off_guide(c: Construction, s: Sweep) -> None:
    """Warn of every slider whose point is off its guide's line (see geokin check)."""
    for name, (i, offset) in sliders_off_guide(s).items():
        print(one_line(f"geokin: warning: slider {quote(name)}: "
                       f"{_off_guide(c, s, name, i, offset)}"), file=sys.stderr)


def _sample_text(c, s, i) -> str:
    return _inputs_text(c, {name: values[i] for name, values in s.inputs.items()}, i)


def _inputs_text(c, values, i) -> str:
    """Say input values in the script's units, or the sample ``i`` without inputs."""
    parts = []
    for name, value in values.items():
        inp = c.inputs[name]
        value = math.degrees(value) if inp.kind == "angle" else value
        parts.append(f"{name} = {_format_value(inp, round(float(value), 9))}")
    return ", ".join(parts) or f"sample {i}"


# -- trace -------------------------------------------------------------------------


TRACE_BLOCK_SAMPLES = STREAM_BLOCK_SAMPLES
"""How many samples ``geokin trace`` sweeps and writes at a time (see
:func:`geokin.engine.sweep_in_blocks`); a sweep of no more is made whole."""

TRACE_MAX_SAMPLES = 10**9
"""The most samples ``geokin trace`` sweeps: a trace to CSV or NPZ longer than
one block is swept and written block by block, in bounded memory; every
other command holds its sweep whole, up to :data:`MAX_SAMPLES`."""


def _positive_int(text, least=2, most=MAX_SAMPLES):
    try:
        value = int(text)
    except ValueError:  # also for more digits than Python reads
        raise argparse.ArgumentTypeError(f"expected an integer, got {shorten(text)!r}") from None
    if value < least:
        raise argparse.ArgumentTypeError(f"expected at least {least}, got {value}")
    if value > most:
        raise argparse.ArgumentTypeError(f"at most {most}, got {value}")
    return value


def _sample_count(text):
    """Read the value of --samples: one sample is one configuration."""
    return _positive_int(text, least=1)


def _trace_sample_count(text):
    """Read the value of --samples of ``trace``, which streams long sweeps."""
    return _positive_int(text, least=1, most=TRACE_MAX_SAMPLES)


def _finite(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {shorten(text)!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {shorten(text)!r}")
    return value


def _step_size(text):
    """Read the value of --step: a positive number, as the range gives the direction."""
    value = _finite(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"expected a positive number (the range gives the "
                                         f"direction), got {shorten(text)!r}")
    return value


_START_HELP = ("start the circuit at VALUE of the first input: the circuit through VALUE "
               "(an input that can be assembled in several intervals has a circuit in each)")


def _add_sweep_options(p, count=_sample_count):
    group = p.add_argument_group("sweep", "of the first input, in script units "
                                          "(degrees for an angle)")
    group.add_argument("--range", nargs=2, type=_finite, metavar=("A", "B"),
                       help="sweep from A to B instead of the declared range")
    spacing = group.add_mutually_exclusive_group()
    spacing.add_argument("--samples", type=count, metavar="N",
                         help="N samples, both ends included (1: the start of the range "
                              "alone)")
    spacing.add_argument("--step", type=_step_size, metavar="S",
                         help="samples S apart from the start of the range towards its end "
                              "(S > 0; the range gives the direction)")
    group.add_argument("--circuit", action="store_true",
                       help="sweep the whole circuit instead: the input runs to each limit of "
                            "its motion and the mechanism passes the toggle onto the other "
                            "branch, until it returns (--samples then counts per pass)")
    group.add_argument("--start", type=_finite, metavar="VALUE",
                       help=_START_HELP + " (with --circuit)")


def add_trace(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "trace", help="the motion as data (CSV, JSON or NPZ)",
        description="Sweep a construction and write the motion: the input (script units), "
                    "valid, and <point>.x, <point>.y for each point; with --derivatives "
                    "also <point>.vx, .vy, .ax, .ay per second at the input's speed. "
                    "--links and --sliders add link angles (degrees) and slider positions. "
                    "NaN where a sample cannot be assembled, except for ground points, "
                    "which are known at every sample: if none can be, the columns are "
                    "written and the status is 1.")
    p.add_argument("script", metavar="SCRIPT", help="construction script (.toml)")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="write FILE.csv, FILE.json or FILE.npz (default: CSV on standard output)")
    p.add_argument("--points", metavar="NAMES",
                   help="comma-separated points to write (default: all)")
    p.add_argument("--links", metavar="NAMES",
                   help="comma-separated links whose angle to write: <link>.angle in degrees, "
                        "unwrapped (with --derivatives also .omega in deg/s and .alpha in "
                        "deg/s^2)")
    p.add_argument("--sliders", metavar="NAMES",
                   help="comma-separated sliders whose position along the guide, from its "
                        "first point, to write: <slider>.position (with --derivatives also "
                        ".velocity and .acceleration along the guide)")
    p.add_argument("--derivatives", action="store_true",
                   help="add velocities and accelerations per second")
    _add_set_option(p)
    _add_sweep_options(p, count=_trace_sample_count)
    p.set_defaults(run=run_trace)


def _output_kind(path, formats, what) -> str:
    suffix = pathlib.Path(path).suffix.lower()
    if suffix not in formats:
        raise UsageError(f"cannot write {what} to {path!r}: use a "
                         f"{', '.join(formats[:-1])} or {formats[-1]} file")
    return suffix


_TRACED = {"point": "--points", "link": "--links", "slider": "--sliders"}
"""What ``geokin trace`` writes columns of, and the option that names them."""


def _selected(construction, text, kind):
    """Return the names of points, links or sliders an option of ``trace`` gives.

    Without the option: every point, and no link or slider. A name of
    another kind is named as such, with the option that takes it.
    """
    option = _TRACED[kind]
    declared = {"point": list(construction.nodes), "link": list(construction.links),
                "slider": list(construction.sliders)}
    if text is None:
        return declared["point"] if kind == "point" else []
    # names are declared in Unicode form NFKC: a name typed another way is the same
    chosen = [unicodedata.normalize("NFKC", p.strip()) for p in text.split(",")]
    if not any(chosen):
        raise UsageError(f"{option} names no {kind}")
    if not all(chosen):
        raise UsageError(f"{option} {text!r} has an empty name between commas")
    names = declared[kind]
    for name in chosen:
        if name in names:
            continue
        other = next((k for k in declared if name in declared[k]), None)
        if other is not None:
            raise UsageError(f"{option}: {name!r} is a {other}, not a {kind}; "
                             f"use {_TRACED[other]} {name}")
        listed = f"{kind}s: {', '.join(names)}" if names else f"the construction has no {kind}s"
        raise UsageError(f"{option}: no {kind} {name!r}{did_you_mean(name, names)} ({listed})")
    return chosen


def run_trace(args: argparse.Namespace) -> int:
    if args.output is not None:
        _output_kind(args.output, EXPORT_FORMATS, "a trace")
        require_folder(args.output)  # say so before a long sweep, not after
    script = script_of(args.script, args)
    long = None if args.circuit else _long_sweep(args, script[0])
    if long is not None:
        return _trace_in_blocks(args, *script, *long)
    # where nothing assembles, the ground points are still known: write them, then say so
    m, _ = motion_of(args.script, args, assembled=False, script=script)
    points = _selected(m.construction, args.points, "point")
    links = _selected(m.construction, args.links, "link")
    sliders = _selected(m.construction, args.sliders, "slider")
    rates = None
    if args.derivatives:
        if not m.construction.inputs:
            raise UsageError("--derivatives needs a construction with an input")
        rates = motion(m.sweep, next(iter(m.construction.inputs)))
    # inputs in the script's units, as swept: degrees converted back from radians
    # could be an ulp off the values asked for; link angles in degrees too
    table = columns(m.sweep, points, motion=rates, branches=args.circuit or None,
                    inputs=m.inputs, links=links, sliders=sliders, degrees=True)
    if args.output is None:
        write_csv(table, sys.stdout)
        sys.stdout.flush()
    else:
        path = export_sweep(table, args.output)
    # the one line of stderr if no sample can be assembled, saying what was written
    _assembled(m.sweep, None if args.output is None else path, "the ground points' columns")
    if args.output is not None:
        print(escape(f"wrote {path}: {len(m.sweep)} samples, {len(table)} columns"),
              file=sys.stderr)
    return 0


def _assembled(sweep: Sweep, written, what: str) -> None:
    """Raise the sweep's AssemblyError if no sample assembles, naming what was written anyway."""
    try:
        sweep.require_assembled()
    except AssemblyError as err:
        if written is None:
            raise
        raise AssemblyError(f"{err}; wrote {written} with {what}",
                            node=err.node) from None


def _long_sweep(args, construction):
    """Return the sampling of a trace too long to hold whole, else None.

    A sweep of more samples than a block, written to CSV or NPZ, is traced
    block by block; JSON (one object) and shorter sweeps are made whole.
    """
    if args.output is not None and pathlib.Path(args.output).suffix.lower() == ".json":
        if args.samples is not None and args.samples > MAX_SAMPLES:
            raise UsageError(f"--samples {args.samples}: a JSON trace holds at most "
                             f"{MAX_SAMPLES} samples; write CSV or NPZ for more")
        return None
    # a sweep of one block is made whole, and sampled again, by motion_of
    count, between = sweep_sampling(construction, args, most=TRACE_MAX_SAMPLES, warn=False)
    if count <= TRACE_BLOCK_SAMPLES:
        return None
    _warn_of_pairing(construction, args)
    return count, between


def _trace_in_blocks(args, construction, compiled, count, between) -> int:
    """Trace a long sweep block by block: swept, differentiated and written as it goes."""
    points = _selected(construction, args.points, "point")
    links = _selected(construction, args.links, "link")
    sliders = _selected(construction, args.sliders, "slider")
    if args.derivatives and not construction.inputs:
        raise UsageError("--derivatives needs a construction with an input")
    inputs = construction.inputs

    def radians(i, j):
        return {name: from_script(inputs[name], v) for name, v in between(i, j).items()}

    progress = _Progress(count, "trace")
    causes: list = []
    state: dict = {"assembled": False, "lo": 0, "angles": {}, "time": None, "columns": 0}

    def tables():
        blocks = sweep_in_blocks(compiled, radians, count, block_samples=TRACE_BLOCK_SAMPLES)
        for block in blocks:
            lo = state["lo"]
            rates = motion(block, next(iter(inputs))) if args.derivatives else None
            table = columns(block, points, motion=rates, inputs=between(lo, lo + len(block)),
                            links=links, sliders=sliders, degrees=True)
            _continue_block(table, links, state, rates, block)
            state["assembled"] |= bool(block.valid.any())
            causes.extend(failure_causes(block, lo))
            state["lo"], state["columns"] = lo + len(block), len(table)
            progress.show(state["lo"])
            yield table

    try:
        if args.output is None:
            for i, table in enumerate(tables()):
                write_csv(table, sys.stdout, header=i == 0)
            sys.stdout.flush()
        else:
            path = export_blocks(tables(), args.output, count)
    finally:
        progress.close()
    if not state["assembled"]:
        error = unassembled_error(compiled, causes, count)
        if args.output is None:
            raise error
        raise AssemblyError(f"{error}; wrote {path} with the ground points' columns",
                            node=error.node)
    if args.output is not None:
        print(escape(f"wrote {path}: {count} samples, {state['columns']} columns"),
              file=sys.stderr)
    return 0


def _continue_block(table, links, state, rates, block):
    """Make a block's columns go on from the last block's: link angles and time.

    A link's angle is unwrapped within a block; it goes on by whole turns
    from where the last block left it. Time runs on from the last block's
    last sample at the input's speed.
    """
    for link in links:
        angle = table[f"{link}.angle"]
        finite = np.flatnonzero(np.isfinite(angle))
        last = state["angles"].get(link)
        if finite.size and last is not None:
            turns = np.round((last - angle[finite[0]]) / 360.0)
            if turns:
                table[f"{link}.angle"] = angle = angle + 360.0 * turns
        if finite.size:
            state["angles"][link] = angle[finite[-1]]
    if rates is not None:
        values = next(iter(block.inputs.values()))
        previous = state["time"]
        if previous is not None:
            last_time, last_value = previous
            step = abs(values[0] - last_value) / abs(rates.speed[0])
            table["time"] = table["time"] + (last_time + step)
        state["time"] = (float(table["time"][-1]), float(values[-1]))


class _Progress:
    """A progress line on a terminal's standard error (nothing elsewhere)."""

    def __init__(self, total: int, what: str) -> None:
        self.total, self.what = total, what
        self.shown = -1
        self.on = sys.stderr.isatty()

    def show(self, done: int) -> None:
        percent = 100 * done // self.total
        if self.on and percent != self.shown:
            self.shown = percent
            print(f"\r{self.what}: {percent}% of {self.total:,} samples", end="",
                  file=sys.stderr, flush=True)

    def close(self) -> None:
        if self.on and self.shown >= 0:
            print("\r\033[K", end="", file=sys.stderr, flush=True)


# -- plot and animate --------------------------------------------------------------


def _plotting():
    # matplotlib is imported only by the commands that draw
    from . import plotting

    return plotting


def add_plot(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "plot", help="draw the mechanism at one input value, with its traced paths",
        description="Draw the mechanism at one input value (ground pivots, links, sliders, "
                    "the input) with the paths of its traced points over the whole sweep.")
    p.add_argument("script", metavar="SCRIPT", help="construction script (.toml)")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="FILE.png or FILE.svg (default, here: the script's name with .png, "
                        "or with -kinematics.png for --kinematics)")
    p.add_argument("--at", type=_finite, metavar="VALUE",
                   help="the first input's value to draw, in script units, within the range "
                        "swept (default: the first sample that can be assembled)")
    p.add_argument("--title", help="the figure's title (default: the construction's name)")
    p.add_argument("--kinematics", action="store_true",
                   help="instead of the mechanism, plot the angle, angular velocity and "
                        "angular acceleration of every declared link against time")
    _add_set_option(p)
    _add_sweep_options(p)
    p.set_defaults(run=run_plot)


def run_plot(args: argparse.Namespace) -> int:
    # the kinematics chart has a name of its own, so as not to replace the mechanism's
    stem = pathlib.Path(args.script).stem
    output = args.output or (f"{stem}-kinematics.png" if args.kinematics else f"{stem}.png")
    plotting = _plotting()
    _output_kind(output, plotting.SAVE_FORMATS, "a picture")
    require_folder(output)
    if args.kinematics:
        if args.at is not None:
            raise UsageError("--at draws one pose; --kinematics plots against time: "
                             "give one or the other")
        if args.samples == 1:
            raise UsageError("--kinematics plots against time: it needs at least 2 samples")
        # the links' angles: where nothing assembles nothing of them is known, no chart
        m, _ = motion_of(args.script, args)
        first = next(iter(m.construction.inputs), None)
        if first is None:
            raise UsageError("--kinematics needs a construction with an input")
        fig, _ = plotting.figure_kinematics(motion(m.sweep, first), title=args.title)
        print(escape(f"wrote {plotting.save(fig, output)}"), file=sys.stderr)
        return 0
    # where nothing assembles, the ground pivots are still known: draw them, then say so
    m, index = motion_of(args.script, args, at=args.at, assembled=False)
    _warn_off_guide(m.construction, m.sweep)
    if index is not None and not m.sweep.valid[index] and m.sweep.valid.any():
        s = m.sweep
        drawn = plotting.layout.pose_drawn(s, index)
        which = "last assembled pose before" if drawn < index else "first assembled pose after"
        print(one_line(f"geokin: warning: {_sample_text(m.construction, s, index)}: node "
                       f"{s.failed_node[index]!r} cannot be assembled: "
                       f"{s.failure_reason[index]}; drawn instead, faded: the {which} it, "
                       f"at {_sample_text(m.construction, s, drawn)}"),
              file=sys.stderr)
    from matplotlib.figure import Figure

    fig = Figure(figsize=plotting.FIGSIZE, layout="constrained")
    ax = fig.add_subplot()
    plotting.plot_mechanism(m.sweep, index, ax=ax, title=args.title)
    path = plotting.save(fig, output)
    _assembled(m.sweep, path, "the ground pivots")
    print(escape(f"wrote {path}"), file=sys.stderr)
    return 0


def add_animate(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "animate", help="write an animation (GIF, HTML or MP4)",
        description="Animate the motion with the traced paths growing: .gif (Pillow), "
                    ".html (a self-contained page) or .mp4 (needs ffmpeg).")
    p.add_argument("script", metavar="SCRIPT", help="construction script (.toml)")
    p.add_argument("-o", "--output", metavar="FILE", required=True,
                   help="FILE.gif, FILE.html or FILE.mp4")
    p.add_argument("--fps", type=_finite, default=25.0,
                   help="frames per second, from 0.01 to 100 (default 25)")
    p.add_argument("--frames", type=_positive_int, metavar="N",
                   help="number of frames, evenly chosen among the samples (default 60, a "
                        "few seconds' work; more for a smoother animation, up to every "
                        "sample)")
    p.add_argument("--dpi", type=_finite, metavar="DPI",
                   help="pixels per inch of the 8 by 6 inch frames, from 1 to 1000 "
                        "(default 72: 576 x 432 pixels; 100 gives 800 x 600)")
    p.add_argument("--no-progress", action="store_true", help="do not show a progress bar")
    _add_set_option(p)
    _add_sweep_options(p)
    p.set_defaults(run=run_animate)


def run_animate(args: argparse.Namespace) -> int:
    plotting = _plotting()
    _output_kind(args.output, plotting.ANIMATION_FORMATS, "an animation")
    require_folder(args.output)
    if not plotting.MIN_FPS <= args.fps <= plotting.MAX_FPS:
        raise UsageError(f"--fps must be from {plotting.MIN_FPS:g} to {plotting.MAX_FPS:g} "
                         f"frames per second, got {args.fps:g}")
    if args.dpi is not None and not 1 <= args.dpi <= 1000:
        raise UsageError(f"--dpi must be from 1 to 1000, got {args.dpi:g}")
    # as plot: the pivots (and a crank turning alone) where nothing assembles, then exit 1
    m, _ = motion_of(args.script, args, assembled=False)
    _warn_off_guide(m.construction, m.sweep)
    frames = plotting.DEFAULT_FRAMES if args.frames is None else args.frames
    dpi = plotting.DEFAULT_DPI if args.dpi is None else args.dpi
    path = plotting.animate(m.sweep, args.output, fps=args.fps, frames=frames, dpi=dpi,
                            progress=not args.no_progress)
    _assembled(m.sweep, path, "the ground pivots")
    n = len(m.sweep)
    shown = min(frames, n)
    said = f"wrote {path}: {shown} frames of {n} samples at {dpi:g} dpi"
    if shown < n:
        said += f"; --frames {n} for every sample"
    print(escape(said), file=sys.stderr)
    return 0


# -- analyze -----------------------------------------------------------------------


def add_analyze(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "analyze", help="degrees of freedom, motion limits, Grashof class, transmission "
                        "angles, strokes and curve measures",
        description="Analyse a construction over the whole circuit of its first input: "
                    "degrees of freedom (Gruebler), the assemblable intervals of each input "
                    "with the node that limits them, the Grashof class of each four-bar loop, "
                    "the transmission angle at each circle-circle node, strokes and time "
                    "ratios, and measures of the traced curves. Angles in degrees.")
    p.add_argument("script", metavar="SCRIPT", help="construction script (.toml)")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.add_argument("--start", type=_finite, metavar="VALUE",
                   help=_START_HELP + ", in script units (degrees for an angle)")
    _add_set_option(p)
    p.set_defaults(run=run_analyze)


def run_analyze(args: argparse.Namespace) -> int:
    construction, compiled = script_of(args.script, args)
    if args.start is not None and len(construction.inputs) != 1:
        raise UsageError("--start picks the circuit of an input; this construction has "
                         + (f"{len(construction.inputs)} inputs, swept together"
                            if construction.inputs else "no input"))
    if args.start is not None:
        _circuit_start(construction, compiled, args.start)  # refused in script units
    report = analyze(compiled, degrees=True, start=args.start)
    if args.json:
        json.dump(report.to_dict(), sys.stdout, indent=2, allow_nan=False,
                  default=lambda value: None)
        sys.stdout.write("\n")
    else:
        _print_lines(report.to_text(construction.units).rstrip("\n"))
    return 0


# -- tolerance ---------------------------------------------------------------------


def add_tolerance(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "tolerance", help="how the tolerances of parameters spread the motion (Monte Carlo)",
        description="Draw N design variants, each named parameter around its value in the "
                    "script (normal with sigma = T/3, or uniform in +-T), sweep them all, "
                    "and report the fraction that assembles at every sample, each traced "
                    "point's deviation from its nominal path, the spread of each moving "
                    "link's and slider's stroke, and the sensitivity of each to each "
                    "parameter (derivative times tolerance).")
    p.add_argument("script", metavar="SCRIPT", help="construction script (.toml)")
    p.add_argument("--tol", action="append", metavar="NAME=T",
                   help="a parameter and its tolerance T (+-T, in the script's units; "
                        "degrees for a parameter used as an angle); once per parameter")
    p.add_argument("-n", "--variants", type=_variant_count, default=1000, metavar="N",
                   help="number of variants (default 1000)")
    p.add_argument("--seed", type=_seed, default=0, metavar="S",
                   help="seed of the draws (default 0): variant i depends on the seed and i "
                        "alone")
    p.add_argument("--distribution", choices=DISTRIBUTIONS, default="normal",
                   help="normal (sigma = T/3, the default) or uniform in +-T")
    p.add_argument("--json", action="store_true", help="print the study as JSON")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="also draw FILE.png or FILE.svg: a traced path with its envelope and "
                        "some variants, beside the histogram of a stroke")
    p.add_argument("--points", metavar="NAMES",
                   help="comma-separated points whose paths to study (default: the traced "
                        "points, or every moving point)")
    p.add_argument("--histogram", metavar="NAME",
                   help="the stroke drawn as a histogram, such as rocker.angle (default: the "
                        "one that spreads the most)")
    p.add_argument("--percentile", type=_finite, default=95.0, metavar="P",
                   help="the percentile of the paths' envelope (default 95)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=_variant_count, metavar="K",
                       help="run the variants on a local dask.distributed cluster of K worker "
                            "processes, at most one a core (pip install 'geokin[dask]')")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run the variants on the dask.distributed cluster whose scheduler "
                            "is at ADDRESS (tcp://host:8786); its workers need geokin")
    _add_set_option(p)
    group = p.add_argument_group("sweep", "of the first input, in script units "
                                          "(degrees for an angle)")
    group.add_argument("--range", nargs=2, type=_finite, metavar=("A", "B"),
                       help="sweep from A to B instead of the declared range")
    spacing = group.add_mutually_exclusive_group()
    spacing.add_argument("--samples", type=_sample_count, metavar="N",
                         help="N samples, both ends included")
    spacing.add_argument("--step", type=_step_size, metavar="S",
                         help="samples S apart from the start of the range towards its end "
                              "(S > 0; the range gives the direction)")
    p.set_defaults(run=run_tolerance)


MAX_VARIANTS = 100_000_000
"""The most variants ``geokin tolerance -n`` takes: a study's per-variant results
(whether it assembles, its strokes) are kept, a few bytes each."""


def _variant_count(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {shorten(text)!r}") from None
    if not 1 <= value <= MAX_VARIANTS:
        raise argparse.ArgumentTypeError(f"expected from 1 to {MAX_VARIANTS:,}, got {value}")
    return value


def _seed(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {shorten(text)!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a non-negative integer, got {value}")
    return value


@contextlib.contextmanager
def _cluster(args: argparse.Namespace):
    """Yield a dask.distributed client for --workers or --scheduler, or None for neither."""
    if args.workers is None and args.scheduler is None:
        yield None
        return
    distributed = dask_distributed()
    if args.workers is not None:
        with local_cluster(args.workers) as client:
            yield client
        return
    try:
        client = distributed.Client(args.scheduler, timeout="10s")
    except (OSError, ValueError, TypeError) as err:
        raise UsageError(f"--scheduler {shorten(args.scheduler)!r}: cannot connect: "
                         f"{_describe(err)}") from None
    with client:
        yield client


def _angle_parameters(compiled: Compiled) -> set[str]:
    """Return the parameters that scripts give in degrees, and only so.

    A script's angle is read in degrees, and the loader converts it with
    ``radians(...)``: a parameter is in degrees where it stands only in
    such calls (:func:`~geokin.expressions.names_only_within`).
    """
    values = [value for step in compiled.steps for value in step.node.value_fields().values()]
    return names_only_within(values, "radians") & compiled.parameters.keys()


SIGN_CHANGE_WARNING = 1e-3
"""``geokin tolerance`` warns where at least this share of the variants is
expected to draw a parameter with the other sign than its nominal value
(a length drawn below zero is no part that can be made); not for a
parameter the script gives in degrees, which may turn either way."""


def usable_cores() -> int:
    """Return how many cores this process may run on (its affinity, where known)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0)) or 1
    return os.cpu_count() or 1


def _sign_changes(nominal: float, half: float, distribution: str) -> float:
    """Return the share of draws expected on the other side of zero from ``nominal``.

    Examples
    --------
    >>> round(_sign_changes(10.0, 10.0, "normal"), 5)  # three standard deviations
    0.00135
    >>> _sign_changes(10.0, 30.0, "uniform")
    0.3333333333333333
    """
    if nominal == 0:
        return 0.0
    if distribution == "uniform":
        return max(0.0, 0.5 * (1 - abs(nominal) / half))  # 2 * half may overflow
    return 0.5 * math.erfc(abs(nominal) / (half / 3) / math.sqrt(2))


def _sensitivity_noise(result: Tolerance, output: str) -> float:
    """Return the rounding a central difference of the batch may leave in a sensitivity.

    A sensitivity is the output's change over :data:`SENSITIVITY_STEP` of the
    tolerance, divided by it: the output's rounding, a few units in the last
    place of its size (a link's angles, the coordinates of a slider's
    points, or the traced point's), divided by the step. Below it, a
    parameter changes nothing that can be told.
    """
    def largest(points):
        with np.errstate(invalid="ignore"):
            return max(float(np.nanmax(np.abs(result.nominal[p]), initial=0.0)) for p in points)

    stroke = result.strokes.get(output)
    if stroke is None:
        size = largest([output.removesuffix(".path")])
    elif stroke.kind == "angle":
        size = max(abs(stroke.nominal), 2 * math.pi)
    else:
        # a slider's place on its guide is rounded as its points' coordinates are
        slider = next(s for s in result.construction.sliders
                      if f"{s.name}.position" == output)
        size = max(abs(stroke.nominal), largest((slider.point, *slider.along)))
    return 8 * np.finfo(float).eps * size / (2 * SENSITIVITY_STEP)


def _tolerance_text(result: Tolerance, construction: Construction,
                    changed: Mapping[str, float] | None = None) -> str:
    """Return the study as the text ``geokin tolerance`` prints, angles in degrees.

    ``changed`` holds the values ``--set`` gave, in the script's units.
    """
    units = one_line(construction.units, 100) if construction.units else ""
    spread = ("sigma = T/3" if result.distribution == "normal" else "anywhere in +-T")
    assembled = int(result.assembled.sum())
    angles = _angle_parameters(result.construction)
    variants = f"{result.variants:,} variant{'' if result.variants == 1 else 's'}"
    lines = [f"{one_line(result.construction.name, 200)}: {variants}, "
             f"{result.distribution} ({spread}), seed {result.seed}",
             "tolerances: " + ", ".join(
                 f"{k} = {result.construction.parameters[k]:g} +- {v:g}"
                 + (" deg" if k in angles else "")
                 for k, v in result.tolerances.items())
             + (f" ({units})" if units and set(result.tolerances) - angles else "")]
    if changed:
        lines.append("set: " + ", ".join(f"{k} = {shortest_text(v)}"
                                         + (" deg" if k in angles else "")
                                         for k, v in changed.items()))
    lines.append(f"assemble at every sample: {assembled:,} of {result.variants:,} "
                 f"({100 * result.assemblable_fraction:.2f}% +- "
                 f"{100 * result.assemblable_error:.2f}%)")
    for node, count in result.failures.items():
        lines.append(f"  {count:,} fail first at node {node!r}")
    for point, p in result.paths.items():
        d = p.to_dict()
        if d["largest_mean"] is None:  # no variant assembles at every sample
            lines.append(f"path of {point}: no variant assembles at every sample")
            continue
        worst = (f"worst {d['largest_worst']:.4g} (variant {p.worst_variant})"
                 if p.worst_variant >= 0 else "no variant assembles")
        lines.append(f"path of {point}: over the samples, mean deviation from nominal at "
                     f"most {d['largest_mean']:.4g}, percentile {p.level:g} at most "
                     f"{d[f'largest_p{p.level:g}']:.4g}, {worst}")
    for name, stroke in result.strokes.items():
        d = stroke.to_dict(degrees=True)
        unit = " deg" if stroke.kind == "angle" else (f" {units}" if units else "")
        if d["mean"] is None:
            nominal = ("" if d["nominal"] is None
                       else f"; nominal {d['nominal']:.6g}{unit}")
            lines.append(f"stroke of {name}: no variant assembles at every sample{nominal}")
            continue
        # a nominal design that fails at some samples has no stroke, some variants may
        nominal = ("none (not assembled at every sample)" if d["nominal"] is None
                   else f"{d['nominal']:.6g}{unit}")
        if d["std"] <= 1e-9 * max(1.0, abs(d["mean"])):
            # the variants' own stroke, which need not be the nominal design's
            same = d["nominal"] is not None and (
                abs(d["mean"] - d["nominal"]) <= 1e-9 * max(1.0, abs(d["nominal"])))
            lines.append(f"stroke of {name}: {d['mean']:.6g}{unit} in every variant"
                         + ("" if same else f" (nominal {nominal})"))
            continue
        lines.append(f"stroke of {name}: nominal {nominal}, mean "
                     f"{d['mean']:.6g}, std {d['std']:.3g}, 5% {d['p5']:.6g}, "
                     f"95% {d['p95']:.6g}")
    lines.append("sensitivity (derivative x tolerance), largest first:")
    for output, ranked in result.sensitivity.items():
        scale = (math.degrees(1) if output in result.strokes
                 and result.strokes[output].kind == "angle" else 1.0)
        if all(v == 0 for _, v in ranked):
            lines.append(f"  {output}: none of the parameters changes it")
            continue
        floor = _sensitivity_noise(result, output)
        lines.append(f"  {output}: " + ", ".join(
            f"{k} n/a" if not math.isfinite(v) else f"{k} 0" if abs(v) <= floor
            else f"{k} {v * scale:+.4g}" for k, v in ranked))
    return "\n".join(lines)


def run_tolerance(args: argparse.Namespace) -> int:
    plotting = None
    if args.output is not None:
        plotting = _plotting()
        _output_kind(args.output, plotting.SAVE_FORMATS, "a picture")
        require_folder(args.output)
    tolerances = _assignments(args.tol, "--tol")
    if not tolerances:
        raise UsageError("--tol NAME=T is required: the parameters to draw, with their "
                         "tolerances")
    for name, value in tolerances.items():
        if not value > 0:
            raise UsageError(f"--tol {name}={value:g}: the tolerance must be a positive number")
    if not 0 < args.percentile < 100:
        raise UsageError(f"--percentile must be between 0 and 100, got {args.percentile:g}")
    cores = usable_cores()
    if args.workers is not None and args.workers > cores:
        raise UsageError(f"--workers {args.workers}: more than the {cores} "
                         f"core{'s' if cores > 1 else ''} this machine gives the program; to "
                         "run on more, join a cluster with --scheduler")
    construction, compiled = script_of(args.script, args)
    names = list(compiled.parameters)
    for name in tolerances:
        if name not in compiled.parameters:
            listed = (f"parameters: {', '.join(names)}" if names else
                      "the script has no parameters: name its lengths in [parameters]")
            raise UsageError(f"--tol {name}: no parameter {name!r}{did_you_mean(name, names)} "
                             f"({listed})")
    points = (_selected(construction, args.points, "point") if args.points is not None
              else None)
    args.circuit = False
    values = sweep_values(construction, args)
    radians = {k: from_script(construction.inputs[k], v) for k, v in values.items()}
    angles = _angle_parameters(compiled)
    for name, half in tolerances.items():
        share = _sign_changes(compiled.parameters[name], half, args.distribution)
        if share >= SIGN_CHANGE_WARNING and name not in angles:  # an angle may turn negative
            nominal = compiled.parameters[name]
            print(one_line(f"geokin: warning: --tol {name}={half:g}: about {100 * share:.2g}% "
                           f"of the variants draw {quote(name)} "
                           f"{'below' if nominal > 0 else 'above'} zero, where its nominal "
                           f"value is {nominal:g}"), file=sys.stderr)
    with _cluster(args) as client:
        result = tolerance(compiled, tolerances, n=args.variants, seed=args.seed,
                           distribution=args.distribution, values=radians or None,
                           points=points, level=args.percentile, client=client)
    if args.histogram is not None and args.histogram not in result.strokes:
        strokes = list(result.strokes)
        raise UsageError(f"--histogram: no stroke {args.histogram!r}"
                         f"{did_you_mean(args.histogram, strokes)} "
                         f"(strokes: {', '.join(strokes) or 'none'})")
    if args.json:
        data = result.to_dict(degrees=True)
        data["inputs"] = {k: v.tolist() for k, v in values.items()}  # as swept, script units
        data["set"] = _assignments(args.set, "--set")
        json.dump(data, sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
    else:
        _print_lines(_tolerance_text(result, construction, _assignments(args.set, "--set")))
    if not result.assembled.any():
        raise AssemblyError("no variant assembles at every sample"
                            + _nominal_failure(construction, result.nominal)
                            + ("; no picture is drawn" if plotting is not None else ""))
    if plotting is not None:
        fig, _ = plotting.figure_tolerance(result, output=args.histogram)
        print(escape(f"wrote {plotting.save(fig, args.output)}"), file=sys.stderr)
    return 0


def _nominal_failure(construction: Construction, nominal: Sweep) -> str:
    """Say where the nominal design of a study cannot be assembled, if anywhere, and what to do."""
    if nominal.valid.all():
        return ""
    i = int(np.argmin(nominal.valid))
    return (f", nor does the nominal design (at {_sample_text(construction, nominal, i)}, node "
            f"{quote(nominal.failed_node[i])}: {nominal.failure_reason[i]}): sweep where it "
            "assembles with --range (geokin analyze gives its limits)")


# -- the program ---------------------------------------------------------------------

COMMANDS = [add_check, add_trace, add_plot, add_animate, add_analyze, add_tolerance]
"""The functions that declare each command, in the order ``geokin --help`` lists them."""


class _Parser(argparse.ArgumentParser):
    """An argument parser that takes negative numbers as values and errs in one line.

    An argument that a command does not take is reported by that command,
    with the closest of its options.
    """

    def __init__(self, *args, **kwargs):
        # an abbreviated option would silently change meaning once a longer one is added
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)
        # so that `--range -1e3 0` and `--at -inf` are read as values, not as options
        self._negative_number_matcher = re.compile(
            r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE)
        self.commands: dict[str, _Parser] = {}  # name -> its parser, for the top-level one

    def error(self, message):
        """Print one line naming what is wrong, without the usage, and exit with status 2."""
        self.exit(2, f"geokin: error: {one_line(message)} (see '{self.prog} --help')\n")

    def parse_args(self, args=None, namespace=None):
        """Parse the arguments; exit naming one that no option takes, where it was given."""
        args = sys.argv[1:] if args is None else list(args)
        for arg in args:  # options before the command are the program's own
            if not arg.startswith("-") or self._negative_number_matcher.match(arg):
                if self.commands and arg not in self.commands:
                    self.refuse_command(arg)
                break
            name = arg.split("=", 1)[0]
            if name not in self._option_string_actions:
                self.refuse([arg], None)
        parsed, extra = self.parse_known_args(args, namespace)
        if extra:
            name = getattr(parsed, "command", None)
            (self.commands.get(name) or self).refuse(extra, name)
        return parsed

    def refuse_command(self, name: str) -> None:
        """Exit naming a command that does not exist, with the closest one or else all."""
        close = did_you_mean(name, self.commands)
        listed = "" if close else f" (commands: {', '.join(self.commands)})"
        self.error(f"{self.prog} has no command {quote(name)}{close}{listed}")

    def refuse(self, extra: list[str], command: str | None) -> None:
        """Exit naming the first argument in ``extra``, an option before a value."""
        who = command or self.prog
        options = [a for a in extra if a.startswith("-") and a != "-"
                   and not self._negative_number_matcher.match(a)]
        if not options:
            self.error(f"{who} does not take the argument {quote(extra[0])}")
        name = options[0].split("=", 1)[0]
        # a long option has a closest one, among those it starts with or that start
        # with it if any (--tol for --tolerance); a letter is as near to any other letter
        close = ""
        if name.startswith("--"):
            longs = [o for o in self._option_string_actions if o.startswith("--")]
            within = [o for o in longs if name.startswith(o) or o.startswith(name)]
            if within:
                named = [quote(o) for o in sorted(within)]
                either = ", ".join(named[:-1]) + " or " if len(named) > 1 else ""
                close = f"; did you mean {either}{named[-1]}?"
            else:
                # judged without the dashes every long option shares
                best = closest_name(name[2:], [o[2:] for o in longs])
                close = "" if best is None else f"; did you mean {quote('--' + best)}?"
        self.error(f"{who} has no option {quote(name)}{close}")


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of the ``geokin`` command."""
    parser = _Parser(
        prog="geokin",
        description="Kinematics of planar linkages described as construction scripts. "
                    "Angles are in degrees on the command line and in scripts.")
    parser.add_argument("--version", action="version", version=f"geokin {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for add in COMMANDS:
        add(subparsers)
    parser.commands = dict(subparsers.choices)
    return parser


def _describe(err: BaseException) -> str:
    """Return an exception's message, whatever its ``__str__`` does."""
    try:
        return str(err)
    except Exception:  # e.g. a message holding an integer too long to write out
        return f"({type(err).__name__} with a message that cannot be shown)"


def _print_error(err, script=None):
    """Print an error in one line, after the script it is about if the error does not name it."""
    if isinstance(err, OSError) and not isinstance(err, GeokinError):
        name = err.filename if err.filename is not None else ""
        message = f"cannot open {shorten(str(name), 1000)!r}: {err.strerror or _describe(err)}"
    else:
        message = _describe(err)
    if script is not None:
        message = f"{shorten(str(script), 1000)}: {message}"
    print(f"geokin: error: {one_line(message)}", file=sys.stderr)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """Print a warning as one line, like an error, without the source line."""
    print(one_line(f"geokin: warning: {category.__name__}: {message}"), file=sys.stderr)


class Terminated(BaseException):
    """SIGTERM arrived: raised like KeyboardInterrupt, so that partial outputs are removed.

    :func:`main` then prints one line and ends the process by SIGTERM.
    """


def _terminate(signum, frame):
    raise Terminated


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``geokin`` command with ``argv`` (the process arguments by default).

    Whatever happens, what reaches the terminal is one line per error, with
    everything from a script or an argument escaped, and no traceback.

    Returns
    -------
    int
        The exit status: 0 on success, 1 when the construction cannot be
        assembled at any sample (after writing what is known: the ground
        pivots), 2 for any other error
        (a bad script or argument; printed on standard error) and 130 after
        Ctrl-C, which leaves every output file as it was. SIGTERM cleans up
        the same way, then ends the process by that signal.
    """
    sigterm = None
    if threading.current_thread() is threading.main_thread():
        if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
            sigterm = signal.signal(signal.SIGTERM, _terminate)
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning
            return _run(argv)
    finally:
        if sigterm is not None:
            signal.signal(signal.SIGTERM, sigterm)


def _run(argv) -> int:
    args = None
    try:
        parser = build_parser()
        try:
            args = parser.parse_args(argv)
        except SystemExit as exc:  # --help, --version, or a usage error already printed
            return exc.code if isinstance(exc.code, int) else 2
        return args.run(args)
    except BrokenPipeError:  # pragma: no cover - e.g. `geokin trace ... | head`
        # the reader has gone: stop quietly, and keep Python from complaining at exit
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except AssemblyError as err:  # the script is valid, its mechanism does not assemble
        _print_error(err, getattr(args, "script", None))
        return 1
    except (GeokinError, OSError) as err:
        _print_error(err)
        return 2
    except KeyboardInterrupt:
        print("geokin: interrupted", file=sys.stderr)
        return 130
    except Terminated:
        print("geokin: terminated", file=sys.stderr)
        # outputs are cleaned up: now end as SIGTERM asked, so the parent sees why
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGTERM)
        return 143
    except MemoryError:
        print("geokin: error: not enough memory for this job; ask for fewer samples, points "
              "or frames", file=sys.stderr)
        return 2
    except Exception as err:  # a fault of geokin itself: say so, in one line
        if os.environ.get("GEOKIN_DEBUG"):
            raise
        print(one_line(f"geokin: internal error: {type(err).__name__}: {_describe(err)} "
                       "(please report it with the script; set GEOKIN_DEBUG=1 to see the "
                       "traceback)"), file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
