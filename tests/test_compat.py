"""Names of earlier versions keep working, each with a DeprecationWarning naming the new one."""

import contextlib
import re
import warnings

import numpy as np
import pytest
from mechanisms import triple_rocker

import geokin
from geokin.analysis import fourbar_transmission_extremes, fourth_link_range, grashof, stroke
from geokin.circuits import circuit, limits
from geokin.engine import evaluate
from geokin.kinematics import input_derivatives, motion
from geokin.loops import fourbar_closed_form


@contextlib.contextmanager
def deprecated(match):
    """Expect a DeprecationWarning matching ``match``; the call's other ones are its too."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield
    messages = [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning)]
    assert any(re.search(match, m) for m in messages), (match, messages)


def test_old_keywords_give_the_same_results_as_the_new_ones():
    c = triple_rocker("crank")
    s = geokin.sweep(c, np.linspace(-1, 1, 9))
    with deprecated(r"motion\(input=\.\.\.\) is now motion\(input_name=\.\.\.\)"):
        old = motion(s, input="theta2")
    np.testing.assert_array_equal(old.velocity["C"], motion(s, "theta2").velocity["C"])
    with deprecated("input_derivatives"):
        assert input_derivatives(s, input="theta2").input_name == "theta2"
    with deprecated("search_range"):
        found = limits(c, input="theta2", range=(-3, 3))
    assert found.as_values() == limits(c, "theta2", search_range=(-3, 3)).as_values()
    with deprecated("start_branches"):
        right = geokin.sweep(c, np.linspace(-1, 1, 9), branches={"C": "right"})
    np.testing.assert_array_equal(right["C"], geokin.sweep(
        c, np.linspace(-1, 1, 9), start_branches={"C": "right"})["C"])
    with deprecated("start_branches"):
        assert circuit(c, input="theta2", branches=None).valid.any()
    with deprecated("held"):
        held = evaluate(c, {"theta2": np.zeros(3)}, 3, branches={"C": 1})
    assert (held.branches["C"] == 1).all()
    with deprecated("input_link"):
        assert grashof(7, 5, 6, 5).kind == grashof(ground=7, input=5, coupler=6, output=5).kind
    with deprecated("input_link"):
        assert fourbar_transmission_extremes(ground=7, input=4, coupler=5, output=5) == \
            fourbar_transmission_extremes(7, 4, 5, 5)
    with deprecated("input_link"):
        assert fourth_link_range(ground=7, input=5, coupler=6, kind="grashof") == \
            fourth_link_range(7, 5, 6, "grashof")
    t = np.linspace(0, 2 * np.pi, 361)
    with deprecated("input_values"):
        assert stroke(np.sin(t), input=t) == stroke(np.sin(t), t)


def test_old_attributes_read_the_new_ones():
    c = triple_rocker("crank")
    s = geokin.sweep(c, np.linspace(-1, 1, 5))
    with deprecated(r"Sweep\.input is now Sweep\.input_values"):
        np.testing.assert_array_equal(s.input, s.input_values)
    with deprecated("named_branches"):
        assert list(s.branch_names("C")) == list(s.named_branches("C"))
    m = motion(s)
    with deprecated("Motion.input is now Motion.input_name"):
        assert m.input == m.input_name == "theta2"
    with deprecated("Derivatives.input"):
        assert m.derivatives.input == "theta2"
    found = limits(c)
    with deprecated("Limits.input"):
        assert found.input == "theta2"
    with deprecated("held_branches"):
        assert found.branches == found.held_branches


def test_the_old_open_argument_of_the_closed_form_still_chooses_the_circuit():
    # before, the sixth argument was open=True; crossed is keyword-only, so an old
    # positional True still means the open circuit
    new_open = fourbar_closed_form(24, 10.55, 25, 14, 0.3)
    new_crossed = fourbar_closed_form(24, 10.55, 25, 14, 0.3, crossed=True)
    with deprecated("crossed=not open"):
        np.testing.assert_array_equal(fourbar_closed_form(24, 10.55, 25, 14, 0.3, True), new_open)
    with deprecated("crossed=not open"):
        np.testing.assert_array_equal(fourbar_closed_form(24, 10.55, 25, 14, 0.3, open=False),
                                      new_crossed)
    with deprecated("input_link"):
        np.testing.assert_array_equal(
            fourbar_closed_form(ground=24, input=10.55, coupler=25, output=14, theta2=0.3),
            new_open)


def test_a_keyword_given_by_both_names_is_refused():
    with pytest.raises(TypeError, match="both input= and input_name="):
        motion(geokin.sweep(triple_rocker("crank"), [0.0]), input="theta2",
               input_name="theta2")


def test_the_report_still_reads_as_the_dict_it_was():
    report = geokin.analyze(triple_rocker("crank"))
    with deprecated("report.to_dict"):
        assert report["inputs"] == report.to_dict()["inputs"]
