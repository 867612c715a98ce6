"""The engine: evaluate a construction over arrays of inputs, tracking branches.

:func:`sweep` evaluates every step of a compiled construction for all
samples at once (numpy arrays, no Python loop per sample) and keeps every
two-root node on its assembly branch as the mechanism moves.

Branch rules
------------
1. A two-root node starts on the branch its declaration names (``left`` or
   ``right`` for circle-circle, ``first`` or ``second`` along the line for
   the line-based kinds), or, with ``near=(x, y)``, on the root nearer to
   that position at the first sample where the node can be assembled.
2. Between two consecutive samples the inputs move along the straight
   segment joining them. The branch is the sign of the square root in the
   node's intersection formula; it changes exactly where the two roots meet
   along that path (a graze, as at a change point), so that the motion
   continues smoothly, and nowhere else, however coarse the steps and
   wherever the path turns back.
3. Whether the roots meet inside a step is decided by looking inside it, not
   by fitting the samples: a step whose roots stay further apart than their
   motion over the step could close (:data:`SAFETY`) is settled by its ends;
   any other step is cut into pieces (:data:`ANGLE_RESOLUTION`,
   :data:`LENGTH_RESOLUTION`) and the construction is evaluated at
   intermediate inputs, all doubtful pieces at once, cutting pieces finer
   (:data:`CUTS`) until the roots provably stay apart or come within
   :data:`MEET_RTOL` of the node's scale of each other (more for a node
   far from the origin: :func:`_meet_tolerance`): they meet there.
4. Roots that meet at a sample (within that tolerance) meet there: the
   node changes branch after that sample if it can be assembled at the
   samples on both sides and the path goes on through the sample; where the
   path turns back there, it keeps its branch, as it does turning back just
   short of the meeting. Roots meeting at the first or the last sample, or
   next to a sample that cannot be assembled, change nothing; consecutive
   samples between which the roots stay together count as one meeting.
5. Where a node cannot be assembled, the sample is invalid and the failing
   node and the reason are recorded. Beyond the gap the node resumes on the
   branch it had before the gap: an assembly mode is never reset silently.
   The same holds for a stretch between two samples that cannot be
   assembled.
6. :attr:`Sweep.branches` records the branch of every node at every sample,
   and :attr:`Sweep.events` every change, so any change is visible.
"""

from __future__ import annotations

import functools
import math
import threading
import weakref
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, replace
from functools import partial
from types import MappingProxyType

import numpy as np
from numpy.typing import ArrayLike

from .budgets import check_sweep_memory
from .compat import renamed_keywords
from .construction import Compiled, Construction, as_compiled
from .errors import (
    AssemblyError,
    ConstructionError,
    degrees_hint,
    did_you_mean,
    range_looks_like_degrees,
    warn_of_degrees,
)
from .expressions import Expr
from .frozen import read_only, read_only_mapping
from .nodes import Candidates, Node, failure_reasons
from .primitives import extremes, largest_element, least_element
from .results import BranchEvent, PointTable, Sweep

__all__ = ["assembly_guesses", "evaluate", "input_arrays", "meeting_rtol", "start_labels",
           "sweep", "sweep_in_blocks", "variant_values"]

MEET_RTOL = 1e-7
"""Roots closer than this times the node's scale meet (a graze or a toggle).

Near a meeting the distance between the roots comes from the square root of
a difference of squares, so it is known only to about the square root of
the machine epsilon (1.5e-8) of the scale: this is as close as roots can be
told apart. A node found from moving points whose coordinates are R times its
scale (far from the origin of the frame it is evaluated in) has them rounded R
times coarser, and its roots meet within ``MEET_RTOL * sqrt(R)``
(:func:`_meet_tolerance`)."""

FAR_RATIO = 1e8
"""The largest ratio of a node's coordinates to its scale that widens
:data:`MEET_RTOL`: beyond it the node's coordinates keep too few of its digits
for its roots to be told apart at all."""

SAFETY = 2.0
"""A step is settled without looking inside when the roots stay further apart,
at both ends, than this many times the distance their chord could move in it
(estimated from its rate over the step and its neighbours)."""

ANGLE_RESOLUTION = np.pi / 90
"""The longest step of an angle input (radians) settled by its ends alone;
longer steps are cut into pieces this long before they are checked."""

LENGTH_RESOLUTION = 1 / 100
"""The same for a length input, as a fraction of the node's scale."""

EDGE_WIDTH = 2.0**-44
"""How finely the edge of a stretch that cannot be assembled, or a meeting,
is located inside a step, as a fraction of the step: about the rounding of
the inputs."""

_EPS = float(np.finfo(float).eps)
"""The rounding of one operation, relative: a root a relative distance ``a``
from the other is known to ``_EPS / (2 a)`` of its node's scale."""

MAX_PIECES = 2**16
"""The most pieces one step is cut into before cutting finer (a step of 180 turns at
:data:`ANGLE_RESOLUTION`): a longer step cannot be resolved, and is not looked
into (the node keeps its branch across it)."""

PIECES_PER_BLOCK = 2**15
"""How many pieces of doubtful steps are evaluated together, at most (about;
one step's pieces stay together): memory stays bounded however coarse and
long the sweep."""

MAX_OPEN_PIECES = PIECES_PER_BLOCK
"""The most pieces the steps looked into together may leave open (neither
settled nor met) after a round. A meeting or the edge of a gap leaves a few
pieces open each, a flat near-miss a thousand or so; roots whose distance, or
whose existence, is rounding noise over a whole stretch (a node past the
resolution of its coordinates) leave more each round. Past this bound the
steps holding more than :data:`OPEN_PER_PIECE` open pieces for each they were
first cut in, and :data:`MIN_CROWD` at least, are closed, the most crowded
first, until the rest are within it: what is still open in them counts as
met, as after :data:`MAX_HALVINGS` rounds, and memory stays bounded. A quiet
step is never closed, so no step decides for another (a design variant for
the others swept with it)."""

OPEN_PER_PIECE, MIN_CROWD = 4, 4096
"""See :data:`MAX_OPEN_PIECES`."""

MAX_HALVINGS = 60
"""How many rounds a doubtful piece of a step may be cut in (each cuts it in
two at least); what is still open then lies within rounding of the inputs,
and counts as a meeting."""

CUTS = 8
"""The most pieces a doubtful piece is cut into in one round: as many as its
test asks (a power of two, two at least), and always this many for a piece
holding a gap's edge, which is so found in a third of the rounds halving
would take. Each round evaluates the construction once for all its cuts, at
most :data:`PIECES_PER_BLOCK` at a time. The pieces' widths are exact, and
neighbouring pieces share their ends."""


def input_arrays(compiled: Compiled, values: ArrayLike | Mapping[str, ArrayLike] | None = None,
                 samples: int | None = None) -> tuple[dict[str, np.ndarray], int]:
    """Return the input arrays of a sweep, broadcast to one length N.

    ``values`` is an array (for a construction with one input), a mapping of
    input names to arrays or numbers, or None for every input's default range.
    """
    names = list(compiled.inputs)
    if (type(values) is np.ndarray and len(names) == 1 and values.ndim == 1 and values.size
            and values.dtype == float):
        return {names[0]: values}, values.shape[0]  # the commonest call, quickly
    if values is None:
        values = {}
    elif not isinstance(values, Mapping):
        if len(names) != 1:
            raise ConstructionError(
                f"this construction has {len(names)} inputs ({', '.join(names) or 'none'}); "
                "pass a mapping of input names to values")
        values = {names[0]: values}
    for name in values:
        if name not in compiled.inputs:
            raise ConstructionError(f"unknown input {name!r}{did_you_mean(name, names)}",
                                    node=name, kind="input")
    arrays = {name: np.asarray(values[name], dtype=float) for name in names if name in values}
    # inputs left to their defaults share one number of samples: that of the given
    # values, else the first defaulted input's own sampling
    given = [a.shape[0] for a in arrays.values() if a.ndim == 1]
    for name in names:
        if name not in arrays:
            count = samples or (given[0] if given else None)
            arrays[name] = compiled.inputs[name].values(count)
            given.append(len(arrays[name]))
    if not arrays:
        return {}, 1
    try:
        shape = (next(iter(arrays.values())).shape if len(arrays) == 1
                 else np.broadcast_shapes(*(a.shape for a in arrays.values())))
    except ValueError:
        lengths = ", ".join(f"{k}: {a.shape[0] if a.ndim else 1}" for k, a in arrays.items())
        raise ConstructionError(f"the inputs' values have different lengths ({lengths}); "
                                "give every input the same number of samples, or a "
                                "single value") from None
    if len(shape) > 1:
        raise ConstructionError(f"input values must be one-dimensional, got shape {shape}")
    n = shape[0] if shape else 1
    if n == 0:
        raise ConstructionError("a sweep needs at least one sample; the input values are empty")
    return {k: _over_samples(v, n).astype(float, copy=False) for k, v in arrays.items()}, n


_NUMBERS = (float, np.float64)
"""The types of one number as evaluated (checked with ``type(x) in _NUMBERS``)."""


@dataclass(frozen=True)
class _PlannedStep:
    """A step with its constant values evaluated once and its varying ones listed."""

    index: int
    node: Node
    constants: dict
    varying: tuple  # (field, expression)
    # a point that never moves (a one-root node of the ground, its values all
    # constants): its candidates, found once; None for any other
    known: Candidates | None = None
    # whether the node's branch can decide where it or a later node is found
    branch_decides: bool = True
    # where that point is, if it is known and finite (no sample can fail there)
    fixed_at: tuple[float, float] | None = None


_PLANS: dict[tuple[int, frozenset[str]], tuple[_PlannedStep, ...]] = {}
"""Evaluation plans by the id of their compiled construction and the parameters
that vary from sample to sample, dropped with the construction."""


_NONE: frozenset[str] = frozenset()


def _plan(compiled: Compiled, varied: frozenset[str] = _NONE) -> tuple[_PlannedStep, ...]:
    """Return the evaluation plan of a compiled construction, made once and kept.

    ``varied`` names the parameters given per sample (design variants):
    values that use them are evaluated with the inputs.
    """
    key = (id(compiled), varied)
    plan = _PLANS.get(key)
    if plan is not None:
        return plan
    planned = []
    fixed = compiled.parameters.keys() - varied
    found: dict[str, tuple] = {}  # the coordinates of the points found once
    finding = {p: step.node for step in compiled.steps for p in step.node.defines}
    with np.errstate(all="ignore"):
        for step in compiled.steps:
            node = step.node
            constants, varying = {}, []
            fields = node.value_fields()
            length = _frame_length(node, finding)
            if length is not None:
                fields["frame_length"] = length
            for field_name, expr in fields.items():
                if expr.names() <= fixed:
                    constants[field_name] = float(expr.evaluate(compiled.parameters))
                else:
                    varying.append((field_name, expr))
            cand = None
            if (node.name in compiled.ground and not varying and node.roots == 1
                    and not node.continued and set(node.depends_on()) <= found.keys()):
                cand = node.candidates(found, constants)
                x, y = cand.x[0], cand.y[0]
                if type(x) in _NUMBERS and type(y) in _NUMBERS:
                    found[node.name] = (x, y)
                else:
                    cand = None
            fixed_at = (found[node.name] if cand is not None
                        and math.isfinite(found[node.name][0])
                        and math.isfinite(found[node.name][1]) else None)
            planned.append(_PlannedStep(step.index, node, constants, tuple(varying), cand,
                                        fixed_at=fixed_at))
    plan = tuple(_deciding_branches(planned))
    # the plan lives as long as the construction: a later one may reuse the id
    weakref.finalize(compiled, _PLANS.pop, key, None)
    _PLANS[key] = plan
    return plan


def _frame_length(node: Node, finding: Mapping[str, Node]) -> Expr | None:
    """Return the distance between the two points a node is built in the frame of, if known.

    Known where one lies on a circle about the other (:meth:`Node.radius_about`):
    a coupler point in the frame of the crank pin and the joint found on a
    circle about it. ``finding`` gives the node that finds each point.
    """
    frame = node.missing_where_coincide
    if frame is None:
        return None
    for center, on_circle in (frame, frame[::-1]):
        found_by = finding.get(on_circle)
        radius = None if found_by is None else found_by.radius_about(center)
        if radius is not None:
            return radius
    return None


FRAME_RATIO = 4.0
"""A construction whose fixed points lie more than this many times its size
from (0, 0) is evaluated around them (see :func:`_far_frame`)."""


_FRAMES: dict[int, tuple[float, float] | None] = {}
"""The frame of each compiled construction (by id), found once and dropped with it."""


def _frame_of(compiled: Compiled) -> tuple[float, float] | None:
    """Return :func:`_far_frame` of a construction with its own parameters, found once."""
    key = id(compiled)
    if key not in _FRAMES:
        _FRAMES[key] = _far_frame(_plan(compiled))
        weakref.finalize(compiled, _FRAMES.pop, key, None)
    return _FRAMES[key]


def _far_frame(plan: tuple[_PlannedStep, ...]) -> tuple[float, float] | None:
    """Return where to put the origin of a construction far from (0, 0), or None.

    Near the mean of its fixed points, when that lies more than
    :data:`FRAME_RATIO` sizes from (0, 0); the size is the larger of the
    fixed points' distance from their mean and the largest constant length
    of its other nodes. Along an axis the mechanism is far along, the
    origin is a whole multiple of a power of two near the size, so that
    fixed points shift to it and back exactly; along the other it is 0.
    Found there, every point is found as precisely as at the origin.

    Examples
    --------
    >>> from geokin import Construction
    >>> c = Construction()
    >>> c.input("t")
    >>> c.fixed("O", 2500.3, -1800.7)
    >>> c.polar("A", "O", 10, "t")
    >>> _far_frame(_plan(c.compile()))
    (2504.0, -1800.0)
    """
    # a fixed point of degenerate geometry (parallel guides) is NaN: it marks its
    # samples invalid, and has no place
    fixed = [(step.known.x[0], step.known.y[0]) for step in plan if step.known is not None
             and math.isfinite(step.known.x[0]) and math.isfinite(step.known.y[0])]
    if not fixed:
        return None
    x = math.fsum(p[0] for p in fixed) / len(fixed)
    y = math.fsum(p[1] for p in fixed) / len(fixed)
    size = max([math.hypot(px - x, py - y) for px, py in fixed]
               + [abs(value) for step in plan if not step.node.ground_kind
                  for name, value in step.constants.items()
                  if name not in step.node.angle_fields() and math.isfinite(value)])
    if not 0 < size < math.inf or math.hypot(x, y) <= FRAME_RATIO * size:
        return None
    unit = 2.0 ** math.floor(math.log2(size))

    def snapped(mean):
        # an axis the mechanism is not far along keeps its origin: a coordinate
        # near 0 would not shift exactly to a whole multiple of the unit
        return unit * round(mean / unit) if abs(mean) > FRAME_RATIO * size else 0.0

    origin = snapped(x), snapped(y)
    return None if origin == (0.0, 0.0) else origin


def _deciding_branches(planned: list[_PlannedStep]) -> list[_PlannedStep]:
    """Mark the steps whose branch can decide where they or a later node are found.

    A node's branch decides where it is found if one root can be missing
    where the other is not; it decides where a later node is found if that
    node can be missing by where its points are
    (:attr:`Node.missing_by_position`) and is built on it, at any remove,
    unless that node is missing only where two points coincide and every
    root of the node is as far from the other one.
    """
    by_point = {p: step.node for step in planned for p in step.node.defines}

    def blind_to(node, point):  # whether ``point``'s branch cannot make ``node`` missing
        pair = node.missing_where_coincide
        if pair is None or point not in pair:
            return False
        other = pair[1] if point == pair[0] else pair[0]
        return other in by_point[point].equidistant_from

    decisive: set[str] = set()  # the points whose branch decides something
    marked = []
    for step in reversed(planned):
        node = step.node
        deciding = node.missing_by_branch or not decisive.isdisjoint(node.defines)
        marked.append(replace(step, branch_decides=deciding))
        if deciding:
            decisive.update(node.depends_on())
        elif node.missing_by_position:
            decisive.update(p for p in node.depends_on() if not blind_to(node, p))
    return marked[::-1]


def _environment(compiled: Compiled, inputs):
    env = dict(compiled.parameters)
    env.update(inputs)
    return env


def _step_values(step: _PlannedStep, env) -> Mapping:
    """Return a step's value fields: its constants, and its varying values evaluated."""
    if not step.varying:
        return step.constants
    values = dict(step.constants)
    for field_name, expr in step.varying:
        values[field_name] = expr.evaluate(env)
    return values


def _candidates(step: _PlannedStep, coords, values, origin, guess=None, sketch=None,
                paths=1, between=None, positions=None):
    if step.node.continued:
        # followed along the samples (each path on its own), or solved from a guess per
        # sample (held): its guesses and sketch are absolute positions, shifted like the
        # points
        if guess is not None and origin is not None:
            guess = np.asarray(guess, dtype=float) - np.tile(origin, np.shape(guess)[1] // 2)
        # mypy: candidates of a continued node take the guess, the origin and the paths
        cand = step.node.candidates(coords, values, guess=guess,  # type: ignore[call-arg]
                                    origin=origin, sketch=sketch, paths=paths,
                                    between=between, positions=positions)
        if cand.also:
            coords.update(cand.also)
        return cand
    cand = step.node.candidates(coords, values)
    # a ground kind's values are absolute coordinates; every other node is found
    # from points already relative to the origin
    if origin is not None and step.node.ground_kind:
        cand = type(cand)((cand.x[0] - origin[0],), (cand.y[0] - origin[1],))
    return cand


BLOCK_SAMPLES = 2**15
"""How many samples a long evaluation takes at a time (each step's candidates
of a tracked sweep; every step of an evaluation that tracks no branch, as the
bisections of limits): its temporary arrays then stay in the processor's cache
and are reused, and memory beyond the results does not grow with the number of
samples."""


BLOCKED_ABOVE = 4 * BLOCK_SAMPLES
"""An evaluation of more samples than this is done :data:`BLOCK_SAMPLES` at a
time; below it the arrays fit the cache as they are, and blocks would only add
their own cost."""


@dataclass
class _Evaluated:
    """What evaluating every step gives, before it is made a Sweep."""

    coords: dict[str, tuple[np.ndarray, np.ndarray]]
    labels: dict[str, np.ndarray | int]
    margins: dict[str, np.ndarray]
    parameters: dict[str, np.ndarray]
    events: list[BranchEvent]
    valid: np.ndarray
    failed_step: np.ndarray
    reason_code: np.ndarray
    complete: bool | None = None  # whether valid is True everywhere, where known


@renamed_keywords(branches="held", initial="start")
def evaluate(construction: Construction | Compiled, inputs: Mapping[str, np.ndarray], n: int,
             held: Mapping[str, np.ndarray | int] | None = None, *, track: bool = True,
             start: Mapping[str, int] | None = None,
             origin: tuple[float, float] | None = None,
             sketches: Mapping[str, np.ndarray] | None = None,
             parameters: Mapping[str, np.ndarray] | None = None, paths: int = 1,
             track_incomplete: bool = True) -> Sweep:
    """Evaluate every step for all samples.

    Parameters
    ----------
    construction : Construction or Compiled
    inputs : mapping of str to ndarray, shape (N,)
        Input values in radians (lengths for length inputs). Over several
        paths, an input may instead be given once, shape (N / paths,):
        every path takes these values.
    n : int
        The number of samples N.
    held : mapping of str to ndarray, optional
        A branch held fixed (0 or 1, scalar or per sample) for some two-root
        nodes; the others are chosen and tracked by the branch rules.
    track : bool
        Whether the samples form a path along which branches are tracked
        (rules 2 to 4); turned off when evaluating at isolated perturbed inputs.
        Without tracking, more than :data:`BLOCKED_ABOVE` samples are
        evaluated :data:`BLOCK_SAMPLES` at a time where no node's branch
        depends on all of them (a ``near`` choice).
    start : mapping of str to int, optional
        The branch (0 or 1) some nodes start on, instead of their declared choice.
    origin : (float, float), optional
        Evaluate in a frame with its origin here: every point is found
        relative to it (constructions move with their fixed points), which
        keeps digits for a mechanism far from (0, 0). Positions in the result
        are then relative to ``origin``. Without it, a construction whose
        fixed points lie far from (0, 0) is evaluated around them
        (:func:`_far_frame`), and its positions are given back where they are.
    sketches : mapping of str to ndarray, optional
        For some continued nodes (closure groups), the positions (x, y of
        each point it finds, absolute) to start the continuation from at the
        first sample, instead of the group's sketch: a circuit continues a
        group from where its last pass ended, or across a fold.
    parameters : mapping of str to ndarray, shape (N,) or (paths,), optional
        Values of some parameters at every sample, instead of the
        construction's own (design variants); over several paths, they may
        instead be given once per path, and are then left out of the
        result's ``parameters``.
    paths : int
        The samples are this many paths of N / paths samples, one after the
        other (the variants of a design): branches are tracked along each
        path and never from one to the next, and each starts on its own
        initial branch. Every path has the same input values (the first
        path's, repeated); a closure group is followed along each path on
        its own only when the paths are swept one by one (as
        :func:`sweep` does).
    track_incomplete : bool
        Over several paths, whether a node's branches are tracked along a
        path at some sample of which it is missing. Without, the node keeps
        its initial branch along such a path wherever its branch cannot
        decide where anything is found: its two roots are found together,
        and no later node that where its points are can make missing (an
        intersection) is built on it, at any remove (a point in the frame
        of two points counts only if the node's roots are not equally far
        from the other point, as they are from a circle's centre). What is
        found where (``valid``, ``failed_step``, ``reason_code``) and
        everything of the other paths are as with tracking; only that
        path's positions and branches may differ, and the node gives no
        branch events there. A study that keeps only the paths found
        everywhere needs no more, and is spared looking for the edges of
        each path's gaps.

    Returns
    -------
    Sweep
    """
    compiled = as_compiled(construction)
    if paths > 1:
        inputs = _over_paths(inputs, n, paths)
    varied = {name: np.asarray(values, dtype=float) for name, values in (parameters or {}).items()}
    per_path = (paths > 1 and n != paths and bool(varied)
                and all(v.shape == (paths,) for v in varied.values()))
    if per_path and any(step.node.continued for step in compiled.steps):
        varied, per_path = {k: _repeated(v, n // paths) for k, v in varied.items()}, False
    if varied and not per_path:
        varied = {k: np.broadcast_to(v, (n,)) for k, v in varied.items()}
    plan = _plan(compiled, frozenset(varied) if varied else _NONE)
    # a construction far from (0, 0) is found around its fixed points, its positions
    # moved back at the end; the frame is that of its own parameters, which its
    # variants share
    frame = _frame_of(compiled) if origin is None else None
    origin = frame or origin
    if not track and n > BLOCKED_ABOVE and paths == 1 and _blocks_apart(plan, start, held):
        parts = _evaluate_in_blocks(compiled, plan, {**inputs, **varied}, n, held, start,
                                    origin)
    else:
        parts = _evaluate_steps(compiled, plan, inputs, n, held, start, origin, track, sketches,
                                varied, paths, per_path, track_incomplete)

    if frame is not None:
        parts.coords = {name: (x + frame[0], y + frame[1])
                        for name, (x, y) in parts.coords.items()}

    def per_sample(array):
        return _sealed(_over_samples(np.asarray(array, dtype=float), n))

    def labels(label):
        if type(label) is int:  # one branch throughout, the commonest
            return _throughout(label, n, "int8")
        return read_only(_over_samples(np.asarray(label, dtype=np.int8), n))

    # read-only as made, without the checks of Sweep(...): a sweep is made at every call
    return Sweep._made_read_only(
        construction=compiled, inputs=read_only_mapping(inputs),
        points=PointTable(parts.coords, parts.valid, parts.complete),
        valid=_sealed(parts.valid), failed_step=_sealed(parts.failed_step),
        reason_code=_sealed(parts.reason_code),
        branches=_proxy({name: labels(label) for name, label in parts.labels.items()}),
        events=tuple(parts.events),
        margins=_proxy({name: per_sample(margin) for name, margin in parts.margins.items()}),
        line_parameters=_proxy({name: per_sample(t) for name, t in parts.parameters.items()}),
        parameters=read_only_mapping({} if per_path else varied))


def _sealed(array: np.ndarray) -> np.ndarray:
    """Return an array the evaluation made, marked read-only in place (no view needed)."""
    if array.flags.writeable:
        array.setflags(write=False)
    return array


def _proxy(mapping: dict) -> Mapping:
    """Return a read-only view of a mapping whose values are read-only already."""
    return MappingProxyType(mapping) if mapping else _NO_VALUES


_NO_VALUES: Mapping = MappingProxyType({})


@functools.lru_cache(maxsize=64)
def _throughout(value: float, n: int, dtype: str = "float64") -> np.ndarray:
    """Return one number at N samples: read-only, without memory for them, shared.

    A branch label, no failing step (0) at any sample, or a linspace's steps.
    """
    return _constant(value, n, np.dtype(dtype), shared=True)


def _blocks_apart(plan, start, held) -> bool:
    """Whether an evaluation without tracking can be cut into blocks of samples.

    It can unless something depends on all of them: a node chosen ``near`` a
    position whose branch is not given, or a closure group whose solution is
    not held.
    """
    chosen = {**(start or {}), **(held or {})}
    return (all(step.node.name in chosen or not step.node.chosen_by_position
                for step in plan if step.node.roots == 2)
            and all(step.node.name in (held or {}) for step in plan if step.node.continued))


def _over_paths(inputs, n, paths):
    """Return the inputs over all samples of ``paths`` paths of the same input values.

    An input given over one path's samples is repeated for every path; one
    given over all samples is refused unless every path repeats the first.
    """
    if n % paths:
        raise ConstructionError(f"{n} samples cannot be {paths} paths of equal length")
    whole = {}
    for name, values in inputs.items():
        if np.shape(values) == (n // paths,):
            whole[name] = np.tile(values, paths)
            continue
        whole[name] = values
        rows = np.broadcast_to(values, (n,)).reshape(paths, -1)
        same = (rows == rows[0]) | (np.isnan(rows) & np.isnan(rows[0]))
        if not same.all():
            raise ConstructionError(f"over {paths} paths every path takes the same values of "
                                    f"input {name!r}, the first path's repeated", node=name)
    return whole


def _evaluate_steps(compiled, plan, inputs, n, held, start, origin, track,
                    sketches=None, varied=None, paths=1, per_path=False,
                    track_incomplete=True) -> _Evaluated:
    """Evaluate every step for all N samples at once, tracking branches if asked.

    Over several paths with the same inputs and parameters constant along
    each (design variants), the steps are evaluated on arrays of shape
    (paths, N / paths), the inputs a row and the parameters a column
    broadcast against each other, as one would write it by hand: what
    depends on the inputs alone is computed once for all paths.
    """
    rows = None
    if paths > 1 and varied and not any(step.node.continued for step in plan):
        rows = (paths, n // paths)
        env = _environment(compiled, {
            **{k: np.broadcast_to(v, (n,))[:rows[1]].reshape(1, -1) for k, v in inputs.items()},
            **{k: (v if per_path else v[::rows[1]]).reshape(-1, 1) for k, v in varied.items()}})
        by_rows: dict[str, tuple] = {}
    else:
        env = _environment(compiled, {**inputs, **varied} if varied else inputs)
    coords: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    label: np.ndarray | int | None
    labels: dict[str, np.ndarray | int] = {}
    margins: dict[str, np.ndarray] = {}
    parameters: dict[str, np.ndarray] = {}
    events: list[BranchEvent] = []
    valid = np.empty(n, dtype=bool)
    valid.fill(True)  # what np.ones does, in a third of the time
    # made where a first sample fails: most sweeps have none
    failed_step: np.ndarray | None = None
    reason_code: np.ndarray | None = None
    complete = True  # till a step is not found everywhere
    # where the samples lie in the space of the inputs, for the closure groups
    positions = None
    with np.errstate(all="ignore"):
        tracker = (_Tracker(compiled, plan, inputs, n, origin, varied, paths, per_path,
                            track_incomplete)
                   if track and n // paths >= 2 else None)
        for position, step in enumerate(plan):
            node = step.node
            if step.fixed_at is not None and origin is None:
                # a point that never moves, where it is found at every sample
                coords[node.name] = step.fixed_at
                if rows is not None:
                    by_rows[node.name] = step.fixed_at
                continue
            values = _step_values(step, env)
            if node.continued:  # all samples at once: it follows them as a path
                if positions is None:
                    positions = _positions(env, compiled, n)
                # between samples, what it is found from moves as the inputs do, along
                # the straight segment, the branches before it held as at the first
                between = (None if any(s.node.continued for s in plan[:position]) else
                           partial(_between_samples, compiled, plan, position, env, labels,
                                   origin))
                cand = _candidates(step, coords, values, origin,
                                   None if held is None else held.get(node.name),
                                   None if sketches is None else sketches.get(node.name), paths,
                                   between, positions)
                if tracker is not None:
                    found = {**(cand.also or {}), node.name: (cand.x[0], cand.y[0])}
                    tracker.solutions[node.name] = np.column_stack([
                        np.broadcast_to(c, (n,)) for p in node.defines for c in found[p]])
            elif step.known is not None and origin is None:
                cand = step.known
            elif rows is not None:
                cand = _candidates_in_rows(step, by_rows, values, origin, rows)
            elif n > BLOCKED_ABOVE:
                cand = _candidates_in_blocks(step, coords, values, origin, n)
            elif origin is None:  # what _candidates does, without its call
                cand = node.candidates(coords, values)
            else:
                cand = _candidates(step, coords, values, origin)
            if node.roots == 1:
                if cand.margin is not None:
                    margins[node.name] = cand.margin
                x, y = cand.x[0], cand.y[0]
                label = None
            else:
                if held is not None and node.name in held:
                    label = held[node.name]
                    if tracker is not None:  # held: later nodes see it between samples too
                        tracker.labels[node.name] = label
                else:
                    first = _initial_label(node, cand, n, (start or {}).get(node.name), paths,
                                           origin)
                    if tracker is None:
                        label = first
                    else:
                        label, found = tracker.track(
                            position, cand, first,
                            partial(_tolerance_at, node, coords, values, rows,
                                    compiled.ground, origin=origin))
                        events.extend(found)
                x, y = _choose(cand, label)
                labels[node.name] = label
                margins[node.name] = cand.margin
                if cand.t is not None:
                    parameters[node.name] = (cand.t[label] if np.ndim(label) == 0
                                             else np.where(label, cand.t[1], cand.t[0]))
            coords[node.name] = (x, y)
            if rows is not None:
                by_rows[node.name] = (_as_rows(x, rows), _as_rows(y, rows))
            if _all_finite(x, y):
                continue
            complete = False
            finite = np.isfinite(x) & np.isfinite(y)
            failing = valid & ~finite if np.ndim(finite) else (None if finite else valid.copy())
            if failing is not None and failing.any():
                # the first step that fails at a sample is its reason: recorded now, so
                # that no step's candidates are kept for later
                if rows is not None:
                    values = {k: _as_samples(v, rows) for k, v in values.items()}
                if failed_step is None or reason_code is None:
                    failed_step = np.zeros(n, dtype=np.int32)
                    reason_code = np.zeros(n, dtype=np.int8)
                _record_failures(step, cand, values, label, failing, failed_step, reason_code)
                valid &= ~failing
    events.sort(key=lambda e: (e.index, e.fraction))
    return _Evaluated(coords, labels, margins, parameters, events, valid,
                      _throughout(0, n, "int32") if failed_step is None else failed_step,
                      _throughout(0, n, "int8") if reason_code is None else reason_code,
                      complete)


def _positions(env, compiled, n: int) -> np.ndarray:
    """Return the samples' positions in the space of the inputs and varied parameters.

    One row per sample, one column per input or parameter that varies
    (the values, not converted): what moves along the straight segment
    between two samples.
    """
    columns = [np.broadcast_to(v, (n,)) for k, v in env.items()
               if np.ndim(v) and (k in compiled.inputs or k in compiled.parameters)]
    return np.column_stack(columns) if columns else np.zeros((n, 0))


def _between_samples(compiled, plan, position, env, labels, origin, a, b, t):
    """Return what step ``plan[position]`` is found from at fractions t from sample a to b.

    The inputs and varied parameters (``env``) move along the straight
    segment from their values at sample a to those at b; the steps before
    it are evaluated there, each two-root node on its branch at sample a.
    Returns their positions and the step's values.
    """
    m = t.shape[0]

    def moved(value):
        if np.ndim(value) == 0:
            return value
        return value[a] + t * (value[b] - value[a])

    inputs = {k: moved(v) for k, v in env.items() if k in compiled.inputs}
    varied = {k: moved(v) for k, v in env.items()
              if k not in compiled.inputs and np.ndim(v)}
    held = {k: (v if np.ndim(v) == 0 else int(v[a])) for k, v in labels.items()}
    parts = _evaluate_steps(compiled, plan[:position], inputs, m, held, None, origin, False,
                            varied=varied or None)
    step_env = {**_environment(compiled, inputs), **varied}
    return parts.coords, _step_values(plan[position], step_env)


def _constant(value: float | np.ndarray, n: int, dtype=float, shared: bool = False) -> np.ndarray:
    """Return one number as a read-only array of N samples, without memory for them.

    A ``shared`` one (kept and given to several sweeps) holds its one element
    in immutable bytes, so that neither it nor its base can be made writeable
    again.
    """
    # what np.broadcast_to(value, (n,)) gives, a few times faster
    one = np.empty(1, dtype)
    one[0] = value
    if shared:
        one = np.frombuffer(one.tobytes(), dtype)
    array = np.ndarray((n,), dtype, one, 0, (0,))
    array.setflags(write=False)
    return array


def _over_samples(value, n: int) -> np.ndarray:
    """Return ``value`` as an array of N samples: itself if it is one, else broadcast."""
    if type(value) is np.ndarray:
        if value.shape == (n,):
            return value
        if value.ndim == 0:
            return _constant(value, n, value.dtype)
    return np.broadcast_to(value, (n,))


DOT_BELOW = 8192
"""Arrays up to this size are checked finite by one dot product (one thread)."""


def _all_finite(x, y) -> bool:
    """Whether every coordinate is finite, told by a dot product or two sums.

    A sum of products is finite only if every factor is (inf times zero is
    NaN); one that overflows (coordinates beyond about 1e154) takes the
    longer way, which is exact. The dot
    product only for short arrays: on long ones the BLAS starts threads
    that keep spinning, and take the other cores' time.
    """
    if type(x) is np.ndarray and type(y) is np.ndarray and x.shape == y.shape:
        # whatever their layout; whole numbers are finite, and so is their dot product
        if x.ndim == 1 and x.size <= DOT_BELOW:
            return math.isfinite(x.dot(y))
    elif (type(x) in _NUMBERS and type(y) in _NUMBERS) or (np.ndim(x) == 0 and np.ndim(y) == 0):
        return math.isfinite(x) and math.isfinite(y)
    return bool(np.isfinite(np.add.reduce(x, axis=None) + np.add.reduce(y, axis=None)))


def _candidates_in_blocks(step, coords, values, origin, n):
    """Compute a step's candidates :data:`BLOCK_SAMPLES` samples at a time.

    The same numbers as one pass (every operation is elementwise), with the
    primitives' temporary arrays small enough to stay in the cache.
    """
    def part(value, lo, hi):
        return value[lo:hi] if np.ndim(value) else value

    return _candidates_in_parts(step, coords, values, origin, part, n, BLOCK_SAMPLES)


def _candidates_in_parts(step, coords, values, origin, part, count, size):
    """Compute a step's candidates ``size`` at a time along the first axis of ``count``.

    ``part(value, lo, hi)`` takes a value's share of ``lo`` to ``hi``;
    each field of the candidates is gathered into one array of the whole
    first axis (a field of one number stays one), or, in one part, left
    as the part computed it.
    """
    whole = None
    for lo in range(0, count, size):
        hi = min(lo + size, count)
        cand = _candidates(step, {k: (part(x, lo, hi), part(y, lo, hi))
                                  for k, (x, y) in coords.items()},
                           {k: part(v, lo, hi) for k, v in values.items()}, origin)
        fields = [cand.x, cand.y, cand.margin, cand.on_line, cand.t]
        if whole is None:
            if hi == count:
                return cand

            def room(a):
                a = np.asarray(a)
                return a if a.ndim == 0 else np.empty((count, *a.shape[1:]), dtype=a.dtype)

            whole = [None if f is None else tuple(map(room, f)) if isinstance(f, tuple)
                     else room(f) for f in fields]
        for mine, theirs in zip(whole, fields, strict=True):
            if isinstance(mine, tuple):
                for out, block in zip(mine, theirs, strict=True):
                    if np.ndim(out):
                        out[lo:hi] = block
            elif mine is not None and np.ndim(mine):
                mine[lo:hi] = theirs
    assert whole is not None
    return type(cand)(*whole)


def _as_rows(value, rows):
    """Return per-sample values as an array of rows (one number stays one)."""
    return value if np.ndim(value) == 0 else np.reshape(value, rows)


def _as_samples(value, rows):
    """Return values given on rows (or broadcast to them) as one array per sample."""
    return value if np.ndim(value) == 0 else np.broadcast_to(value, rows).reshape(-1)


def _candidates_in_rows(step, coords, values, origin, rows):
    """Compute a step's candidates on rows of samples, as one array over all samples.

    ``coords`` and ``values`` are numbers, rows of shape (1, M), columns of
    shape (P, 1) or arrays of shape (P, M), broadcast together; about
    :data:`BLOCK_SAMPLES` samples are computed at a time, for the cache.
    """
    paths, length = rows

    def part(value, lo, hi):
        return value[lo:hi] if np.ndim(value) == 2 and value.shape[0] == paths else value

    cand = _candidates_in_parts(step, coords, values, origin, part, paths,
                                max(1, BLOCK_SAMPLES // length))
    return type(cand)(*[None if f is None else tuple(_as_samples(a, rows) for a in f)
                        if isinstance(f, tuple) else _as_samples(f, rows)
                        for f in (cand.x, cand.y, cand.margin, cand.on_line, cand.t)])


def _evaluate_in_blocks(compiled, plan, inputs, n, held, start, origin) -> _Evaluated:
    """Evaluate without tracking, :data:`BLOCK_SAMPLES` samples at a time, into whole arrays."""
    whole: _Evaluated | None = None
    for lo in range(0, n, BLOCK_SAMPLES):
        hi = min(lo + BLOCK_SAMPLES, n)

        def part(value, lo=lo, hi=hi):
            return value[lo:hi] if np.ndim(value) else value

        block = _evaluate_steps(compiled, plan, {k: v[lo:hi] for k, v in inputs.items()},
                                hi - lo, None if held is None else
                                {k: part(v) for k, v in held.items()}, start, origin, False)
        if whole is None:
            whole = _Evaluated(
                {k: (_whole(x, n), _whole(y, n)) for k, (x, y) in block.coords.items()},
                {k: _whole(v, n, np.int8) for k, v in block.labels.items()},
                {k: _whole(v, n) for k, v in block.margins.items()},
                {k: _whole(v, n) for k, v in block.parameters.items()}, [],
                np.empty(n, dtype=bool), np.empty(n, dtype=np.int32), np.empty(n, dtype=np.int8))
        for name, (x, y) in block.coords.items():
            _fill(whole.coords[name][0], x, lo, hi)
            _fill(whole.coords[name][1], y, lo, hi)
        for mine, theirs in ((whole.labels, block.labels), (whole.margins, block.margins),
                             (whole.parameters, block.parameters)):
            for name, value in theirs.items():
                _fill(mine[name], value, lo, hi)
        whole.valid[lo:hi] = block.valid
        whole.failed_step[lo:hi] = block.failed_step
        whole.reason_code[lo:hi] = block.reason_code
    assert whole is not None  # n > BLOCK_SAMPLES: at least one block
    return whole


def _whole(value, n, dtype=float):
    """Return room for a value over all N samples: the value itself if it is one number."""
    return value if np.ndim(value) == 0 else np.empty(n, dtype=dtype)


def _fill(whole, value, lo, hi):
    if np.ndim(whole):
        whole[lo:hi] = value


def _choose(cand, label):
    """Take root ``label`` (an int, or an array of 0 and 1 per sample)."""
    if type(label) is int or np.ndim(label) == 0:
        x, y = cand.x[label], cand.y[label]
        if cand.on_line is not None:
            off = ~cand.on_line[label]
            x, y = np.where(off, np.nan, x), np.where(off, np.nan, y)
        return x, y
    second = label.astype(bool)
    x = np.where(second, cand.x[1], cand.x[0])
    y = np.where(second, cand.y[1], cand.y[0])
    if cand.on_line is not None:
        off = ~np.where(second, cand.on_line[1], cand.on_line[0])
        x, y = np.where(off, np.nan, x), np.where(off, np.nan, y)
    return x, y


def _record_failures(step, cand, values, label, failing, failed_step, reason_code):
    """Record that ``step`` is the first to fail at the ``failing`` samples, and why."""
    n = len(failing)
    at = np.flatnonzero(failing)

    def pick(a):
        return None if a is None else np.broadcast_to(a, (n,))[at]

    local = type(cand)(tuple(pick(a) for a in cand.x), tuple(pick(a) for a in cand.y),
                       pick(cand.margin),
                       None if cand.on_line is None else tuple(map(pick, cand.on_line)),
                       reason=pick(cand.reason))
    root = 0 if label is None else pick(np.asarray(label))
    failed_step[at] = step.index
    reason_code[at] = failure_reasons(local, {k: pick(v) for k, v in values.items()}, root,
                                      step.node.nonnegative_fields())


def assembly_guesses(sweep: Sweep, at: slice | np.ndarray | None = None,
                     repeat: int = 1) -> dict[str, np.ndarray]:
    """Return a sweep's solutions of its continued nodes, to hold in :func:`evaluate`.

    A closure group evaluated at isolated inputs near the sweep's samples
    (finite differences, bisections) starts each from the solution of its
    own sample, as a two-root node keeps the sample's branch.

    Parameters
    ----------
    sweep : Sweep
    at : slice or ndarray, optional
        The samples; all by default.
    repeat : int
        How many times the samples are repeated, one after the other.

    Returns
    -------
    dict of str to ndarray, shape (M * repeat, 2k)
        By node name: the positions of the points it finds, (x, y) each.
    """
    guesses = {}
    for step in sweep.construction.steps:
        node = step.node
        if node.continued:
            columns = [c[slice(None) if at is None else at]
                       for p in node.defines for c in sweep.points.xy(p)]
            guesses[node.name] = np.tile(np.column_stack(columns), (repeat, 1))
    return guesses


@renamed_keywords(branches="start_branches")
def sweep(construction: Construction | Compiled,
          values: ArrayLike | Mapping[str, ArrayLike] | None = None, *, samples: int | None = None,
          start_branches: Mapping[str, object] | None = None,
          parameters: Mapping[str, ArrayLike] | None = None,
          track_incomplete: bool = True) -> Sweep:
    """Evaluate a construction over a sweep of its inputs.

    Parameters
    ----------
    construction : Construction or Compiled
    values : array_like or mapping, optional
        The input values, radians for an angle: an array for a construction
        with one input, or a mapping of input names to arrays (broadcast
        together). Samples are taken in order as a path: branch tracking
        follows them. By default each input's declared range.
    samples : int, optional
        Number of samples of each defaulted input's range.
    start_branches : mapping of str to str or int, optional
        The branch some two-root nodes start on, by name
        (``{"B": "right"}``), instead of their declared choice; the branch is
        still tracked along the sweep.
    parameters : mapping of str to array_like, optional
        Design variants: values of some of the construction's parameters,
        each a number or an array of shape (V,), broadcast together. Every
        variant is swept over the same input values, its branches tracked
        along its own samples and never from one variant to the next, each
        starting on its own initial branch; the sweep then has a leading
        variant axis (see :class:`~geokin.results.Sweep`). Without it, the
        construction's own values.
    track_incomplete : bool
        With variants, whether branches are tracked along a variant that
        cannot be assembled at every sample. Without, such a variant's
        ``valid``, ``failed_step`` and ``reason_code`` are as with tracking,
        and so is everything of the variants assembled everywhere; its
        positions and branches may not be, and the nodes left untracked
        along it give no events there (which nodes:
        :func:`~geokin.engine.evaluate`).
        A study of the variants that assemble is spared finding the edges
        of the others' gaps.

    Returns
    -------
    Sweep

    Raises
    ------
    BudgetError
        If the sweep's arrays would not fit in memory (see
        :func:`geokin.budgets.check_sweep_memory`).
    ConstructionError
        For a varied name that is not a parameter, or values that are not
        numbers of one shape (V,).

    Examples
    --------
    >>> c = Construction("crank and rocker")
    >>> c.input("theta")
    >>> c.fixed("O2", 0, 0)
    >>> c.fixed("O4", 40, 0)
    >>> c.polar("A", "O2", 10, "theta")
    >>> c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
    >>> s = sweep(c, np.linspace(0, 2 * np.pi, 5))
    >>> bool(s.valid.all()), s["B"].shape
    (True, (5, 2))
    >>> np.allclose(np.hypot(*(s["B"] - s["A"]).T), 35)
    True

    Three rockers of different lengths at once:

    >>> c.parameter("r4", 30)
    >>> c.circle_circle("C", ("A", "O4"), (35, "r4"), branch="left")
    >>> v = sweep(c, np.linspace(0, 2 * np.pi, 5), parameters={"r4": [5, 30, 40]})
    >>> v["C"].shape, v.valid.all(axis=1).tolist()
    ((3, 5, 2), [False, True, True])
    """
    compiled = as_compiled(construction)
    inputs, n = input_arrays(compiled, values, samples)
    if values is not None and n > 1:
        _warn_of_degrees(compiled, inputs, values)
    start = start_labels(compiled, start_branches)
    if parameters is None:
        # refused before allocating, with the estimate and a block that would fit
        check_sweep_memory(len(compiled.steps), n)
        return evaluate(compiled, inputs, n, start=start)
    varied, count = variant_values(compiled, parameters)
    check_sweep_memory(len(compiled.steps), count * n)
    if any(step.node.continued for step in compiled.steps):
        # a closure group is continued along one path: each variant alone
        return _joined([evaluate(compiled, inputs, n, start=start,
                                 parameters={k: np.full(n, v[i]) for k, v in varied.items()})
                        for i in range(count)]).as_variants(count)
    flat = evaluate(compiled, inputs, count * n, start=start, parameters=varied, paths=count,
                    track_incomplete=track_incomplete)
    # each variant's values at its samples: a view, not a copy
    return replace(flat.as_variants(count), parameters={
        k: np.broadcast_to(v[:, None], (count, n)) for k, v in varied.items()})


def _warn_of_degrees(compiled: Compiled, inputs: Mapping[str, np.ndarray],
                     given: ArrayLike | Mapping[str, ArrayLike]) -> None:
    """Warn of each angle input given values that run between ends that look like degrees."""
    for name in (inputs if type(given) is np.ndarray or not isinstance(given, Mapping)
                 else given):
        values = inputs[name]
        if compiled.inputs[name].kind == "angle" and values.ndim == 1:
            low, high = values.item(0), values.item(-1)
            if range_looks_like_degrees(low, high):
                warn_of_degrees(f"sweep: input {name!r} runs from {low:g} to {high:g}, which "
                                f"{degrees_hint(abs(high - low))}")


def _repeated(values: np.ndarray, times: int) -> np.ndarray:
    """Return each value repeated ``times`` times, in order (``np.repeat``, faster)."""
    return np.broadcast_to(values[:, None], (len(values), times)).reshape(-1)


def variant_values(compiled: Compiled,
                   parameters: Mapping[str, ArrayLike]) -> tuple[dict[str, np.ndarray], int]:
    """Return the values of varied parameters as arrays of one shape (V,), and V.

    Raises
    ------
    ConstructionError
        For a name that is not a parameter of the construction, or values
        that are not finite numbers, or do not broadcast to one shape (V,).

    Examples
    --------
    >>> from geokin import Construction
    >>> c = Construction()
    >>> c.parameter("a", 1)
    >>> c.parameter("b", 2)
    >>> c.fixed("O", "a", "b")
    >>> values, count = variant_values(c.compile(), {"a": [1, 2, 3], "b": 5})
    >>> count, values["b"].tolist()
    (3, [5.0, 5.0, 5.0])
    """
    names = list(compiled.parameters)
    arrays = {}
    for name, value in parameters.items():
        if name not in compiled.parameters:
            what = " (it is an input: give its values as the sweep's)" \
                if name in compiled.inputs else did_you_mean(name, names)
            raise ConstructionError(f"no parameter {name!r} to vary{what}", node=name,
                                    kind="parameter")
        try:
            array = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ConstructionError(f"the values of parameter {name!r} are not numbers",
                                    node=name, kind="parameter") from None
        if array.ndim > 1:
            raise ConstructionError(f"the values of parameter {name!r} must be a number or "
                                    f"one-dimensional, got shape {array.shape}", node=name,
                                    kind="parameter")
        if not np.isfinite(array).all():
            # as with_parameters refuses: a variant of NaN size is no design
            first = int(np.flatnonzero(~np.isfinite(array.reshape(-1)))[0])
            which = f"variant {first} is" if array.ndim else "it is"
            raise ConstructionError(f"the values of parameter {name!r} must be finite numbers; "
                                    f"{which} {array.reshape(-1)[first]}", node=name,
                                    kind="parameter")
        arrays[name] = array
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays.values()))
    except ValueError:
        counts = ", ".join(f"{k}: {a.size}" for k, a in arrays.items())
        raise ConstructionError(f"the varied parameters have different numbers of values "
                                f"({counts}); give each the same number, or one") from None
    count = shape[0] if shape else 1
    if count == 0:
        raise ConstructionError("a sweep of variants needs at least one variant; the "
                                "parameters' values are empty")
    return {k: np.broadcast_to(a, (count,)) for k, a in arrays.items()}, count


def _joined(sweeps: list[Sweep]) -> Sweep:
    """Return sweeps of one construction as one sweep of their samples, one after the other."""
    first = sweeps[0]
    offsets = np.cumsum([0] + [len(s) for s in sweeps])

    def joined(arrays):
        return np.concatenate([np.broadcast_to(a, (len(s),)) for a, s in
                               zip(arrays, sweeps, strict=True)])

    coords = {name: tuple(joined([s.points.coords(name)[i] for s in sweeps]) for i in (0, 1))
              for name in first.points}
    valid = joined([s.valid for s in sweeps])
    return Sweep(
        construction=first.construction,
        inputs={k: joined([s.inputs[k] for s in sweeps]) for k in first.inputs},
        points=PointTable(coords, valid), valid=valid,
        failed_step=joined([s.failed_step for s in sweeps]),
        reason_code=joined([s.reason_code for s in sweeps]),
        branches={k: joined([s.branches[k] for s in sweeps]) for k in first.branches},
        events=tuple(replace(e, index=e.index + offset)
                     for s, offset in zip(sweeps, offsets, strict=False) for e in s.events),
        margins={k: joined([s.margins[k] for s in sweeps]) for k in first.margins},
        line_parameters={k: joined([s.line_parameters[k] for s in sweeps])
                         for k in first.line_parameters},
        parameters={k: joined([s.parameters[k] for s in sweeps]) for k in first.parameters})


STREAM_BLOCK_SAMPLES = 2**18
"""How many samples :func:`sweep_in_blocks` yields at a time by default: a
block's sweep holds a few hundred bytes per sample."""

LOOK_BACK = 3
"""How many samples before a block its evaluation starts at: the branch rules
decide what happens at a sample and on a step from the samples and steps on
either side, so a block sees the two steps before its first sample."""


def sweep_in_blocks(construction: Construction | Compiled,
                    values_between: Callable[[int, int], Mapping[str, np.ndarray]],
                    samples: int, *, start_branches: Mapping[str, object] | None = None,
                    block_samples: int = STREAM_BLOCK_SAMPLES) -> Iterator[Sweep]:
    """Evaluate a long sweep block by block, each block as the whole sweep has it.

    For sweeps too long to hold whole (10**8 samples): memory stays that of
    one block. Each block is evaluated from :data:`LOOK_BACK` samples before
    it, starting on the branches the sweep has there (and a closure group
    from its solution there), and two samples beyond it, so that every
    branch change at its samples and on its steps is decided as it is in
    one sweep of all samples. Its branches are checked against the last
    block's on the samples they share, and it is evaluated again from
    corrected branches where they differ.

    Parameters
    ----------
    construction : Construction or Compiled
    values_between : callable
        ``values_between(start, stop)`` returns the input values (radians
        for an angle) of samples ``start`` to ``stop - 1``, a mapping of
        input names to arrays: the path is made as it is walked.
    samples : int
        How many samples the whole sweep has.
    start_branches : mapping of str to str or int, optional
        As for :func:`sweep`.
    block_samples : int
        Samples per block.

    Yields
    ------
    Sweep
        The sweep of each block's samples, in order: its arrays those of the
        whole sweep there, its events those on its steps and on the step into
        its first sample (index 0).

    Examples
    --------
    >>> from geokin import Construction
    >>> c = Construction()
    >>> c.input("theta")
    >>> c.fixed("O2", 0, 0)
    >>> c.fixed("O4", 10, 0)
    >>> c.polar("A", "O2", 4, "theta")
    >>> c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
    >>> theta = np.linspace(0, 4 * np.pi, 101)
    >>> blocks = list(sweep_in_blocks(c, lambda i, j: {"theta": theta[i:j]}, 101,
    ...                               block_samples=10))
    >>> whole = sweep(c, theta)
    >>> np.array_equal(np.concatenate([b.branches["B"] for b in blocks]), whole.branches["B"])
    True
    >>> [e.index for b in blocks for e in b.events] == [e.index % 10 for e in whole.events]
    True
    """
    compiled = as_compiled(construction)
    if block_samples < 1:
        raise ValueError(f"a block needs at least one sample, got {block_samples}")
    start = start_labels(compiled, start_branches)
    two_root = [step.node.name for step in compiled.steps if step.node.roots == 2]
    window: Sweep | None = None
    begin, lo = 0, 0
    while lo < samples:
        hi = min(lo + block_samples, samples)
        while True:
            stop = min(hi + 2, samples)
            if window is None or lo == 0:
                found, found_begin = evaluate(compiled, values_between(0, stop), stop,
                                              start=start), 0
            else:
                found, found_begin = _next_window(compiled, values_between, window, begin, lo,
                                                  stop, two_root), max(lo - LOOK_BACK, 0)
            # the next block starts its evaluation LOOK_BACK samples before its first:
            # there no two roots may meet, so that every meeting it sees begins after
            # a sample it sees too (consecutive meeting samples are one meeting)
            seam = _meeting_until(found, found_begin, hi - LOOK_BACK, two_root)
            if hi == samples or seam is None:
                break
            hi = min(max(hi + 1, seam + LOOK_BACK + 1), samples)
        window, begin = found, found_begin
        yield window.part(lo - begin, hi - begin)
        lo = hi


def _meeting_until(sweep: Sweep, offset: int, at: int, names) -> int | None:
    """Return the last sample of the meeting of roots at sample ``at``, if any node has one.

    ``sweep`` holds samples from ``offset`` on; a meeting is as the branch
    rules have it (:func:`_meet_tolerance`), and it lasts over consecutive
    samples where the roots stay met, up to the last the sweep holds.
    """
    if at < offset:
        return None
    n = len(sweep)
    last = None
    compiled = sweep.construction
    steps = {step.node.name: step for step in _plan(compiled)}
    env = _environment(compiled, dict(sweep.inputs))
    i = at - offset
    tail = np.arange(i, n)  # the samples from ``at`` on
    for name in names:
        x = np.broadcast_to(sweep.points.xy(name)[0], (n,))[tail]
        margin = np.broadcast_to(sweep.margins[name], (n,))[tail]
        node = steps[name].node
        coords = {p: sweep.points.xy(p) for p in node.depends_on()}
        with np.errstate(all="ignore"):
            tolerance = _tolerance_at(node, coords, _step_values(steps[name], env), None,
                                      compiled.ground, tail, np.zeros(tail.size, int))
            met = _apart_at(np.isfinite(x), margin) <= tolerance
        if not met[0]:
            continue
        after = np.flatnonzero(~met)
        end = offset + i + (int(after[0]) - 1 if after.size else n - 1 - i)
        last = end if last is None else max(last, end)
    return last


def _next_window(compiled, values_between, last, last_begin, lo, stop, two_root):
    """Evaluate samples ``lo - LOOK_BACK`` to ``stop - 1`` on the branches ``last`` has there."""
    begin = max(lo - LOOK_BACK, 0)

    def label(sweep, offset, name, i):
        return int(np.broadcast_to(sweep.branches[name], (len(sweep),))[i - offset])

    # on the first step the branch is the one after any change at its first sample
    changed = {e.node for e in last.events
               if e.index + last_begin == begin + 1 and e.fraction == 0}
    first = {name: label(last, last_begin, name, begin) ^ (name in changed) for name in two_root}
    sketches = {name: guess[0] for name, guess in
                assembly_guesses(last, slice(begin - last_begin, begin - last_begin + 1)).items()}
    inputs = values_between(begin, stop)
    for _ in range(4):
        window = evaluate(compiled, inputs, stop - begin, start=first, sketches=sketches or None)
        wrong = {name: label(last, last_begin, name, lo - 1) ^ label(window, begin, name, lo - 1)
                 for name in two_root}
        wrong = {name: flip for name, flip in wrong.items() if flip}
        if not wrong:
            return window
        # the first step was decided otherwise than with the step before it in view
        for name, flip in wrong.items():
            first[name] ^= flip
    raise AssemblyError(f"the sweep could not be evaluated block by block at sample {lo}: "
                        f"the branches of {', '.join(map(repr, wrong))} there differ from "
                        "the block before; sweep it whole", node=next(iter(wrong)))

def start_labels(compiled: Compiled,
                 start_branches: Mapping[str, object] | None) -> dict[str, int] | None:
    """Return the branches some nodes start on, as root indices (0 or 1).

    Parameters
    ----------
    compiled : Compiled
    start_branches : mapping of str to str or int, or None
        By node name: a branch name (``"left"``) or a root index.

    Raises
    ------
    ConstructionError
        For a node that is not a two-root node, or an unknown branch.

    Examples
    --------
    >>> from geokin import Construction
    >>> c = Construction()
    >>> c.fixed("O", 0, 0)
    >>> c.fixed("Q", 3, 0)
    >>> c.circle_circle("P", ("O", "Q"), (2, 2), branch="left")
    >>> start_labels(c.compile(), {"P": "right"})
    {'P': 1}
    """
    if not start_branches:
        return None
    start = {}
    nodes = {step.node.name: step.node for step in compiled.steps}
    for name, branch in start_branches.items():
        node = nodes.get(name)
        if node is None or node.roots != 2:
            raise ConstructionError(f"no two-root node {name!r}{did_you_mean(name, nodes)}",
                                    node=name, field="branch")
        options = node.branch_names
        if isinstance(branch, int | np.integer) and not isinstance(branch, bool) \
                and branch in (0, 1):
            start[name] = int(branch)
        elif branch in options:
            start[name] = options.index(str(branch))
        else:
            raise ConstructionError(f"unknown branch {branch!r}; use "
                                    f"{' or '.join(map(repr, options))} or 0 or 1", node=name,
                                    field="branch")
    return start


def _initial_label(node, cand, n, override, paths=1, origin=None) -> int | np.ndarray:
    """Return the branch a node starts on: the one given, else the node's own choice.

    Over several paths it may differ from path to path: it is then given at
    every sample, each path's at all of its samples. Roots found relative to
    ``origin`` are compared with a sketch position (``near``, absolute) where
    they are.
    """
    if override is not None:
        return override
    if origin is not None and node.chosen_by_position:
        cand = replace(cand, x=tuple(x + origin[0] for x in cand.x),
                       y=tuple(y + origin[1] for y in cand.y))
    first = node.initial_root(cand, n, paths)
    return first if type(first) is int or np.ndim(first) == 0 else _repeated(first, n // paths)


class _Tracker:
    """Branch tracking along the path of a sweep's samples (rules 2 to 4).

    Nodes are tracked in evaluation order; the tracker keeps what it decided
    for each (its branch at every sample and where in a step its roots meet),
    so that a later node can be evaluated between samples with every node
    before it on the right branch there.

    How fast the roots can close in on each other within a step is not seen
    at its ends alone (at a graze the roots leave the way they came, and a
    step across it can end where it began), so it is estimated from the
    rate at which their chord moves per unit of input over the step and its
    neighbours; steps where the path turns back, and a sweep of one step,
    are always looked into.
    """

    def __init__(self, compiled: Compiled, plan, inputs, n: int, origin, varied=None,
                 paths: int = 1, per_path: bool = False, track_incomplete: bool = True):
        self.compiled = compiled
        self.track_incomplete = track_incomplete
        self.plan = plan
        self.given_inputs = inputs
        self.varied = varied or {}
        self.per_path = per_path  # the varied parameters are given once per path
        self.n = n
        self.origin = origin
        self.paths = paths
        self.labels: dict[str, object] = {}
        self.flip_after: dict[str, np.ndarray] = {}  # a meeting at the sample itself
        self.meetings: dict[str, np.ndarray] = {}    # step + fraction, sorted
        # a continued node's solution at the samples, (N, 2k): between two samples it
        # starts from their solutions interpolated
        self.solutions: dict[str, np.ndarray] = {}
        # by node (its place in the plan): the two-root nodes it is found from
        self.ancestors: dict[int, frozenset[str]] = {}
        self.prepared = False

    def _prepare(self) -> None:
        """Read the path the inputs take, once a first node is to be tracked."""
        self.prepared = True
        compiled, n, paths = self.compiled, self.n, self.paths
        self.inputs = {k: _over_samples(v, n) for k, v in self.given_inputs.items()}
        # the steps from the end of one path to the start of the next (design variants):
        # never looked into, nor crossed by a branch
        self.length = n // paths
        self.cut: np.ndarray | None = None
        if paths > 1:
            self.cut = np.zeros(n - 1, dtype=bool)
            self.cut[self.length - 1::self.length] = True
        self.angle_steps = self.length_steps = None
        if paths == 1 and n > 2 and len(self.inputs) == 1 and self._prepare_steady():
            return
        # how far the path moves in each step, all inputs together, and where it turns
        travel = None
        # where the path turns back, and which steps are between finite inputs: made
        # only for paths that need them, to spare a monotone sweep two arrays
        self.turning: np.ndarray | bool = (np.zeros(n - 1, dtype=bool) if n > 2
                                           else np.ones(n - 1, dtype=bool))
        turns_back = n <= 2
        self.finite: np.ndarray | bool = True
        # each input's shortest and longest step, where it runs one way
        spans: list[tuple[float, float] | None] = []
        for name, values in self.inputs.items():
            if len(self.inputs) == 1:
                # into memory kept from sweep to sweep: a fresh array of this size costs
                # page faults that would double what tracking costs a sweep
                step = np.subtract(values[1:], values[:-1], out=kept_memory(n - 1, "tracking"))
            else:
                step = np.diff(values)
            if self.cut is not None:
                # a step between paths counts as the one before it, so that paths that
                # each run one way still do all together
                step[self.cut] = step[np.flatnonzero(self.cut) - 1]
            # as Python numbers: the tests on them below cost less than on numpy's
            low, high = extremes(step) if step.size else (0.0, 0.0)
            one_way = (low > 0 and high > 0) or (low < 0 and high < 0)
            steady = one_way and high - low <= 1e-9 * max(abs(low), abs(high))
            if len(self.inputs) == 1 and not steady:
                step = step.copy()  # kept beyond this sweep's scratch work
            if low >= 0 or high <= 0:
                moved = step if low >= 0 else -step
                spans.append((min(abs(low), abs(high)) if one_way else 0.0,
                              max(abs(low), abs(high))))
            else:
                spans.append(None)
                moved = np.abs(step)
                if not np.isfinite(moved).all():
                    self.finite = self.finite & np.isfinite(moved)
                    moved = np.where(self.finite, moved, 0.0)
                # where a step goes the other way from the last step that moved, the
                # path turns back (repeated samples in between or not)
                moving = np.flatnonzero(moved > 0)
                sign = np.sign(step[moving])
                turns = np.flatnonzero(sign[1:] * sign[:-1] < 0)
                self.turning[moving[turns]] = self.turning[moving[turns + 1]] = True
                turns_back = turns_back or bool(turns.size)
            travel = moved if travel is None else travel + moved
            if compiled.inputs[name].kind == "angle":
                self.angle_steps = moved if self.angle_steps is None else np.fmax(
                    self.angle_steps, moved)
            else:
                self.length_steps = moved if self.length_steps is None else np.fmax(
                    self.length_steps, moved)
        if travel is None or travel.size == 0:
            travel = np.zeros(max(n - 1, 0))
        if self.angle_steps is None:
            self.angle_steps = np.zeros(n - 1)
        scratch = None
        if len(spans) == 1 and spans[0] is not None and math.isfinite(spans[0][1]):
            # one input running one way (a linspace, most often): its extremes are known,
            # and its steps can be held as numbers, freeing their array for scratch work
            shortest, self.longest = spans[0]
            self.even = self.longest - shortest <= 1e-9 * self.longest
            if self.even:
                scratch = travel
                travel = _constant(self.longest, travel.shape[0])
                if self.length_steps is None:
                    self.angle_steps = travel
                else:
                    self.length_steps = travel
        else:
            self.longest = float(travel.max(initial=0.0))
            # steps of equal length need no rates per unit of travel
            self.even = (self.longest - float(travel.min(initial=self.longest))
                         <= 1e-9 * self.longest)
        self.travel = travel
        self.any_coarse = (self.length_steps is not None or turns_back
                           or (self.longest if self.even and scratch is not None else float(
                               self.angle_steps.max(initial=0.0)))
                           > ANGLE_RESOLUTION * (1 + 1e-9))
        # memory for the per-step work of the whole-sweep test, reused from node to node
        self.scratch = np.empty(n - 1) if scratch is None else scratch

    def _prepare_steady(self) -> bool:
        """Read the path of one input moving one way in equal steps (a linspace), if it is.

        Such a path, the commonest, is known by its step alone; for any
        other, nothing is kept and False returned.
        """
        ((name, values),) = self.inputs.items()
        # a few thousand steps cost less to allocate than to look up kept memory for
        step = np.subtract(values[1:], values[:-1],
                           out=kept_memory(self.n - 1, "tracking") if self.n > DOT_BELOW else None)
        low, high = extremes(step)
        shortest, longest = (low, high) if low > 0 else (-high, -low)
        # steps either way, NaN and infinite ones fail this test
        if not 0 < shortest <= longest <= shortest + 1e-9 * longest < math.inf:
            return False
        self.turning = False  # at no step: a number serves for all
        self.finite = True
        self.longest, self.even = longest, True
        self.travel = _throughout(longest, self.n - 1)
        if self.compiled.inputs[name].kind == "angle":
            self.angle_steps = self.travel
            self.any_coarse = longest > ANGLE_RESOLUTION * (1 + 1e-9)
        else:
            self.angle_steps, self.length_steps = np.zeros(self.n - 1), self.travel
            self.any_coarse = True
        self.scratch = step
        return True

    def track(self, position: int, cand, start: int | np.ndarray,
              tolerance_at: Callable[[np.ndarray, np.ndarray], float | np.ndarray] | None = None
              ):
        """Return the branch of node ``plan[position]`` at every sample, and its events.

        ``tolerance_at(samples, path)`` gives how close its roots meet at
        some samples, each on its path (:func:`_tolerance_at`;
        :data:`MEET_RTOL` without it).
        """
        if not self.prepared:
            self._prepare()
        node = self.plan[position].node
        n = self.n
        margin = _over_samples(cand.margin, n)
        # the samples looked at closely below: all, or those of the paths (variants) that
        # the quick test, each path on its own, does not settle
        keep = None
        if self.cut is not None:
            whole = None
            if not (self.track_incomplete or self.plan[position].branch_decides):
                # its branch along a path it misses somewhere decides nothing that is kept
                whole = self._whole_paths(cand)
            if not self.any_coarse:
                keep = self._unsettled(margin, whole)
            elif whole is not None:
                keep = self._samples_of(np.flatnonzero(whole))
            if keep is not None and keep.size == 0:
                self.labels[node.name] = start
                return start, []
        elif not self.any_coarse:
            # rule 3's test over the whole sweep at once, which settles most sweeps: the
            # half-distance between the roots over the node's scale, u (the square
            # root of the margin; NaN where the roots do not exist, which sends the
            # sweep to the closer look below), against how fast it moves. First on the
            # margin itself, which spares a square root: |du| <= sqrt(|d(u**2)|)
            # NaN in the margin fails both tests whatever the reductions make of it: the
            # faster ones that carry NaN will do
            moved = self.scratch
            np.subtract(margin[1:], margin[:-1], out=moved)
            low, high = extremes(moved)
            fastest = max(high, -low)
            if not self.even:
                fastest = float(np.fmax.reduce(np.abs(moved) / self.travel)) * self.longest
            if least_element(margin) > (SAFETY * SAFETY) * fastest:
                self.labels[node.name] = start
                return start, []
            apart = np.sqrt(margin)
            np.subtract(apart[1:], apart[:-1], out=moved)
            np.abs(moved, out=moved)
            if not self.even:
                np.divide(moved, self.travel, out=moved)
            fastest = (largest_element(moved) if self.even
                       else np.fmax.reduce(moved) * self.longest)
            if least_element(apart) > SAFETY * fastest:
                self.labels[node.name] = start
                return start, []
        # per sample and per step, of the samples looked at: the step from sample i of
        # them to sample i + 1 is step kept[i] of the sweep
        if keep is None:
            kept, m, inputs, cut = None, n, self.inputs, self.cut
        else:
            kept, m = keep[:-1], keep.size
            margin = margin[keep]
            inputs = {name: values[keep] for name, values in self.inputs.items()}
            cut = np.zeros(m - 1, dtype=bool)
            cut[self.length - 1::self.length] = True

        def per_step(value):
            return value if kept is None or np.ndim(value) == 0 else value[kept]

        travel, turning, finite = per_step(self.travel), per_step(self.turning), per_step(
            self.finite)
        # zero where they meet, also for roots within the primitives' tangency tolerance:
        # it folds at a graze like a V
        present = np.isfinite(_over_samples(cand.x[0], n))
        if keep is not None:
            present = present[keep]
        apart = _apart_at(present, margin)
        moved = np.abs(apart[1:] - apart[:-1])
        if cut is not None:
            moved[cut] = 0.0
        # what it could move per unit of travel, over each step and its neighbours
        rate = moved if self.even else moved / travel
        if m > 2:
            # the rate over a step is at most the largest of it and its neighbours'
            rate = np.fmax(rate, np.concatenate([rate[1:], rate[-1:]]))
            rate = np.fmax(rate, np.concatenate([rate[:1], rate[:-1]]))
        reach = rate if self.even else rate * travel
        both = present[:-1] & present[1:]
        # a step into or out of a gap is looked into up to the gap's edge
        edge = present[:-1] != present[1:]
        settled = np.fmin(apart[:-1], apart[1:]) > SAFETY * reach
        if cut is not None:
            both, edge = both & ~cut, edge & ~cut
        if not self.any_coarse and not ((both & ~settled) | edge).any():
            self.labels[node.name] = start
            return start, []
        # a step looked into is cut at half the resolution: a narrow dip of the roots'
        # distance shows at one cut at least
        assert self.angle_steps is not None  # _prepare sets it
        angle_steps = per_step(self.angle_steps)
        pieces = np.ceil(angle_steps / (ANGLE_RESOLUTION / 2) - 1e-9)
        coarse = turning | (angle_steps > ANGLE_RESOLUTION * (1 + 1e-9))
        if self.length_steps is not None:
            # the node's scale: over the sweep, or each path's own (a variant is looked
            # into as it would be alone)
            scale = (_node_scale(cand, n) if self.cut is None
                     else per_step(_repeated(_path_scales(cand, n, self.length),
                                             self.length)[:-1]))
            pieces = np.fmax(pieces, np.ceil(per_step(self.length_steps)
                                             / (LENGTH_RESOLUTION / 2 * scale)))
            coarse = coarse | (pieces > 1)
        # a step of more than MAX_PIECES pieces (hundreds of turns) is past resolving
        doubtful = ((both & ~settled) | edge | coarse) & finite & (pieces <= MAX_PIECES)
        if cut is not None:
            doubtful &= ~cut
        doubtful = np.flatnonzero(doubtful)
        # the tolerance of the roots' meeting, where it can matter: at samples close
        # enough to meet, and at the ends of the steps looked into
        tolerance: float | np.ndarray = MEET_RTOL
        if tolerance_at is not None:
            with np.errstate(invalid="ignore"):
                close = apart <= MEET_RTOL * math.sqrt(FAR_RATIO)
            close[doubtful] = close[doubtful + 1] = True
            close = np.flatnonzero(close)
            if close.size:
                samples = close if keep is None else keep[close]
                found = tolerance_at(samples, samples // self.length)
                if np.ndim(found):
                    tolerance = np.full(m, MEET_RTOL)
                    tolerance[close] = found

        def step_tolerance(steps):
            """Return the tolerance of some steps: the larger of their ends'."""
            if isinstance(tolerance, np.ndarray):
                return np.fmax(tolerance[steps], tolerance[steps + 1])
            return tolerance

        at_sample = present & (apart <= tolerance)
        # each doubtful step is looked into at two pieces at least, so many steps at a
        # time that their pieces stay within a block of memory
        pieces = np.maximum(pieces[doubtful], 2).astype(np.int64)
        block = np.cumsum(pieces) // PIECES_PER_BLOCK
        cuts = np.flatnonzero(np.diff(block)) + 1
        inner = np.concatenate([np.empty(0)] + [
            self._meetings_inside(position, steps, counts, reach[steps], apart, at_sample,
                                  step_tolerance(steps), kept)
            for steps, counts in zip(np.split(doubtful, cuts), np.split(pieces, cuts),
                                     strict=True) if steps.size])
        inner.sort()
        # consecutive meeting samples are one meeting where the roots stay together
        # between them (looked at off the middle, where a meeting of its own would hide
        # their parting), and two where they part
        together = np.zeros(m - 1, dtype=bool)
        pairs = at_sample[:-1] & at_sample[1:]
        if cut is not None:
            pairs &= ~cut
        pairs = np.flatnonzero(pairs)
        if pairs.size:
            twice = np.concatenate([pairs, pairs])  # steps of the samples looked at
            inner_apart = self._apart(position, twice if kept is None else kept[twice],
                                      np.repeat([0.382, 0.618], pairs.size))
            together[pairs] = ~(inner_apart > step_tolerance(twice)).reshape(2, -1).any(axis=0)
        flip_after = _flips_at_samples(at_sample, present, together, inputs, self.length)
        if keep is not None:
            flip_after, looked = np.zeros(n, dtype=bool), flip_after
            flip_after[keep] = looked
        flips = flip_after[:-1].astype(np.int64)
        if inner.size:
            np.add.at(flips, np.floor(inner).astype(np.int64), 1)
        if not flips.any():
            self.labels[node.name] = start
            return start, []
        label = np.empty(n, dtype=np.int8)
        label[0] = 0
        label[1:] = np.cumsum(flips) % 2
        if self.cut is not None:  # each path counts its own changes
            label ^= _repeated(label[::self.length], self.length)
        label ^= np.asarray(start, dtype=np.int8)
        self.labels[node.name] = label
        self.flip_after[node.name] = flip_after
        self.meetings[node.name] = inner
        names = node.branch_names
        events = [BranchEvent(node.name, int(i) + 1, names[label[i]], names[label[i] ^ 1], 0.0)
                  for i in np.flatnonzero(flip_after[:-1])]
        steps = np.floor(inner).astype(np.int64)
        # meetings inside one step alternate the branch from the one the step set out on
        earlier = np.arange(inner.size) - np.searchsorted(inner, steps.astype(float))
        before = label[steps] ^ flip_after[steps] ^ (earlier % 2).astype(np.int8)
        events += [BranchEvent(node.name, int(i) + 1, names[b], names[b ^ 1], float(key - i))
                   for i, b, key in zip(steps, before, inner, strict=True)]
        return label, events

    def _meetings_inside(self, position, steps, pieces, step_reach, apart, at_sample,
                         step_tolerance, kept=None):
        """Return where the roots meet inside the given steps, as step + fraction, sorted.

        Each step is cut into its pieces; pieces whose roots neither stay
        provably apart nor meet are cut again (:data:`CUTS`), all at once,
        until each is decided. A piece's rate (how far the roots' distance
        may change over a whole step) is at first the largest seen over it,
        its neighbours and the step's neighbours; a piece cut from another
        takes the largest of that one's rate and the rates seen over each
        of its pieces, so that it never falls. Meetings
        that touch a sample where the roots meet belong to that sample
        (rule 4) and are left out here. Where only some samples are looked
        at, ``steps``, ``apart`` and ``at_sample`` are of those, and
        ``kept`` gives the sweep's step of each; the meetings are returned
        on the sweep's steps. ``step_tolerance`` is each step's
        :func:`_meet_tolerance` (a number for all).
        """
        def sweep_step(step):
            return step if kept is None else kept[step]

        step = np.repeat(steps, pieces)
        first = np.repeat(np.cumsum(pieces) - pieces, pieces)
        k = np.arange(step.size) - first
        count = np.repeat(pieces, pieces)
        low, high = k / count, (k + 1) / count
        inside = low > 0
        at_low = apart[step]
        at_low[inside] = self._apart(position, sweep_step(step[inside]), low[inside])
        # a piece ends where the next begins; the last piece ends at the next sample
        last = high == 1
        at_high = np.roll(at_low, -1)
        at_high[last] = apart[step[last] + 1]
        rate = np.abs(at_high - at_low) * count
        # the largest of each piece's own rate, its neighbours' in the step, and the step's
        rate = np.fmax(rate, np.where(last, rate, np.roll(rate, -1)))
        rate = np.fmax(rate, np.where(k == 0, rate, np.roll(rate, 1)))
        rate = np.fmax(rate, np.repeat(step_reach, pieces))

        def closable_above(some):
            """Return how many open pieces a step may hold before it can be closed."""
            return np.maximum(OPEN_PER_PIECE * pieces[np.searchsorted(steps, some)], MIN_CROWD)
        tolerance = (step_tolerance if np.ndim(step_tolerance) == 0
                     else np.repeat(step_tolerance, pieces))
        found_step, found_low, found_high = [], [], []
        edge_step, edge_low, edge_high = [], [], []
        for _ in range(MAX_HALVINGS):
            closest = np.fmin(at_low, at_high)
            reach = rate * (high - low)
            present = np.isfinite(at_low) & np.isfinite(at_high)
            # near a meeting the distance is known only to rounding: a small piece with
            # an end within the tolerance meets, and nothing closer is settled apart
            meet = present & (closest <= tolerance) & (reach <= tolerance)
            settled = (closest > SAFETY * reach) & (closest > tolerance)
            # a piece with one end in a gap holds the gap's edge: cut until it is found
            straddling = np.isfinite(at_low) != np.isfinite(at_high)
            found = straddling & (high - low <= EDGE_WIDTH)
            # a piece at the inputs' rounding is decided: it meets only if the roots
            # are within the tolerance at one of its ends
            open_ = (present & ~meet & ~settled & (high - low > EDGE_WIDTH)) | (
                straddling & ~found)
            crowded = _most_crowded(step[open_], MAX_OPEN_PIECES, closable_above)
            if crowded is not None:
                # rounding noise over a stretch: its gaps' edges and its meetings lie
                # where it is still open
                crowded = open_ & np.isin(step, crowded)
                found |= crowded & straddling
                meet |= crowded & ~straddling
                open_ &= ~crowded
            edge_step.append(step[found])
            edge_low.append(low[found])
            edge_high.append(high[found])
            found_step.append(step[meet])
            found_low.append(low[meet])
            found_high.append(high[meet])
            if not open_.any():
                break
            # each open piece is cut as finely as its test asks, in 2 to CUTS pieces
            # (a power of two); one holding a gap's edge in CUTS, to find it in few
            # rounds
            closest, reach = closest[open_], reach[open_]
            if np.ndim(tolerance):
                tolerance = tolerance[open_]
            with np.errstate(divide="ignore", invalid="ignore"):
                asks = np.where(closest <= tolerance, reach / tolerance, SAFETY * reach / closest)
                asks = 2.0 ** np.ceil(np.log2(asks))
            ways = np.where(straddling[open_] | ~(asks < CUTS), CUTS,
                            np.maximum(asks, 2)).astype(np.int64)
            del closest, reach, asks
            step, low, high, rate = step[open_], low[open_], high[open_], rate[open_]
            width = (high - low) / ways  # exact: a power of two
            # the ends of each piece's pieces in a row (low, the cuts, high), each
            # cut shared by the two pieces either side of it
            first = np.cumsum(ways + 1) - (ways + 1)
            last = first + ways
            owner = np.repeat(np.arange(step.size, dtype=np.int32), ways + 1)
            ends = np.arange(owner.size, dtype=float)
            ends -= first[owner]  # each end's place in its piece: 0 to ways
            ends *= width[owner]
            ends += low[owner]
            ends[last] = high
            at = np.empty(ends.size)
            at[first], at[last] = at_low[open_], at_high[open_]
            inner = np.ones(ends.size, dtype=bool)
            inner[first] = inner[last] = False
            cuts = np.flatnonzero(inner)
            del inner
            for lo in range(0, cuts.size, PIECES_PER_BLOCK):
                some = cuts[lo:lo + PIECES_PER_BLOCK]
                at[some] = self._apart(position, sweep_step(step[owner[some]]), ends[some])
            del cuts
            moved = np.abs(np.diff(at))
            moved[first[1:] - 1] = np.nan  # from one piece's high end to the next one's low
            rate = np.fmax(rate, np.fmax.reduceat(moved, first) / width)
            del moved
            new = np.ones(ends.size, dtype=bool)
            new[last] = False  # every end but a piece's last starts a new piece
            new = np.flatnonzero(new)
            owner = owner[new]
            step, rate = step[owner], rate[owner]
            if np.ndim(tolerance):
                tolerance = tolerance[owner]
            low, high, at_low, at_high = ends[new], ends[new + 1], at[new], at[new + 1]
        else:
            # still open after every cut: the roots meet within rounding of the inputs
            found_step.append(step)
            found_low.append(low)
            found_high.append(high)
        edges = tuple(map(np.concatenate, (edge_step, edge_low, edge_high)))
        return self._merge_meetings(position, steps, np.concatenate(found_step),
                                    np.concatenate(found_low), np.concatenate(found_high),
                                    at_sample, edges, step_tolerance, sweep_step)

    def _merge_meetings(self, position, steps, step, low, high, at_sample, edges,
                        step_tolerance=MEET_RTOL, sweep_step=None):
        """Return one meeting per place the roots meet, as step + fraction, sorted.

        Touching meeting pieces are one meeting; so are pieces apart by a gap
        where the roots stay within rounding of each other (the distance
        between nearly equal roots is noisy, so one meeting can show as
        several islands). Meetings joined to a sample where the roots meet
        belong to that sample (rule 4), and those joined to the edge of a
        stretch that cannot be assembled belong to that stretch (rule 5):
        both are left out. ``step_tolerance`` is the :func:`_meet_tolerance`
        of each of ``steps`` (sorted), or a number for all.
        """
        # the meeting samples at the ends of the steps looked into, as pieces of no
        # width, and the edges of gaps: a group holding one of them is left out
        start, end = at_sample[steps], at_sample[steps + 1]
        edge_step, edge_low, edge_high = edges
        owned = np.zeros(step.size, dtype=bool)
        step = np.concatenate([step, steps[start], steps[end], edge_step])
        low = np.concatenate([low, np.zeros(start.sum()), np.ones(end.sum()), edge_low])
        high = np.concatenate([high, np.zeros(start.sum()), np.ones(end.sum()), edge_high])
        owned = np.concatenate([owned, np.ones(step.size - owned.size, dtype=bool)])
        if step.size == 0:
            return np.empty(0)
        order = np.lexsort((low, step))
        step, low, high, owned = step[order], low[order], high[order], owned[order]
        same = step[1:] == step[:-1]
        gap = same & (low[1:] > high[:-1])
        joined = same & ~gap
        if gap.any():
            at = np.flatnonzero(gap)
            between = step[at] if sweep_step is None else sweep_step(step[at])
            # the stretch's ends and middle, in a row each
            fraction = np.stack([high[at], 0.5 * (high[at] + low[at + 1]), low[at + 1]])
            present, margin, shift = self._margin(position, np.tile(between, 3),
                                                  fraction.reshape(-1), rounding=True)
            middle = _apart_at(present, margin).reshape(3, -1)[1]
            # roots that cannot be assembled between two pieces: the edge of a gap,
            # which flickers within rounding of the primitives' tangency test
            tolerance = (step_tolerance if np.ndim(step_tolerance) == 0
                         else step_tolerance[np.searchsorted(steps, step[at])])
            # or within what the rounding of earlier nodes' roots makes of their
            # distance (next to such a node's meeting): their margin within four times
            # what it moves by that rounding, as near as can be told, they stay met.
            # The least rounding over the stretch: its middle may fall on that earlier
            # node's own meeting, where its rounding is largest, while its ends do not
            least = np.min(shift.reshape(3, -1), axis=0)
            joined[at] = ~((middle > 4 * tolerance) & (middle > 2 * np.sqrt(least)))
            owned[at[np.isnan(middle)] + 1] = True
        group = np.concatenate([[0], np.cumsum(~joined)])
        count = group[-1] + 1
        g_step = step[np.flatnonzero(np.concatenate([[True], ~joined]))]
        g_low = np.full(count, np.inf)
        g_high = np.full(count, -np.inf)
        np.minimum.at(g_low, group, low)
        np.maximum.at(g_high, group, high)
        g_owned = np.zeros(count, dtype=bool)
        np.logical_or.at(g_owned, group, owned)
        keep = ~g_owned
        found = g_step[keep] if sweep_step is None else sweep_step(g_step[keep])
        return np.sort(found + 0.5 * (g_low[keep] + g_high[keep]))

    def _whole_paths(self, cand) -> np.ndarray:
        """Return whether a node is found at every sample of each path."""
        present = np.isfinite(_over_samples(cand.x[0], self.n))
        return np.logical_and.reduce(present.reshape(-1, self.length), axis=1)

    def _samples_of(self, paths: np.ndarray) -> np.ndarray:
        """Return the samples of some paths, in order."""
        return (paths[:, None] * self.length + np.arange(self.length)).reshape(-1)

    def _unsettled(self, margin, among=None):
        """Return the samples of the paths that rule 3's quick test does not settle.

        The test of :meth:`track` over a whole sweep, made on each path (each
        variant) on its own: a path is settled by its own margins and rates,
        as it is swept alone. A NaN margin leaves its path open. With
        ``among`` (whether to look at each path), the others count as settled.
        """
        paths, length = self.n // self.length, self.length
        # each path's steps in a row, the step to the next path last, where it is zero
        moved = kept_memory(self.n, "tracking")
        np.subtract(margin[1:], margin[:-1], out=moved[:-1])
        moved = moved.reshape(paths, length)
        moved[:, -1] = 0.0
        np.abs(moved, out=moved)
        per_travel = 1.0
        if not self.even:
            per_travel = np.ones(length)
            per_travel[:-1] = self.longest / np.broadcast_to(self.travel, (self.n - 1,))[
                :length - 1]
            moved *= per_travel
        rows = margin.reshape(paths, length)
        with np.errstate(invalid="ignore"):
            settled = np.min(rows, axis=1) > (SAFETY * SAFETY) * np.max(moved, axis=1)
            if among is not None:
                settled |= ~among
            if not settled.all():
                open_ = np.flatnonzero(~settled)
                apart = np.sqrt(rows[open_])
                moved = np.zeros_like(apart)
                moved[:, :-1] = np.abs(np.diff(apart, axis=1))
                moved *= per_travel
                settled[open_] = np.min(apart, axis=1) > SAFETY * np.max(moved, axis=1)
        return self._samples_of(np.flatnonzero(~settled))

    def _apart(self, position, step, fraction):
        """Return how far apart a node's roots are at fractions of steps.

        The distance is relative, as in :meth:`track`, with every earlier node
        on its branch there; NaN where the roots do not exist.
        """
        return _apart_at(*self._margin(position, step, fraction))

    def _margin(self, position, step, fraction, rounding=False):
        """Return whether a node's roots exist at fractions of steps, and its margin there.

        Every earlier node is on its branch there (:meth:`_label_between`).
        With ``rounding``, also how far the margin moves when each moving
        two-root node it is found from moves by its own rounding: a root a
        relative distance ``a`` from the other is known to ``eps / (2 a)``
        of its node's scale (about ``sqrt(eps)`` where they meet), towards or
        away from it. Next to such a node's meeting its points are known
        coarsely, and so is the margin, as far as it depends on them.

        Returns
        -------
        present : ndarray of bool
        margin : ndarray
        shift : ndarray
            Only with ``rounding``: the margin's move, zero where it does not
            depend on such a node.
        """
        inputs = {name: values[step] + fraction * (values[step + 1] - values[step])
                  for name, values in self.inputs.items()}
        at = step // self.length if self.per_path else step
        inputs.update({name: values[at] for name, values in self.varied.items()})
        env = _environment(self.compiled, inputs)
        coords: dict[str, tuple] = {}
        moved: dict[str, tuple] = {}  # the points that move with those roundings
        ancestors = self._two_root_ancestors(position) if rounding else frozenset()
        size = step.size
        for planned in self.plan[:position + 1]:
            node = planned.node
            guess = None
            if node.continued:
                solution = self.solutions[node.name]
                guess = (solution[step] + fraction[:, None] * (solution[step + 1]
                                                               - solution[step]))
                if self.origin is not None:  # shifted back in _candidates
                    guess = guess + np.tile(self.origin, guess.shape[1] // 2)
            values = _step_values(planned, env)
            cand = _candidates(planned, coords, values, self.origin, guess)
            again = (_candidates(planned, {**coords, **moved}, values, self.origin, guess)
                     if moved and not moved.keys().isdisjoint(node.depends_on()) else None)
            if planned is self.plan[position]:
                present = np.isfinite(np.broadcast_to(cand.x[0], (size,)))
                margin = np.broadcast_to(cand.margin, (size,))
                if not rounding:
                    return present, margin
                shift = (np.zeros(size) if again is None
                         else np.abs(np.broadcast_to(again.margin, (size,)) - margin))
                return present, margin, shift
            if node.roots == 1:
                coords[node.name] = (cand.x[0], cand.y[0])
                if again is not None:
                    moved[node.name] = (again.x[0], again.y[0])
                continue
            label = self._label_between(node.name, step, fraction)
            coords[node.name] = _choose(cand, label)
            if again is not None:
                moved[node.name] = _choose(again, label)
            if node.name in ancestors:
                (x, y), (ox, oy) = moved.get(node.name, coords[node.name]), _choose(cand, 1 - label)
                toward = _EPS / (4 * np.fmax(np.broadcast_to(cand.margin, (size,)), _EPS))
                moved[node.name] = (x + toward * (ox - coords[node.name][0]),
                                    y + toward * (oy - coords[node.name][1]))
        raise AssertionError("unreachable")

    def _two_root_ancestors(self, position) -> frozenset[str]:
        """Return the moving two-root nodes node ``plan[position]`` is found from, at any remove."""
        found = self.ancestors.get(position)
        if found is None:
            # the plan is in the order points are found: walking back, a node that
            # finds a point needed finds its own from earlier ones
            needed = set(self.plan[position].node.depends_on())
            two_root = set()
            for planned in reversed(self.plan[:position]):
                node = planned.node
                if needed.isdisjoint(node.defines):
                    continue
                needed.update(node.depends_on())
                # a fixed point is rounded once, the same at every sample: a mechanism
                # a rounding apart, not noise
                if node.roots == 2 and node.name not in self.compiled.ground:
                    two_root.add(node.name)
            found = self.ancestors[position] = frozenset(two_root)
        return found

    def _label_between(self, name, step, fraction):
        """Return a tracked node's branch at fractions of steps (after its meetings there)."""
        label = self.labels[name]
        if np.ndim(label) == 0:
            return label
        label = np.asarray(label)[step]
        if name in self.flip_after:
            label = label ^ self.flip_after[name][step]
        meetings = self.meetings.get(name, np.empty(0))
        if meetings.size:
            before = (np.searchsorted(meetings, step + fraction)
                      - np.searchsorted(meetings, step.astype(float)))
            label = label ^ (before % 2).astype(np.int8)
        return label


_KEPT = threading.local()


def kept_memory(size: int, purpose: str) -> np.ndarray:
    """Return ``size`` floats of this thread's memory for ``purpose``, kept between calls.

    A fresh array of many samples costs more to fault in than the work done
    in it; up to 2**22 floats (32 MiB) are kept per thread and purpose. Each
    purpose has its own, so that one never writes into another's.

    Examples
    --------
    >>> a = kept_memory(10, "example")
    >>> a.shape, kept_memory(5, "example").base is a.base
    ((10,), True)
    """
    buffers = _KEPT.__dict__.setdefault("buffers", {})
    buffer = buffers.get(purpose)
    if buffer is None or buffer.size < size:
        buffer = np.empty(size)
        if size <= 2**22:
            buffers[purpose] = buffer
    return buffer[:size]


def _node_scale(cand, n) -> float:
    """Return a node's largest scale.

    That is its roots' half-distance over the square root of its margin (the
    squared half-distance over the squared scale).
    """
    margin = _over_samples(cand.margin, n)
    dx = _over_samples(cand.x[1], n) - _over_samples(cand.x[0], n)
    dy = _over_samples(cand.y[1], n) - _over_samples(cand.y[0], n)
    usable = margin > 1e-12
    if usable.any():
        scale = float(np.nanmax(0.5 * np.hypot(dx[usable], dy[usable])
                                / np.sqrt(margin[usable])))
        if np.isfinite(scale) and scale > 0:
            return scale
    return 1.0


def _most_crowded(step: np.ndarray, most: int, least: Callable[[np.ndarray], np.ndarray]
                  ) -> np.ndarray | None:
    """Return the steps to close so that at most ``most`` open pieces are left.

    ``step`` holds the step of each open piece. Only a step with more open
    pieces than ``least(steps)`` gives for it is closed, the steps with the
    most first: a step of rounding noise leaves the others be, and a quiet
    one is never closed. None when there is none to close.

    Examples
    --------
    >>> def least(steps):
    ...     return np.full(steps.shape, 1)
    >>> _most_crowded(np.array([4, 4, 4, 7, 9, 9]), 3, least).tolist()
    [4]
    """
    if step.size <= most:
        return None
    steps, counts = np.unique(step, return_counts=True)
    closable = counts > least(steps)
    if not closable.any():
        return None
    steps, counts = steps[closable], counts[closable]
    order = np.argsort(-counts, kind="stable")
    left = step.size - np.cumsum(counts[order])
    enough = left <= most
    return steps[order[:int(np.argmax(enough)) + 1 if enough.any() else order.size]]


def _filled_tolerance(tolerance, path):
    """Return tolerances with those not known (NaN) the largest known on their path.

    An island of assembly inside a step whose ends fail is as far from the
    origin as the samples of its path where the node is found; a path with
    none takes :data:`MEET_RTOL`. ``path`` numbers each sample's path.

    Examples
    --------
    >>> _filled_tolerance(np.array([2e-7, np.nan, np.nan]), np.array([0, 0, 1])).tolist()
    [2e-07, 2e-07, 1e-07]
    """
    if np.ndim(tolerance) == 0 or not np.isnan(tolerance).any():
        return tolerance
    best = np.full(int(path.max()) + 1, -np.inf)
    np.fmax.at(best, path, tolerance)
    fill = best[path]
    fill[~np.isfinite(fill)] = MEET_RTOL
    return np.where(np.isnan(tolerance), fill, tolerance)


def _meet_tolerance(coordinates, scale, n: int) -> float | np.ndarray:
    """Return how close a node's roots meet at each of N samples, relative to its scale.

    That is :data:`MEET_RTOL`, widened by ``sqrt(R)`` where the
    ``coordinates`` of the moving points the node is found from (x and y
    arrays) are R times its ``scale`` (each sample's, or None): they are
    rounded R times coarser than the scale, and the distance between the
    roots, a square root of a difference of squares, the square root of
    that. Roots found far from the origin of their frame would otherwise seem
    apart by rounding alone wherever they touch, and be looked into without
    end. Points that do not move are left out: their rounding is the same at
    every sample, a mechanism a rounding apart, not noise from sample to
    sample. NaN where the node's points are not found (see
    :func:`_filled_tolerance`).

    Examples
    --------
    >>> x, y = np.array([1000.0]), np.array([0.0])
    >>> float(_meet_tolerance((x, y), np.array([1.0]), 1)[0] / MEET_RTOL)
    31.622776601683793
    """
    if scale is None or not coordinates:
        return MEET_RTOL
    with np.errstate(all="ignore"):
        largest = np.fmax.reduce([np.abs(np.broadcast_to(c, (n,))) for c in coordinates])
        return meeting_rtol(np.where(scale == 0, 1.0, largest / scale))


def meeting_rtol(ratio: ArrayLike) -> np.ndarray:
    """Return how close two roots meet, relative to their node's scale, R times it from (0, 0).

    The branch rules take roots this close (over the node's scale) as
    meeting: :data:`MEET_RTOL`, widened by ``sqrt(R)`` for a node found
    from moving points R times its scale from the origin of its frame (their
    rounding is R times coarser, and the roots' distance its square root),
    R taken from 1 to :data:`FAR_RATIO`.

    Examples
    --------
    >>> meeting_rtol([0.5, 100.0]).tolist()
    [1e-07, 1e-06]
    """
    return MEET_RTOL * np.sqrt(np.clip(np.asarray(ratio, dtype=float), 1.0, FAR_RATIO))


def _tolerance_at(node, coords, values, rows, ground, samples, path, origin=None):
    """Return a node's :func:`_meet_tolerance` at some samples of an evaluation.

    ``coords`` and ``values`` are the evaluation's, at every sample (over
    design variants evaluated on rows, ``values`` are on the rows), its
    points relative to ``origin``; ``ground`` names the points that do not
    move. The tolerance is that of the points where they are: a mechanism
    found around its pivots far from (0, 0) is known to the rounding of
    the coordinates it is written in (a parallelogram written there is a
    parallelogram only to within it). Where the node's points are not
    found, the largest known on the sample's ``path`` (one number per
    sample) stands in (:func:`_filled_tolerance`).
    """
    if rows is not None:
        values = {k: _as_samples(v, rows) for k, v in values.items()}

    def part(value):
        return value[samples] if np.ndim(value) else value

    picked = {p: (part(coords[p][0]), part(coords[p][1])) for p in node.depends_on()}
    scale = node.scale(picked, {k: part(v) for k, v in values.items()})
    ox, oy = origin or (0.0, 0.0)
    moving = [c for p in node.depends_on() if p not in ground
              for c in (picked[p][0] + ox, picked[p][1] + oy)]
    return _filled_tolerance(_meet_tolerance(moving, scale, samples.size), path)


def _apart_at(present, margin):
    """Return how far apart two roots are, over the node's scale; NaN where they are not.

    Zero where they meet, also for roots within the primitives' tangency
    tolerance (a negative margin): it folds at a graze like a V.
    """
    return np.where(present, np.sqrt(np.maximum(margin, 0.0)), np.nan)


def _path_scales(cand, n, length) -> np.ndarray:
    """Return :func:`_node_scale` of each path of ``length`` samples, on its own."""
    margin = _over_samples(cand.margin, n).reshape(-1, length)
    dx = (_over_samples(cand.x[1], n) - _over_samples(cand.x[0], n)).reshape(-1, length)
    dy = (_over_samples(cand.y[1], n) - _over_samples(cand.y[0], n)).reshape(-1, length)
    with np.errstate(all="ignore"):
        ratio = np.where(margin > 1e-12, 0.5 * np.hypot(dx, dy) / np.sqrt(margin), -np.inf)
        scale = np.max(ratio, axis=1)
    return np.where(np.isfinite(scale) & (scale > 0), scale, 1.0)


def _flips_at_samples(at_sample, present, together, inputs, length=None):
    """Return where meetings at samples change the branch.

    Meeting samples joined by steps along which the roots stay together
    (``together``, per step) are one meeting. Its branch changes after its
    last sample if the node can be assembled at the samples on both sides
    and the path goes on through it; where the path turns back there (its
    steps before and after point opposite ways), the branch is kept, as it
    is when the path turns back just short of the meeting. The samples may
    be several paths of ``length`` samples: a meeting at the first or the
    last sample of any changes nothing.
    """
    n = at_sample.size
    flip = np.zeros(n, dtype=bool)
    if not at_sample.any():
        return flip
    joined = np.zeros(n, dtype=bool)  # sample i continues the meeting of sample i - 1
    joined[1:] = at_sample[1:] & at_sample[:-1] & together
    starts = np.flatnonzero(at_sample & ~joined)
    ends = np.flatnonzero(at_sample & ~np.append(joined[1:], False))
    length = n if length is None else length
    ok = (starts % length != 0) & (ends % length != length - 1)
    starts, ends = starts[ok], ends[ok]
    ok = present[starts - 1] & present[ends + 1]
    starts, ends = starts[ok], ends[ok]
    onwards = sum((values[starts] - values[starts - 1]) * (values[ends + 1] - values[ends])
                  for values in inputs.values())
    flip[ends[~(np.asarray(onwards) < 0)]] = True
    return flip
