"""Pictures of a tolerance study: path envelopes and stroke histograms.

:func:`plot_envelope` draws a traced point's nominal path inside the band
its variants stay in, with a sample of the variants' paths, over the
nominal mechanism; :func:`plot_histogram` the distribution of a stroke;
:func:`figure_tolerance` both, side by side. matplotlib is imported inside
the functions.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..analysis.tolerance import Tolerance, envelope_outline
from ..errors import GeokinError, did_you_mean
from ..results import short_name
from .layout import length_unit, shown_text
from .mechanism import FIGSIZE, TRACE_COLORS, plot_mechanism

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["figure_tolerance", "plot_envelope", "plot_histogram", "spread_output"]

VARIANT_PATHS = 20
"""How many variants' paths :func:`plot_envelope` draws by default."""


def _point(result: Tolerance, point: str | None) -> str:
    names = list(result.paths)
    if point is None:
        if not names:
            raise GeokinError("the study has no point whose path it measured")
        return names[0]
    if point not in result.paths:
        raise GeokinError(f"the study measured no path of {point!r}"
                          f"{did_you_mean(point, names)} (points: {', '.join(names)})")
    return point


def plot_envelope(result: Tolerance, point: str | None = None, *, ax: Axes | None = None,
                  variants: int = VARIANT_PATHS, title: str | None = None) -> Axes:
    """Draw a point's nominal path, its envelope band and some variants' paths.

    The band holds, at every sample, the positions within the envelope's
    percentile of deviation from the nominal position
    (:func:`~geokin.analysis.tolerance.envelope_outline`); the nominal
    mechanism is drawn at its first assembled sample.

    Parameters
    ----------
    result : Tolerance
    point : str, optional
        The point; the first studied one by default.
    ax : matplotlib.axes.Axes, optional
    variants : int
        How many of the kept variants' paths to draw.
    title : str, optional
        The title; the construction's name and the share that assembles by default.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import geokin
    >>> from geokin.analysis.tolerance import tolerance
    >>> c = geokin.load(f"{geokin.__path__[0]}/../constructions/fourbar_open.toml")
    >>> t = tolerance(c, {"c": 0.3}, n=30)
    >>> fig, ax = plt.subplots()
    >>> ax = plot_envelope(t, ax=ax)
    >>> [text.get_text() for text in ax.get_legend().get_texts()][:2]
    ['nominal path of B', '95% envelope']
    >>> plt.close(fig)
    """
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path

    point = _point(result, point)
    if ax is None:
        import matplotlib.pyplot as plt

        ax = plt.gca()
    shown = (f"{int(result.assembled.sum()):,} of {result.variants:,} variants assemble "
             f"at every sample")
    if title is None:
        title = f"{result.construction.name}: {shown}"
    plot_mechanism(result.nominal, ax=ax, title=title, traces=[])
    spread = result.paths[point]
    band = envelope_outline(result, point)
    polygons = getattr(band, "geoms", [band])
    vertices, codes = [], []
    for polygon in polygons:
        if polygon.is_empty:
            continue
        for ring in (polygon.exterior, *polygon.interiors):
            xy = np.asarray(ring.coords)
            vertices.append(xy)
            codes.append([Path.MOVETO] + [Path.LINETO] * (len(xy) - 2) + [Path.CLOSEPOLY])
    color = TRACE_COLORS[0]
    if vertices:
        ax.add_patch(PathPatch(Path(np.concatenate(vertices), np.concatenate(codes)),
                               facecolor=color, alpha=0.18, edgecolor="none", zorder=0.5,
                               label=f"{spread.level:g}% envelope"))
    paths = np.asarray(result.sample_paths[point])[:max(variants, 0)]
    for i, path in enumerate(paths):
        ax.plot(path[:, 0], path[:, 1], color="#777777", lw=0.5, alpha=0.6, zorder=0.7,
                label=f"{len(paths)} of the variants" if i == 0 else None)
    nominal = np.asarray(result.nominal[point])
    ax.plot(nominal[:, 0], nominal[:, 1], color=color, lw=1.6, zorder=0.9,
            label=shown_text(f"nominal path of {point}"))
    # the order of the legend: the nominal path first
    handles, labels = ax.get_legend_handles_labels()
    order = sorted(range(len(labels)), key=lambda i: (not labels[i].startswith("nominal"),
                                                      "variants" in labels[i]))
    ax.legend([handles[i] for i in order], [labels[i] for i in order], fontsize=8,
              loc="best")
    ax.relim()
    ax.autoscale_view()
    return ax


def spread_output(result: Tolerance) -> str | None:
    """Return the stroke whose spread is the largest relative to its nominal value.

    Relative to the variants' mean instead where the nominal design has no
    stroke (it does not assemble at every sample).

    Strokes the same in every variant (a crank's full turn) come last;
    None for a study without strokes.

    Examples
    --------
    >>> import geokin
    >>> from geokin.analysis.tolerance import tolerance
    >>> c = geokin.load(f"{geokin.__path__[0]}/../constructions/fourbar_open.toml")
    >>> t = tolerance(c, {"c": 0.3}, n=30)
    >>> spread_output(t)
    'rocker.angle'
    """
    best, largest = None, -1.0
    for name, spread in result.strokes.items():
        # relative to the variants' mean where the nominal design has no stroke
        reference = spread.nominal if math.isfinite(spread.nominal) else spread.mean
        relative = spread.std / max(abs(reference), 1e-300)
        relative = relative if math.isfinite(relative) else -0.5
        if relative > largest:
            best, largest = name, relative
    return best


def plot_histogram(result: Tolerance, output: str | None = None, *, ax: Axes | None = None,
                   bins: int = 40, degrees: bool = True) -> Axes:
    """Draw the histogram of a stroke over the variants that assemble, with its nominal value.

    Parameters
    ----------
    result : Tolerance
    output : str, optional
        A key of ``result.strokes`` (``"rocker.angle"``); by default the
        one that spreads the most (:func:`spread_output`).
    ax : matplotlib.axes.Axes, optional
    bins : int
    degrees : bool
        Angles in degrees (radians otherwise).

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import geokin
    >>> from geokin.analysis.tolerance import tolerance
    >>> c = geokin.load(f"{geokin.__path__[0]}/../constructions/fourbar_open.toml")
    >>> t = tolerance(c, {"c": 0.3}, n=30)
    >>> fig, ax = plt.subplots()
    >>> ax = plot_histogram(t, "rocker.angle", ax=ax)
    >>> ax.get_xlabel()
    'stroke of rocker.angle (deg)'
    >>> plt.close(fig)
    """
    from matplotlib.ticker import MaxNLocator

    names = list(result.strokes)
    if output is None:
        output = spread_output(result)
        if output is None:
            raise GeokinError("the study has no stroke: declare links or sliders that move")
    if output not in result.strokes:
        raise GeokinError(f"no stroke {output!r}{did_you_mean(output, names)} "
                          f"(strokes: {', '.join(names) or 'none'})")
    if ax is None:
        import matplotlib.pyplot as plt

        ax = plt.gca()
    spread = result.strokes[output]
    if spread.kind == "angle":
        scale, unit = (math.degrees(1), "deg") if degrees else (1.0, "rad")
    else:
        scale, unit = 1.0, length_unit(result.nominal)
    values = spread.assembled * scale
    if values.size:
        lo, hi = float(values.min()), float(values.max())
        if not hi - lo > 1e-9 * max(1.0, abs(hi)):  # the same in every variant: one bar
            lo, hi = lo - 0.5, hi + 0.5
        ax.hist(values, bins=bins, range=(lo, hi), color=TRACE_COLORS[1], alpha=0.8)
    if math.isfinite(spread.nominal):  # none where the nominal fails at some sample
        ax.axvline(spread.nominal * scale, color="#222222", lw=1.2, ls="--",
                   label=f"nominal {spread.nominal * scale:.4g}")
    for q, style in ((5, ":"), (95, ":")):
        if values.size:
            ax.axvline(np.percentile(values, q), color="#555555", lw=1, ls=style,
                       label=f"{q}%: {np.percentile(values, q):.4g}" if q else None)
    ax.set_xlabel(shown_text(f"stroke of {output}" + (f" ({unit})" if unit else "")),
                  parse_math=False)
    ax.set_ylabel("variants")
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))  # counts: no "17.5 variants"
    ax.set_title(shown_text(f"{short_name(output)[1:-1]}: mean {spread.mean * scale:.4g}, "
                            f"std {spread.std * scale:.3g} over {values.size:,} variants"),
                 fontsize=10, parse_math=False)
    ax.legend(fontsize=8)
    ax.grid(True, color="#dddddd", lw=0.8)
    return ax


def figure_tolerance(result: Tolerance, point: str | None = None, output: str | None = None,
                     *, title: str | None = None) -> tuple[Figure, list[Axes]]:
    """Return a new figure: a point's envelope beside the histogram of a stroke.

    Without any stroke (no moving link or slider declared) the envelope alone.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import geokin
    >>> from geokin.analysis.tolerance import tolerance
    >>> c = geokin.load(f"{geokin.__path__[0]}/../constructions/fourbar_open.toml")
    >>> t = tolerance(c, {"c": 0.3}, n=30)
    >>> fig, axes = figure_tolerance(t)
    >>> len(axes)
    2
    """
    from matplotlib.figure import Figure

    has_histogram = bool(result.strokes)
    width = FIGSIZE[0] * (1.6 if has_histogram else 1)
    fig = Figure(figsize=(width, FIGSIZE[1]), layout="constrained")
    if has_histogram:
        axes = list(fig.subplots(1, 2, width_ratios=[1.25, 1]))
    else:
        axes = [fig.add_subplot()]
    plot_envelope(result, point, ax=axes[0], title=title)
    if has_histogram:
        plot_histogram(result, output, ax=axes[1])
    return fig, axes
