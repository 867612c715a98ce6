"""Figures and animations of a sweep, drawn with matplotlib.

Every function takes a :class:`~geokin.results.Sweep` (the positions are
computed by :func:`geokin.sweep`, never here) and draws on a given ``ax``
or the current one, returning what it drew, as shapely's plotting module and
networkx's ``draw`` do. matplotlib is imported inside the functions, so
``import geokin`` and ``import geokin.plotting`` stay fast.

- :mod:`~geokin.plotting.layout`: what a drawing shows (ground, joints,
  bars, the crank, sizes, the view), without matplotlib;
- :mod:`~geokin.plotting.mechanism`: the mechanism at one sample
  (:func:`plot_mechanism`, :func:`figure_mechanism`) and :func:`save`;
- :mod:`~geokin.plotting.animation`: :func:`animate` to a GIF, an HTML page
  or an MP4, :func:`animation_html` to play in a notebook, and
  :func:`animation_estimate`;
- :mod:`~geokin.plotting.charts`: :func:`plot_input_output` and
  :func:`figure_kinematics`;
- :mod:`~geokin.plotting.tolerance`: a tolerance study's path envelope
  (:func:`plot_envelope`), stroke histogram (:func:`plot_histogram`), and
  both (:func:`figure_tolerance`).
"""

from .animation import (
    ANIMATION_FORMATS,
    DEFAULT_DPI,
    DEFAULT_FRAMES,
    MAX_FPS,
    MAX_FRAMES,
    MIN_FPS,
    AnimationHTML,
    animate,
    animation_estimate,
    animation_html,
)
from .charts import figure_kinematics, plot_input_output
from .mechanism import (
    FIGSIZE,
    GROUND_COLOR,
    INPUT_COLOR,
    LINK_COLORS,
    SAVE_FORMATS,
    TRACE_COLORS,
    figure_mechanism,
    plot_mechanism,
    save,
)
from .tolerance import figure_tolerance, plot_envelope, plot_histogram, spread_output

__all__ = [
    "ANIMATION_FORMATS",
    "DEFAULT_DPI",
    "DEFAULT_FRAMES",
    "AnimationHTML",
    "FIGSIZE",
    "GROUND_COLOR",
    "INPUT_COLOR",
    "LINK_COLORS",
    "MAX_FPS",
    "MAX_FRAMES",
    "MIN_FPS",
    "SAVE_FORMATS",
    "TRACE_COLORS",
    "animate",
    "animation_estimate",
    "animation_html",
    "figure_kinematics",
    "figure_mechanism",
    "figure_tolerance",
    "plot_envelope",
    "plot_histogram",
    "plot_input_output",
    "plot_mechanism",
    "save",
    "spread_output",
]
