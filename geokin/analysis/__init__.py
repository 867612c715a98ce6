"""Engineering analysis of a linkage and of its motion.

- :mod:`~geokin.analysis.fourbar`: Grashof classification and transmission angles;
- :mod:`~geokin.analysis.mobility`: degrees of freedom;
- :mod:`~geokin.analysis.measures`: stroke, time ratio and coupler-curve measures;
- :mod:`~geokin.analysis.report`: all of these for one construction (:func:`analyze`,
  which returns a :class:`Report`);
- :mod:`~geokin.analysis.tolerance`: how the tolerances of parameters spread the
  motion (:func:`geokin.tolerance`, which returns a :class:`Tolerance`).

Angles are radians throughout, except in a report asked for in degrees
(``analyze(c, degrees=True)``), which says so in its ``angle_unit``.
"""

from ..kinematics import link_angles, slider_positions, unwrap_valid
from .fourbar import (
    KINDS,
    Grashof,
    TransmissionAngle,
    fourbar_transmission_extremes,
    fourth_link_range,
    grashof,
    transmission_angles,
)
from .measures import Curve, Stroke, curve_measures, refine_extreme, stroke, time_ratio
from .mobility import Crank, Mobility, cranks, degrees_of_freedom
from .report import (
    CurveReport,
    FourBarReport,
    InputReport,
    LimitReport,
    Report,
    StrokeReport,
    TransmissionReport,
    analyze,
)
from .tolerance import PathSpread, StrokeSpread, Tolerance

__all__ = [
    "KINDS",
    "Crank",
    "Curve",
    "CurveReport",
    "FourBarReport",
    "Grashof",
    "InputReport",
    "LimitReport",
    "Mobility",
    "PathSpread",
    "Report",
    "Stroke",
    "StrokeReport",
    "StrokeSpread",
    "Tolerance",
    "TransmissionAngle",
    "TransmissionReport",
    "analyze",
    "cranks",
    "curve_measures",
    "degrees_of_freedom",
    "fourbar_transmission_extremes",
    "fourth_link_range",
    "grashof",
    "link_angles",
    "refine_extreme",
    "slider_positions",
    "stroke",
    "time_ratio",
    "transmission_angles",
    "unwrap_valid",
]
