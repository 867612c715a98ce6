"""HTML for notebooks: escaped tables and pictures of paths, drawn from arrays.

Results show themselves in Jupyter through ``_repr_html_``, built from the
pieces here: :func:`text` makes anything from a script safe to put in HTML,
:func:`table` lays rows out, :func:`svg_paths` draws point paths as SVG
polylines, each decimated to a few hundred points (:func:`decimate`), so a
picture of a million samples stays a few kilobytes and takes milliseconds.
Nothing here imports matplotlib or IPython, and nothing below the drawing
layer needs them.

Examples
--------
>>> print(table("Sweep of <b>", [("samples", "3"), ("input", "0 to 90 deg")]))
<table class="geokin">
<thead><tr><th colspan="2" style="text-align:left">Sweep of &lt;b&gt;</th></tr></thead>
<tbody>
<tr><th style="text-align:left">samples</th><td style="text-align:left">3</td></tr>
<tr><th style="text-align:left">input</th><td style="text-align:left">0 to 90 deg</td></tr>
</tbody>
</table>
"""

from __future__ import annotations

import html
import math
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from .terminal import escape, shorten

__all__ = [
    "MAX_LISTED",
    "PATH_COLORS",
    "POLYLINE_POINTS",
    "angle",
    "decimate",
    "legend",
    "names",
    "number",
    "side_by_side",
    "svg_paths",
    "table",
    "text",
]

POLYLINE_POINTS = 400
"""The most samples of one path drawn in a picture."""

MAX_LISTED = 12
"""The most names listed in one cell of a table; the rest are counted."""

PATH_COLORS = ("#d62976", "#1f9bd1", "#6a9a1f", "#f0a202", "#7b4fc9", "#333333")
"""Colours of the paths, in order (those of the traced paths in figures)."""

_MECHANISM_COLOR = "#9a9a9a"
_GROUND_COLOR = "#3b3b3b"


def text(value: object, limit: int = 200) -> str:
    r"""Return text from a script made safe to put in HTML.

    Control characters are written as escapes, long text is shortened
    (see :mod:`geokin.terminal`), and ``<``, ``>``, ``&`` and quotes become
    entities.

    Examples
    --------
    >>> text('<script>alert("x")</script>\x1b[2J')
    '&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt;\\x1b[2J'
    """
    return html.escape(escape(shorten(str(value), limit)), quote=True)


def number(value: float, unit: str = "") -> str:
    """Return a number with six significant digits, and its unit after a space.

    Examples
    --------
    >>> number(1800.0, "deg"), number(0.1 + 0.2), number(float("nan"), "mm")
    ('1800 deg', '0.3', 'nan mm')
    """
    return f"{value:.6g} {unit}" if unit else f"{value:.6g}"


def angle(radians: float, unit: str = "deg") -> str:
    """Return an angle given in radians as degrees: ``"90 deg"``, or ``"90 deg/s"``.

    Examples
    --------
    >>> angle(math.pi / 2), angle(2 * math.pi, "deg/s")
    ('90 deg', '360 deg/s')
    """
    return number(math.degrees(radians), unit)


def names(items: Iterable[str], limit: int = MAX_LISTED) -> str:
    """Return names as a comma-separated list, the ones over ``limit`` counted.

    The result is plain text (not escaped).

    Examples
    --------
    >>> names(["A", "B", "C"], 2)
    'A, B and 1 more'
    >>> names([])
    'none'
    """
    items = list(items)
    if not items:
        return "none"
    shown = ", ".join(shorten(str(item), 60) for item in items[:limit])
    return shown if len(items) <= limit else f"{shown} and {len(items) - limit:,} more"


def table(caption: str, rows: Sequence[tuple[str, str]]) -> str:
    """Return an HTML table of ``(heading, value)`` rows under a caption.

    Every text is escaped with :func:`text`, so any of them may come from a
    script.

    Parameters
    ----------
    caption : str
        The table's heading.
    rows : sequence of (str, str)
        Each row's heading and value, as plain text.

    Returns
    -------
    str
    """
    left = ' style="text-align:left"'
    lines = ['<table class="geokin">',
             f'<thead><tr><th colspan="2"{left}>{text(caption)}</th></tr></thead>', "<tbody>"]
    lines += [f"<tr><th{left}>{text(head)}</th><td{left}>{text(value, 400)}</td></tr>"
              for head, value in rows]
    lines += ["</tbody>", "</table>"]
    return "\n".join(lines)


def decimate(count: int, limit: int = POLYLINE_POINTS) -> np.ndarray:
    """Return at most ``limit`` sample indices evenly spread over ``count``, both ends kept.

    Examples
    --------
    >>> decimate(10, 4).tolist()
    [0, 3, 6, 9]
    >>> decimate(3).tolist()
    [0, 1, 2]
    """
    if count <= limit:
        return np.arange(count)
    return np.unique(np.linspace(0, count - 1, max(int(limit), 2)).round().astype(np.intp))


def svg_paths(paths: Mapping[str, tuple[np.ndarray, np.ndarray]], *,
              pose: Mapping[str, tuple[float, float]] | None = None,
              bars: Sequence[Sequence[str]] = (), ground: Iterable[str] = (),
              width: int = 320, height: int = 240) -> str:
    """Return an inline SVG picture of point paths, with one pose of the mechanism.

    Parameters
    ----------
    paths : mapping of str to (x, y)
        Each path's coordinates, arrays of shape (M,), already decimated
        (see :func:`decimate`); NaN breaks a path. Coloured with
        :data:`PATH_COLORS` in order, named by an SVG title.
    pose : mapping of str to (x, y), optional
        Where each point is at one sample, to draw ``bars`` and ``ground``.
    bars : sequence of sequence of str
        Links drawn in grey through their points at ``pose``.
    ground : iterable of str
        Points drawn as small dark squares at ``pose``.
    width, height : int
        The largest size of the picture in pixels; the drawing keeps x and
        y at one scale, y upwards.

    Returns
    -------
    str
        An ``<svg>`` element, or ``""`` where nothing finite is to be drawn.

    Examples
    --------
    >>> x = np.array([0.0, 1.0, np.nan, 2.0, 3.0])
    >>> svg = svg_paths({"P": (x, x)}, width=100, height=100)
    >>> svg.count("<polyline")  # two runs, broken at the NaN
    2
    >>> svg_paths({"P": (np.array([np.nan]), np.array([np.nan]))})
    ''
    """
    pose = dict(pose or {})
    xs = [np.asarray(x, dtype=float) for x, _ in paths.values()]
    ys = [np.asarray(y, dtype=float) for _, y in paths.values()]
    xs += [np.array([p[0]], dtype=float) for p in pose.values()]
    ys += [np.array([p[1]], dtype=float) for p in pose.values()]
    xs_all = np.concatenate(xs) if xs else np.zeros(0)
    ys_all = np.concatenate(ys) if ys else np.zeros(0)
    finite = np.isfinite(xs_all) & np.isfinite(ys_all)
    if not finite.any():
        return ""
    with np.errstate(over="ignore", invalid="ignore"):
        low = np.array([xs_all[finite].min(), ys_all[finite].min()])
        high = np.array([xs_all[finite].max(), ys_all[finite].max()])
        extent = high - low
        span = float(np.max(extent))
    if not math.isfinite(span):
        return ""
    margin = 8.0
    if span > 0:
        scale = min((width - 2 * margin) / extent[0] if extent[0] > 0 else math.inf,
                    (height - 2 * margin) / extent[1] if extent[1] > 0 else math.inf)
    else:
        scale = 1.0
    if not math.isfinite(scale):
        return ""
    size = np.maximum(np.round(extent * scale + 2 * margin), 2 * margin).astype(int)

    def to_pixels(x, y):
        with np.errstate(over="ignore", invalid="ignore"):
            return (margin + (np.asarray(x) - low[0]) * scale,
                    size[1] - margin - (np.asarray(y) - low[1]) * scale)

    def polyline(x, y, style):
        u, v = to_pixels(x, y)
        ok = np.isfinite(u) & np.isfinite(v)
        out = []
        # one polyline for each run of finite points
        edges = np.flatnonzero(np.diff(np.r_[0, ok.astype(np.int8), 0]))
        for start, stop in zip(edges[::2], edges[1::2], strict=True):
            coords = " ".join(f"{a:.1f},{b:.1f}" for a, b in zip(u[start:stop], v[start:stop],
                                                                  strict=True))
            out.append(f'<polyline points="{coords}" {style}/>')
        return out

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{size[0]}" height="{size[1]}" '
             f'viewBox="0 0 {size[0]} {size[1]}" role="img" '
             'style="background:#ffffff;border:1px solid #dddddd">']
    for points in bars:
        at = [pose[p] for p in points if p in pose]
        if len(at) >= 2:
            x, y = np.array(at, dtype=float).T
            if len(at) > 2:  # a plate: closed outline
                x, y = np.r_[x, x[0]], np.r_[y, y[0]]
            parts += polyline(x, y, f'fill="none" stroke="{_MECHANISM_COLOR}" '
                                    'stroke-width="2.5" stroke-linejoin="round"')
    for k, (name, (x, y)) in enumerate(paths.items()):
        color = PATH_COLORS[k % len(PATH_COLORS)]
        lines = polyline(x, y, f'fill="none" stroke="{color}" stroke-width="1.5" '
                               'stroke-linejoin="round"')
        if lines:
            parts.append(f"<g><title>path of {text(name)}</title>")
            parts += lines
            parts.append("</g>")
    for name in ground:
        if name in pose:
            u, v = to_pixels(*pose[name])
            if np.isfinite(u) and np.isfinite(v):
                parts.append(f'<rect x="{u - 3:.1f}" y="{v - 3:.1f}" width="6" height="6" '
                             f'fill="{_GROUND_COLOR}"><title>{text(name)}</title></rect>')
    parts.append("</svg>")
    return "\n".join(parts)


def legend(labels: Sequence[str], note: str = "") -> str:
    """Return a line naming the paths of :func:`svg_paths` in their colours, and a note.

    Examples
    --------
    >>> legend(["M"], "grey: <the mechanism>")
    '<div style="font-size:smaller"><span style="color:#d62976">&#x2501;</span> path of M \
&nbsp; grey: &lt;the mechanism&gt;</div>'
    """
    items = [f'<span style="color:{PATH_COLORS[k % len(PATH_COLORS)]}">&#x2501;</span> '
             f"path of {text(label, 60)}" for k, label in enumerate(labels)]
    if note:
        items.append(text(note))
    return f'<div style="font-size:smaller">{" &nbsp; ".join(items)}</div>'


def side_by_side(*blocks: str) -> str:
    """Return HTML blocks laid out in a row, wrapping on a narrow page."""
    inner = "\n".join(f"<div>{block}</div>" for block in blocks if block)
    return ('<div style="display:flex;flex-wrap:wrap;gap:1em;align-items:flex-start">\n'
            f"{inner}\n</div>")
