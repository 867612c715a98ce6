"""The results of a sweep: immutable, with public fields only.

:class:`Sweep` is what every layer above the engine reads: kinematics,
limits, analysis, export and drawing. It holds arrays over the N samples of
a sweep; nothing in it changes once the engine has made it.
"""

from __future__ import annotations

import math
import unicodedata
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from . import display
from .compat import renamed_attribute
from .construction import Compiled
from .errors import AssemblyError, did_you_mean, quote
from .frozen import Frozen, read_only
from .nodes import REASONS
from .terminal import shorten

__all__ = ["BranchEvent", "PointTable", "Sweep", "failure_causes", "short_name",
           "unassembled_error"]


def short_name(name: str | None) -> str:
    """Return a name quoted for a repr, shortened to keep the repr on one short line.

    Examples
    --------
    >>> short_name("six-bar"), short_name(None)
    ("'six-bar'", 'None')
    >>> len(short_name("x" * 10_000)) < 70
    True
    """
    return "None" if name is None else repr(shorten(str(name), 40))


@dataclass(frozen=True)
class BranchEvent:
    """A change of branch of one node between samples ``index - 1`` and ``index``."""

    node: str
    index: int
    before: str
    after: str
    fraction: float = 0.0
    """Where the roots meet, as a fraction of the step from sample ``index - 1``
    to ``index``: 0 at sample ``index - 1`` itself."""
    variant: int | None = None
    """In a sweep of design variants, the variant it happens in; None otherwise."""

    def __str__(self) -> str:
        if self.fraction > 0:
            where = f"between samples {self.index - 1} and {self.index}"
        else:
            where = f"at sample {self.index - 1}"
        which = "" if self.variant is None else f"in variant {self.variant}, "
        # a closure group's assemblies meet at its fold, as two roots do at a graze
        meeting = ("the group folds" if self.before.startswith("assembly")
                   else "the two roots meet")
        return (f"{which}node {self.node!r} changes branch from {self.before} to {self.after} "
                f"at sample {self.index} ({meeting} {where})")


@dataclass(frozen=True, eq=False)
class Sweep(Frozen):
    """The motion of a construction over a sweep of its inputs.

    Made by :func:`geokin.sweep` (and by :func:`geokin.circuit`); every field
    is public and none changes after it is made (the arrays are read-only).

    Attributes
    ----------
    construction : Compiled
        What was evaluated.
    inputs : mapping of str to ndarray, shape (N,)
        Input values, radians for angles.
    points : mapping of str to ndarray, shape (N, 2)
        Position of every point; NaN at samples that cannot be assembled.
    valid : ndarray of bool, shape (N,)
        Whether each sample can be assembled.
    failed_step : ndarray of int, shape (N,)
        The 1-based index of the step that failed first at each sample, 0 where valid.
    reason_code : ndarray of int8, shape (N,)
        Why it failed (see :attr:`failure_reason`).
    branches : mapping of str to ndarray of int8, shape (N,)
        For every two-root node, 0 or 1 at every sample: the index of its
        root in the primitive's order (``left``/``right``,
        ``first``/``second``). A node that keeps one branch throughout has
        a broadcast array (stride 0).
    events : tuple of BranchEvent
        Every branch change along the sweep, in order.
    margins : mapping of str to ndarray, shape (N,)
        For every two-root node, its distance from tangency (positive: two
        roots, zero: tangent, negative: none), relative to its scale.
    line_parameters : mapping of str to ndarray, shape (N,)
        For every ray or segment node, its chosen root's parameter ``t``
        along the line: the root is ``line[0] + t * (line[1] - line[0])``,
        on the ray for ``t >= 0`` and on the segment for ``0 <= t <= 1``.
    parameters : mapping of str to ndarray
        The parameters whose values vary in this sweep, with their value at
        every sample (the shape of ``valid``); empty for a sweep of one design.

    Design variants
    ---------------
    A sweep of V design variants (``geokin.sweep(..., parameters=...)``)
    has a leading variant axis on every per-sample array: ``valid``,
    ``failed_step``, ``reason_code``, ``branches``, ``margins`` and
    ``line_parameters`` are (V, N), ``points[name]`` is (V, N, 2), and each
    event names its variant. The inputs stay (N,): every variant runs over
    the same samples. :meth:`variant` gives one variant as a sweep of its
    own, and :attr:`variants` their number.
    """

    construction: Compiled
    inputs: Mapping[str, np.ndarray]
    points: PointTable
    valid: np.ndarray
    failed_step: np.ndarray
    reason_code: np.ndarray
    branches: Mapping[str, np.ndarray]
    events: tuple[BranchEvent, ...]
    margins: Mapping[str, np.ndarray]
    line_parameters: Mapping[str, np.ndarray] = field(default_factory=dict)
    parameters: Mapping[str, np.ndarray] = field(default_factory=dict)

    input = renamed_attribute("input", "input_values")
    _read_only = ("inputs", "branches", "margins", "line_parameters", "valid", "failed_step",
                  "reason_code", "parameters")

    def __len__(self) -> int:
        """Return the number of samples N (of each variant)."""
        return self.valid.shape[-1]

    def __getitem__(self, name: str) -> np.ndarray:
        """Return the (N, 2) positions of a point ((V, N, 2) for V variants)."""
        return self.points[name]

    def __repr__(self) -> str:
        count = (f"{len(self)} samples" if self.variants is None
                 else f"{self.variants} variants x {len(self)} samples")
        return (f"<Sweep of {short_name(self.construction.name)}: {count}, "
                f"{int(self.valid.sum())} valid, {len(self.events)} branch changes>")

    @property
    def variants(self) -> int | None:
        """Return the number of design variants V, or None for a sweep of one design."""
        return None if self.valid.ndim == 1 else self.valid.shape[0]

    def variant(self, index: int) -> Sweep:
        """Return one design variant as a sweep of its own.

        Its construction holds the variant's parameter values; its arrays
        are views of this sweep's.

        Examples
        --------
        >>> from geokin import Construction, sweep
        >>> c = Construction()
        >>> c.parameter("r", 1)
        >>> c.input("theta")
        >>> c.fixed("O", 0, 0)
        >>> c.polar("A", "O", "r", "theta")
        >>> s = sweep(c, [0.0, np.pi / 2], parameters={"r": [1.0, 2.0, 3.0]})
        >>> s["A"].shape, s.variants
        ((3, 2, 2), 3)
        >>> one = s.variant(2)
        >>> one.construction.parameters["r"], one["A"][0].tolist()
        (3.0, [3.0, 0.0])
        """
        count = self.variants
        if count is None:
            raise ValueError("this sweep is of one design: it has no variants")
        if not -count <= index < count:
            raise IndexError(f"variant {index} out of range for {count} variants")
        index = index % count
        values = {name: float(v[index].flat[0]) for name, v in self.parameters.items()}
        compiled = replace(self.construction,
                           parameters={**self.construction.parameters, **values})

        def row(array):
            return array if np.ndim(array) < 2 else array[index]

        return self._remade(row, construction=compiled, inputs=self.inputs,
                            events=(replace(e, variant=None) for e in self.events
                                    if e.variant == index), parameters=False)

    def part(self, start: int, stop: int) -> Sweep:
        """Return the sweep of samples ``start`` to ``stop - 1`` of this one, as they are in it.

        Its arrays are views of this sweep's; its events are those between
        its samples and on the step into its first (index 0 there), indexed
        from ``start``.

        Examples
        --------
        >>> from geokin import Construction, sweep
        >>> c = Construction()
        >>> c.input("theta")
        >>> c.fixed("O2", 0, 0)
        >>> c.fixed("O4", 10, 0)
        >>> c.polar("A", "O2", 4, "theta")
        >>> c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
        >>> s = sweep(c, np.radians([160.0, 170.0, 190.0, 200.0]))
        >>> later = s.part(2, 4)
        >>> len(later), later.named_branches("B").tolist(), later.events[0].index
        (2, ['right', 'right'], 0)
        """
        if self.variants is not None:
            raise ValueError("a part of a sweep of variants: take a variant first")
        n = len(self)
        start, stop, _ = slice(start, stop).indices(n)
        stop = max(start, stop)

        def part(array):
            array = np.asarray(array)
            return array if array.ndim == 0 else np.broadcast_to(array, (n,))[start:stop]

        return self._remade(part, inputs={k: v[start:stop] for k, v in self.inputs.items()},
                            events=(replace(e, index=e.index - start) for e in self.events
                                    if start <= e.index < stop))

    def flat(self) -> Sweep:
        """Return a sweep of V variants as one sweep of V * N samples, variant after variant.

        Its inputs repeat for every variant and its ``parameters`` give each
        sample's values: evaluating the construction at its samples with
        those values gives its points. The kinematics of variants are found
        on it; :meth:`as_variants` undoes it.
        """
        count = self.variants
        if count is None:
            return self
        n = len(self)

        def flat(array):
            array = np.asarray(array)
            return array if array.ndim < 2 else array.reshape(-1)

        return self._remade(flat, inputs={k: np.tile(v, count) for k, v in self.inputs.items()},
                            events=(replace(e, index=(e.variant or 0) * n + e.index,
                                            variant=None) for e in self.events))

    def as_variants(self, count: int) -> Sweep:
        """Return a sweep of ``count`` variants of N samples each, one after the other.

        The inverse of :meth:`flat`: this sweep's V * N samples are cut into
        V rows; its events are given their variant.
        """
        if self.variants is not None:
            raise ValueError("this sweep already has a variant axis")
        total = len(self)
        if count < 1 or total % count:
            raise ValueError(f"{total} samples cannot be cut into {count} variants")
        n = total // count

        def rows(array):
            array = np.asarray(array)
            return array if array.ndim == 0 else np.broadcast_to(array, (total,)).reshape(count, n)

        return self._remade(rows, inputs={k: v[:n] for k, v in self.inputs.items()},
                            events=(replace(e, index=e.index % n, variant=e.index // n)
                                    for e in self.events))

    def _remade(self, per_sample, *, inputs, events, construction: Compiled | None = None,
                parameters: bool = True) -> Sweep:
        """Return this sweep with every per-sample array remade by ``per_sample``.

        The one place that lists what a sweep holds per sample, for
        :meth:`variant`, :meth:`part`, :meth:`flat` and :meth:`as_variants`:
        the points' coordinates, validity, failures, branches, margins, line
        parameters and (unless ``parameters`` is false) varied parameters.
        """
        def remade(mapping):
            return {k: per_sample(v) for k, v in mapping.items()}

        coords = {name: tuple(per_sample(c) for c in self.points.coords(name))
                  for name in self.points}
        valid = per_sample(self.valid)
        return Sweep(
            construction=self.construction if construction is None else construction,
            inputs=inputs, points=PointTable(coords, valid), valid=valid,
            failed_step=per_sample(self.failed_step), reason_code=per_sample(self.reason_code),
            branches=remade(self.branches), events=tuple(events),
            margins=remade(self.margins), line_parameters=remade(self.line_parameters),
            parameters=remade(self.parameters) if parameters else {})

    def _repr_html_(self) -> str:
        """Return a table of the sweep and a picture of its paths, for a notebook.

        The table gives the samples and how many can be assembled (and
        where the first that cannot fails), each input's range (degrees for
        an angle, the construction's units for a length) and the branch
        changes; the picture draws the traced points' paths (every moving
        point's if none is traced, at most six) over the mechanism at its
        first assembled sample, each path decimated to
        :data:`~geokin.display.POLYLINE_POINTS` samples. Everything from
        the script is escaped.

        Examples
        --------
        >>> from geokin import Construction, sweep
        >>> c = Construction("crank")
        >>> c.input("theta")
        >>> c.fixed("O", 0, 0)
        >>> c.polar("A", "O", 10, "theta")
        >>> page = sweep(c, np.linspace(0, np.pi, 7))._repr_html_()
        >>> "0 to 180 deg" in page, page.count("<polyline")
        (True, 1)

        A sweep of variants shows how many assemble, its parameters' ranges,
        and its first variant:

        >>> c.parameter("r", 10)
        >>> c.polar("B", "O", "r", "theta")
        >>> page = sweep(c, np.linspace(0, np.pi, 7), parameters={"r": [1, 2]})._repr_html_()
        >>> "2 variants" in page and "parameter r" in page
        True
        """
        if self.variants is not None:
            return self._variants_html()
        compiled = self.construction
        n, valid = len(self), int(np.count_nonzero(self.valid))
        rows = [("samples", f"{n:,}, all valid" if valid == n else f"{n:,}: {valid:,} valid")]
        for name, values in list(self.inputs.items())[:display.MAX_LISTED]:
            low, high = (np.nanmin(values), np.nanmax(values)) if n else (np.nan, np.nan)
            rows.append((f"input {name}", f"{self._value(name, low, '')} to "
                                          f"{self._value(name, high)}"))
        if valid < n:
            first = int(np.argmin(self.valid))
            rows.append(("cannot be assembled", (
                f"{n - valid:,} samples; the first, sample {first} ({self._at(first)}): "
                f"node {self.failed_node[first]!r}: {self.failure_reason[first]}")))
        changes = [f"{e.node}: {e.before} to {e.after} at sample {e.index} "
                   f"({self._at_event(e)})" for e in self.events[:3]]
        if len(self.events) > 3:
            changes.append(f"and {len(self.events) - 3:,} more")
        rows.append(("branch changes", f"{len(self.events):,}" + (
            f": {'; '.join(changes)}" if changes else "")))
        moving = [p for p in compiled.point_names if p not in compiled.ground]
        drawn = list(compiled.traced or moving)[:len(display.PATH_COLORS)]
        table = display.table(f"Sweep of {compiled.name!r}", rows)
        picture = self._svg(drawn)
        if picture:
            first = int(np.argmax(self.valid))
            note = (f"grey: the links at sample {first} ({self._at(first)})"
                    if compiled.links else "")
            if drawn or note:
                picture += "\n" + display.legend(drawn, note)
        return display.side_by_side(table, picture)

    def _variants_html(self) -> str:
        """Return the table of a sweep of variants, and the picture of its first."""
        count = self.variants or 0
        whole = int(np.count_nonzero(self.valid.all(axis=1)))
        rows = [("variants", f"{count:,}: {whole:,} assemble at every sample"),
                ("samples", f"{len(self):,} each")]
        for name, values in list(self.parameters.items())[:display.MAX_LISTED]:
            rows.append((f"parameter {name}", f"{display.number(float(np.min(values)))} to "
                                              f"{display.number(float(np.max(values)))}"))
        rows.append(("branch changes", f"{len(self.events):,} in all"))
        rows.append(("variant 0", "drawn here; sweep.variant(i) is variant i alone"))
        table = display.table(f"Sweep of {self.construction.name!r}, {count:,} variants", rows)
        first = self.variant(0)
        picture = first._svg(list(first.construction.traced or [
            p for p in first.construction.point_names
            if p not in first.construction.ground])[:len(display.PATH_COLORS)])
        return display.side_by_side(table, picture) if picture else table

    def _value(self, name: str, value: float, unit: str | None = None) -> str:
        """Return an input's value as a reader reads it: degrees, or the length unit."""
        if self.construction.inputs[name].kind == "angle":
            return display.angle(value, "deg" if unit is None else unit)
        return display.number(value, self.construction.units if unit is None else unit)

    def _at(self, index: int) -> str:
        return ", ".join(f"{name} = {self._value(name, values[index])}"
                         for name, values in list(self.inputs.items())[:3])

    def _at_event(self, event: BranchEvent) -> str:
        at = self.event_inputs(event)
        return ", ".join(f"{name} = {self._value(name, at[name])}" for name in list(at)[:3])

    def _svg(self, names: list[str]) -> str:
        """Return an SVG picture of the paths of ``names``, decimated, and one pose."""
        compiled, n = self.construction, len(self)
        if not n or not self.valid.any():
            return ""
        keep = display.decimate(n)
        # a path breaks where any sample between two kept ones cannot be assembled
        failed = np.cumsum(~self.valid)
        gap = np.flatnonzero(np.diff(failed[keep]) > 0) + 1
        shown_valid = self.valid[keep]
        paths = {}
        for name in names:
            x, y = self.points.xy(name)
            x, y = np.where(shown_valid, x[keep], np.nan), np.where(shown_valid, y[keep], np.nan)
            paths[name] = (np.insert(x, gap, np.nan), np.insert(y, gap, np.nan))
        first = int(np.argmax(self.valid))
        pose = {p: (float(self.points.xy(p)[0][first]), float(self.points.xy(p)[1][first]))
                for p in compiled.point_names}
        bars = [link.points for link in compiled.links]
        linked = {p for points in bars for p in points}
        ground = [p for p in compiled.point_names if p in compiled.ground
                  and (p in linked or not bars)]
        return display.svg_paths(paths, pose=pose, bars=bars, ground=ground)

    @property
    def input_values(self) -> np.ndarray:
        """Return the values of the construction's first input (radians for an angle)."""
        if not self.inputs:
            raise AttributeError(f"construction {self.construction.name!r} has no input")
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

    def event_inputs(self, event: BranchEvent) -> dict[str, float]:
        """Return the input values where the roots of a branch change meet.

        They lie on the straight path from sample ``event.index - 1`` to
        ``event.index``, at ``event.fraction`` of it.

        Examples
        --------
        A parallelogram (ground 10, crank 4, coupler 10, rocker 4) passes its
        change point at 180 degrees, three tenths of the way along a step:

        >>> from geokin import Construction, sweep
        >>> c = Construction()
        >>> c.input("theta")
        >>> c.fixed("O2", 0, 0)
        >>> c.fixed("O4", 10, 0)
        >>> c.polar("A", "O2", 4, "theta")
        >>> c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
        >>> s = sweep(c, np.radians([177.0, 187.0]))
        >>> round(float(np.degrees(s.event_inputs(s.events[0])["theta"])), 4)
        180.0
        """
        before, after = event.index - 1, event.index
        return {name: float(values[before] + event.fraction * (values[after] - values[before]))
                for name, values in self.inputs.items()}

    def branch_names(self, node: str) -> np.ndarray:
        """Return :meth:`named_branches` (the old name of it, deprecated)."""
        warnings.warn("Sweep.branch_names(node) is now Sweep.named_branches(node); the old "
                      "name will be removed", DeprecationWarning, stacklevel=2)
        return self.named_branches(node)

    def named_branches(self, node: str) -> np.ndarray:
        """Return the branch of a two-root node at each sample, by name.

        Examples
        --------
        >>> from geokin import Construction, sweep
        >>> c = Construction()
        >>> c.input("theta")
        >>> c.fixed("O2", 0, 0)
        >>> c.fixed("O4", 10, 0)
        >>> c.polar("A", "O2", 4, "theta")
        >>> c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
        >>> sweep(c, np.radians([170.0, 190.0])).named_branches("B").tolist()
        ['left', 'right']
        """
        step = self.construction.step_named(node)
        if not step.node.branch_names:
            raise KeyError(f"point {node!r} is a {step.node.kind} node: it has one root")
        return np.array(step.node.branch_names, dtype=object)[self.branches[node]]

    def require_assembled(self) -> Sweep:
        """Return this sweep if any of its samples can be assembled; raise if none can.

        A sweep where some samples cannot be assembled is data (NaN there);
        one where none can has nothing to show, which a caller that draws or
        writes the motion wants to say rather than write NaN.

        Returns
        -------
        Sweep
            This sweep.

        Raises
        ------
        AssemblyError
            Naming the node that fails and why, with the number of samples
            where it does: every cause of failure, the most frequent first
            (up to three). Its ``node`` is the most frequent failing node.

        Examples
        --------
        A four-bar whose coupler and rocker are too short to meet:

        >>> from geokin import Construction, sweep
        >>> c = Construction("too short")
        >>> c.input("theta")
        >>> c.fixed("O2", 0, 0)
        >>> c.fixed("O4", 40, 0)
        >>> c.polar("A", "O2", 10, "theta")
        >>> c.circle_circle("B", ("A", "O4"), (5, 5), branch="left")
        >>> sweep(c, np.radians([0.0, 90.0, 180.0])).require_assembled()
        ... # doctest: +NORMALIZE_WHITESPACE
        Traceback (most recent call last):
        ...
        geokin.errors.AssemblyError: no sample can be assembled: node 'B' fails at all 3
        samples: no intersection: the curves do not meet
        """
        if self.valid.size == 0 or self.valid.any():
            return self
        raise unassembled_error(self.construction, failure_causes(self), self.valid.size)

    def explain(self, index: int) -> str:
        """Say in words whether sample ``index`` is assembled, and if not why.

        Examples
        --------
        >>> from geokin import Construction, sweep
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

        An angle input is said in degrees (the sweep holds radians):

        >>> c = Construction("crank")
        >>> c.input("theta")
        >>> c.fixed("O", 0, 0)
        >>> c.polar("A", "O", 1, "theta")
        >>> sweep(c, [-np.pi]).explain(0)
        'sample 0 (theta = -180 deg): assembled'
        """
        if self.variants is not None:
            raise ValueError(f"a sweep of {self.variants} variants: say which, as in "
                             f"sweep.variant(i).explain({index})")
        values = ", ".join(f"{k} = {self._input_text(k, v[index])}"
                           for k, v in self.inputs.items())
        if self.valid[index]:
            return f"sample {index} ({values}): assembled"
        return (f"sample {index} ({values}): node {self.failed_node[index]!r} cannot be "
                f"assembled: {self.failure_reason[index]}")


    def _input_text(self, name: str, value: float) -> str:
        """Return an input's value as :meth:`explain` says it: degrees for an angle."""
        if self.construction.inputs[name].kind == "angle":
            return f"{math.degrees(value):g} deg"
        return f"{value:g}"


def failure_causes(sweep: Sweep, offset: int = 0) -> list[tuple[int, int, int, int]]:
    """Return why a sweep's samples cannot be assembled, one entry per cause.

    Each cause is (step, reason code, number of samples, first sample,
    counted from ``offset``), as :func:`unassembled_error` takes them; the
    causes of consecutive parts of a long sweep add up.
    """
    failing = ~sweep.valid.reshape(-1)
    key = (sweep.failed_step.reshape(-1)[failing].astype(np.int64) * 256
           + sweep.reason_code.reshape(-1)[failing].astype(np.int64))
    keys, first, counts = np.unique(key, return_index=True, return_counts=True)
    where = np.flatnonzero(failing)[first] + offset
    return [(int(k // 256), int(k % 256), int(c), int(w))
            for k, c, w in zip(keys, counts, where, strict=True)]


def unassembled_error(construction: Compiled, causes: list[tuple[int, int, int, int]],
                      samples: int) -> AssemblyError:
    """Return the error that says no sample of a sweep can be assembled, and why.

    ``causes`` are :func:`failure_causes`, of the whole sweep or added up
    over its parts (a cause met in several parts is summed); the most
    frequent is named first (up to three).
    """
    merged: dict[tuple[int, int], list[int]] = {}
    for step, reason, count, first in causes:
        entry = merged.setdefault((step, reason), [0, first])
        entry[0] += count
        entry[1] = min(entry[1], first)
    order = sorted(merged.items(), key=lambda item: (-item[1][0], item[1][1]))
    names = ["", *construction.point_names]
    shown = [(names[step], REASONS[reason], count) for (step, reason), (count, _) in order]
    node, why, _ = shown[0]
    if len(shown) == 1:
        where = "the one sample" if samples == 1 else f"all {samples:,} samples"
        text = f"node {quote(node)} fails at {where}: {why}"
    else:
        parts = [f"node {quote(name)} at {k:,} of {samples:,} samples ({why})"
                 for name, why, k in shown[:3]]
        if len(shown) > 3:
            rest = sum(k for _, _, k in shown[3:])
            parts.append(f"{len(shown) - 3} other cause(s) at {rest:,}")
        text = "nodes fail: " + ", ".join(parts)
    return AssemblyError(f"no sample can be assembled: {text}", node=node)


class PointTable(Mapping):
    """Point positions as (N, 2) arrays, stacked from coordinates when first read.

    Parameters
    ----------
    coords : mapping of str to (x, y)
        Each point's coordinates as evaluated, arrays of shape (N,) or
        numbers for a point that does not move.
    valid : ndarray of bool, shape (N,)
    complete : bool, optional
        Whether ``valid`` is True at every sample, where the caller knows;
        by default it is counted when a first point is read.
    """

    def __init__(self, coords: Mapping[str, tuple[np.ndarray, np.ndarray]],
                 valid: np.ndarray, complete: bool | None = None) -> None:
        self._coords = coords
        self._valid = valid
        self._complete = complete
        self._stacked: dict[str, np.ndarray] = {}

    def xy(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """Return a point's x and y coordinates as two read-only arrays of shape (N,).

        They are the coordinates as evaluated, without the copy that stacking
        makes: unlike ``table[name]`` they are not NaN at a sample where the
        point was found but a later one failed.

        Examples
        --------
        >>> from geokin import Construction, sweep
        >>> c = Construction()
        >>> c.input("t")
        >>> c.fixed("O", 0, 0)
        >>> c.polar("A", "O", 2, "t")
        >>> x, y = sweep(c, [0.0, np.pi]).points.xy("A")
        >>> x.round(12).tolist()
        [2.0, -2.0]
        """
        x, y = self._coords[self._name(name)]
        return self._whole(x), self._whole(y)

    def _whole(self, value) -> np.ndarray:
        """Return coordinates as evaluated at every sample, read-only, without a copy."""
        shape = self._valid.shape
        if type(value) is np.ndarray and value.shape == shape and value.dtype == float:
            return read_only(value)
        return read_only(np.broadcast_to(np.asarray(value, dtype=float), shape))

    def coords(self, name: str) -> tuple[np.ndarray | float, np.ndarray | float]:
        """Return a point's x and y as evaluated: numbers for a point that does not move.

        Arrays are read-only views: the table stacks its points from them.
        """
        x, y = self._coords[self._name(name)]
        return (read_only(x) if isinstance(x, np.ndarray) else x,
                read_only(y) if isinstance(y, np.ndarray) else y)

    def _name(self, name: str) -> str:
        if isinstance(name, str) and not name.isascii():
            name = unicodedata.normalize("NFKC", name)  # names are declared in NFKC
        if name not in self._coords:
            raise KeyError(f"no point {name!r}{did_you_mean(name, self._coords)}")
        return name

    def __getitem__(self, name: str) -> np.ndarray:
        stacked = self._stacked.get(name)
        if stacked is not None:
            return stacked
        name = self._name(name)
        x, y = self._coords[name]
        stacked = np.empty((*self._valid.shape, 2))
        stacked[..., 0] = x
        stacked[..., 1] = y
        if self._complete is None:
            # as valid.all(), a few times faster
            self._complete = np.count_nonzero(self._valid) == self._valid.size
        if not self._complete:
            stacked[~self._valid] = np.nan
        stacked.setflags(write=False)  # its own memory: no view needed
        self._stacked[name] = stacked
        return stacked

    def __iter__(self):
        return iter(self._coords)

    def __len__(self):
        return len(self._coords)


