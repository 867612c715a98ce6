"""Drawings of a mechanism at one sample, and pictures of them written to files.

:func:`plot_mechanism` draws on a given ``ax`` or the current one and
returns it; :func:`figure_mechanism` makes a new figure; :func:`save` writes
a figure as PNG or SVG. What is drawn is decided by
:class:`~geokin.plotting.layout.Layout`; the :class:`Scene` here makes the
artists and moves them to any sample, for one picture or for every frame of
an animation. matplotlib is imported inside the functions.

What a mechanism drawing shows:

- ground pivots (points that never move, joined to a link) as triangles on
  hatched ground, below the pivot where there is room, otherwise on a side
  clear of the other pivots and the frame, and smaller where pivots are close;
- links as bars, a link of three or more points as a translucent plate;
  a construction without links gets a bar from each point to the points
  it is built on;
- sliders as blocks on their guide, drawn over the block's travel along it
  (a moving guide within the link that carries it), on hatched ground when
  the guide is ground;
- the driving input: an arc arrow at the driven crank's pivot and the input
  value (degrees for an angle) in the corner;
- point labels, each in a gap between its bars (beside the blocks on its
  point) and clear of the other labels, points, ground symbols and the
  input's arrow; and the paths of
  the traced points over the whole sweep, broken where the mechanism cannot
  be assembled.

A sample that cannot be assembled is shown as the last assembled pose
before it (or the first after it), faded, with the reason and the input
value of the pose drawn in the corner (see
:func:`~geokin.plotting.layout.pose_drawn`). Where no sample can be assembled,
each shows what is known there, with why nothing assembles: the ground
pivots, and the points found before the node that fails (a crank turning
alone), with the bars and sliders between them.

Examples
--------
>>> import matplotlib
>>> matplotlib.use("Agg")
>>> import numpy as np
>>> from geokin import Construction, sweep
>>> c = Construction("crank and rocker")
>>> c.input("theta")
>>> c.fixed("O2", 0, 0)
>>> c.fixed("O4", 40, 0)
>>> c.polar("A", "O2", 10, "theta")
>>> c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
>>> fig, ax = figure_mechanism(sweep(c, np.linspace(0, 2 * np.pi, 73)))
>>> [line.get_label() for line in ax.get_legend().get_lines()]
['path of A', 'path of B']
>>> import matplotlib.pyplot as plt
>>> plt.close(fig)
"""

from __future__ import annotations

import math
import os
import pathlib
import textwrap
from collections.abc import Iterable
from typing import TYPE_CHECKING, Literal

import numpy as np

from ..atomic import replacing, require_folder
from ..errors import GeokinError
from ..results import Sweep
from .layout import (
    Layout,
    distance_to_segment,
    input_text,
    length_unit,
    signed_turn,
    title_text,
    title_width,
)

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "FIGSIZE",
    "GROUND_COLOR",
    "INPUT_COLOR",
    "LINK_COLORS",
    "SAVE_FORMATS",
    "TRACE_COLORS",
    "Scene",
    "figure_mechanism",
    "plot_mechanism",
    "save",
    "setup_axes",
]

LINK_COLORS = ("#2f6db5", "#e07b00", "#3a9a4b", "#8a55b5", "#b8433e", "#2a9d9d", "#8c6d46")
"""Colours of the links, in declaration order."""

TRACE_COLORS = ("#d62976", "#1f9bd1", "#6a9a1f", "#f0a202", "#7b4fc9", "#333333")
"""Colours of the traced paths."""

GROUND_COLOR = "#3b3b3b"
INPUT_COLOR = "#c0392b"
FIGSIZE = (8.0, 6.0)
SAVE_FORMATS = (".png", ".svg")
_Z_TRACE, _Z_GROUND, _Z_LINK, _Z_SLIDER, _Z_JOINT, _Z_LABEL = 1, 2, 3, 4, 5, 6
_LABEL_REACH = 1.1  # from a point to the middle of its label, about, in symbol sizes
STATUS_CORNERS: dict[str, tuple[float, float, Literal["left", "right"],
                                Literal["top", "bottom"]]] = {
    "upper left": (0.015, 0.985, "left", "top"),
    "upper right": (0.985, 0.985, "right", "top"),
    "lower left": (0.015, 0.015, "left", "bottom"),
    "lower right": (0.985, 0.015, "right", "bottom")}
"""Where the status box may go, in axes fractions, with its alignment; an animation's
stays in the first."""


class Scene:
    """The artists of one mechanism drawing, updatable to any sample.

    :func:`plot_mechanism` draws one sample with it, and
    :func:`~geokin.plotting.animation.animate` every frame, by moving the
    same artists.

    Parameters
    ----------
    sweep : Sweep
    ax : matplotlib.axes.Axes
        Where the artists are added.
    traces : list of str, optional
        The points whose paths are drawn (see :class:`~geokin.plotting.layout.Layout`).

    Attributes
    ----------
    layout : Layout
        What is drawn.
    trace_lines : list of matplotlib.lines.Line2D
        One path per traced point, in the order of ``layout.traces``.
    """

    def __init__(self, sweep: Sweep, ax: Axes, traces: Iterable[str] | None = None) -> None:
        from matplotlib.colors import to_rgba
        from matplotlib.lines import Line2D
        from matplotlib.patches import FancyArrowPatch, Polygon

        self.sweep, self.ax = sweep, ax
        self.layout = layout = Layout(sweep, traces)
        # the artists are made at the origin and moved later: the view is the layout's
        # bounds (see setup_axes), not theirs, with whatever the axes held before
        limits, ignored = ax.dataLim.frozen(), ax.ignore_existing_data_limits
        self.linewidth = 5.0
        self.mechanism: list[Artist] = []  # artists faded at samples that cannot be assembled

        def polygon(**kwargs):
            patch = Polygon(np.zeros((3, 2)), closed=True, **kwargs)
            ax.add_patch(patch)
            self.mechanism.append(patch)
            return patch

        def line(*, mechanism=True, **kwargs):
            artist = Line2D([], [], **kwargs)
            ax.add_line(artist)
            if mechanism:
                self.mechanism.append(artist)
            return artist

        self.trace_lines = []
        for k, name in enumerate(layout.traces):
            color = TRACE_COLORS[k % len(TRACE_COLORS)]
            self.trace_lines.append(line(mechanism=False, color=color, lw=1.6, alpha=0.9,
                                         zorder=_Z_TRACE, label=f"path of {name}"))
        self.ground = []
        for _ in layout.pivots:
            hatch = polygon(facecolor="none", edgecolor=GROUND_COLOR, lw=0, hatch="////",
                            zorder=_Z_GROUND)
            base = line(color=GROUND_COLOR, lw=1.5, zorder=_Z_GROUND, solid_capstyle="butt")
            triangle = polygon(facecolor="#d9d9d9", edgecolor=GROUND_COLOR, lw=1.5,
                               zorder=_Z_GROUND + 0.1)
            self.ground.append((triangle, hatch, base))
        self.bars = []
        moving = 0
        for points in layout.links:
            if all(p in layout.ground for p in points):
                # the ground: its pivots are drawn hatched; a thin line shows the frame
                closed = (*points, points[0]) if len(points) > 2 else points
                artist = line(color=GROUND_COLOR, lw=1.2, ls=(0, (4, 3)), zorder=_Z_GROUND)
                self.bars.append((closed, artist))
                continue
            color = LINK_COLORS[moving % len(LINK_COLORS)]
            moving += 1
            points = layout.bar_ends(points)
            if len(points) == 2:
                artist = line(color=color, lw=self.linewidth, solid_capstyle="round",
                              zorder=_Z_LINK)
            else:
                artist = polygon(facecolor=to_rgba(color, 0.28), edgecolor=color, lw=2.5,
                                 joinstyle="round", zorder=_Z_LINK)
            self.bars.append((points, artist))
        self.blocks = []
        for slider in layout.sliders:
            grounded = all(p in layout.ground for p in slider.along)
            guide = line(color=GROUND_COLOR, lw=1.0, ls=(0, (8, 3, 2, 3)), zorder=_Z_GROUND)
            surface = line(color=GROUND_COLOR, lw=1.5, zorder=_Z_GROUND) if grounded else None
            hatch = (polygon(facecolor="none", edgecolor=GROUND_COLOR, lw=0, hatch="////",
                             zorder=_Z_GROUND) if grounded else None)
            block = polygon(facecolor="#f4d58d", edgecolor="#8a6d1f", lw=1.8, zorder=_Z_SLIDER)
            self.blocks.append((slider, block, guide, surface, hatch))
        traced = set(layout.traces)
        joints = [p for p in layout.shown if p not in layout.references]
        self.joint_names = [p for p in joints if p not in traced or p in layout.pivots
                            or any(p in pts for pts in layout.links)]
        self.joints = line(ls="none", marker="o", ms=7, mfc="white", mec="#222222", mew=1.5,
                           zorder=_Z_JOINT)
        self.loose_names = [p for p in joints if p not in self.joint_names]
        self.loose = line(ls="none", marker="o", ms=6, mfc="#222222", mec="white", mew=1.0,
                          zorder=_Z_JOINT)
        self.reference_marks = line(ls="none", marker="+", ms=9, mew=1.5, color="#777777",
                                    zorder=_Z_JOINT)
        def input_arrow():  # placed at each pose
            arrow = FancyArrowPatch((0, 0), (1, 1), arrowstyle="-|>", mutation_scale=14,
                                    lw=1.8, color=INPUT_COLOR, shrinkA=0, shrinkB=0,
                                    zorder=_Z_LABEL)
            ax.add_patch(arrow)
            self.mechanism.append(arrow)
            return arrow

        # an arc arrow on the crank of each input that turns one, and a straight one
        # beside each point an input places directly
        self.crank_arrows = [(crank, input_arrow()) for crank in layout.driven]
        self.push_arrows = [(point, input_arrow()) for point, _ in layout.pushed]
        self.labels = {}
        for name in layout.shown:
            self.labels[name] = ax.annotate(
                name, (0, 0), xytext=(0, 0), textcoords="offset points", ha="center",
                va="center", fontsize=10, fontweight="bold", color="#222222", zorder=_Z_LABEL,
                bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.75))
            self.mechanism.append(self.labels[name])
        x, y, ha, va = STATUS_CORNERS["upper left"]
        self.status = ax.text(x, y, "", transform=ax.transAxes, ha=ha, va=va,
                              fontsize=10, zorder=_Z_LABEL + 1, parse_math=False,
                              bbox=dict(boxstyle="round,pad=0.3", fc="white", ec="#bbbbbb",
                                        alpha=0.9))
        self._alpha = {id(a): a.get_alpha() for a in self.mechanism}
        ax.dataLim.set(limits)
        ax.ignore_existing_data_limits = ignored

    @property
    def artists(self) -> list[Artist]:
        """Every artist of the drawing."""
        return [*self.trace_lines, *self.mechanism, self.joints, self.loose,
                self.reference_marks, self.status]

    @property
    def drawn_paths(self) -> list[Artist]:
        """The paths of :attr:`trace_lines` with a sample to show, for the legend."""
        return [line for name, line in zip(self.layout.traces, self.trace_lines, strict=True)
                if np.isfinite(self.sweep.points[name]).all(axis=1).any()]

    def update(self, index: int, *, grow: bool = False) -> None:
        """Draw sample ``index``; with ``grow`` the paths end at that sample."""
        sweep, layout = self.sweep, self.layout
        for name, artist in zip(layout.traces, self.trace_lines, strict=True):
            xy = sweep.points[name]
            xy = xy[: index + 1] if grow else xy
            artist.set_data(xy[:, 0], xy[:, 1])
        text = input_text(sweep, index)
        pose = layout.pose_index(index)
        if pose is None and layout.unassembled:
            text += "\n" + _wrapped(layout.unassembled)
        elif pose is not None and not sweep.valid[index]:
            text += (f"\ncannot be assembled at {sweep.failed_node[index]!r}:\n"
                     f"{sweep.failure_reason[index]}\n"
                     f"drawn: the pose at {input_text(sweep, pose)}")
        self.status.set_text(text)
        box = self.status.get_bbox_patch()
        if box is not None:
            box.set_edgecolor("#bbbbbb" if sweep.valid[index] else INPUT_COLOR)
        if pose is None:
            # nothing assembles: no pose to borrow, so this sample's own, as far as it
            # is known (NaN beyond the failing node)
            at = {name: np.array([c[index] for c in sweep.points.xy(name)])
                  for name in layout.nodes}
            self._draw_pose(at, index)
            faded = False
        else:
            self._draw_pose({name: sweep.points[name][pose] for name in layout.nodes}, pose)
            faded = not sweep.valid[index]
        for artist in self.mechanism:
            alpha = self._alpha[id(artist)]
            artist.set_alpha(0.2 * (alpha or 1.0) if faded else alpha)
        for artist in (self.joints, self.loose, self.reference_marks):
            artist.set_alpha(0.2 if faded else None)

    def place_status(self) -> None:
        """Move the status box to the corner where it covers the least of the drawing.

        Of the four corners of the axes, the first (upper left, upper right,
        lower left, lower right) whose box crosses the fewest paths, bars and
        labels drawn; for one picture, once its view is set. (An animation
        keeps it in one place.)
        """
        from matplotlib.backends.backend_agg import RendererAgg
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch
        from matplotlib.text import Text
        from matplotlib.transforms import Bbox

        ax, status = self.ax, self.status
        if not status.get_text() or ax.figure is None:
            return
        # the view as it will be drawn (equal axes widen it); the texts measured as the
        # Agg renderer draws them, without drawing the figure (a layout engine may still
        # move the axes a little, the corners with them)
        ax.apply_aspect()
        dpi = ax.figure.dpi
        renderer = RendererAgg(1, 1, dpi)
        extent = status.get_window_extent(renderer).padded(4 * dpi / 72)
        width, height, frame = extent.width, extent.height, ax.bbox
        paths, boxes = [], []
        for artist in [*self.trace_lines, *self.mechanism, self.joints, self.loose]:
            if not artist.get_visible():
                continue
            if isinstance(artist, Text):
                boxes.append(artist.get_window_extent(renderer))
            elif isinstance(artist, Line2D | Patch):
                paths.append(artist.get_transform().transform_path(artist.get_path()))
        def covered(corner):
            x, y, ha, va = STATUS_CORNERS[corner]
            x0 = frame.x0 + x * frame.width - (width if ha == "right" else 0.0)
            y0 = frame.y0 + y * frame.height - (height if va == "top" else 0.0)
            box = Bbox.from_bounds(x0, y0, width, height)
            return (sum(path.intersects_bbox(box, filled=False) for path in paths)
                    + sum(box.overlaps(other) for other in boxes))

        x, y, ha, va = STATUS_CORNERS[min(STATUS_CORNERS, key=covered)]
        status.set_position((x, y))
        status.set_horizontalalignment(ha)
        status.set_verticalalignment(va)

    def _draw_pose(self, at, pose):
        """Draw the points at ``at`` (name to x, y); what is not finite there is hidden."""
        layout = self.layout
        known = {name for name, xy in at.items() if np.isfinite(xy).all()}
        for name, (triangle, hatch, base) in zip(layout.pivots, self.ground, strict=True):
            for artist in (triangle, hatch, base):
                artist.set_visible(name in known)
            if name not in known:
                continue
            # the triangle's tip on the pivot, its hatched base on the side chosen for it
            angle, g = layout.ground_directions[name], layout.ground_sizes[name]
            d = np.array([math.cos(angle), math.sin(angle)])
            e = np.array([-d[1], d[0]])
            here = at[name]
            middle = here + 1.5 * g * d
            triangle.set_xy([here, middle - 1.0 * g * e, middle + 1.0 * g * e])
            width, depth = 1.6 * g * e, 0.7 * g * d
            hatch.set_xy([middle - width, middle + width, middle + width + depth,
                          middle - width + depth])
            base.set_data(*np.array([middle - width, middle + width]).T)
        for points, artist in self.bars:
            artist.set_visible(known.issuperset(points))
            xy = np.array([at[p] for p in points])
            if hasattr(artist, "set_data"):
                artist.set_data(xy[:, 0], xy[:, 1])
            else:
                artist.set_xy(xy)
        self._on_blocks = {}
        self._grounds = []  # the middle lines of the hatched grounds under fixed guides
        for slider, block, guide, surface, hatch in self.blocks:
            shown = known.issuperset((slider.point, *slider.along))
            for artist in (block, guide, surface, hatch):
                if artist is not None:
                    artist.set_visible(shown)
            if shown:
                self._draw_slider(at, slider, block, guide, surface, hatch)

        def marks(names):
            return np.array([at[p] for p in names if p in known] or
                            np.empty((0, 2))).reshape(-1, 2).T

        for artist, names in ((self.joints, self.joint_names), (self.loose, self.loose_names),
                              (self.reference_marks, layout.references)):
            artist.set_data(*marks(names))
            artist.set_visible(True)
        self._arrow_points = np.empty((0, 2))
        for crank, arrow in self.crank_arrows:
            arrow.set_visible(known.issuperset((crank.origin, crank.tip)))
            if arrow.get_visible():
                self._draw_crank(crank, arrow, at, pose)
        for point, arrow in self.push_arrows:
            arrow.set_visible(point in known and self._draw_push(point, arrow, at, pose))
        for name, label in self.labels.items():
            label.set_visible(name in known)
        centre = np.mean([at[p] for p in layout.shown if p in known] or [np.zeros(2)], axis=0)
        # each label where it is clear of the others: placed one by one (the labels on
        # blocks first, which have fewer places), then each placed again knowing where
        # all are
        reach = _LABEL_REACH * layout.size
        placed: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        for name in sorted((p for p in self.labels if p in known),
                           key=lambda name: name not in self._on_blocks):
            self._placed = [a + reach * d for a, d in placed.values()]
            placed[name] = self._label_place(name, at, centre)
        for name in placed:
            self._placed = [a + reach * d for other, (a, d) in placed.items() if other != name]
            placed[name] = self._label_place(name, at, centre)
        for name, (anchor, direction) in placed.items():
            label = self.labels[name]
            label.xy = tuple(anchor)
            label.set_position(tuple(8 * direction))
            # align the text's near side to the point, so long names do not cover it
            dx, dy = direction
            label.set_horizontalalignment("left" if dx > 0.3 else "right" if dx < -0.3
                                          else "center")
            label.set_verticalalignment("bottom" if dy > 0.3 else "top" if dy < -0.3
                                        else "center")

    def _label_place(self, name, at, centre):
        """Return where a point's label goes: its anchor, and a unit vector from there.

        Into the widest gap between its bars and its ground symbol, and
        clear of the other points, the ground symbols and the labels placed
        before it: two points close together get their labels on different
        sides. The anchor is the point, or for a point on blocks the edge of
        its blocks that way, so the label is beside them, not on them.
        Distances are judged in symbol sizes, which are a fixed part of the
        drawing.
        """
        layout, here = self.layout, at[name]
        s = layout.size
        pulls = []
        for other in layout.neighbours[name]:
            d = at[other] - here
            if np.hypot(*d) > 0:
                pulls.append(math.atan2(d[1], d[0]))
        if name in layout.pivots:  # the ground symbol
            side = layout.ground_directions[name]
            pulls += [side - math.radians(35), side, side + math.radians(35)]
        others = [at[p] for p in layout.shown if p != name and np.isfinite(at[p]).all()]
        # the ground symbols, and the hatched grounds of fixed guides; of its own symbol,
        # which is among the pulls, only the far strip
        symbols = [line for p in layout.pivots if np.isfinite(at[p]).all()
                   for line in layout.symbol_lines(p, at[p])[p == name:]]
        symbols += self._grounds
        if not pulls and not others and not self._placed:
            away = here - centre
            norm = np.hypot(*away)
            d = away / norm if norm > 1e-9 else np.array([0.7071, 0.7071])
            return here + self._past_blocks(name, d[None, :])[0] * d, d
        # every candidate at once: 16 directions, from up-right round
        angles = np.radians(np.arange(45, 405, 22.5))
        c = np.column_stack([np.cos(angles), np.sin(angles)])
        if pulls:
            gap = np.min(np.abs(signed_turn(angles[:, None], np.array(pulls)[None, :])), axis=1)
        else:
            gap = np.full(len(angles), math.pi)
        clear = self._past_blocks(name, c)
        labels = here + (clear + _LABEL_REACH * s)[:, None] * c

        def crowding(distances, reach):
            """How far into the reach of each obstacle each candidate comes, summed."""
            return np.sum(np.maximum(0.0, 1.0 - distances / reach), axis=-1)

        def to_points(points):
            points = np.asarray(points, dtype=float).reshape(-1, 2)
            return np.hypot(*(labels[:, None, :] - points[None, :, :]).transpose(2, 0, 1))

        # on another point's marker; a label beside blocks, away from its point, keeps
        # further from the others, so that it is not read as theirs
        crowded = crowding(to_points(others), (1.2 * s + clear)[:, None])
        crowded += 1.5 * crowding(to_points(self._placed), 2.4 * s)  # on another label
        if symbols:  # on a ground symbol or a guide's hatched ground
            ends = np.array(symbols, dtype=float)  # (m, 2, 2)
            crowded += crowding(distance_to_segment(labels[:, None, :], ends[None, :, 0],
                                                    ends[None, :, 1]), 1.1 * s)
        if len(self._arrow_points):  # on the input's arrow
            near = np.min(to_points(self._arrow_points), axis=1)
            crowded += 1.5 * np.maximum(0.0, 1.0 - near / (1.5 * s))
        best = int(np.argmax(gap - 2.5 * crowded))
        return here + clear[best] * c[best], c[best]

    def _past_blocks(self, name, directions):
        """Return how far from a point each direction (k, 2) leaves the blocks on it: 0 if none."""
        clear = np.zeros(len(directions))
        for u, n, half_l, half_h in self._on_blocks.get(name, ()):
            with np.errstate(divide="ignore"):  # straight along a side: the other side decides
                out = np.minimum(half_l / np.abs(directions @ u), half_h / np.abs(directions @ n))
            clear = np.maximum(clear, out)
        return clear

    def _draw_slider(self, at, slider, block, guide, surface, hatch):
        """Draw a block centred on its point, along the guide's current direction."""
        s = self.layout.size
        p, q = at[slider.along[0]], at[slider.along[1]]
        u = q - p
        length = np.hypot(*u)
        u = u / length if length > 0 else np.array([1.0, 0.0])
        n = np.array([-u[1], u[0]])
        centre = at[slider.point]
        half_l, half_h = 1.6 * s, 1.0 * s
        self._on_blocks.setdefault(slider.point, []).append((u, n, half_l, half_h))
        block.set_xy([centre - half_l * u - half_h * n, centre + half_l * u - half_h * n,
                      centre + half_l * u + half_h * n, centre - half_l * u + half_h * n])
        # the block's travel along its guide, not the whole line across the mechanism
        t_lo, t_hi = self.layout.guide_spans[slider.name]
        a, b = p + t_lo * u, p + t_hi * u
        guide.set_data([a[0], b[0]], [a[1], b[1]])
        if surface is not None:
            out = self.layout.guide_sides[slider.name] * n  # towards the ground
            a, b = a + half_h * out, b + half_h * out
            surface.set_data([a[0], b[0]], [a[1], b[1]])
            depth = 0.7 * s * out
            hatch.set_xy([a, b, b + depth, a + depth])
            self._grounds.append((a + 0.5 * depth, b + 0.5 * depth))

    def _draw_crank(self, crank, arrow, at, pose):
        o, a = at[crank.origin], at[crank.tip]
        size = self.layout.size
        radius = min(max(0.5 * np.hypot(*(a - o)), 1.2 * size), 4.0 * size)
        phi = math.atan2(a[1] - o[1], a[0] - o[0])
        sense = self._crank_sense(crank, pose)
        span = math.radians(70)
        start, end = phi - sense * (span + math.radians(25)), phi - sense * math.radians(25)
        arrow.set_positions(
            (o[0] + radius * math.cos(start), o[1] + radius * math.sin(start)),
            (o[0] + radius * math.cos(end), o[1] + radius * math.sin(end)))
        arrow.set_connectionstyle(f"arc3,rad={sense * math.tan(span / 4):.4f}")
        along = np.linspace(start, end, 12)
        self._arrow_points = np.vstack([
            self._arrow_points, o + radius * np.column_stack([np.cos(along), np.sin(along)])])

    def _draw_push(self, point, arrow, at, pose) -> bool:
        """Draw the arrow beside a point an input places, the way it moves at ``pose``.

        Beside the point, clear of its block; returns False where the point
        does not move there.
        """
        xy = self.sweep.points[point]
        n = len(xy)
        step = None
        for i, j in ((pose, pose + 1), (pose - 1, pose)):
            if 0 <= i and j < n and np.isfinite(xy[[i, j]]).all():
                step = xy[j] - xy[i]
                if np.hypot(*step) > 0:
                    break
        if step is None or not np.hypot(*step) > 0:
            return False
        u = step / np.hypot(*step)
        # beside the point: away from the ground of a fixed guide it runs on, else above
        # it (or to its left, moving up or down)
        side = np.array([-u[1], u[0]])
        for slider in self.layout.sliders:
            if slider.point == point and slider.name in self.layout.guide_sides:
                p, q = (at[name] for name in slider.along)
                guide = (q - p) / max(np.hypot(*(q - p)), 1e-300)
                side = -self.layout.guide_sides[slider.name] * np.array([-guide[1], guide[0]])
                break
        else:
            if side[1] < 0 or (side[1] == 0 and side[0] > 0):
                side = -side
        size = self.layout.size
        middle = at[point] + 2.6 * size * side
        arrow.set_positions(tuple(middle - 1.6 * size * u), tuple(middle + 1.6 * size * u))
        self._arrow_points = np.vstack([self._arrow_points,
                                        middle + np.linspace(-1.6, 1.6, 7)[:, None] * size * u])
        return True

    def _crank_sense(self, crank, pose):
        """+1 if the crank turns counter-clockwise at ``pose``, -1 if clockwise."""
        # as evaluated: the crank is known where a node after it fails
        (x0, y0), (x1, y1) = self.sweep.points.xy(crank.origin), self.sweep.points.xy(crank.tip)
        angle = np.arctan2(y1 - y0, x1 - x0)
        n = len(angle)
        for i, j in ((pose, pose + 1), (pose - 1, pose)):
            if 0 <= i and j < n:
                step = (angle[j] - angle[i] + np.pi) % (2 * np.pi) - np.pi
                if np.isfinite(step) and step != 0:
                    return 1.0 if step > 0 else -1.0
        return 1.0


def _wrapped(text: str, width: int = 44) -> str:
    """Break a message into short lines for a figure's corner, at its colons where it can.

    Examples
    --------
    >>> print(_wrapped("no sample can be assembled: node 'B' fails at all 361 samples: "
    ...                "no intersection: the curves do not meet"))
    no sample can be assembled:
    node 'B' fails at all 361 samples:
    no intersection: the curves do not meet
    """
    parts = text.split(": ", 2)
    return "\n".join(textwrap.fill(part + (":" if k < len(parts) - 1 else ""), width)
                     for k, part in enumerate(parts))


def setup_axes(ax: Axes, layout: Layout, title: str | None) -> None:
    """Fit the view to the whole motion, equal in x and y, with a grid and a title.

    The axes are labelled with the construction's length unit
    (:attr:`~geokin.construction.Compiled.units`), "x (mm)", or "x" without one.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    layout : Layout
    title : str or None
        None for the construction's name, ``""`` for none.
    """
    lower, upper = layout.bounds()
    ax.update_datalim([tuple(lower), tuple(upper)])
    ax.set_aspect("equal", adjustable="datalim")
    ax.autoscale_view()
    ax.grid(True, color="#dddddd", lw=0.8)
    ax.set_axisbelow(True)
    # in the construction's length unit, as the script gives it
    unit = length_unit(layout.sweep)
    ax.set_xlabel(f"x ({unit})" if unit else "x", parse_math=False)
    ax.set_ylabel(f"y ({unit})" if unit else "y", parse_math=False)
    if title is None:
        title = layout.sweep.construction.name
    if title:
        # a name is text, not mathtext: "$" in it must not stop the drawing
        ax.set_title(title_text(title, title_width(ax)), parse_math=False)


def _check_index(sweep, index):
    n = len(sweep)
    if index is None:
        valid = np.flatnonzero(sweep.valid)
        return int(valid[0]) if valid.size else 0
    if isinstance(index, bool) or not isinstance(index, int | np.integer):
        raise GeokinError(f"index must be an integer, got {index!r}")
    if not -n <= index < n:
        raise GeokinError(f"index {index} is out of range for a sweep of {n} samples")
    return int(index) % n


def plot_mechanism(sweep: Sweep, index: int | None = None, *, ax: Axes | None = None,
                   title: str | None = None, traces: Iterable[str] | None = None) -> Axes:
    """Draw the mechanism at one sample, with the paths of its traced points.

    Parameters
    ----------
    sweep : Sweep
        The motion, from :func:`geokin.sweep`.
    index : int, optional
        The sample to draw (negative counts from the end); by default the
        first sample that can be assembled. A sample that cannot be
        assembled shows the last assembled pose before it (or the first
        after it), faded, the reason and the input value of the pose drawn;
        if none can be, what is known at this one (the ground pivots, the
        points found before the node that fails) and why none can be.
    ax : matplotlib.axes.Axes, optional
        Where to draw; the current axes by default.
    title : str, optional
        The title; the construction's name by default, none if ``""``.
    traces : list of str, optional
        The points whose paths are drawn; by default the construction's
        traced points, or else every point that moves.

    Returns
    -------
    matplotlib.axes.Axes

    Raises
    ------
    GeokinError
        For an index out of range.
    ConstructionError
        For an unknown traced point (a :class:`GeokinError` too).

    See Also
    --------
    figure_mechanism, animate

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np
    >>> from geokin import Construction, sweep
    >>> c = Construction("crank")
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta")
    >>> fig, ax = plt.subplots()
    >>> ax = plot_mechanism(sweep(c, np.linspace(0, np.pi, 19)), 9, ax=ax)
    >>> ax.texts[-1].get_text()
    'θ = 90.0°'
    >>> plt.close(fig)
    """
    index = _check_index(sweep, index)
    if ax is None:
        import matplotlib.pyplot as plt

        ax = plt.gca()
    scene = Scene(sweep, ax, traces)
    scene.update(index)
    setup_axes(ax, scene.layout, title)
    scene.place_status()
    if scene.drawn_paths:
        ax.legend(handles=scene.drawn_paths, loc="best", fontsize=9, framealpha=0.9)
    return ax


def figure_mechanism(sweep: Sweep, index: int | None = None, *, title: str | None = None,
                     traces: Iterable[str] | None = None) -> tuple[Figure, Axes]:
    """Make a new figure of the mechanism at one sample.

    Parameters
    ----------
    sweep : Sweep
    index : int, optional
        The sample to draw; the first that can be assembled by default.
    title : str, optional
        The title; the construction's name by default.
    traces : list of str, optional
        The points whose paths are drawn (see :func:`plot_mechanism`).

    Returns
    -------
    fig : matplotlib.figure.Figure
        An 8 by 6 inch pyplot figure (close it with ``plt.close(fig)``).
    ax : matplotlib.axes.Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> from geokin import Construction, sweep
    >>> c = Construction("crank")
    >>> c.input("theta", samples=9)
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta")
    >>> fig, ax = figure_mechanism(sweep(c))
    >>> ax.get_title()
    'crank'
    >>> plt.close(fig)
    """
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=FIGSIZE, layout="constrained")
    plot_mechanism(sweep, index, ax=ax, title=title, traces=traces)
    return fig, ax


def save(fig: Figure, path: str | os.PathLike[str]) -> pathlib.Path:
    """Write a figure to a PNG or SVG file, chosen by the extension.

    The image has the figure's size and resolution: a PNG is
    ``fig.get_size_inches() * fig.dpi`` pixels.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    path : str or os.PathLike
        Ending in ``.png`` or ``.svg``.

    Returns
    -------
    pathlib.Path
        The path written. The file is replaced whole once the picture is
        complete (see :mod:`geokin.atomic`): an error or Ctrl-C leaves the
        old file.

    Raises
    ------
    GeokinError
        For another extension.
    geokin.atomic.OutputError
        For a folder that does not exist, or a file that cannot be written.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from matplotlib.figure import Figure
    >>> save(Figure(), "picture.jpg")
    Traceback (most recent call last):
    ...
    geokin.errors.GeokinError: cannot save a figure as 'picture.jpg': use a .png or .svg file
    """
    path = pathlib.Path(path)
    suffix = path.suffix.lower()
    if suffix not in SAVE_FORMATS:
        raise GeokinError(f"cannot save a figure as {str(path)!r}: use a .png or .svg file")
    require_folder(path)
    with replacing(path, "wb") as f:
        fig.savefig(f, format=suffix[1:], dpi="figure")
    return path
