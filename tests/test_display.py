"""Results as a notebook shows them: short reprs, HTML tables and SVG pictures."""

import re

import numpy as np
import pytest
from mechanisms import sixbar

import geokin
from geokin import Construction
from geokin.kinematics import input_derivatives

LONG = "x" * 5000  # a name no repr should print whole


def long_named_sixbar():
    """Seed 003's six-bar under a very long name, its input renamed to a long one too."""
    c = sixbar()
    c.name = LONG
    return c


@pytest.fixture(scope="module")
def large():
    """A sweep of 200,000 samples, its motion, limits and report."""
    c = long_named_sixbar()
    s = geokin.sweep(c, np.linspace(0, 10 * np.pi, 200_000))
    return {"sweep": s, "motion": geokin.motion(s), "derivatives": input_derivatives(s),
            "limits": geokin.limits(c), "report": geokin.analyze(c)}


def test_reprs_stay_short_for_a_large_sweep(large):
    report = large["report"]
    shown = {name: repr(value) for name, value in large.items()}
    shown |= {f"{name}.{key}": repr(entry) for name in ("inputs", "transmission_angles",
                                                         "strokes", "curves")
              for key, entry in getattr(report, name).items()}
    shown |= {f"four_bars[{i}]": repr(bar) for i, bar in enumerate(report.four_bars)}
    for name, text in shown.items():
        assert len(text) < 200, (name, text)
        assert "\n" not in text, name
    assert shown["motion"] == (f"<Motion of {display_name()} driven by 'theta': 200000 "
                               f"samples, {int(large['motion'].flagged.sum())} flagged>")
    assert shown["sweep"].startswith(f"<Sweep of {display_name()}: 200000 samples, ")
    assert shown["limits"] == "<Limits of 'theta': turns fully>"
    assert shown["report"].startswith(f"<Report of {display_name()}: DOF 1, 1 input(s), "
                                      "four-bars: crank-rocker, ")


def display_name():
    return repr(f"{'x' * 26}…{'x' * 13} [5,000 characters]")


def test_a_repr_says_what_a_result_holds():
    c = sixbar()
    s = geokin.sweep(c)
    m = geokin.motion(s)
    assert repr(m) == f"<Motion of 'six-bar' driven by 'theta': 113 samples, " \
                      f"{int(m.flagged.sum())} flagged>"
    assert repr(m.derivatives) == ("<Derivatives by 'theta': 113 samples, step "
                                   f"{m.derivatives.step:.3g}, 0 without a stencil>")
    rocker = Construction("triple rocker")
    rocker.input("theta2", range=(-np.pi, np.pi))
    rocker.fixed("A", 0, 0)
    rocker.fixed("D", 7, 0)
    rocker.polar("B", "A", 5, "theta2")
    rocker.circle_circle("C", ("B", "D"), (6, 5), branch="left")
    assert repr(geokin.limits(rocker)) == ("<Limits of 'theta2': -2.30693 to 2.30693 "
                                           "(tangent at 'C', tangent at 'C')>")
    report = geokin.analyze(rocker, degrees=True)
    assert repr(report.inputs["theta2"]) == ("<InputReport (angle): 1 interval(s) from "
                                             "-132.177 to 132.177, 2 limit(s)>")
    assert repr(report.inputs["theta2"].limits[0]) == "<LimitReport: tangent at -132.177, " \
                                                      "node 'C'>"
    assert re.fullmatch(r"<FourBarReport at 'C': triple-rocker RRR1 \(RRR1\); ground 7, "
                        r"input 5, coupler 6, output 5>", repr(report.four_bars[0]))
