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
3. Where the two roots meet and part again between two samples (a graze,
   as at a change point, or a toggle where the input turns back), the
   branch changes if that continues the motion smoothly: the node's
   half-chord, taken with the branch's sign, must run smoothly through zero.
   The samples count as evenly spaced in time. The change is recorded as a
   :class:`BranchEvent`. A meeting closer to a sample than the sampling can
   resolve may put that one sample on the other root, which is then as close
   to it as the roots are to each other.
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

from .construction import REASONS, Compiled, Construction, failure_reasons
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
    points : mapping of str to ndarray, shape (N, 2)
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

    def __init__(self, construction, inputs, coords, valid, failed_step, reason_code,
                 labels, events, margins, parameters=None):
        self.construction: Compiled = construction
        self.inputs = inputs
        self.points = _PointTable(coords, valid)
        self.valid = valid
        self.failed_step = failed_step
        self.reason_code = reason_code
        self.events = events
        self._labels = labels
        self._margins = margins
        # the chosen root's parameter along each ray or segment node
        self._parameters = parameters or {}

    def __len__(self):
        return len(self.valid)

    def __getitem__(self, name: str) -> np.ndarray:
        """Return the (N, 2) positions of a point."""
        return self.points[name]

    def __repr__(self):
        return (f"<Sweep of {self.construction.name!r}: {len(self)} samples, "
                f"{int(self.valid.sum())} valid, {len(self.events)} branch changes>")

    @property
    def input(self) -> np.ndarray:
        """Return the values of the first input (radians for an angle)."""
        if not self.inputs:
            raise AttributeError(f"construction {self.construction.name!r} has no input")
        return next(iter(self.inputs.values()))

    @property
    def branches(self) -> dict[str, np.ndarray]:
        """Return the branch (0 or 1) of every two-root node at every sample."""
        n = len(self)
        return {name: np.broadcast_to(np.asarray(label, dtype=np.int8), (n,))
                for name, label in self._labels.items()}

    @property
    def margins(self) -> dict[str, np.ndarray]:
        """Return every two-root node's distance from tangency at every sample."""
        n = len(self)
        return {name: np.broadcast_to(m, (n,)) for name, m in self._margins.items()}

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


class _PointTable(Mapping):
    """Point positions as (N, 2) arrays, stacked from coordinates when first read."""

    def __init__(self, coords, valid):
        self._coords = coords
        self._valid = valid
        self._stacked = {}

    def __getitem__(self, name):
        stacked = self._stacked.get(name)
        if stacked is None:
            try:
                x, y = self._coords[name]
            except KeyError:
                raise KeyError(f"no point {name!r}{did_you_mean(name, self._coords)}") from None
            stacked = np.empty((len(self._valid), 2))
            stacked[:, 0] = x
            stacked[:, 1] = y
            if not self._valid.all():
                stacked[~self._valid] = np.nan
            self._stacked[name] = stacked
        return stacked

    def __iter__(self):
        return iter(self._coords)

    def __len__(self):
        return len(self._coords)


def _compiled(construction) -> Compiled:
    if isinstance(construction, Construction):
        return construction.compile()
    if isinstance(construction, Compiled):
        return construction
    raise TypeError(f"expected a Construction, got {type(construction).__name__}")


def input_name(compiled: Compiled, name: str | None, purpose: str = "move") -> str:
    """Return the input called ``name``, or the only input when ``name`` is None.

    Raises
    ------
    ConstructionError
        For an unknown name (with the closest one), or None when the
        construction has several inputs or none.
    """
    names = list(compiled.inputs)
    if name is None:
        if len(names) != 1:
            raise ConstructionError(f"this construction has {len(names)} inputs "
                                    f"({', '.join(names) or 'none'}); name the one to {purpose}")
        return names[0]
    if name not in compiled.inputs:
        raise ConstructionError(f"unknown input {name!r}{did_you_mean(name, names)}", node=name)
    return name


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
        shape = np.broadcast_shapes(*(a.shape for a in arrays.values()))
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
    return {k: np.broadcast_to(v, (n,)).astype(float, copy=False) for k, v in arrays.items()}, n


@dataclass(frozen=True)
class _PlannedStep:
    """A step with its constant values evaluated once and its varying ones listed."""

    index: int
    node: object
    constants: dict
    varying: tuple  # (field, expression, factor to radians or None)


def _plan(compiled: Compiled) -> tuple[_PlannedStep, ...]:
    """Return the evaluation plan of a compiled construction, made once and cached."""
    plan = compiled.cache.get("plan")
    if plan is not None:
        return plan
    to_radians = np.pi / 180 if compiled.angle_unit == "deg" else None
    planned = []
    with np.errstate(all="ignore"):
        for step in compiled.steps:
            node = step.node
            constants, varying = {}, []
            for field_name, expr in compiled._values[node.name].items():
                factor = to_radians if field_name in node.angle_fields() else None
                if expr.names() <= compiled.parameters.keys():
                    value = expr.evaluate(compiled.parameters)
                    constants[field_name] = float(value * factor if factor else value)
                else:
                    varying.append((field_name, expr, factor))
            planned.append(_PlannedStep(step.index, node, constants, tuple(varying)))
    compiled.cache["plan"] = plan = tuple(planned)
    return plan


def _environment(compiled: Compiled, inputs):
    env = dict(compiled.parameters)
    for name, value in inputs.items():
        if compiled.angle_unit == "deg" and compiled.inputs[name].kind == "angle":
            value = np.degrees(value)
        env[name] = value
    return env


def evaluate(construction, inputs: Mapping[str, np.ndarray], n: int,
             branches: Mapping[str, np.ndarray] | None = None, *, track: bool = True,
             initial: Mapping[str, int] | None = None, origin=None) -> Sweep:
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
    origin : (float, float), optional
        Evaluate in a frame with its origin here: every point is found
        relative to it (constructions move with their fixed points), which
        keeps digits for a mechanism far from (0, 0). Positions in the result
        are then relative to ``origin``.

    Returns
    -------
    Sweep
    """
    compiled = _compiled(construction)
    plan = _plan(compiled)
    env = _environment(compiled, inputs)
    coords, labels, margins, parameters, events, results = {}, {}, {}, {}, [], []
    with np.errstate(all="ignore"):
        for step in plan:
            node = step.node
            values = step.constants
            if step.varying:
                values = dict(values)
                for field_name, expr, factor in step.varying:
                    value = expr.evaluate(env)
                    values[field_name] = value * factor if factor else value
            cand = node.candidates(coords, values)
            if origin is not None and node.kind == "fixed":
                cand = type(cand)((cand.x[0] - origin[0],), (cand.y[0] - origin[1],))
            if node.roots == 1:
                x, y = cand.x[0], cand.y[0]
                label = None
            else:
                if branches is not None and node.name in branches:
                    label = branches[node.name]
                else:
                    label, found = _track(node, cand, n, track, (initial or {}).get(node.name))
                    events.extend(found)
                x, y = _choose(cand, label)
                labels[node.name] = label
                margins[node.name] = cand.margin
                if cand.t is not None:
                    parameters[node.name] = (cand.t[label] if np.ndim(label) == 0
                                             else np.where(label, cand.t[1], cand.t[0]))
            coords[node.name] = (x, y)
            results.append((step, cand, values, label, np.isfinite(x) & np.isfinite(y)))
        valid = np.ones(n, dtype=bool)
        for *_, finite in results:
            valid &= finite
    failed_step = np.zeros(n, dtype=np.int16)
    reason_code = np.zeros(n, dtype=np.int8)
    if not valid.all():
        _record_failures(results, n, failed_step, reason_code)
    return Sweep(compiled, dict(inputs), coords, valid, failed_step, reason_code, labels,
                 events, margins, parameters)


def _choose(cand, label):
    """Take root ``label`` (an int, or an array of 0 and 1 per sample)."""
    if np.ndim(label) == 0:
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


def _record_failures(results, n, failed_step, reason_code):
    """Name the first node that fails at each invalid sample, and why."""
    pending = np.ones(n, dtype=bool)
    for step, cand, values, label, finite in results:
        failing = pending & ~np.broadcast_to(finite, (n,))
        if not failing.any():
            continue
        at = np.flatnonzero(failing)

        def pick(a, at=at):
            return None if a is None else np.broadcast_to(a, (n,))[at]

        local = type(cand)(tuple(pick(a) for a in cand.x), tuple(pick(a) for a in cand.y),
                           pick(cand.margin),
                           None if cand.on_line is None else tuple(map(pick, cand.on_line)))
        root = 0 if label is None else pick(np.asarray(label))
        failed_step[at] = step.index
        reason_code[at] = failure_reasons(local, {k: pick(v) for k, v in values.items()}, root)
        pending &= ~failing


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


def _initial_label(node, cand, n, override) -> int:
    if override is not None:
        return override
    if node.near is None:
        return node.branch_names().index(node.branch)
    x0, y0, x1, y1 = (np.broadcast_to(a, (n,)) for a in (*cand.x, *cand.y))
    usable = [np.isfinite(x0), np.isfinite(x1)]
    if cand.on_line is not None:  # a root off its ray or segment cannot be assembled
        usable = [u & np.broadcast_to(on, (n,)) for u, on in zip(usable, cand.on_line,
                                                                  strict=True)]
    exists = np.flatnonzero(usable[0] | usable[1])
    if exists.size == 0:
        return 0
    i = exists[0]
    near_x, near_y = node.near
    distance = [np.hypot(x0[i] - near_x, y0[i] - near_y) if usable[0][i] else np.inf,
                np.hypot(x1[i] - near_x, y1[i] - near_y) if usable[1][i] else np.inf]
    return int(distance[1] < distance[0])


def _track(node, cand, n, track, override=None):
    """Choose the branch of a two-root node at every sample (rules 1 to 3).

    The branch is the sign of the square root, kept from the start. It can
    change only where the two roots meet and part between samples, near a
    local minimum of the node's margin (its squared half-chord). There the
    half-chord ``u = sqrt(margin)``, taken with the sign of the branch, runs
    smoothly through zero, while taken without sign it folds back in a V.
    Of three readings of the samples around the minimum (no crossing, a
    crossing just before the middle sample, one just after it) the one whose
    signed half-chords are smoothest is taken, the samples counting as evenly
    spaced in time. Everything is computed for all samples at once.

    Returns the branch as an int where it never changes, else an int8 array.
    """
    start = _initial_label(node, cand, n, override)
    margin = np.broadcast_to(cand.margin, (n,))
    if not track or n < 3 or not (np.fmin.reduce(margin) < GRAZE_MARGIN):
        return start, []
    # samples are taken as evenly spaced in time: where the input turns back at a
    # limit (a rocker swinging), the half-chord then folds through zero as at a graze
    t = np.arange(n, dtype=float)
    u = np.sqrt(np.maximum(margin, 0.0))
    m_left, m_mid, m_right = margin[:-2], margin[1:-1], margin[2:]
    # local minima of the margin, where the roots come closest (where the margin
    # stays at zero the roots stay equal, and there is nothing to choose)
    low = ((m_mid <= m_left) & (m_mid <= m_right) & (m_mid < GRAZE_MARGIN)
           & (np.fmax(m_left, m_right) > 1e-14))
    centre = np.flatnonzero(low) + 1
    first_after = []
    if centre.size:
        # five samples around each minimum (three at the ends of the sweep)
        wide = (centre >= 2) & (centre <= n - 3)
        offsets = np.arange(-2, 3)[:, None]
        window = np.where(wide, centre + offsets, np.clip(centre + offsets, 0, n - 1))
        y, x = u[window], t[window]
        flip_after = np.array([1, 1, 1, -1, -1])[:, None]   # meet between centre, centre+1
        flip_before = np.array([1, 1, -1, -1, -1])[:, None]  # between centre-1 and centre
        none, after, before = (np.where(wide, _wiggle(y * sign, x),
                                        _bend(*(y * sign)[1:4], *x[1:4]))
                               for sign in (1, flip_after, flip_before))
        first_after += [centre[(after < none) & (after <= before)] + 1,
                        centre[(before < none) & (before < after)]]
    first_after = np.unique(np.concatenate(first_after or [np.empty(0, int)])).astype(int)
    if first_after.size == 0:
        return start, []
    flips = np.zeros(n, dtype=np.int8)
    flips[first_after] = 1
    label = ((start + np.cumsum(flips)) % 2).astype(np.int8)
    names = node.branch_names()
    events = [BranchEvent(node.name, int(i), names[label[i - 1]], names[label[i]])
              for i in first_after]
    return label, events


def _bend(y_left, y_mid, y_right, t_left, t_mid, t_right):
    """Return how sharply three samples of y(t) bend: the change of slope at the middle."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.abs((y_right - y_mid) / (t_right - t_mid) - (y_mid - y_left) / (t_mid - t_left))


def _wiggle(y, t):
    """Return how much samples y(t) depart from a smooth curve, for each column.

    The sum of the third divided differences over consecutive runs of four
    rows: zero on any parabola, large where the samples fold.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        d1 = np.diff(y, axis=0) / np.diff(t, axis=0)
        d2 = np.diff(d1, axis=0) / (t[2:] - t[:-2])
        d3 = np.diff(d2, axis=0) / (t[3:] - t[:-3])
    return np.abs(d3).sum(axis=0)
