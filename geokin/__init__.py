"""geokin: kinematics of planar linkages from geometric constructions.

Declare a linkage as a :class:`Construction` (fixed pivots, a driven input,
and points found by intersecting lines, rays and circles), then
:func:`sweep` it over the input range to get every point's motion on the
right assembly branch.

>>> import geokin
>>> import numpy as np
>>> c = geokin.Construction("crank")
>>> c.input("theta")
>>> c.fixed("O", 0, 0)
>>> c.polar("A", "O", 10, "theta")
>>> geokin.sweep(c, [0.0, np.pi / 2])["A"].round(12)
array([[10.,  0.],
       [ 0., 10.]])
"""

from .analysis import Report, Tolerance, analyze
from .analysis.tolerance import tolerance
from .circuits import Limits, circuit, limits
from .construction import Compiled, Construction, Input, Link, Parameter, Slider
from .engine import sweep
from .errors import (
    AnalysisError,
    AssemblyError,
    BudgetError,
    ConstructionError,
    DegreesWarning,
    GeokinError,
    PairingWarning,
    RadiansWarning,
    ScriptError,
)
from .io import dump, load, loads
from .kinematics import Motion, motion
from .results import BranchEvent, Sweep

__all__ = [
    "AnalysisError",
    "AssemblyError",
    "BudgetError",
    "BranchEvent",
    "Compiled",
    "Construction",
    "ConstructionError",
    "DegreesWarning",
    "GeokinError",
    "Input",
    "Limits",
    "Link",
    "Motion",
    "PairingWarning",
    "Parameter",
    "RadiansWarning",
    "Report",
    "ScriptError",
    "Slider",
    "Sweep",
    "Tolerance",
    "analyze",
    "circuit",
    "dump",
    "limits",
    "load",
    "loads",
    "motion",
    "sweep",
    "tolerance",
]
__version__ = "0.1.0"
