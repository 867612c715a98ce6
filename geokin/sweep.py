"""Evaluate a construction over arrays of input values, tracking branches.

:func:`sweep` evaluates every step of a compiled construction for all
samples at once (numpy arrays, no Python loop per sample) and keeps every
two-root node on its assembly branch as the mechanism moves.

Branch rules
------------
1. A two-root node starts on the branch its declaration names (``left`` or
   ``right`` for circle-circle, ``first`` or ``second`` along the line for
   the line-based kinds), or, with ``near=(x, y)``, on the root nearer to
   that position at the first sample where the node can be assembled.
2. The branch is the sign of the square root in the node's intersection
   formula. It stays the same along the motion, because the two roots can
   only exchange places where they meet.
3. Where the two roots meet and part again between two samples (the curves
   graze, as at a change point), the branch changes if that continues the
   motion smoothly; the change is recorded as a :class:`BranchEvent`.
4. Where a node cannot be assembled, the sample is invalid and the failing
   node and the reason are recorded. Beyond the gap the node resumes on the
   branch it had before the gap: an assembly mode is never reset silently.
5. :attr:`Sweep.branches` records the branch of every node at every sample,
   so any change is visible.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .construction import REASONS, Compiled, Construction
from .errors import ConstructionError, did_you_mean

__all__ = ["BranchEvent", "Sweep", "evaluate", "sweep"]

GRAZE_MARGIN = 0.04
"""Nodes whose margin (squared half-chord over squared scale) never falls
below this cannot graze between samples; their branch tracking is skipped."""


@dataclass(frozen=True)
class BranchEvent:
    """A change of branch of one node between samples ``index - 1`` and ``index``."""

    node: str
    index: int
    before: str
    after: str

    def __str__(self):
        return (f"node {self.node!r} changes branch from {self.before} to {self.after} "
                f"at sample {self.index} (the two roots meet and part)")


class Sweep:
    """The motion of a construction over a sweep of its inputs.

    Attributes
    ----------
    construction : Compiled
        What was evaluated.
    inputs : dict of str to ndarray, shape (N,)
        Input values, radians for angles.
    points : dict of str to ndarray, shape (N, 2)
        Position of every point; NaN at samples that cannot be assembled.
    valid : ndarray of bool, shape (N,)
        Whether each sample can be assembled.
    failed_step : ndarray of int, shape (N,)
        The 1-based index of the step that failed first at each sample, 0 where valid.
    reason_code : ndarray of int8, shape (N,)
        Why it failed (see :attr:`failure_reason`).
    branches : dict of str to ndarray of int8, shape (N,)
        For every two-root node, 0 or 1: the index of its root in the
        primitive's order (``left``/``right``, ``first``/``second``).
    events : list of BranchEvent
        Every branch change along the sweep.
    margins : dict of str to ndarray, shape (N,)
        For every two-root node, its distance from tangency (positive: two
        roots, zero: tangent, negative: none), relative to its scale.
    """

    def __init__(self, construction, inputs, points, valid, failed_step, reason_code,
                 branches, events, margins):
        self.construction: Compiled = construction
        self.inputs = inputs
        self.points = points
        self.valid = valid
        self.failed_step = failed_step
        self.reason_code = reason_code
        self.branches = branches
        self.events = events
        self.margins = margins

    def __len__(self):
        return len(self.valid)

    def __getitem__(self, name: str) -> np.ndarray:
        """Return the (N, 2) positions of a point."""
        try:
            return self.points[name]
        except KeyError:
            raise KeyError(f"no point {name!r}{did_you_mean(name, self.points)}") from None

    def __repr__(self):
        return (f"<Sweep of {self.construction.name!r}: {len(self)} samples, "
                f"{int(self.valid.sum())} valid, {len(self.events)} branch changes>")

    @property
    def input(self) -> np.ndarray:
        """Return the values of the first input (radians for an angle)."""
        return next(iter(self.inputs.values()))

    @property
    def failed_node(self) -> np.ndarray:
        """Return the name of the node that failed at each sample ('' where valid)."""
        names = np.array(["", *self.construction.point_names], dtype=object)
        return names[self.failed_step]

    @property
    def failure_reason(self) -> np.ndarray:
        """Return why each sample failed, as text ('' where valid)."""
        return np.array(REASONS, dtype=object)[self.reason_code]

    def branch_names(self, node: str) -> np.ndarray:
        """Return the branch of a two-root node at each sample, by name."""
        step = self._step(node)
        if step.node.roots != 2:
            raise KeyError(f"point {node!r} is a {step.node.kind} node: it has one root")
        return np.array(step.node.branch_names(), dtype=object)[self.branches[node]]

    def explain(self, index: int) -> str:
        """Say in words whether sample ``index`` is assembled, and if not why.

        Examples
        --------
        >>> c = Construction("reach")
        >>> c.input("r", kind="length", range=(1, 3), samples=3)
        >>> c.fixed("O", 0, 0)
        >>> c.fixed("Q", 4, 0)
        >>> c.circle_circle("P", ("O", "Q"), ("r", 1), branch="left")
        >>> s = sweep(c)
        >>> s.explain(0)
        "sample 0 (r = 1): node 'P' cannot be assembled: no intersection: the curves do not meet"
        >>> s.explain(2)
        'sample 2 (r = 3): assembled'
        """
        values = ", ".join(f"{k} = {v[index]:g}" for k, v in self.inputs.items())
        if self.valid[index]:
            return f"sample {index} ({values}): assembled"
        return (f"sample {index} ({values}): node {self.failed_node[index]!r} cannot be "
                f"assembled: {self.failure_reason[index]}")

    def _step(self, name):
        for step in self.construction.steps:
            if step.node.name == name:
                return step
        raise KeyError(f"no point {name!r}{did_you_mean(name, self.construction.point_names)}")


def _compiled(construction) -> Compiled:
    if isinstance(construction, Construction):
        return construction.compile()
    if isinstance(construction, Compiled):
        return construction
    raise TypeError(f"expected a Construction, got {type(construction).__name__}")


def input_arrays(compiled: Compiled, values=None, samples: int | None = None):
    """Return the input arrays of a sweep, broadcast to one length N.

    ``values`` is an array (for a construction with one input), a mapping of
    input names to arrays or numbers, or None for every input's default range.
    """
    names = list(compiled.inputs)
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
                                    node=name)
    arrays = {}
    for name in names:
        if name in values:
            arrays[name] = np.asarray(values[name], dtype=float)
        else:
            arrays[name] = compiled.inputs[name].values(samples)
    if not arrays:
        return {}, 1
    shape = np.broadcast_shapes(*(a.shape for a in arrays.values()))
    if len(shape) > 1:
        raise ConstructionError(f"input values must be one-dimensional, got shape {shape}")
    n = shape[0] if shape else 1
    return {k: np.broadcast_to(v, (n,)).astype(float, copy=False) for k, v in arrays.items()}, n


def _environment(compiled: Compiled, inputs):
    env = dict(compiled.parameters)
    for name, value in inputs.items():
        if compiled.angle_unit == "deg" and compiled.inputs[name].kind == "angle":
            value = np.degrees(value)
        env[name] = value
    return env


def evaluate(construction, inputs: Mapping[str, np.ndarray], n: int,
             branches: Mapping[str, np.ndarray] | None = None, *, track: bool = True,
             initial: Mapping[str, int] | None = None):
    """Evaluate every step for all samples.

    Parameters
    ----------
    construction : Construction or Compiled
    inputs : mapping of str to ndarray, shape (N,)
        Input values in radians (lengths for length inputs).
    n : int
        The number of samples N.
    branches : mapping of str to ndarray, optional
        A fixed branch (0 or 1, scalar or per sample) for some two-root
        nodes; the others are chosen and tracked by the branch rules.
    track : bool
        Whether to look for grazes (rule 3); turned off when evaluating at
        isolated perturbed inputs.
    initial : mapping of str to int, optional
        Initial branches (0 or 1) replacing the declared choice of some nodes.

    Returns
    -------
    Sweep
    """
    compiled = _compiled(construction)
    env = _environment(compiled, inputs)
    to_radians = np.pi / 180 if compiled.angle_unit == "deg" else None
    coords = {}
    valid = np.ones(n, dtype=bool)
    failed_step = np.zeros(n, dtype=np.int16)
    reason_code = np.zeros(n, dtype=np.int8)
    chosen, margins, events = {}, {}, []
    for step in compiled.steps:
        node = step.node
        values = {}
        for field_name, expr in compiled._values[node.name].items():
            value = expr.evaluate(env)
            if to_radians is not None and field_name in node.angle_fields():
                value = value * to_radians
            values[field_name] = value
        cand = node.candidates(coords, values)
        if node.roots == 1:
            x, y, ok, why = cand.x[0], cand.y[0], cand.valid[0], cand.reason[0]
        else:
            if branches is not None and node.name in branches:
                label = np.broadcast_to(np.asarray(branches[node.name], dtype=np.int8), (n,))
            else:
                label, found = _track(node, cand, n, track, (initial or {}).get(node.name))
                events.extend(found)
            chosen[node.name] = label
            margins[node.name] = np.broadcast_to(cand.margin, (n,))
            second = label.astype(bool)
            x = np.where(second, cand.x[1], cand.x[0])
            y = np.where(second, cand.y[1], cand.y[0])
            ok = np.where(second, cand.valid[1], cand.valid[0])
            why = np.where(second, cand.reason[1], cand.reason[0])
        ok = np.broadcast_to(ok, (n,))
        if not ok.all():
            newly = valid & ~ok
            failed_step[newly] = step.index
            reason_code[newly] = np.broadcast_to(why, (n,))[newly]
            valid &= ok
        coords[node.name] = (x, y)
    points = {}
    for name, (x, y) in coords.items():
        xy = np.empty((n, 2))
        xy[:, 0] = x
        xy[:, 1] = y
        if not valid.all():
            xy[~valid] = np.nan
        points[name] = xy
    return Sweep(compiled, dict(inputs), points, valid, failed_step, reason_code, chosen,
                 events, margins)


def sweep(construction, values=None, *, samples: int | None = None,
          branches: Mapping[str, object] | None = None) -> Sweep:
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
    branches : mapping of str to str or int, optional
        Override the initial branch of two-root nodes by name
        (``{"B": "right"}``); the branch is still tracked along the sweep.

    Returns
    -------
    Sweep

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
    """
    compiled = _compiled(construction)
    inputs, n = input_arrays(compiled, values, samples)
    initial = None
    if branches:
        initial = {}
        nodes = {step.node.name: step.node for step in compiled.steps}
        for name, branch in branches.items():
            node = nodes.get(name)
            if node is None or node.roots != 2:
                raise ConstructionError(
                    f"no two-root node {name!r}{did_you_mean(name, nodes)}", node=name,
                    field="branch")
            options = node.branch_names()
            if branch in (0, 1):
                initial[name] = int(branch)
            elif branch in options:
                initial[name] = options.index(branch)
            else:
                raise ConstructionError(f"unknown branch {branch!r}; use "
                                        f"{' or '.join(map(repr, options))}", node=name,
                                        field="branch")
    return evaluate(compiled, inputs, n, initial=initial)


def _initial_label(node, cand, override) -> int:
    if override is not None:
        return override
    if node.near is None:
        return node.branch_names().index(node.branch)
    exists = np.flatnonzero(np.isfinite(np.atleast_1d(cand.x[0] + cand.x[1])))
    if exists.size == 0:
        return 0
    i = exists[0]
    near_x, near_y = node.near
    d0 = np.hypot(cand.x[0][i] - near_x, cand.y[0][i] - near_y)
    d1 = np.hypot(cand.x[1][i] - near_x, cand.y[1][i] - near_y)
    return int(d1 < d0)


def _track(node, cand, n, track, override=None):
    """Choose the branch of a two-root node at every sample (rules 1 to 3)."""
    start = _initial_label(node, cand, override)
    label = np.full(n, start, dtype=np.int8)
    margin = np.broadcast_to(cand.margin, (n,))
    if not track or n < 3 or not (np.nanmin(margin, initial=np.inf) < GRAZE_MARGIN):
        return label, []
    x0, y0, x1, y1 = (np.broadcast_to(a, (n,)) for a in (cand.x[0], cand.y[0],
                                                          cand.x[1], cand.y[1]))
    separation = np.hypot(x1 - x0, y1 - y0)
    step = np.fmax(np.hypot(np.diff(x0), np.diff(y0)), np.hypot(np.diff(x1), np.diff(y1)))
    # at a graze the kept root barely moves across the pair itself: judge the
    # separation against the motion of the neighbouring pairs as well
    motion = step.copy()
    motion[1:] = np.fmax(motion[1:], step[:-1])
    motion[:-1] = np.fmax(motion[:-1], step[1:])
    with np.errstate(invalid="ignore"):
        close = np.minimum(separation[:-1], separation[1:]) <= 2 * motion
    pairs = np.flatnonzero(close)
    if pairs.size == 0:
        return label, []
    roots = np.stack([np.stack([x0, y0], axis=-1), np.stack([x1, y1], axis=-1)])
    names = node.branch_names()
    flips, events, current = np.zeros(n, dtype=np.int8), [], start
    for i in pairs:
        # the branch at sample i is `current`; should sample i+1 take the other root?
        before = current ^ flips[i]  # the branch at sample i-1
        if _smoother_to_switch(roots, i, before, current, n):
            flips[i + 1] = 1
            events.append(BranchEvent(node.name, int(i + 1), names[current], names[1 - current]))
            current = 1 - current
    label = ((start + np.cumsum(flips)) % 2).astype(np.int8)
    return label, events


def _smoother_to_switch(roots, i, before, current, n) -> bool:
    """Whether taking the other root at sample i+1 continues the motion more smoothly.

    ``roots`` has shape (2, N, 2); the path is on root ``before`` at sample
    i-1 and on root ``current`` at sample i.
    """
    here = roots[current, i]
    keep, switch = roots[current, i + 1], roots[1 - current, i + 1]
    if i < 1 or not (np.isfinite(keep).all() and np.isfinite(here).all()):
        return False
    previous = roots[before, i - 1]
    if not np.isfinite(previous).all():
        return False
    predicted = 2 * here - previous
    keep_error = np.hypot(*(keep - predicted))
    switch_error = np.hypot(*(switch - predicted))
    if i + 2 < n:
        # the sample after: does each choice carry on straight?
        keep_next, switch_next = roots[current, i + 2], roots[1 - current, i + 2]
        if np.isfinite(keep_next).all() and np.isfinite(switch_next).all():
            keep_error += np.hypot(*(keep_next - 2 * keep + here))
            switch_error += np.hypot(*(switch_next - 2 * switch + here))
    return bool(switch_error < 0.5 * keep_error)
