"""Degrees and radians at the edge: inside geokin every angle is radians.

Scripts and the command line give angles in degrees. These helpers convert
an input's values between the script's units (degrees for an angle input,
the length unit for a length input) and geokin's (radians or the length
unit); :mod:`geokin.io` and :mod:`geokin.cli` use them, nothing below them
does. :func:`script_degrees`, the shortest degree value of an angle, lives
in :mod:`geokin.expressions`, which shows angles in degrees too (a
construction's step list), and is given here as well.

Examples
--------
>>> import math
>>> from geokin.construction import Input
>>> theta = Input("theta")
>>> to_script(theta, math.pi / 2)
90.0
>>> bool(from_script(theta, [180.0])[0] == math.pi)
True
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .construction import Input
from .expressions import script_degrees

__all__ = ["angles_to_script", "from_script", "script_degrees", "to_script", "to_script_array"]


def to_script(inp: Input, value: float) -> float:
    """Return one value of an input in the script's units (degrees, shortest exact)."""
    return script_degrees(value) if inp.kind == "angle" else float(value)


def to_script_array(inp: Input, values: ArrayLike) -> np.ndarray:
    """Return an input's values in the script's units."""
    return np.degrees(values) if inp.kind == "angle" else np.asarray(values, dtype=float)


def angles_to_script(values: ArrayLike) -> np.ndarray:
    """Return angles, or angular rates, in the script's unit: radians to degrees.

    For what is an angle whatever the inputs are: link angles (deg), their
    angular velocities (deg/s) and accelerations (deg/s^2).

    Examples
    --------
    >>> angles_to_script([np.pi, -np.pi / 2]).tolist()
    [180.0, -90.0]
    """
    return np.degrees(np.asarray(values, dtype=float))


def from_script(inp: Input, values: ArrayLike) -> np.ndarray:
    """Return an input's values given in the script's units, in geokin's."""
    return np.radians(values) if inp.kind == "angle" else np.asarray(values, dtype=float)
