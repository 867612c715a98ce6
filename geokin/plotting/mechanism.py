"""Figures and animations of a sweep, drawn with matplotlib.

Every function takes a :class:`~geokin.sweep.Sweep` (the positions are
computed by :func:`~geokin.sweep.sweep`, never here) and draws on a given
``ax`` or the current one, returning what it drew, as shapely's plotting
module and networkx's ``draw`` do. matplotlib is imported inside the
functions, so ``import geokin`` stays fast.

What a mechanism drawing shows:

- ground pivots (fixed points joined to a link) as triangles on hatched ground;
- links as bars, a link of three or more points as a translucent plate;
  a construction without links gets a bar from each point to the points
  it is built on;
- sliders as blocks on their guide line, on hatched ground when the guide is fixed;
- the driving input: an arc arrow at the driven crank's pivot and the input
  value (degrees for an angle) in the corner;
- point labels, and the paths of the traced points over the whole sweep,
  broken where the mechanism cannot be assembled.

A sample that cannot be assembled is shown as the nearest assembled pose,
faded, with the reason in the corner.

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

import base64
import contextlib
import html
import io
import math
import os
import pathlib
import shutil
import sys
import time

import numpy as np

from ..atomic import replacing, replacing_path
from ..errors import GeokinError, did_you_mean
from .layout import Layout, input_text, shown_text

__all__ = [
    "animate",
    "figure_kinematics",
    "figure_mechanism",
    "plot_input_output",
    "plot_mechanism",
    "save",
]

LINK_COLORS = ("#2f6db5", "#e07b00", "#3a9a4b", "#8a55b5", "#b8433e", "#2a9d9d", "#8c6d46")
"""Colours of the links, in declaration order."""

TRACE_COLORS = ("#d62976", "#1f9bd1", "#6a9a1f", "#f0a202", "#7b4fc9", "#333333")
"""Colours of the traced paths."""

GROUND_COLOR = "#3b3b3b"
INPUT_COLOR = "#c0392b"
FIGSIZE = (8.0, 6.0)
MAX_FRAMES = 300
"""The most frames of an animation unless more are asked for."""

MIN_FPS, MAX_FPS = 0.01, 100.0
"""The frame rates an animation may have: a GIF counts delays in hundredths of a second."""

SAVE_FORMATS = (".png", ".svg")
ANIMATION_FORMATS = (".gif", ".html", ".htm", ".mp4")

# bytes per pixel of one frame in the file: twice the most measured on constructions/ at
# 800 x 600 (0.023 for a GIF, whose frames hold what changed since the last; 0.107 for a page,
# a whole PNG in base64 per frame); for an .mp4, a guess well above what H.264 makes of such
# drawings
_FILE_BYTES_PER_PIXEL = {".gif": 0.05, ".html": 0.25, ".htm": 0.25, ".mp4": 0.03}

_Z_TRACE, _Z_GROUND, _Z_LINK, _Z_SLIDER, _Z_JOINT, _Z_LABEL = 1, 2, 3, 4, 5, 6


def _pyplot():
    import matplotlib.pyplot as plt

    return plt


def _frame_indices(n, frames):
    """Return up to ``frames`` sample indices evenly spread over ``n`` samples.

    Examples
    --------
    >>> _frame_indices(10, 4).tolist()
    [0, 3, 6, 9]
    >>> len(_frame_indices(1000, None))
    300
    """
    if frames is None:
        frames = min(n, MAX_FRAMES)
    if isinstance(frames, bool) or not isinstance(frames, int | np.integer) or frames < 1:
        raise GeokinError(f"frames must be a positive integer, got {frames!r}")
    count = min(int(frames), n)
    return np.unique(np.linspace(0, n - 1, count).round().astype(int))


# -- drawing -------------------------------------------------------------------


class _Scene:
    """The artists of one mechanism drawing, updatable to any sample."""

    def __init__(self, sweep, ax, traces=None):
        from matplotlib.colors import to_rgba
        from matplotlib.lines import Line2D
        from matplotlib.patches import FancyArrowPatch, Polygon

        self.sweep, self.ax = sweep, ax
        self.layout = layout = Layout(sweep, traces)
        self.linewidth = 5.0
        self.mechanism = []  # artists faded at samples that cannot be assembled

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
            if all(p in layout.fixed for p in points):
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
            grounded = all(p in layout.fixed for p in slider.along)
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
        self.crank_arrow = None
        if layout.crank is not None:
            self.crank_arrow = FancyArrowPatch((0, 0), (1, 1), arrowstyle="-|>",
                                               mutation_scale=14, lw=1.8, color=INPUT_COLOR,
                                               shrinkA=0, shrinkB=0, zorder=_Z_LABEL)
            ax.add_patch(self.crank_arrow)
            self.mechanism.append(self.crank_arrow)
        self.labels = {}
        for name in layout.shown:
            self.labels[name] = ax.annotate(
                name, (0, 0), xytext=(0, 0), textcoords="offset points", ha="center",
                va="center", fontsize=10, fontweight="bold", color="#222222", zorder=_Z_LABEL,
                bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.75))
            self.mechanism.append(self.labels[name])
        self.status = ax.text(0.015, 0.985, "", transform=ax.transAxes, ha="left", va="top",
                              fontsize=10, zorder=_Z_LABEL + 1,
                              bbox=dict(boxstyle="round,pad=0.3", fc="white", ec="#bbbbbb",
                                        alpha=0.9))
        self._alpha = {id(a): a.get_alpha() for a in self.mechanism}

    @property
    def artists(self):
        """Every artist of the drawing."""
        return [*self.trace_lines, *self.mechanism, self.joints, self.loose,
                self.reference_marks, self.status]

    def update(self, index, *, grow=False):
        """Draw sample ``index``; with ``grow`` the paths end at that sample."""
        sweep, layout = self.sweep, self.layout
        for name, artist in zip(layout.traces, self.trace_lines, strict=True):
            xy = sweep.points[name]
            xy = xy[: index + 1] if grow else xy
            artist.set_data(xy[:, 0], xy[:, 1])
        text = input_text(sweep, index)
        pose = layout.pose_index(index)
        if not sweep.valid[index]:
            text += (f"\ncannot be assembled at {sweep.failed_node[index]!r}:\n"
                     f"{sweep.failure_reason[index]}")
        self.status.set_text(text)
        self.status.get_bbox_patch().set_edgecolor(
            "#bbbbbb" if sweep.valid[index] else INPUT_COLOR)
        for artist in [*self.mechanism, self.joints, self.loose, self.reference_marks]:
            artist.set_visible(pose is not None)
        if pose is None:
            return
        at = {name: sweep.points[name][pose] for name in layout.nodes}
        self._draw_pose(at, pose)
        faded = not sweep.valid[index]
        for artist in self.mechanism:
            alpha = self._alpha[id(artist)]
            artist.set_alpha(0.2 * (alpha or 1.0) if faded else alpha)
        for artist in (self.joints, self.loose, self.reference_marks):
            artist.set_alpha(0.2 if faded else None)

    def _draw_pose(self, at, pose):
        layout, s = self.layout, self.layout.size
        for name, (triangle, hatch, base) in zip(layout.pivots, self.ground, strict=True):
            x, y = at[name]
            half, height = 1.0 * s, 1.5 * s
            triangle.set_xy([(x, y), (x - half, y - height), (x + half, y - height)])
            width, depth = 1.6 * s, 0.7 * s
            hatch.set_xy([(x - width, y - height), (x + width, y - height),
                          (x + width, y - height - depth), (x - width, y - height - depth)])
            base.set_data([x - width, x + width], [y - height, y - height])
        for points, artist in self.bars:
            xy = np.array([at[p] for p in points])
            if hasattr(artist, "set_data"):
                artist.set_data(xy[:, 0], xy[:, 1])
            else:
                artist.set_xy(xy)
        self._on_blocks = {}
        for slider, block, guide, surface, hatch in self.blocks:
            self._draw_slider(at, slider, block, guide, surface, hatch)
        self.joints.set_data(*np.array([at[p] for p in self.joint_names] or
                                       np.empty((0, 2))).reshape(-1, 2).T)
        self.loose.set_data(*np.array([at[p] for p in self.loose_names] or
                                      np.empty((0, 2))).reshape(-1, 2).T)
        self.reference_marks.set_data(*np.array([at[p] for p in layout.references] or
                                                np.empty((0, 2))).reshape(-1, 2).T)
        if self.crank_arrow is not None:
            self._draw_crank(at, pose)
        centre = np.mean([at[p] for p in layout.shown], axis=0)
        for name, label in self.labels.items():
            if name in self._on_blocks:
                # above the block, clear of it
                anchor, direction = self._on_blocks[name]
            else:
                anchor, direction = at[name], self._label_direction(name, at, centre)
            label.xy = tuple(anchor)
            label.set_position(tuple(8 * direction))
            # align the text's near side to the point, so long names do not cover it
            dx, dy = direction
            label.set_horizontalalignment("left" if dx > 0.3 else "right" if dx < -0.3
                                          else "center")
            label.set_verticalalignment("bottom" if dy > 0.3 else "top" if dy < -0.3
                                        else "center")

    def _label_direction(self, name, at, centre):
        """Return a unit vector from a point into the widest gap between its bars."""
        here = at[name]
        pulls = []
        for other in self.layout.neighbours[name]:
            d = at[other] - here
            if np.hypot(*d) > 0:
                pulls.append(math.atan2(d[1], d[0]))
        if name in self.layout.pivots:  # the ground symbol below
            pulls += [math.radians(235), math.radians(270), math.radians(305)]
        if not pulls:
            away = here - centre
            norm = np.hypot(*away)
            return away / norm if norm > 1e-9 else np.array([0.7071, 0.7071])
        candidates = np.radians(np.arange(45, 405, 22.5))
        gaps = [min(abs((c - p + np.pi) % (2 * np.pi) - np.pi) for p in pulls)
                for c in candidates]
        best = candidates[int(np.argmax(gaps))]
        return np.array([math.cos(best), math.sin(best)])

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
        self._on_blocks[slider.point] = (centre + half_h * n, n)
        block.set_xy([centre - half_l * u - half_h * n, centre + half_l * u - half_h * n,
                      centre + half_l * u + half_h * n, centre - half_l * u + half_h * n])
        with np.errstate(invalid="ignore"):
            t = (self.sweep.points[slider.point] - p) @ u
        t_lo = min(np.nanmin(t, initial=np.inf), 0.0 if surface is not None else np.inf)
        t_hi = np.nanmax(t, initial=-np.inf)
        t_lo, t_hi = t_lo - 2.5 * s, t_hi + 2.5 * s
        a, b = p + t_lo * u, p + t_hi * u
        guide.set_data([a[0], b[0]], [a[1], b[1]])
        if surface is not None:
            a, b = a - half_h * n, b - half_h * n
            surface.set_data([a[0], b[0]], [a[1], b[1]])
            depth = 0.7 * s * n
            hatch.set_xy([a, b, b - depth, a - depth])

    def _draw_crank(self, at, pose):
        origin, tip, _ = self.layout.crank
        o, a = at[origin], at[tip]
        size = self.layout.size
        radius = min(max(0.5 * np.hypot(*(a - o)), 1.2 * size), 4.0 * size)
        phi = math.atan2(a[1] - o[1], a[0] - o[0])
        sense = self._crank_sense(pose)
        span = math.radians(70)
        start, end = phi - sense * (span + math.radians(25)), phi - sense * math.radians(25)
        self.crank_arrow.set_positions(
            (o[0] + radius * math.cos(start), o[1] + radius * math.sin(start)),
            (o[0] + radius * math.cos(end), o[1] + radius * math.sin(end)))
        self.crank_arrow.set_connectionstyle(f"arc3,rad={sense * math.tan(span / 4):.4f}")

    def _crank_sense(self, pose):
        """+1 if the crank turns counter-clockwise at ``pose``, -1 if clockwise."""
        origin, tip, _ = self.layout.crank
        d = self.sweep.points[tip] - self.sweep.points[origin]
        angle = np.arctan2(d[:, 1], d[:, 0])
        n = len(angle)
        for i, j in ((pose, pose + 1), (pose - 1, pose)):
            if 0 <= i and j < n:
                step = (angle[j] - angle[i] + np.pi) % (2 * np.pi) - np.pi
                if np.isfinite(step) and step != 0:
                    return 1.0 if step > 0 else -1.0
        return 1.0


def _setup_axes(ax, layout, title):
    lower, upper = layout.bounds()
    ax.update_datalim([tuple(lower), tuple(upper)])
    ax.set_aspect("equal", adjustable="datalim")
    ax.autoscale_view()
    ax.grid(True, color="#dddddd", lw=0.8)
    ax.set_axisbelow(True)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    if title is None:
        title = layout.sweep.construction.name
    if title:
        # a name is text, not mathtext: "$" in it must not stop the drawing
        ax.set_title(shown_text(title), parse_math=False)


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


def plot_mechanism(sweep, index=None, *, ax=None, title=None, traces=None):
    """Draw the mechanism at one sample, with the paths of its traced points.

    Parameters
    ----------
    sweep : Sweep
        The motion, from :func:`geokin.sweep`.
    index : int, optional
        The sample to draw (negative counts from the end); by default the
        first sample that can be assembled. A sample that cannot be
        assembled shows the nearest assembled pose, faded, and the reason.
    ax : matplotlib.axes.Axes, optional
        Where to draw; the current axes by default.
    title : str, optional
        The title; the construction's name by default, none if ``""``.
    traces : list of str, optional
        The points whose paths are drawn; by default the construction's
        traced points, or else every point that is not fixed.

    Returns
    -------
    matplotlib.axes.Axes

    Raises
    ------
    GeokinError
        For an index out of range or an unknown traced point.

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
        ax = _pyplot().gca()
    scene = _Scene(sweep, ax, traces)
    scene.update(index)
    _setup_axes(ax, scene.layout, title)
    if scene.trace_lines:
        ax.legend(handles=scene.trace_lines, loc="best", fontsize=9, framealpha=0.9)
    return ax


def figure_mechanism(sweep, index=None, *, title=None, traces=None):
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
    fig, ax = _pyplot().subplots(figsize=FIGSIZE, layout="constrained")
    plot_mechanism(sweep, index, ax=ax, title=title, traces=traces)
    return fig, ax


def save(fig, path):
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
        For another extension, or a folder that does not exist.

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
    if not path.parent.is_dir():
        raise GeokinError(f"cannot save {str(path)!r}: the folder {str(path.parent)!r} "
                          "does not exist")
    with replacing(path, "wb") as f:
        fig.savefig(f, format=suffix[1:], dpi="figure")
    return path


class _Progress:
    """A text progress bar on stderr, shown on a terminal once a job takes over 2 s.

    Nothing is written where stderr is not a terminal (a log or a pipe).
    """

    def __init__(self, label, enabled, stream=None, delay=2.0, width=30):
        self.label, self.enabled = label, enabled
        self.stream = stream if stream is not None else sys.stderr
        self.delay, self.width = delay, width
        self.start = time.monotonic()
        self.shown = False

    def __call__(self, current, total):
        if not self.enabled:
            return
        done = current + 1
        if not self.shown:
            isatty = getattr(self.stream, "isatty", lambda: False)()
            if not (isatty and time.monotonic() - self.start >= self.delay):
                return
            self.shown = True
        if total:
            filled = min(int(self.width * done / total), self.width)
            bar = "#" * filled + "-" * (self.width - filled)
            self.stream.write(f"\r{self.label} [{bar}] {done}/{total}")
        else:
            self.stream.write(f"\r{self.label}: frame {done}")
        self.stream.flush()

    def close(self):
        if self.shown:
            self.stream.write("\n")
            self.stream.flush()


class _GifWriter:
    """Write a GIF a frame at a time: each frame is encoded and written as it comes.

    Only the previous frame is kept, to write each new one as the rectangle
    that changed (with its own palette) over the last, which is what makes
    an animation of a mechanism small.
    """

    def __init__(self, stream, fps):
        self.stream = stream
        self.duration = 1000.0 / fps  # milliseconds; the file keeps hundredths of a second
        self.previous = None

    def add(self, rgb):
        from PIL import GifImagePlugin, Image

        if self.previous is None:
            image = _paletted(Image.fromarray(rgb))
            header, _ = GifImagePlugin.getheader(image, None,
                                                 {"loop": 0, "duration": self.duration})
            self.stream.write(b"".join(header))
            box, local = (0, 0), False
        else:
            changed = np.any(rgb != self.previous, axis=2)
            rows, cols = np.flatnonzero(changed.any(axis=1)), np.flatnonzero(changed.any(axis=0))
            if rows.size:
                top, bottom, left, right = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
            else:  # nothing changed: one pixel keeps the frame and its delay
                top, bottom, left, right = 0, 1, 0, 1
            image = _paletted(Image.fromarray(rgb[top:bottom, left:right]))
            box, local = (int(left), int(top)), True
        self.stream.write(b"".join(GifImagePlugin.getdata(
            image, box, duration=self.duration, disposal=1, include_color_table=local)))
        self.previous = rgb.copy()

    def finish(self):
        self.stream.write(b";")  # the GIF trailer


def _paletted(image):
    """Return an RGB image with an adaptive palette of at most 256 colours, undithered."""
    from PIL import Image

    return image.convert("P", palette=Image.Palette.ADAPTIVE, colors=256)


_PAGE_HEAD = """<!DOCTYPE html>
<html>
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
body {{ font-family: sans-serif; margin: 1em; }}
.player img {{ display: block; max-width: 100%; height: auto; border: 1px solid #dddddd; }}
.player .controls {{ display: flex; gap: 0.3em; align-items: center; margin-top: 0.5em;
                     max-width: {width}px; }}
.player button {{ font-size: 1.1em; min-width: 2.4em; }}
.player input[type=range] {{ flex: 1; }}
</style>
</head>
<body>
<div class="player">
<img id="frame" width="{width}" height="{height}" alt="{title}">
<div class="controls">
<button id="first" title="first frame">&#x23EE;</button>
<button id="back" title="one frame back">&#x23F4;&#x2502;</button>
<button id="play" title="play or pause">&#x23F8;</button>
<button id="forward" title="one frame forward">&#x2502;&#x23F5;</button>
<button id="last" title="last frame">&#x23ED;</button>
<input id="slider" type="range" min="0" max="{last}" value="0">
<span id="counter"></span>
<label><input id="loop" type="checkbox" checked> loop</label>
</div>
</div>
<script>
var frames = [
"""

_PAGE_TAIL = """];
</script>
<script>
(function () {{
  var interval = {interval};
  var element = function (id) {{ return document.getElementById(id); }};
  var image = element("frame"), slider = element("slider"), counter = element("counter");
  var play = element("play"), loop = element("loop");
  var current = 0, timer = null;
  function show(i) {{
    current = Math.min(Math.max(i, 0), frames.length - 1);
    image.src = frames[current];
    slider.value = current;
    counter.textContent = (current + 1) + " / " + frames.length;
  }}
  function stop() {{
    if (timer !== null) {{ clearInterval(timer); timer = null; }}
    play.innerHTML = "&#x25B6;";
  }}
  function tick() {{
    if (current + 1 < frames.length) {{ show(current + 1); }}
    else if (loop.checked) {{ show(0); }}
    else {{ stop(); }}
  }}
  function start() {{
    if (timer === null) {{ timer = setInterval(tick, interval); play.innerHTML = "&#x23F8;"; }}
  }}
  play.onclick = function () {{ if (timer === null) {{ start(); }} else {{ stop(); }} }};
  element("first").onclick = function () {{ stop(); show(0); }};
  element("back").onclick = function () {{ stop(); show(current - 1); }};
  element("forward").onclick = function () {{ stop(); show(current + 1); }};
  element("last").onclick = function () {{ stop(); show(frames.length - 1); }};
  slider.oninput = function () {{ stop(); show(parseInt(slider.value, 10)); }};
  show(0);
  start();
}})();
</script>
</body>
</html>
"""


class _PageWriter:
    """Write an animation as one self-contained HTML page, a frame at a time.

    The page holds every frame as a PNG in base64 and a small player
    (play, pause, step, a slider, loop), and fetches nothing from the web.
    Each frame is written out as soon as it is drawn.
    """

    def __init__(self, stream, fps, title, size, frames):
        self.stream = stream
        self.fps = fps
        width, height = size
        self.stream.write(_PAGE_HEAD.format(title=html.escape(shown_text(title)), width=width,
                                            height=height, last=frames - 1).encode("utf-8"))

    def add(self, rgb):
        from PIL import Image

        png = io.BytesIO()
        Image.fromarray(rgb).save(png, format="PNG")
        self.stream.write(b'"data:image/png;base64,' + base64.b64encode(png.getvalue())
                          + b'",\n')

    def finish(self):
        interval = f"{1000.0 / self.fps:.6g}"
        self.stream.write(_PAGE_TAIL.format(interval=interval).encode("utf-8"))


def _available_memory() -> int | None:
    """Return the bytes of memory available to a new allocation, or None if unknown."""
    with contextlib.suppress(OSError, ValueError):
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    with contextlib.suppress(AttributeError, ValueError, OSError):
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    return None


def animation_estimate(frames, width, height, suffix, *, samples=0, traces=0):
    """Estimate the file size and the memory of an animation, before drawing it.

    Frames are streamed to the file, so the memory does not grow with their
    number: it is a few copies of one frame, plus the traced paths that
    matplotlib keeps while drawing them (``traces`` paths of up to
    ``samples`` points). The file grows by about a frame's compressed size
    per frame.

    Parameters
    ----------
    frames : int
    width, height : int
        The size of a frame in pixels.
    suffix : {".gif", ".html", ".htm", ".mp4"}
    samples : int
        The samples of the sweep animated.
    traces : int
        The number of traced paths.

    Returns
    -------
    file_bytes, memory_bytes : int

    Examples
    --------
    >>> file_bytes, memory_bytes = animation_estimate(3000, 800, 600, ".gif")
    >>> f"{file_bytes / 1e6:.0f} MB, {memory_bytes / 1e6:.0f} MB"
    '72 MB, 11 MB'
    """
    pixels = int(width) * int(height)
    file_bytes = int(frames * pixels * _FILE_BYTES_PER_PIXEL[suffix]) + 4096
    # the canvas (RGBA), this and the last frame (RGB), the palette or PNG copy
    memory_bytes = pixels * (4 + 3 + 3 + 4 + 8) + 48 * samples * traces
    return file_bytes, memory_bytes


def _check_room(path, frames, width, height, suffix, samples, traces):
    """Refuse, up front, an animation whose file or memory would not fit."""
    file_bytes, memory_bytes = animation_estimate(frames, width, height, suffix,
                                                  samples=samples, traces=traces)
    what = (f"an animation of {frames:,} frames of {width} x {height} pixels needs about "
            f"{_megabytes(file_bytes)} on disk and {_megabytes(memory_bytes)} of memory")
    try:
        free = shutil.disk_usage(path.parent).free
    except OSError:
        free = None
    if free is not None and file_bytes > free:
        raise GeokinError(f"cannot write {str(path)!r}: {what}, but only {_megabytes(free)} "
                          f"are free there; ask for fewer frames, fewer pixels (a lower dpi) "
                          f"or an .mp4")
    available = _available_memory()
    if available is not None and memory_bytes > available:
        raise GeokinError(f"cannot write {str(path)!r}: {what}, but only "
                          f"{_megabytes(available)} of memory are available; ask for fewer "
                          "samples or fewer traced points")


def _megabytes(count: int) -> str:
    return f"{count / 1e6:,.0f} MB" if count >= 1e6 else f"{count / 1e6:.2f} MB"


def animate(sweep, path, *, fps=25, frames=None, progress=True):
    """Write an animation of the motion, the traced paths growing with it.

    The writer is chosen by the extension: ``.gif``, ``.html`` (one
    self-contained page with the frames embedded and a player) or ``.mp4``
    (needs ffmpeg). Samples that cannot be assembled show the last
    assembled pose, faded, with the reason.

    Each frame goes to the file as soon as it is drawn, so memory does not
    grow with the number of frames; an animation whose file would not fit
    on the disk, or whose drawing would not fit in memory, is refused
    before anything is drawn (see :func:`animation_estimate`). The file is
    written whole or not at all (see :mod:`geokin.atomic`).

    Parameters
    ----------
    sweep : Sweep
    path : str or os.PathLike
        The file to write, ending in ``.gif``, ``.html`` or ``.mp4``.
    fps : float
        Frames per second, from :data:`MIN_FPS` to :data:`MAX_FPS`.
    frames : int, optional
        The number of frames: that many samples, evenly chosen. By default
        every sample, at most 300.
    progress : bool
        Show a progress bar on stderr when it is a terminal and writing
        takes more than about 2 s.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    GeokinError
        For an unknown extension, an ``.mp4`` without ffmpeg, bad ``fps``
        or ``frames``, or an animation that would not fit.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from geokin import Construction, sweep
    >>> c = Construction("crank")
    >>> c.input("theta", samples=5)
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta")
    >>> animate(sweep(c), "crank.avi")
    Traceback (most recent call last):
    ...
    geokin.errors.GeokinError: cannot animate to 'crank.avi': use a .gif, .html or .mp4 file
    >>> animate(sweep(c), "crank.gif", frames=3, progress=False)  # doctest: +SKIP
    PosixPath('crank.gif')
    """
    path = pathlib.Path(path)
    suffix = path.suffix.lower()
    if suffix not in ANIMATION_FORMATS:
        raise GeokinError(f"cannot animate to {str(path)!r}: use a .gif, .html or .mp4 file")
    if (isinstance(fps, bool) or not isinstance(fps, int | float)
            or not MIN_FPS <= fps <= MAX_FPS):
        raise GeokinError(f"fps must be a number from {MIN_FPS:g} to {MAX_FPS:g}, got {fps!r}")
    indices = _frame_indices(len(sweep), frames)
    from matplotlib import animation

    if suffix == ".mp4" and not animation.writers.is_available("ffmpeg"):
        raise GeokinError(
            f"cannot write {str(path)!r}: an .mp4 needs ffmpeg, which was not found. "
            "Install ffmpeg (for example 'apt install ffmpeg' or 'conda install ffmpeg') "
            "and make sure it is on PATH, or write a .gif or .html file instead")
    if not path.parent.is_dir():
        raise GeokinError(f"cannot write {str(path)!r}: the folder {str(path.parent)!r} "
                          "does not exist")

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=FIGSIZE, layout="constrained")
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    scene = _Scene(sweep, ax)
    width, height = canvas.get_width_height()
    _check_room(path, len(indices), width, height, suffix, len(sweep),
                len(scene.trace_lines))
    scene.update(int(indices[0]))
    _setup_axes(ax, scene.layout, None)
    if scene.trace_lines:
        ax.legend(handles=scene.trace_lines, loc="upper left", bbox_to_anchor=(1.01, 1.0),
                  fontsize=9, framealpha=0.9)
    # lay the figure out once: the frames keep the same axes
    fig.draw_without_rendering()
    fig.set_layout_engine("none")

    def frames_drawn():
        for k, index in enumerate(indices):
            scene.update(int(index), grow=True)
            yield k

    bar = _Progress(f"writing {path.name}", progress)
    try:
        if suffix == ".mp4":
            _write_movie(fig, path, fps, frames_drawn(), len(indices), bar)
        else:
            with replacing(path, "wb") as f:
                if suffix == ".gif":
                    writer = _GifWriter(f, fps)
                else:
                    writer = _PageWriter(f, fps, sweep.construction.name, (width, height),
                                         len(indices))
                for k in frames_drawn():
                    canvas.draw()
                    writer.add(np.asarray(canvas.buffer_rgba())[..., :3])
                    bar(k, len(indices))
                writer.finish()
    finally:
        bar.close()
    return path


def _write_movie(fig, path, fps, drawn, count, bar):
    """Pipe the frames to ffmpeg, which writes a temporary file renamed into place."""
    import subprocess

    from matplotlib import animation

    with replacing_path(path) as temp:
        writer = animation.FFMpegWriter(fps=fps)
        writer.setup(fig, temp, dpi=fig.dpi)
        stopped = False
        try:
            for k in drawn:
                writer.grab_frame()
                bar(k, count)
        except BrokenPipeError:  # ffmpeg has stopped reading: finish() tells why
            stopped = True
        except BaseException:  # already failing: let ffmpeg go without hiding why
            with contextlib.suppress(Exception):
                writer.finish()
            raise
        try:
            writer.finish()
        except subprocess.CalledProcessError as err:
            said = (err.stderr or "").strip().splitlines()
            raise GeokinError(f"cannot write {str(path)!r}: ffmpeg stopped with status "
                              f"{err.returncode}" + (f": {said[-1]}" if said else "")) from None
        if stopped:
            raise GeokinError(f"cannot write {str(path)!r}: ffmpeg stopped before the last "
                              "frame")


def plot_input_output(sweep, outputs, *, ax=None):
    """Plot quantities of a sweep against its input, in degrees for an angle.

    Parameters
    ----------
    sweep : Sweep
    outputs : mapping of str to array_like, or array_like
        Arrays of shape (N,), one per curve, by label; a single array is
        drawn unlabelled. Samples that cannot be assembled are left out.
    ax : matplotlib.axes.Axes, optional
        Where to draw; the current axes by default.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np
    >>> from geokin import Construction, sweep
    >>> c = Construction("crank")
    >>> c.input("theta", samples=37)
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta")
    >>> s = sweep(c)
    >>> fig, ax = plt.subplots()
    >>> ax = plot_input_output(s, {"x of A": s["A"][:, 0]}, ax=ax)
    >>> ax.get_xlabel(), len(ax.get_lines())
    ('theta (°)', 1)
    >>> plt.close(fig)
    """
    if ax is None:
        ax = _pyplot().gca()
    n = len(sweep)
    if sweep.inputs:
        name, x = next(iter(sweep.inputs.items()))
        if sweep.construction.inputs[name].kind == "angle":
            x, xlabel = np.degrees(x), f"{name} (°)"
        else:
            xlabel = name
    else:
        x, xlabel = np.arange(n), "sample"
    if not hasattr(outputs, "items"):
        outputs = {None: outputs}
    for label, values in outputs.items():
        y = np.asarray(values, dtype=float)
        if y.shape != (n,):
            raise GeokinError(f"output {label or ''!r} has shape {y.shape}; expected ({n},), "
                              "one value per sample")
        y = np.where(sweep.valid, y, np.nan)
        ax.plot(x, y, label=label)
    ax.set_xlabel(xlabel)
    ax.grid(True, color="#dddddd", lw=0.8)
    if any(label is not None for label in outputs):
        ax.legend(fontsize=9)
    return ax


def _robust_limits(values, reference):
    """Return y-limits that show the bulk of the values.

    The rates near a toggle grow without bound and would flatten the rest,
    so the limits hold the 1st to 99th percentile (all of it when that is
    most of the range). A quantity that only wobbles, by less than 1e-5 of
    ``reference`` (the size such a quantity has in this motion), is shown
    flat: that wobble is finite-difference noise about a constant.
    """
    if values.size == 0:
        return -1.0, 1.0
    low, high = np.percentile(values, [1, 99])
    full_low, full_high = values.min(), values.max()
    if (full_high - full_low) <= 3 * (high - low):
        low, high = full_low, full_high
    if high - low <= 1e-5 * reference:
        # a constant, with finite-difference noise around it
        middle = 0.5 * (low + high)
        middle = 0.0 if abs(middle) <= 1e-5 * reference else middle
        pad = 0.1 * max(abs(middle), reference)
        return middle - pad, middle + pad
    pad = 0.06 * (high - low)
    return low - pad, high + pad


def figure_kinematics(motion, *, links=None, title=None):
    """Plot link angles, angular velocities and accelerations against time.

    Three stacked axes, as seed 000 draws them: angle (degrees), angular
    velocity (rad/s) and angular acceleration (rad/s²) of each declared link
    against time (s). Samples flagged near a singular position are left out,
    and each axis shows the 1st to 99th percentile of its values where a few
    samples near a toggle would otherwise flatten the rest.

    Parameters
    ----------
    motion : Motion
        From :func:`geokin.kinematics.motion`.
    links : list of str, optional
        The links to draw; every declared link that moves by default.
    title : str, optional
        The figure's title; the construction's name by default.

    Returns
    -------
    fig : matplotlib.figure.Figure
    axes : array of 3 matplotlib.axes.Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> from geokin import Construction, sweep
    >>> from geokin.kinematics import motion
    >>> c = Construction("crank")
    >>> c.input("theta", samples=9)
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta")
    >>> c.link("crank", "O", "A")
    >>> fig, axes = figure_kinematics(motion(sweep(c)))
    >>> [ax.get_ylabel() for ax in axes]
    ['angle (°)', 'ω (rad/s)', 'α (rad/s²)']
    >>> plt.close(fig)
    """
    if links is None:
        # the ground does not move: leave it out
        names = [n for n, a in motion.angle.items()
                 if np.isfinite(a).any() and np.nanmax(a) - np.nanmin(a) > 0]
    else:
        names = list(links)
    unknown = [n for n in names if n not in motion.angle]
    if unknown:
        raise GeokinError(f"no declared link {unknown[0]!r}"
                          f"{did_you_mean(unknown[0], motion.angle)}")
    if not names and not motion.angle:
        raise GeokinError("the construction declares no links: nothing to plot "
                          "(declare links to see their angles, velocities and accelerations)")
    if not names:
        raise GeokinError("no declared link moves at an assembled sample: nothing to plot")
    fig, axes = _pyplot().subplots(3, 1, sharex=True, figsize=(8.0, 8.0), layout="constrained")
    keep = motion.sweep.valid & ~motion.flagged
    quantities = [(motion.angle, np.degrees, "angle (°)"),
                  (motion.angular_velocity, None, "ω (rad/s)"),
                  (motion.angular_acceleration, None, "α (rad/s²)")]
    # the size a rate of each kind has in this motion, for telling noise from motion
    rates = np.concatenate([np.abs(motion.angular_velocity[n][keep]) for n in names]
                           + [np.abs(motion.speed[keep])])
    omega = float(np.nanmax(rates, initial=0.0)) or 1.0
    for ax, (values, convert, label), reference in zip(axes, quantities,
                                                       (360.0, omega, omega**2), strict=True):
        shown = []
        for name in names:
            y = values[name] if convert is None else convert(values[name])
            y = np.where(keep, y, np.nan)
            ax.plot(motion.time, y, label=name)
            shown.append(y[np.isfinite(y)])
        ax.set_ylim(*_robust_limits(np.concatenate(shown), reference))
        ax.set_ylabel(label)
        ax.grid(True, color="#dddddd", lw=0.8)
    axes[0].legend(fontsize=9, ncols=min(len(names), 4))
    axes[-1].set_xlabel("time (s)")
    heading = motion.sweep.construction.name if title is None else title
    heading = shown_text(heading)
    if motion.flagged.any():
        heading += f" ({int(motion.flagged.sum())} samples near a singular position left out)"
    fig.suptitle(heading, parse_math=False)
    return fig, axes
