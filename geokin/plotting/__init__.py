"""Figures and animations of a sweep, drawn with matplotlib."""

from .animation import (
    ANIMATION_FORMATS,
    MAX_FPS,
    MAX_FRAMES,
    MIN_FPS,
    animate,
    animation_estimate,
)
from .mechanism import (
    FIGSIZE,
    GROUND_COLOR,
    INPUT_COLOR,
    LINK_COLORS,
    SAVE_FORMATS,
    TRACE_COLORS,
    figure_kinematics,
    figure_mechanism,
    plot_input_output,
    plot_mechanism,
    save,
)

__all__ = [
    "ANIMATION_FORMATS",
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
    "figure_kinematics",
    "figure_mechanism",
    "plot_input_output",
    "plot_mechanism",
    "save",
]
