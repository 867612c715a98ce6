"""Charts of a motion: quantities against the input, link kinematics against time.

:func:`plot_input_output` plots any quantity of a sweep against its input;
:func:`figure_kinematics` the angle, angular velocity and angular acceleration
of each link against time. matplotlib is imported inside the functions.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..errors import GeokinError, did_you_mean
from ..kinematics import Motion
from ..results import Sweep
from .layout import broken_title, length_unit, shown_text

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["figure_kinematics", "plot_input_output", "wrap_degrees"]


def plot_input_output(sweep: Sweep, outputs: Mapping[str, ArrayLike] | ArrayLike, *,
                      ax: Axes | None = None, ylabel: str | None = None) -> Axes:
    """Plot quantities of a sweep against its input, in degrees for an angle.

    The x axis is labelled with the input's unit: "theta (deg)" for an
    angle, the construction's length unit for a length input; the y axis
    with ``ylabel``, or the label of the one curve there is.

    Parameters
    ----------
    sweep : Sweep
    outputs : mapping of str to array_like, or array_like
        Arrays of shape (N,), one per curve, by label; a single array is
        drawn unlabelled. Samples that cannot be assembled are left out.
    ax : matplotlib.axes.Axes, optional
        Where to draw; the current axes by default.
    ylabel : str, optional
        The y axis's label; by default the label of the one curve, if one
        labelled curve is drawn, and none otherwise.

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
    >>> ax.get_xlabel(), ax.get_ylabel(), len(ax.get_lines())
    ('theta (deg)', 'x of A', 1)
    >>> plt.close(fig)
    """
    if ax is None:
        import matplotlib.pyplot as plt

        ax = plt.gca()
    n = len(sweep)
    if sweep.inputs:
        name, x = next(iter(sweep.inputs.items()))
        unit = length_unit(sweep)
        if sweep.construction.inputs[name].kind == "angle":
            x, xlabel = np.degrees(x), f"{name} (deg)"
        else:
            xlabel = f"{name} ({unit})" if unit else name
    else:
        x, xlabel = np.arange(n), "sample"
    # anything with items() (a dict, a pandas DataFrame) holds labelled curves
    curves: dict[str | None, ArrayLike] = (dict(outputs.items()) if hasattr(outputs, "items")
                                           else {None: outputs})
    for label, values in curves.items():
        y = np.asarray(values, dtype=float)
        if y.shape != (n,):
            raise GeokinError(f"output {label or ''!r} has shape {y.shape}; expected ({n},), "
                              "one value per sample")
        y = np.where(sweep.valid, y, np.nan)
        ax.plot(x, y, label=label)
    ax.set_xlabel(shown_text(xlabel), parse_math=False)
    if ylabel is None and len(curves) == 1:
        ylabel = next(iter(curves))
    if ylabel is not None:
        ax.set_ylabel(shown_text(str(ylabel)), parse_math=False)
    ax.grid(True, color="#dddddd", lw=0.8)
    if any(label is not None for label in curves):
        ax.legend(fontsize=9)
    return ax


def _turns_fully(angle: np.ndarray) -> bool:
    """Whether a link's angle (radians, unwrapped) covers a whole turn in one run.

    A run is a stretch of samples that can be assembled: across a gap the
    unwrapped angle may take up a turn the link never makes.
    """
    finite = np.isfinite(angle)
    edges = np.flatnonzero(np.diff(finite)) + 1
    return any(run.size and float(np.ptp(run)) >= 2 * np.pi * (1 - 1e-9)
               for run, ok in zip(np.split(angle, edges), np.split(finite, edges), strict=True)
               if ok[0])


def wrap_degrees(x: ArrayLike, angle: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Wrap an unwrapped angle in degrees into (-180, 180], breaking the line at each wrap.

    Where the angle passes ±180 between two samples, the curve is drawn on
    to the edge and starts again from the other edge: a point on 180 and a
    point on -180 at the crossing, interpolated in ``x``, are put in with a
    NaN between them, which leaves a gap in a matplotlib line instead of a
    vertical jump across the axes. NaN samples stay NaN.

    Parameters
    ----------
    x : array_like, shape (N,)
        The abscissa: time or the input.
    angle : array_like, shape (N,)
        Degrees, continuous through full turns (as
        :func:`geokin.kinematics.unwrap_valid` gives, in radians).

    Returns
    -------
    x, wrapped : ndarray
        With three more points per wrap.

    Examples
    --------
    >>> x, y = wrap_degrees([0, 1, 2], [90, 270, 450])
    >>> x.tolist(), y.tolist()
    ([0.0, 0.5, 0.5, 0.5, 1.0, 2.0], [90.0, 180.0, nan, -180.0, -90.0, 90.0])
    """
    x = np.asarray(x, dtype=float)
    angle = np.asarray(angle, dtype=float)
    turns = np.ceil((angle - 180.0) / 360.0)  # the whole turns taken off each sample
    wrapped = angle - 360.0 * turns
    with np.errstate(invalid="ignore"):
        crossing = np.flatnonzero(np.isfinite(angle[:-1]) & np.isfinite(angle[1:])
                                  & (turns[:-1] != turns[1:]))
    if not crossing.size:
        return x, wrapped
    xs: list[np.ndarray] = []
    ys: list[np.ndarray] = []
    start = 0
    for i in crossing.tolist():
        a0, a1 = angle[i], angle[i + 1]
        edge = 180.0 + 360.0 * min(turns[i], turns[i + 1])  # the first edge passed
        at = x[i] + (edge - a0) / (a1 - a0) * (x[i + 1] - x[i])
        before, after = (180.0, -180.0) if a1 > a0 else (-180.0, 180.0)
        xs += [x[start:i + 1], np.array([at, at, at])]
        ys += [wrapped[start:i + 1], np.array([before, np.nan, after])]
        start = i + 1
    xs.append(x[start:])
    ys.append(wrapped[start:])
    return np.concatenate(xs), np.concatenate(ys)


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


def figure_kinematics(motion: Motion, *, links: Iterable[str] | None = None,
                      title: str | None = None) -> tuple[Figure, np.ndarray]:
    """Plot link angles, angular velocities and accelerations against time.

    Three stacked axes, as a course report draws them: angle (deg), angular
    velocity (deg/s) and angular acceleration (deg/s²) of each declared link
    against time (s), in the units of ``geokin trace --derivatives``. The
    angle of a link that turns fully over the sweep is wrapped into
    (-180, 180] (see :func:`wrap_degrees`), its legend says so, so that it
    does not run off to thousands of degrees and flatten the other links;
    the others are drawn as they run. The rates at flagged samples (they
    may be less accurate than stated, as near a toggle) are left out, and
    each axis shows the 1st to 99th percentile of its values where a few
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
    ['angle (deg)', 'ω (deg/s)', 'α (deg/s²)']
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
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8.0, 8.0), layout="constrained")
    keep = motion.sweep.valid & ~motion.flagged
    # degrees throughout, as geokin trace writes them
    quantities = [(motion.angle, "angle (deg)"),
                  (motion.angular_velocity, "ω (deg/s)"),
                  (motion.angular_acceleration, "α (deg/s²)")]
    # the size a rate of each kind has in this motion (radians), for telling noise from motion
    rates = np.concatenate([np.abs(motion.angular_velocity[n][keep]) for n in names]
                           + [np.abs(motion.speed[keep])])
    omega = float(np.nanmax(rates, initial=0.0)) or 1.0
    references = (360.0, np.degrees(omega), np.degrees(omega**2))
    # a link that turns fully runs on to thousands of degrees and would flatten the others
    turning = {name for name in names if _turns_fully(motion.angle[name])}
    for ax, (values, label), reference in zip(axes, quantities, references, strict=True):
        shown = []
        for name in names:
            # an angle is as accurate at a flagged sample as anywhere: only rates are left out
            shown_at = motion.sweep.valid if values is motion.angle else keep
            y = np.where(shown_at, np.degrees(values[name]), np.nan)
            if values is motion.angle and name in turning:
                x, y = wrap_degrees(motion.time, y)
                ax.plot(x, y, label=f"{name} (wrapped to ±180°)")
            else:
                ax.plot(motion.time, y, label=name)
            shown.append(y[np.isfinite(y)])
        ax.set_ylim(*_robust_limits(np.concatenate(shown), reference))
        if values is motion.angle and turning:
            from matplotlib.ticker import MaxNLocator

            # ticks on round angles: 90 or 180 apart over a turn
            ax.yaxis.set_major_locator(MaxNLocator(nbins=6, steps=[1, 1.5, 3, 4.5, 9, 10]))
        ax.set_ylabel(label)
        ax.grid(True, color="#dddddd", lw=0.8)
    # above the curves, not on them: a wrapped angle reaches both edges of its axes
    axes[0].legend(fontsize=9, ncols=min(len(names), 4), loc="lower left",
                   bbox_to_anchor=(0.0, 1.0), frameon=False, borderaxespad=0.2)
    axes[-1].set_xlabel("time (s)")
    heading = shown_text(motion.sweep.construction.name if title is None else title)
    if motion.flagged.any():
        count = int(motion.flagged.sum())
        # flagged: the rates there may be less accurate than stated
        heading += f" (rates not drawn at {count} flagged sample{'' if count == 1 else 's'})"
    # already shown as text: broken into lines, not escaped again
    fig.suptitle(broken_title(heading), parse_math=False)
    return fig, axes
