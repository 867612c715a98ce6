"""The geokin command line, end to end."""

import csv
import io
import json
import pathlib
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from mechanisms import fourbar_closed_form, slider_crank_closed_form
from PIL import Image

import geokin
from geokin.cli import COMMANDS, build_parser, main

CONSTRUCTIONS = pathlib.Path(__file__).resolve().parent.parent / "constructions"
SIXBAR = str(CONSTRUCTIONS / "sixbar.toml")
CRANK = str(CONSTRUCTIONS / "triple_rocker_crank.toml")


def run(capsys, *argv):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return status, out, err


def read_csv(text):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], np.array(rows[1:], dtype=float)


# -- check -------------------------------------------------------------------------


def test_check_prints_steps_inputs_and_degrees_of_freedom(capsys):
    status, out, err = run(capsys, "check", SIXBAR)
    assert status == 0 and err == ""
    assert "construction 'six-bar': 9 steps" in out
    assert "B   = circle_circle(A, l3; B0, l4)  [left]" in out
    assert "theta (angle): 0 to 1800 deg, step 16 deg (113 samples), 360 deg/s" in out
    assert "degrees of freedom: DOF = 3(5) - 2(7) - 0 = 1; 1 input" in out
    assert "sweep: 113 samples, all assembled; 0 branch changes" in out


def test_check_every_shipped_construction(capsys):
    scripts = sorted(CONSTRUCTIONS.glob("*.toml"))
    status, out, _ = run(capsys, "check", *scripts)
    assert status == 0
    assert out.count("all assembled") == len(scripts)


def test_check_reports_samples_that_cannot_be_assembled(capsys, tmp_path):
    script = tmp_path / "wide.toml"
    script.write_text(pathlib.Path(CRANK).read_text().replace("range = [-132, 132]",
                                                              "range = [-140, 140]"))
    status, out, _ = run(capsys, "check", script)
    assert status == 0
    assert "sweep: 281 samples, 265 assembled, 16 cannot be: first at theta2 = -140 deg: " \
           "node 'C': no intersection" in out


def test_check_a_bad_script_exits_2_with_the_place_of_the_error(capsys, tmp_path):
    script = tmp_path / "sixbar.toml"
    script.write_text(pathlib.Path(SIXBAR).read_text().replace('"l3", "l4"', '"l3", "l33"'))
    status, out, err = run(capsys, "check", script, SIXBAR)
    assert status == 2
    assert err.startswith(f"geokin: error: {script}:")
    assert "[points] B.radii[1]: unknown parameter or input 'l33'; did you mean 'l3'?" in err
    assert "construction 'six-bar'" in out  # the good script is still checked


NEVER = """\
[construction]
name = "too short"
trace = ["B"]
[inputs.theta]
range = [0, 360]
[points]
O2 = { op = "fixed", at = [0, 0] }
O4 = { op = "fixed", at = [40, 0] }
A = { op = "polar", origin = "O2", distance = 10, angle = "theta" }
B = { op = "circle_circle", centers = ["A", "O4"], radii = [5, 5], branch = "left" }
[links]
frame = ["O2", "O4"]
crank = ["O2", "A"]
coupler = ["A", "B"]
rocker = ["O4", "B"]
"""
"""A four-bar whose coupler and rocker (5 and 5) cannot reach across: nothing assembles."""

NEVER_ERROR = ("no sample can be assembled: node 'B' fails at all 361 samples: no intersection: "
               "the curves do not meet")


@pytest.fixture
def never(tmp_path):
    path = tmp_path / "never.toml"
    path.write_text(NEVER)
    return path


def one_error_line(err, script, samples=361, written=None):
    """The one line of standard error where no sample can be assembled: the node, and why.

    ``written`` is the file written anyway, and what it holds, which the line names.
    """
    message = NEVER_ERROR.replace("361", str(samples))
    tail = "" if written is None else f"; wrote {written[0]} with {written[1]}"
    assert err == f"geokin: error: {script}: {message}{tail}\n"
    return True


@pytest.mark.parametrize("argv, output, message", [
    (["plot", "--kinematics", "-o"], "out.png", NEVER_ERROR),
    (["plot", "--circuit", "-o"], "out.png", "the construction cannot be assembled anywhere "
                                             "over a whole turn of input 'theta': node 'B': no "
                                             "intersection: the curves do not meet"),
    (["trace", "--circuit", "-o"], "out.csv", "the construction cannot be assembled anywhere "
                                              "over a whole turn of input 'theta': node 'B': "
                                              "no intersection: the curves do not meet"),
    (["analyze"], None, "the construction cannot be assembled anywhere over a whole turn of "
                        "input 'theta': node 'B': no intersection: the curves do not meet"),
])
def test_a_construction_that_never_assembles_with_nothing_known_to_show_writes_nothing(
        capsys, tmp_path, never, argv, output, message):
    # link angles against time, or a circuit that has nowhere to start: nothing is known
    args = [argv[0], never, *argv[1:]]
    if output is not None:
        (tmp_path / output).write_text("the old file")
        args.append(tmp_path / output)
    status, out, err = run(capsys, *args)
    assert (status, out, err) == (1, "", f"geokin: error: {never}: {message}\n")
    if output is not None:
        assert (tmp_path / output).read_text() == "the old file"


PIVOT = 40 + 1 / 3  # O4.x: read back exactly, not only to a few digits


@pytest.mark.parametrize("suffix", [None, ".csv", ".json", ".npz"])
def test_trace_of_a_construction_that_never_assembles_writes_the_ground_pivots(
        capsys, tmp_path, never, suffix):
    never.write_text(NEVER.replace("at = [40, 0]", 'at = ["40 + 1/3", -0.1]'))
    args = ["trace", never, "--derivatives", "--samples", 7]
    out_path = None if suffix is None else tmp_path / f"old{suffix}"
    if out_path is not None:
        out_path.write_text("the old file")
        args += ["-o", out_path]
    status, out, err = run(capsys, *args)
    # one line, which names the file written anyway
    written = None if out_path is None else (out_path, "the ground points' columns")
    assert status == 1 and one_error_line(err, never, 7, written)
    if suffix is None:
        header, data = read_csv(out)
        table = dict(zip(header, data.T, strict=True))
    elif suffix == ".csv":
        header, data = read_csv(out_path.read_text())
        table = dict(zip(header, data.T, strict=True))
    elif suffix == ".json":
        table = {k: np.array([np.nan if v is None else v for v in values], dtype=float)
                 for k, values in json.loads(out_path.read_text()).items()}
    else:
        with np.load(out_path) as archive:
            table = {k: archive[k] for k in archive}
    assert out == "" or suffix is None
    np.testing.assert_array_equal(table["theta"], [0, 60, 120, 180, 240, 300, 360])
    assert (table["valid"] == 0).all()
    # the ground pivots where the script puts them, at rest
    assert (table["O2.x"] == 0).all() and (table["O2.y"] == 0).all()
    assert (table["O4.x"] == PIVOT).all() and (table["O4.y"] == -0.1).all()
    assert (table["O4.vx"] == 0).all() and (table["O4.ay"] == 0).all()
    # the points that move are not known: the mechanism is not assembled
    for name in ("A.x", "A.vy", "B.x", "B.y"):
        assert np.isnan(table[name]).all(), name


@pytest.mark.parametrize("argv", [[], ["--at", 90], ["--title", "short"]])
def test_plot_of_a_construction_that_never_assembles_draws_the_ground_pivots(
        capsys, tmp_path, never, argv):
    out = tmp_path / "old.png"
    out.write_text("the old file")
    status, stdout, err = run(capsys, "plot", never, "-o", out, *argv)
    assert status == 1 and stdout == ""
    assert one_error_line(err, never, written=(out, "the ground pivots"))
    # where the pivots are in the picture: the same drawing, from Python
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    import geokin.plotting as gp

    matplotlib.use("Agg")
    fig = Figure(figsize=gp.FIGSIZE, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    s = geokin.sweep(geokin.load(never))
    gp.plot_mechanism(s, 90 if argv[:1] == ["--at"] else None, ax=ax, title=argv[-1]
                      if argv[:1] == ["--title"] else None)
    fig.draw_without_rendering()
    with Image.open(out) as image:
        assert image.size == (800, 600)
        pixels = np.asarray(image.convert("RGB"), dtype=int)
    for pivot in ((0, 0), (40, 0)):
        x, y = ax.transData.transform(pivot)
        row, column = int(round(600 - y)), int(round(x))
        near = pixels[row - 12:row + 12, column - 12:column + 12]
        assert (near.min(axis=-1) < 120).sum() > 20, pivot  # the pivot's ring and triangle
    assert (pixels.min(axis=-1) < 120).mean() < 0.05  # a drawing, not a dark page


def test_animate_of_a_construction_that_never_assembles_shows_the_pivots(capsys, tmp_path,
                                                                         never):
    out = tmp_path / "never.gif"
    status, stdout, err = run(capsys, "animate", never, "-o", out, "--frames", 3, "--dpi", 25,
                              "--no-progress")
    assert status == 1 and stdout == ""
    assert one_error_line(err, never, written=(out, "the ground pivots"))
    with Image.open(out) as gif:
        assert gif.n_frames == 3


def test_check_of_a_construction_that_never_assembles_exits_1(capsys, tmp_path, never):
    status, out, err = run(capsys, "check", never, SIXBAR)
    assert status == 1
    assert err == f"geokin: error: {never}: {NEVER_ERROR}\n"
    assert ("sweep: 361 samples, 0 assembled, 361 cannot be: first at theta = 0 deg: node 'B': "
            "no intersection: the curves do not meet; 0 branch changes") in out
    assert "construction 'six-bar'" in out  # the next script is still checked
    # a script that cannot be read weighs more: the status says the worse
    bad = tmp_path / "bad.toml"
    bad.write_text('[points]\nA = { op = "fixd", at = [0, 0] }\n')
    status, _, err = run(capsys, "check", never, bad)
    assert status == 2 and err.count("geokin: error: ") == 2


def test_a_construction_that_assembles_somewhere_is_not_an_error(capsys, never):
    # with the rocker's pivot 15 from the crank's, the crank pin comes within reach (10)
    # of it for part of the turn: today's NaN where it does not
    script = never.with_name("some.toml")
    script.write_text(NEVER.replace("at = [40, 0]", "at = [15, 0]"))
    status, out, err = run(capsys, "trace", script, "--points", "B,O4")
    assert status == 0 and err == ""
    header, data = read_csv(out)
    assert header == ["theta", "valid", "B.x", "B.y", "O4.x", "O4.y"]
    valid = data[:, 1] == 1
    assert 0 < valid.sum() < len(valid)
    assert np.isnan(data[~valid, 2:4]).all() and np.isfinite(data[valid, 2:4]).all()
    assert (data[:, 4] == 15).all() and (data[:, 5] == 0).all()  # the pivot, at every sample


# -- trace -------------------------------------------------------------------------


def test_trace_writes_csv_to_standard_output(capsys):
    status, out, err = run(capsys, "trace", SIXBAR)
    assert status == 0 and err == ""
    header, data = read_csv(out)
    points = ["D", "mid", "A0", "B0", "A", "B", "Ap", "C", "M"]
    assert header == ["theta", "valid"] + [f"{p}.{xy}" for p in points for xy in "xy"]
    assert data.shape == (113, 2 + 18)
    np.testing.assert_array_equal(data[:, 0], np.arange(0, 1800, 16))
    assert (data[:, 1] == 1).all()
    s = geokin.sweep(geokin.load(SIXBAR))
    np.testing.assert_allclose(data[:, -2:], s["M"], rtol=1e-15)


def test_trace_options_select_points_and_samples(capsys):
    status, out, _ = run(capsys, "trace", SIXBAR, "--points", "M, B", "--samples", 5,
                         "--range", 0, 360)
    assert status == 0
    header, data = read_csv(out)
    assert header == ["theta", "valid", "M.x", "M.y", "B.x", "B.y"]
    np.testing.assert_array_equal(data[:, 0], [0, 90, 180, 270, 360])
    status, out, _ = run(capsys, "trace", SIXBAR, "--points", "M", "--step", 7.5,
                         "--range", 30, 0)
    header, data = read_csv(out)
    np.testing.assert_array_equal(data[:, 0], [30, 22.5, 15, 7.5, 0])


def test_trace_marks_samples_that_cannot_be_assembled(capsys, tmp_path):
    status, out, _ = run(capsys, "trace", CRANK, "--range", 130, 134, "--step", 1,
                         "--points", "C")
    assert status == 0
    header, data = read_csv(out)
    np.testing.assert_array_equal(data[:, 1], [1, 1, 1, 0, 0])
    assert np.isnan(data[3:, 2:]).all() and np.isfinite(data[:3, 2:]).all()
    path = tmp_path / "crank.json"
    assert main(["trace", CRANK, "--range", "130", "134", "--step", "1", "--points", "C",
                 "-o", str(path)]) == 0
    data = json.loads(path.read_text())
    assert list(data) == ["theta2", "valid", "C.x", "C.y"]
    assert data["valid"] == [True, True, True, False, False]
    assert data["C.x"][3] is None and isinstance(data["C.x"][0], float)


def test_trace_one_sample_prints_one_configuration(capsys):
    status, out, err = run(capsys, "trace", SIXBAR, "--samples", 1, "--range", 40, 100,
                           "--points", "M", "--derivatives")
    assert status == 0 and err == ""
    header, one = read_csv(out)
    assert one.shape == (1, len(header)) and one[0, 0] == 40 and one[0, 1] == 1
    # the derivatives do not depend on the spacing: the same row as in a longer trace
    status, out, _ = run(capsys, "trace", SIXBAR, "--range", 40, 100, "--samples", 7,
                         "--points", "M", "--derivatives")
    np.testing.assert_allclose(one[0], read_csv(out)[1][0], rtol=1e-12)
    assert np.isfinite(one).all()
    # a range of one value, when one sample is asked for
    status, out, _ = run(capsys, "trace", SIXBAR, "--samples", 1, "--range", 40, 40, "--points",
                         "M")
    assert status == 0 and read_csv(out)[1].tolist() == [one[0, [0, 1, 4, 5]].tolist()]


def test_trace_json_and_npz_carry_the_csv_fields(capsys, tmp_path):
    status, out, _ = run(capsys, "trace", SIXBAR, "--derivatives")
    header, table = read_csv(out)
    assert status == 0
    for suffix in (".json", ".npz", ".csv"):
        path = tmp_path / f"six{suffix}"
        status, out, err = run(capsys, "trace", SIXBAR, "--derivatives", "-o", path)
        assert status == 0 and out == "" and "wrote" in err
        if suffix == ".json":
            data = json.loads(path.read_text())
        elif suffix == ".npz":
            data = dict(np.load(path))
            assert data["valid"].dtype == bool
        else:
            names, rows = read_csv(path.read_text())
            data = dict(zip(names, rows.T, strict=True))
        assert list(data) == header
        for i, name in enumerate(header):
            np.testing.assert_allclose(np.asarray(data[name], dtype=float), table[:, i],
                                       rtol=1e-15)


def test_trace_derivatives_are_per_second_at_the_declared_speed(capsys):
    status, out, _ = run(capsys, "trace", SIXBAR, "--derivatives", "--points", "A")
    assert status == 0
    header, data = read_csv(out)
    assert header == ["theta", "valid", "time", "flagged", "A.x", "A.y", "A.vx", "A.vy", "A.ax",
                      "A.ay"]
    # one turn per second: time in seconds is the crank angle over 360 degrees
    np.testing.assert_allclose(data[:, 2], data[:, 0] / 360)
    assert (data[:, 3] == 0).all()
    # the crank tip: radius 20 at one turn per second
    np.testing.assert_allclose(np.hypot(data[:, 6], data[:, 7]), 20 * 2 * np.pi, rtol=1e-6)
    np.testing.assert_allclose(np.hypot(data[:, 8], data[:, 9]), 20 * (2 * np.pi) ** 2,
                               rtol=1e-5)


def test_trace_link_angles_and_rates_in_degrees(capsys):
    """Seed 004's open four-bar at one turn a second, against the closed form."""
    status, out, _ = run(capsys, "trace", CONSTRUCTIONS / "fourbar_open.toml", "--points", "B",
                         "--links", "coupler,rocker", "--derivatives")
    assert status == 0
    header, data = read_csv(out)
    assert header[-6:] == ["coupler.angle", "coupler.omega", "coupler.alpha", "rocker.angle",
                           "rocker.omega", "rocker.alpha"]
    table = dict(zip(header, data.T, strict=True))
    theta2 = np.radians(table["theta2"])
    t3, t4, w3, w4, a3, a4 = fourbar_closed_form(theta2, 10.55, 25, 14, 24, 2 * np.pi)
    ok = table["flagged"] == 0
    assert ok.all()
    fastest = np.degrees(np.max(np.abs([2 * np.pi + 0 * t3, w3, w4]), axis=0))
    largest = np.fmax(np.degrees(np.max(np.abs([a3, a4]), axis=0)),
                      np.degrees(np.radians(fastest) ** 2))
    for link, angle, omega, alpha in (("coupler", t3, w3, a3), ("rocker", t4, w4, a4)):
        gap = np.angle(np.exp(1j * (np.radians(table[f"{link}.angle"]) - angle)))
        assert np.degrees(np.abs(gap)).max() <= 1e-9, link
        assert (np.abs(table[f"{link}.omega"] - np.degrees(omega)) <= 1e-7 * fastest).all()
        assert (np.abs(table[f"{link}.alpha"] - np.degrees(alpha)) <= 1e-5 * largest).all()


def test_trace_slider_positions_along_the_guide(capsys):
    """The offset slider-crank's block (crank 20, rod 70, offset 10) in mm, mm/s, mm/s^2."""
    status, out, _ = run(capsys, "trace", CONSTRUCTIONS / "slider_crank_offset.toml",
                         "--sliders", "slider", "--links", "crank", "--points", "B",
                         "--derivatives", "--samples", 73)
    assert status == 0
    header, data = read_csv(out)
    table = dict(zip(header, data.T, strict=True))
    assert header[-4:] == ["crank.alpha", "slider.position", "slider.velocity",
                           "slider.acceleration"]
    x, v, a = slider_crank_closed_form(np.radians(table["theta"]), 20, 70, 10, 2 * np.pi)
    np.testing.assert_allclose(table["slider.position"], x, rtol=0, atol=1e-12 * 70)
    np.testing.assert_array_equal(table["slider.position"], table["B.x"])  # guide from x = 0
    fastest = np.fmax(20 * 2 * np.pi, np.abs(v))
    largest = np.fmax(20 * (2 * np.pi) ** 2, np.abs(a))
    assert (np.abs(table["slider.velocity"] - v) <= 1e-7 * fastest).all()
    assert (np.abs(table["slider.acceleration"] - a) <= 1e-5 * largest).all()
    np.testing.assert_allclose(table["crank.angle"], table["theta"], rtol=1e-15)
    np.testing.assert_allclose(table["crank.omega"], 360, rtol=1e-9)


def test_a_slider_off_its_guide_is_refused_by_check_and_warned_of_elsewhere(capsys, tmp_path):
    """The quick return's ram B runs on the horizontal line C-G; C-O1 is vertical."""
    text = (CONSTRUCTIONS / "quick_return.toml").read_text()
    wrong = text.replace('ram = { point = "B", along = ["C", "G"] }',
                         'ram = { point = "B", along = ["C", "O1"] }')
    assert wrong != text
    script = tmp_path / "quick_return.toml"
    script.write_text(wrong)
    s = geokin.sweep(geokin.load(script))
    x = s["B"][:, 0] - s["C"][:, 0]  # the distance from the vertical line through C and O1
    i = int(np.argmax(np.abs(x)))
    where = f"theta2 = {round(float(np.degrees(s.inputs['theta2'][i])), 9):g} deg"
    off = (f"its point 'B' is {abs(x[i]):.4g} mm off its guide, the line through 'C' and "
           f"'O1' (farthest at {where}); a slider's point must lie on the line of its guide")
    status, out, err = run(capsys, "check", script)
    assert status == 2 and "sweep: 361 samples, all assembled" in out
    assert err == f"geokin: error: {script}: slider 'ram', field 'point': {off}\n"
    status, _, err = run(capsys, "plot", script, "-o", tmp_path / "x.png")
    assert status == 0 and err.startswith(f"geokin: warning: slider 'ram': {off}\n")
    status, out, _ = run(capsys, "analyze", script)  # over its circuit, sampled its own way
    assert status == 0 and (f"\nwarning: slider 'ram': its point 'B' is {abs(x[i]):.4g} mm "
                            "off its guide, the line through 'C' and 'O1' (farthest at ") in out
    status, _, err = run(capsys, "check", CONSTRUCTIONS / "quick_return.toml")
    assert (status, err) == (0, "")


@pytest.mark.parametrize("argv, message", [
    (["--points", "ram"], "--points: 'ram' is a slider, not a point; use --sliders ram"),
    (["--points", "B,lever"], "--points: 'lever' is a link, not a point; use --links lever"),
    (["--links", "B"], "--links: 'B' is a point, not a link; use --points B"),
    (["--sliders", "lever"], "--sliders: 'lever' is a link, not a slider; use --links lever"),
    (["--links", "lver"], "--links: no link 'lver'; did you mean 'lever'? (links: ground, "
                          "crank, lever)"),
    (["--sliders", ","], "--sliders names no slider"),
])
def test_trace_says_which_option_takes_a_name(capsys, argv, message):
    status, out, err = run(capsys, "trace", CONSTRUCTIONS / "quick_return.toml", *argv)
    assert status == 2 and out == ""
    assert message in err, err


@pytest.mark.parametrize("argv, message", [
    (["trace", "missing.toml"], "geokin: error: cannot open 'missing.toml': No such file"),
    (["trace", SIXBAR, "-o", "out.txt"], "cannot write a trace to 'out.txt': use a .csv, "
                                         ".json or .npz file"),
    (["trace", SIXBAR, "--points", "MM"], "--points: no point 'MM'; did you mean 'M'?"),
    (["trace", SIXBAR, "--points", ","], "--points names no point"),
    (["trace", SIXBAR, "--points", "C,,B"], "has an empty name between commas"),
    (["trace", SIXBAR, "--samples", "x"], "argument --samples: expected an integer"),
    (["trace", SIXBAR, "--samples", "0"], "argument --samples: expected at least 1, got 0"),
    (["trace", SIXBAR, "--range", "40", "40"], "--range 40 40: the two ends are equal, "
                                               "nothing to sweep (--samples 1 gives that one"),
    (["trace", CRANK, "--circuit", "--samples", "1"], "--circuit --samples counts the samples "
                                                      "of each pass between two limits: at "
                                                      "least 2"),
    (["plot", SIXBAR, "--kinematics", "--samples", "1"], "--kinematics plots against time: it "
                                                         "needs at least 2 samples"),
    (["animate", SIXBAR, "-o", "out.gif", "--frames", "1"], "--frames: expected at least 2"),
    (["trace", SIXBAR, "--samples", "5", "--step", "1"], "not allowed with argument"),
    (["trace", SIXBAR, "--range", "0"], "argument --range: expected 2 arguments"),
    (["trace", SIXBAR, "--range", "0", "nan"], "expected a finite number"),
    (["trace", SIXBAR, "--step", "0"], "argument --step: expected a positive number (the "
                                       "range gives the direction), got '0'"),
    (["trace", SIXBAR, "--step", "1e-6"], "samples; at most 1000000"),
    (["trace"], "the following arguments are required: SCRIPT"),
    (["trace", SIXBAR, "-o", "/no/such/folder/out.csv"], "cannot write '/no/such/folder/out"
                                                        ".csv': the folder '/no/such/folder' "
                                                        "does not exist"),
    (["xyzzy"], "geokin has no command 'xyzzy' (commands: check, trace, plot, "
                "animate, analyze, tolerance)"),
    ([], "the following arguments are required: COMMAND"),
    (["plot", SIXBAR, "-o", "out.jpg"], "cannot write a picture to 'out.jpg': use a .png or "
                                        ".svg file"),
    (["animate", SIXBAR], "the following arguments are required: -o/--output"),
    (["animate", SIXBAR, "-o", "out.avi"], "cannot write an animation to 'out.avi'"),
    (["animate", SIXBAR, "-o", "out.gif", "--fps", "0"], "--fps must be from 0.01 to 100"),
    (["animate", SIXBAR, "-o", "out.gif", "--fps", "1e-300"], "--fps must be from 0.01 to 100"),
    (["animate", SIXBAR, "-o", "out.gif", "--fps", "1e300"], "--fps must be from 0.01 to 100"),
    (["animate", SIXBAR, "-o", "out.gif", "--frames", "9" * 5000], "--frames: expected an "
                                                                   "integer, got '9999"),
    (["animate", SIXBAR, "-o", "out.gif", "--frames", "10000000"], "--frames: at most 1000000"),
    (["trace", SIXBAR, "--step", "1e-320"], "--step 1e-320 makes too many samples; at most"),
    (["trace", SIXBAR, "--step", "1e-300"], "--step 1e-300 makes about 1.8e+303 samples; at "),
    (["trace", SIXBAR, "--samples", str(10**30)], "--samples: at most 1000000"),
    (["trace", SIXBAR, "--range", "-1e308", "1e308"], "--range -1e+308 1e+308: too wide"),
    (["trace", SIXBAR, "--range", "-inf", "0"], "--range: expected a finite number, got '-inf'"),
])
def test_errors_exit_2_without_a_traceback(capsys, argv, message):
    status, out, err = run(capsys, *argv)
    assert status == 2
    assert message in err, err
    assert out == ""


@pytest.mark.parametrize("command", ["trace", "plot", "animate", "tolerance"])
@pytest.mark.parametrize("step", ["-5", "0", "-0", "inf", "nan"])
def test_every_sweep_refuses_a_step_that_is_not_positive(capsys, tmp_path, command, step):
    extra = {"animate": ["-o", tmp_path / "x.gif"], "plot": ["-o", tmp_path / "x.png"],
             "tolerance": ["--tol", "r2=0.1"]}.get(command, [])
    status, out, err = run(capsys, command, CRANK, "--range", 0, 90, "--step", step, *extra)
    assert (status, out) == (2, "")
    assert err.startswith("geokin: error: argument --step: expected a ")
    assert f"got '{step}'" in err and err.count("\n") == 1


@pytest.mark.parametrize("argv, message", [
    (["plot", SIXBAR, "--att", "40"], "plot has no option '--att'; did you mean '--at'? "
                                      "(see 'geokin plot --help')"),
    (["plot", "--att=40", SIXBAR], "plot has no option '--att'; did you mean '--at'? "
                                   "(see 'geokin plot --help')"),
    (["trace", SIXBAR, "--derivatves"], "trace has no option '--derivatves'; did you mean "
                                        "'--derivatives'? (see 'geokin trace --help')"),
    (["analyze", SIXBAR, "--jsno"], "analyze has no option '--jsno'; did you mean '--json'? "
                                    "(see 'geokin analyze --help')"),
    (["check", SIXBAR, "--json"], "check has no option '--json' (see 'geokin check --help')"),
    # alike only in the dashes every long option starts with
    (["tolerance", SIXBAR, "--circuit"], "tolerance has no option '--circuit' "
                                         "(see 'geokin tolerance --help')"),
    (["plot", SIXBAR, "--circiut"], "plot has no option '--circiut'; did you mean "
                                    "'--circuit'? (see 'geokin plot --help')"),
    (["trace", SIXBAR, "-x"], "trace has no option '-x' (see 'geokin trace --help')"),
    (["trace", SIXBAR, "other.toml"], "trace does not take the argument 'other.toml' "
                                      "(see 'geokin trace --help')"),
    (["--verison"], "geokin has no option '--verison'; did you mean '--version'? "
                    "(see 'geokin --help')"),
    (["animat", SIXBAR, "-o", "x.gif"], "geokin has no command 'animat'; did you mean "
                                         "'animate'? (see 'geokin --help')"),
    (["analyse", SIXBAR], "geokin has no command 'analyse'; did you mean 'analyze'? "
                          "(see 'geokin --help')"),
    (["--version", "plto"], "geokin has no command 'plto'; did you mean 'plot'? "
                            "(see 'geokin --help')"),
    # an option the given one starts with, before one closer by letters (--range)
    (["tolerance", SIXBAR, "--tolerance", "l3=1"], "tolerance has no option '--tolerance'; "
                                                   "did you mean '--tol'? "
                                                   "(see 'geokin tolerance --help')"),
    (["tolerance", SIXBAR, "--p", "3"], "tolerance has no option '--p'; did you mean "
                                        "'--percentile' or '--points'? "
                                        "(see 'geokin tolerance --help')"),
])
def test_an_unknown_option_is_named_by_its_command_with_the_closest_one(capsys, argv,
                                                                        message):
    status, out, err = run(capsys, *argv)
    assert (status, out, err) == (2, "", f"geokin: error: {message}\n")


@pytest.mark.parametrize("argv, suffix", [
    (["trace", SIXBAR], ".csv"), (["plot", SIXBAR], ".png"),
    (["plot", SIXBAR, "--kinematics"], ".svg"), (["animate", SIXBAR], ".gif"),
])
def test_a_missing_output_folder_is_said_in_the_same_words_by_every_command(
        capsys, tmp_path, monkeypatch, argv, suffix):
    def no_sweep(*args, **kwargs):
        raise AssertionError("swept before the folder was checked")

    monkeypatch.setattr("geokin.cli.run_sweep", no_sweep)
    path = tmp_path / "missing" / f"out{suffix}"
    status, out, err = run(capsys, *argv, "-o", path)
    assert (status, out) == (2, "")
    assert err == (f"geokin: error: cannot write '{path}': the folder '{path.parent}' does not "
                   "exist\n")
    file = tmp_path / "file"
    file.write_text("")
    status, _, err = run(capsys, *argv, "-o", file / f"out{suffix}")
    assert err == f"geokin: error: cannot write '{file / f'out{suffix}'}': '{file}' is not a " \
                  "folder\n"


def test_help_and_version_exit_0(capsys):
    status, out, _ = run(capsys, "--help")
    assert status == 0
    for command in ("check", "trace", "plot", "animate"):
        assert command in out
    status, out, _ = run(capsys, "--version")
    assert status == 0 and out.strip() == f"geokin {geokin.__version__}"
    status, out, _ = run(capsys, "trace", "--help")
    assert status == 0 and "--derivatives" in out and "degrees for an angle" in out


def test_a_command_is_one_function_and_a_parser_entry(capsys, monkeypatch):
    def add_hello(subparsers):
        p = subparsers.add_parser("hello", help="print the construction's name")
        p.add_argument("script")
        p.set_defaults(run=lambda args: print(geokin.load(args.script).name) or 0)

    monkeypatch.setattr("geokin.cli.COMMANDS", [*COMMANDS, add_hello])
    assert "hello" in build_parser().format_help()
    status, out, _ = run(capsys, "hello", SIXBAR)
    assert (status, out) == (0, "six-bar\n")


# -- plot and animate ----------------------------------------------------------------


def test_plot_writes_a_png_of_the_figure_size(capsys, tmp_path):
    from PIL import Image

    path = tmp_path / "six.png"
    status, out, err = run(capsys, "plot", SIXBAR, "-o", path, "--at", 100)
    assert status == 0 and f"wrote {path}" in err
    with Image.open(path) as image:
        assert image.size == (800, 600)


def test_plot_defaults_to_a_png_named_after_the_script(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status, _, _ = run(capsys, "plot", SIXBAR)
    assert status == 0
    with Image.open(tmp_path / "sixbar.png") as image:
        assert image.size == (800, 600)
        # a drawing, not a blank page: the links' colours are there
        assert len(image.convert("RGB").getcolors(maxcolors=1 << 16) or ()) > 20


def test_plot_svg_and_a_value_between_samples(capsys, tmp_path):
    path = tmp_path / "crank.svg"
    status, _, err = run(capsys, "plot", CRANK, "-o", path, "--at", 10.5, "--title", "T")
    assert status == 0
    text = path.read_text()
    assert text.lstrip().startswith("<?xml") and "10.5" in text


def test_plot_where_it_cannot_be_assembled_warns(capsys, tmp_path):
    status, _, err = run(capsys, "plot", CRANK, "-o", tmp_path / "x.png", "--range", -140, 140,
                         "--at", 140)
    assert status == 0
    assert "warning: theta2 = 140 deg: node 'C' cannot be assembled" in err


DOUBLE_ROCKER = """\
[construction]
name = "double rocker"
units = "mm"
[inputs.theta]
range = [0, 360]
[points]
O2 = { op = "fixed", at = [0, 0] }
O4 = { op = "fixed", at = [10, 0] }
A = { op = "polar", origin = "O2", distance = 8, angle = "theta" }
B = { op = "circle_circle", centers = ["A", "O4"], radii = [3, 9], branch = "left" }
[links]
ground = ["O2", "O4"]
crank = ["O2", "A"]
coupler = ["A", "B"]
rocker = ["O4", "B"]
"""
"""A Grashof double rocker (coupler shortest): its crank cannot reach 0 or 180 degrees."""


@pytest.mark.parametrize("at", [0, 180])
def test_plot_at_a_value_that_does_not_assemble_names_the_pose_drawn(capsys, tmp_path, at):
    script = tmp_path / "double_rocker.toml"
    script.write_text(DOUBLE_ROCKER)
    s = geokin.sweep(geokin.load(script))
    i = int(np.flatnonzero(np.isclose(np.degrees(s.inputs["theta"]), at))[0])
    assert not s.valid[i]
    before, after = np.flatnonzero(s.valid[:i]), np.flatnonzero(s.valid[i:]) + i
    drawn = before[-1] if before.size else after[0]
    which = "last assembled pose before" if before.size else "first assembled pose after"
    shown = round(float(np.degrees(s.inputs["theta"][drawn])), 9)
    status, out, err = run(capsys, "plot", script, "--at", at, "-o", tmp_path / "x.svg")
    assert (status, out) == (0, "")
    assert err.splitlines()[0] == (
        f"geokin: warning: theta = {at} deg: node 'B' cannot be assembled: "
        f"{s.failure_reason[i]}; drawn instead, faded: the {which} it, at theta = "
        f"{shown:g} deg")
    picture = (tmp_path / "x.svg").read_text()
    assert f"θ = {at:.1f}°" in picture and f"drawn: the pose at θ = {shown:.1f}°" in picture


@pytest.mark.parametrize("argv, message", [
    ([SIXBAR, "--at", 5000], "--at 5000 is outside the sweep of input 'theta': 0 to 1800 deg"),
    ([SIXBAR, "--at", -1], "--at -1 is outside the sweep of input 'theta': 0 to 1800 deg"),
    ([SIXBAR, "--range", 30, 0, "--at", 40], "--at 40 is outside the sweep of input 'theta': "
                                             "30 to 0 deg"),
    ([SIXBAR, "--range", 40, 40, "--samples", 1, "--at", 41], "--at 41 is outside the sweep of "
                                                              "input 'theta': 40 deg alone"),
    ([CRANK, "--at", 140], "--at 140 is outside the sweep of input 'theta2': -132 to 132 deg"),
    ([CRANK, "--circuit", "--at", 140], "--at 140 is outside the circuit of input 'theta2': "
                                        "-132.177419 to 132.177419 deg"),
])
def test_plot_refuses_a_value_outside_the_sweep_with_its_range(capsys, tmp_path, argv,
                                                               message):
    path = tmp_path / "x.png"
    status, out, err = run(capsys, "plot", *argv, "-o", path)
    assert (status, out, err) == (2, "", f"geokin: error: {message}\n")
    assert not path.exists()


def test_plot_at_the_ends_of_the_range(capsys, tmp_path):
    # the declared range, not only the samples: the six-bar's last sample is 1792
    for at in (0, 1800, 1800 + 1e-10):
        status, _, err = run(capsys, "plot", SIXBAR, "--at", at, "-o", tmp_path / "x.svg")
        assert status == 0 and err == f"wrote {tmp_path / 'x.svg'}\n"
    status, _, err = run(capsys, "plot", SIXBAR, "--range", 30, 0, "--at", 20, "-o",
                         tmp_path / "x.svg")
    assert status == 0 and err == f"wrote {tmp_path / 'x.svg'}\n"


def test_animate_gif_has_the_frames_asked_for(capsys, tmp_path):
    from PIL import Image

    path = tmp_path / "fourbar.gif"
    status, _, err = run(capsys, "animate", CONSTRUCTIONS / "fourbar_open.toml", "-o", path,
                         "--frames", 6, "--fps", 10, "--no-progress")
    assert status == 0 and f"wrote {path}" in err
    with Image.open(path) as image:
        assert image.n_frames == 6


def test_animate_by_default_makes_60_frames_at_72_dpi_and_says_how_to_ask_for_more(
        capsys, tmp_path, monkeypatch):
    from geokin import plotting

    asked = {}

    def animate(sweep, path, **options):
        asked.update(options, samples=len(sweep))
        return pathlib.Path(path)

    monkeypatch.setattr(plotting, "animate", animate)
    path = tmp_path / "six.gif"
    status, _, err = run(capsys, "animate", SIXBAR, "-o", path, "--no-progress")
    assert status == 0
    assert (asked["frames"], asked["dpi"], asked["samples"]) == (60, 72, 113)
    assert err == (f"wrote {path}: 60 frames of 113 samples at 72 dpi; --frames 113 for "
                   "every sample\n")
    status, _, err = run(capsys, "animate", SIXBAR, "-o", path, "--frames", 200, "--dpi", 100)
    assert (asked["frames"], asked["dpi"]) == (200, 100)
    assert err == f"wrote {path}: 113 frames of 113 samples at 100 dpi\n"
    status, _, err = run(capsys, "animate", SIXBAR, "-o", path, "--dpi", 0)
    assert (status, err) == (2, "geokin: error: --dpi must be from 1 to 1000, got 0\n")


def test_animate_help_says_how_to_ask_for_more_frames(capsys):
    status, out, _ = run(capsys, "animate", "--help")
    text = " ".join(out.split())
    assert status == 0
    assert "(default 60, a few seconds' work; more for a smoother animation" in text
    assert "--dpi" in text


def test_animate_html_is_one_page(capsys, tmp_path):
    path = tmp_path / "crank.html"
    status, _, _ = run(capsys, "animate", CRANK, "-o", path, "--frames", 3, "--samples", 10)
    assert status == 0
    text = path.read_text()
    assert "<script" in text and "data:image/png;base64" in text


@pytest.mark.skipif(shutil.which("ffmpeg") is not None, reason="ffmpeg is installed")
def test_animate_mp4_without_ffmpeg_says_so(capsys, tmp_path):
    status, _, err = run(capsys, "animate", CRANK, "-o", tmp_path / "x.mp4", "--frames", 3)
    assert status == 2 and "needs ffmpeg" in err


@pytest.mark.skipif(shutil.which("geokin") is None, reason="the console script is not installed")
def test_the_installed_console_script(tmp_path):
    done = subprocess.run(["geokin", "check", SIXBAR], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    assert "degrees of freedom" in done.stdout
    bad = tmp_path / "bad.toml"
    bad.write_text('[points]\nA = { op = "fixd", at = [0, 0] }\n')
    done = subprocess.run(["geokin", "trace", str(bad)], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2
    assert done.stderr == (f"geokin: error: {bad}:2: [points] A.op: unknown op 'fixd'; did you "
                           "mean 'fixed'? (ops: fixed, polar, local, along, line_line, "
                           "line_circle, segment_circle, ray_circle, circle_circle)\n")
    done = subprocess.run(["geokin", "trace", SIXBAR, "--points", "M"], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0 and len(done.stdout.splitlines()) == 114


def test_python_m_geokin_is_the_command(tmp_path):
    done = subprocess.run([sys.executable, "-m", "geokin", "--version"], capture_output=True,
                          text=True, timeout=120)
    assert (done.returncode, done.stdout, done.stderr) == (0, f"geokin {geokin.__version__}\n",
                                                           "")
    # the exit status is the command's, not the interpreter's
    done = subprocess.run([sys.executable, "-m", "geokin", "check", str(tmp_path / "no.toml")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and done.stderr.startswith("geokin: error: cannot open")


def test_analyze_prints_limits_class_and_transmission_angle(capsys):
    status, out, err = run(capsys, "analyze", str(CONSTRUCTIONS / "triple_rocker_crank.toml"))
    assert status == 0 and err == ""
    assert "assemblable from -132.177419 to 132.177419 deg" in out
    assert "node 'C' becomes tangent (toggle)" in out
    assert "triple-rocker RRR1" in out and "transmission angle at C" in out


def test_analyze_json_has_dof_and_intervals_in_script_units(capsys):
    status, out, _ = run(capsys, "analyze", "--json", str(CONSTRUCTIONS / "sixbar.toml"))
    report = json.loads(out)
    assert status == 0 and report["dof"] == 1
    assert report["inputs"]["theta"]["intervals"] == [[0.0, 1800.0]]
    status, out, _ = run(capsys, "analyze", "--json",
                         str(CONSTRUCTIONS / "triple_rocker_follower.toml"))
    [[lo, hi]] = json.loads(out)["inputs"]["theta4"]["intervals"]
    assert (round(lo, 4), round(hi, 4)) == (47.8226, 312.1774)


def double_rocker_intervals():
    """DOUBLE_ROCKER's crank (8 on a ground of 10) stops where A-O4 is 9 - 3 or 9 + 3."""
    low, high = (np.degrees(np.arccos((8**2 + 10**2 - r**2) / (2 * 8 * 10))) for r in (6, 12))
    return (low, high), (360 - high, 360 - low)


def test_start_picks_the_circuit_of_an_input_assembled_in_two_intervals(capsys, tmp_path):
    """The double rocker's input can be assembled in 36.87 to 82.82 and 277.18 to 323.13 deg."""
    script = tmp_path / "double_rocker.toml"
    script.write_text(DOUBLE_ROCKER)
    spans = [f"from {lo:.6f} to {hi:.6f} deg" for lo, hi in double_rocker_intervals()]
    for start, span in ((50, spans[0]), (300, spans[1])):
        status, out, err = run(capsys, "analyze", script, "--start", start)
        assert (status, err) == (0, "")
        assert (f"warning: input 'theta' can be assembled in 2 intervals on the branches it "
                f"starts on: the figures below are of the circuit {span}") in out
        status, out, _ = run(capsys, "trace", script, "--circuit", "--start", start,
                             "--links", "crank")
        header, data = read_csv(out)
        assert status == 0
        low, high = (float(v) for v in span.split()[1::2])
        angle = dict(zip(header, data.T, strict=True))["theta"]
        assert angle.min() == pytest.approx(low, abs=1e-5)
        assert angle.max() == pytest.approx(high, abs=1e-5)
    status, _, err = run(capsys, "plot", script, "--circuit", "--start", 300, "--at", 300,
                         "-o", tmp_path / "other.png")
    assert (status, err) == (0, f"wrote {tmp_path / 'other.png'}\n")
    status, _, err = run(capsys, "analyze", script, "--start", 200)
    assert status == 2 and err == (
        f"geokin: error: --start 200: input 'theta' cannot be assembled there (it can "
        f"{spans[0]}, {spans[1].removeprefix('from ')})\n")
    status, _, err = run(capsys, "plot", script, "--start", 300, "-o", tmp_path / "x.png")
    assert status == 2 and "--start picks where a circuit starts: use it with --circuit" in err


@pytest.mark.parametrize("script", sorted(CONSTRUCTIONS.glob("*.toml")), ids=lambda p: p.stem)
def test_analyze_prints_the_report_as_text_and_as_data(capsys, script):
    construction = geokin.load(script)
    report = geokin.analyze(construction, degrees=True)
    status, out, _ = run(capsys, "analyze", script)
    assert status == 0 and out == report.to_text(construction.units)
    status, out, _ = run(capsys, "analyze", "--json", script)
    assert status == 0 and out == json.dumps(report.to_dict(), indent=2) + "\n"


def test_trace_circuit_passes_the_toggles_and_closes(capsys):
    status, out, _ = run(capsys, "trace", "--circuit", "--points", "C", "--samples", "91",
                         str(CONSTRUCTIONS / "triple_rocker_crank.toml"))
    header, rows = read_csv(out)
    assert header == ["theta2", "valid", "C.branch", "C.x", "C.y"]
    theta, valid, branch, c = rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3:]
    assert status == 0 and (valid == 1).all()
    assert set(branch) == {0, 1}  # both branches of C, told apart where theta2 repeats
    assert abs(theta.max() - 132.1774) < 1e-4 and abs(theta.min() + 132.1774) < 1e-4
    np.testing.assert_allclose(c[0], c[-1], atol=1e-9)


def test_circuit_refuses_a_range(capsys):
    status, _, err = run(capsys, "trace", "--circuit", "--range", "0", "10",
                         str(CONSTRUCTIONS / "triple_rocker_crank.toml"))
    assert status == 2 and "--circuit" in err and "Traceback" not in err


def test_plot_kinematics_draws_three_axes(capsys, tmp_path):
    out = tmp_path / "k.png"
    status, _, _ = run(capsys, "plot", "--kinematics", str(CONSTRUCTIONS / "crank_rocker.toml"),
                       "-o", str(out))
    assert status == 0
    # the same figure as figure_kinematics draws: three axes, its size
    from geokin import plotting
    from geokin.kinematics import motion

    fig, axes = plotting.figure_kinematics(motion(geokin.sweep(geokin.load(
        CONSTRUCTIONS / "crank_rocker.toml"))))
    assert len(axes) == 3
    import matplotlib.pyplot as plt

    plt.close(fig)
    with Image.open(out) as image:
        assert image.size == tuple(int(round(v)) for v in fig.get_size_inches() * fig.dpi)
        assert len(image.convert("RGB").getcolors(maxcolors=1 << 16) or ()) > 20
    status, _, err = run(capsys, "plot", "--kinematics", "--at", "10",
                         str(CONSTRUCTIONS / "crank_rocker.toml"), "-o", str(out))
    assert status == 2 and "one or the other" in err


# -- hostile input, interrupted output ---------------------------------------------------

HOSTILE = "\x1b]0;owned\x07\x1b[2J\u202e\n\x9b"


def toml_string(text):
    """A TOML basic string holding any text, control characters escaped."""
    return '"' + "".join(c if c.isprintable() and c not in '"\\' else f"\\u{ord(c):04x}"
                         for c in text) + '"'


def hostile_script(tmp_path):
    text = pathlib.Path(SIXBAR).read_text()
    text = text.replace('name = "six-bar"', f"name = {toml_string('six' + HOSTILE)}")
    text = text.replace('description = "Inverted', f"description = {toml_string(HOSTILE)} "
                                                   '# "Inverted')
    text = text.replace('units = "mm"', f"units = {toml_string('mm' + HOSTILE)}")
    path = tmp_path / "hostile.toml"
    path.write_text(text)
    return path


def printable_lines(text):
    return all(line.isprintable() for line in text.splitlines())


def test_check_and_analyze_escape_what_the_script_says(capsys, tmp_path):
    path = hostile_script(tmp_path)
    status, out, err = run(capsys, "check", path)
    assert status == 0 and err == ""
    assert printable_lines(out) and "\x1b" not in out and "\u202e" not in out
    assert "six\\x1b]0;owned\\x07\\x1b[2J\\u202e\\n\\x9b" in out.splitlines()[0]
    assert "lengths in mm\\x1b]0;owned" in out
    assert "construction 'six-bar" not in out  # the name is the script's, escaped
    status, out, err = run(capsys, "analyze", path)
    assert status == 0 and printable_lines(out) and "\x1b" not in out
    assert out.startswith("six\\x1b]0;owned")
    status, out, err = run(capsys, "analyze", "--json", path)
    assert status == 0 and printable_lines(out)
    assert json.loads(out)["construction"] == "six" + HOSTILE  # data stays data


def test_every_error_is_one_escaped_line(capsys, tmp_path, monkeypatch):
    bad = tmp_path / "bad\x1b[31m.toml"
    bad.write_text(f"[points]\n{toml_string('A' + HOSTILE)} = {{ op = \"fixed\", at = [0, 0] }}\n")
    status, out, err = run(capsys, "check", bad)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.endswith("\n") and err[:-1].isprintable()
    assert err.startswith("geokin: error: ") and "bad\\x1b[31m.toml" in err
    # an argument the parser refuses: one line too, without the usage
    status, _, err = run(capsys, "trace", SIXBAR, "--points", "M", "--samples", "x\x1b[2J")
    assert status == 2 and err.count("\n") == 1 and err[:-1].isprintable()
    assert err == ("geokin: error: argument --samples: expected an integer, got 'x\\x1b[2J' "
                   "(see 'geokin trace --help')\n")
    # a fault of geokin itself, however its message reads
    def fail(*args, **kwargs):
        raise ValueError("first line\nsecond line \x1b[2J" + "x" * 100_000)

    monkeypatch.setattr("geokin.cli.load", fail)
    status, _, err = run(capsys, "check", SIXBAR)
    assert status == 2 and err.count("\n") == 1 and err[:-1].isprintable() and len(err) < 2100
    assert err.startswith("geokin: internal error: ValueError: first line\\nsecond line \\x1b")


def test_a_warning_is_one_line_too(capsys, monkeypatch):
    import warnings

    def warn(*args, **kwargs):
        warnings.warn("overflow\nencountered \x1b[2J", RuntimeWarning, stacklevel=1)
        raise geokin.ScriptError("given up")

    monkeypatch.setattr("geokin.cli.load", warn)
    status, _, err = run(capsys, "trace", SIXBAR)
    assert status == 2
    assert err == ("geokin: warning: RuntimeWarning: overflow\\nencountered \\x1b[2J\n"
                   "geokin: error: given up\n")


def test_running_out_of_memory_is_an_error_not_a_fault(capsys, monkeypatch):
    def exhaust(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr("geokin.cli.run_sweep", exhaust)
    status, _, err = run(capsys, "trace", SIXBAR)
    assert status == 2 and err.startswith("geokin: error: not enough memory for this job")


@pytest.mark.parametrize("value", ["-1e3", "-1000", "-1000.0", "-.1e4", "-1E+3"])
def test_negative_numbers_are_option_values(capsys, value):
    status, out, err = run(capsys, "trace", SIXBAR, "--points", "A", "--range", value, "0",
                           "--samples", 3)
    assert status == 0, err
    _, data = read_csv(out)
    np.testing.assert_array_equal(data[:, 0], [-1000, -500, 0])


def test_a_negative_value_to_draw_at(capsys, tmp_path):
    path = tmp_path / "at.svg"
    status, _, err = run(capsys, "plot", CRANK, "--at", "-3.05e1", "-o", path)
    assert status == 0, err
    assert "-30.5" in path.read_text()


def test_an_output_suffix_is_read_in_any_case_and_the_path_kept(capsys, tmp_path):
    for name in ("out.NPZ", "out.Json", "out.CSV"):
        path = tmp_path / name
        status, _, err = run(capsys, "trace", SIXBAR, "--points", "M", "-o", path)
        assert status == 0 and err == f"wrote {path}: 113 samples, 4 columns\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.CSV", "out.Json", "out.NPZ"]
    assert list(np.load(tmp_path / "out.NPZ")) == ["theta", "valid", "M.x", "M.y"]
    assert list(json.loads((tmp_path / "out.Json").read_text())) == ["theta", "valid", "M.x",
                                                                     "M.y"]


@pytest.mark.parametrize("suffix", [".csv", ".json", ".npz"])
def test_a_failing_trace_leaves_the_old_file(capsys, tmp_path, monkeypatch, suffix):
    path = tmp_path / f"old{suffix}"
    path.write_bytes(b"the old file")

    def half_then_fail(columns, stream, **kwargs):
        stream.write("theta,valid\n0,1\n" if "b" not in getattr(stream, "mode", "") else b"PK")
        raise KeyboardInterrupt

    for writer in ("write_csv", "write_json", "write_npz"):
        monkeypatch.setattr(f"geokin.io.export.{writer}", half_then_fail)
    status, _, err = run(capsys, "trace", SIXBAR, "-o", path)
    assert (status, err) == (130, "geokin: interrupted\n")
    assert path.read_bytes() == b"the old file"
    assert [p.name for p in tmp_path.iterdir()] == [path.name]


@pytest.mark.parametrize("signum, status, message", [
    (signal.SIGINT, 130, "geokin: interrupted\n"),
    (signal.SIGTERM, -signal.SIGTERM, "geokin: terminated\n"),  # ended by the signal
])
def test_a_signal_while_writing_a_large_csv_keeps_the_old_file(tmp_path, signum, status,
                                                                 message):
    path = tmp_path / "big.csv"
    old = "theta,valid\n0,1\n"
    path.write_text(old)
    process = subprocess.Popen(
        [sys.executable, "-m", "geokin.cli", "trace", SIXBAR, "--samples", "1000000", "-o",
         str(path)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        # a job started in the background inherits SIGINT ignored, and so would the
        # child: give it the default, as a terminal's foreground job has
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + 120
        while True:  # until the new file is well under way
            partial = [p for p in tmp_path.iterdir() if p != path]
            # signalled as soon as rows are being written: writing them all is quick
            if partial and partial[0].stat().st_size > 0:
                break
            assert process.poll() is None, process.communicate()
            assert time.monotonic() < deadline
            time.sleep(0.005)
        assert partial[0].name.startswith(".big.") and partial[0].name.endswith(".csv")
        process.send_signal(signum)
        out, err = process.communicate(timeout=60)
    finally:
        process.kill()
        process.wait()
    assert (process.returncode, out, err) == (status, "", message)
    assert path.read_text() == old
    assert [p.name for p in tmp_path.iterdir()] == ["big.csv"]


def test_a_deep_path_is_named_whole_in_an_error(capsys, tmp_path):
    folder = tmp_path / ("deep" * 30)
    folder.mkdir()
    script = folder / "bad.toml"
    script.write_text('[points]\nA = { op = "fixd", at = [0, 0] }\n')
    status, _, err = run(capsys, "check", script)
    assert status == 2 and err.startswith(f"geokin: error: {script}:2: [points] A.op: unknown")
    status, _, err = run(capsys, "check", folder / "missing.toml")
    assert err.startswith(f"geokin: error: cannot open '{folder / 'missing.toml'}'")


def test_trace_into_a_link_or_a_pipe(capsys, tmp_path):
    import os
    import threading

    real = tmp_path / "real.csv"
    real.write_text("old\n")
    link = tmp_path / "link.csv"
    link.symlink_to(real)
    status, _, _ = run(capsys, "trace", SIXBAR, "--points", "M", "-o", link)
    assert status == 0 and link.is_symlink()  # the file pointed to is replaced, not the link
    assert real.read_text().startswith("theta,valid,M.x,M.y\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.csv", "real.csv"]

    pipe = tmp_path / "pipe.csv"
    os.mkfifo(pipe)
    received = []
    reader = threading.Thread(target=lambda: received.append(pipe.read_text()))
    reader.start()
    status, _, _ = run(capsys, "trace", SIXBAR, "--points", "M", "-o", pipe)
    reader.join(timeout=30)
    assert status == 0 and received[0].startswith("theta,valid,M.x,M.y\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.csv", "pipe.csv", "real.csv"]


def test_a_full_disk_or_a_closed_folder_names_the_output(capsys, tmp_path, monkeypatch):
    import errno

    path = tmp_path / "old.csv"
    path.write_text("the old file")

    def full(columns, stream, **kwargs):
        stream.write("theta,valid\n")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr("geokin.io.export.write_csv", full)
    status, _, err = run(capsys, "trace", SIXBAR, "-o", path)
    assert (status, err) == (2, f"geokin: error: cannot write '{path}': No space left on "
                                "device\n")
    assert path.read_text() == "the old file" and len(list(tmp_path.iterdir())) == 1
    monkeypatch.undo()

    def closed(name, *args, **kwargs):
        raise PermissionError(errno.EACCES, "Permission denied", name)

    monkeypatch.setattr("geokin.atomic.os.open", closed)
    status, _, err = run(capsys, "plot", SIXBAR, "-o", tmp_path / "new.png")
    assert (status, err) == (2, f"geokin: error: cannot write '{tmp_path / 'new.png'}': "
                                "Permission denied\n")


def test_check_says_where_the_roots_meet_not_where_the_new_branch_is_first_seen(
        capsys, tmp_path):
    script = tmp_path / "parallelogram.toml"
    script.write_text('[inputs.theta]\nrange = [0, 360]\nstep = 50\n[points]\n'
                      'O2 = { op = "fixed", at = [0, 0] }\n'
                      'O4 = { op = "fixed", at = [10, 0] }\n'
                      'A = { op = "polar", origin = "O2", distance = 4, angle = "theta" }\n'
                      'B = { op = "circle_circle", centers = ["A", "O4"], radii = [10, 4], '
                      'branch = "left" }\n')
    status, out, err = run(capsys, "check", str(script))
    assert status == 0
    # the change point lies at 180 degrees, between the samples at 150 and 200
    assert "  at theta = 180 deg: node 'B' changes branch from left to right" in out


def test_check_prints_angles_in_the_scripts_degrees(capsys):
    status, out, err = run(capsys, "check", str(CONSTRUCTIONS / "triple_rocker_coupler.toml"))
    assert status == 0
    assert "B  = polar(C, r3, theta3 + 180)" in out  # held as theta3 + pi inside


# -- long traces, block by block ---------------------------------------------------


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_a_long_trace_written_in_blocks_is_the_trace_made_whole(capsys, tmp_path, monkeypatch,
                                                                 suffix):
    import geokin.cli as cli

    options = ["--samples", "2001", "--links", "crank,output", "--sliders", "block",
               "--derivatives"]
    whole, blocks = tmp_path / f"whole{suffix}", tmp_path / f"blocks{suffix}"
    assert run(capsys, "trace", SIXBAR, *options, "-o", whole)[0] == 0
    # blocks of 150 samples: their edges fall on the crank's turns and the output's
    # branch changes over five turns
    monkeypatch.setattr(cli, "TRACE_BLOCK_SAMPLES", 150)
    status, _, err = run(capsys, "trace", SIXBAR, *options, "-o", blocks)
    assert status == 0 and "2001 samples" in err
    if suffix == ".csv":
        names, a = read_csv(whole.read_text())
        names_b, b = read_csv(blocks.read_text())
        assert names == names_b
    else:
        data_a, data_b = np.load(whole), np.load(blocks)
        names = list(data_a)
        assert names == list(data_b)
        a = np.column_stack([data_a[k].astype(float) for k in names])
        b = np.column_stack([data_b[k].astype(float) for k in names])
    exact = [i for i, k in enumerate(names) if not k.endswith((".vx", ".vy", ".ax", ".ay",
                                                               ".omega", ".alpha", ".velocity",
                                                               ".acceleration", "time", ".angle"))]
    # positions, slider positions and flags exactly; rates to rounding (each block is
    # differentiated in its own frame), angles too (each block unwrapped on its own,
    # then turned on by whole turns)
    np.testing.assert_array_equal(a[:, exact], b[:, exact])
    scale = np.nanmax(np.abs(a), axis=0)
    np.testing.assert_allclose(b, a, rtol=0, atol=1e-9 * np.max(scale))
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([whole.name, blocks.name])


def test_a_long_trace_to_standard_output_has_one_header(capsys, monkeypatch):
    import geokin.cli as cli

    monkeypatch.setattr(cli, "TRACE_BLOCK_SAMPLES", 40)
    status, out, _ = run(capsys, "trace", CRANK, "--samples", "101", "--points", "C")
    names, rows = read_csv(out)
    assert status == 0 and names == ["theta2", "valid", "C.x", "C.y"] and len(rows) == 101
    monkeypatch.setattr(cli, "TRACE_BLOCK_SAMPLES", 1000)
    assert run(capsys, "trace", CRANK, "--samples", "101", "--points", "C")[1] == out


def test_a_long_trace_that_never_assembles_says_so_once(capsys, tmp_path, monkeypatch):
    import geokin.cli as cli

    script = tmp_path / "short.toml"
    script.write_text((CONSTRUCTIONS / "crank_rocker.toml").read_text().replace(
        "l3 = { value = 35", "l3 = { value = 12").replace("l4 = { value = 30", "l4 = { value = 10"))
    whole = run(capsys, "trace", script, "--samples", "500", "-o", tmp_path / "w.npz")
    monkeypatch.setattr(cli, "TRACE_BLOCK_SAMPLES", 64)
    blocks = run(capsys, "trace", script, "--samples", "500", "-o", tmp_path / "b.npz")
    assert whole[0] == blocks[0] == 1
    assert blocks[2] == whole[2].replace("w.npz", "b.npz") and blocks[2].count("\n") == 1
    a, b = np.load(tmp_path / "w.npz"), np.load(tmp_path / "b.npz")
    assert all(np.array_equal(a[k], b[k], equal_nan=True) for k in a)


def test_only_a_trace_takes_more_samples_than_a_sweep_held_whole(capsys):
    status, _, err = run(capsys, "plot", SIXBAR, "--samples", "2000000", "-o", "x.png")
    assert status == 2 and "at most 1000000" in err
    status, _, err = run(capsys, "trace", SIXBAR, "--samples", "2000000", "-o", "x.json")
    assert status == 2 and "CSV or NPZ" in err


def test_plot_kinematics_keeps_the_mechanism_picture(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    script = str(CONSTRUCTIONS / "crank_rocker.toml")
    assert run(capsys, "plot", script, "--samples", "37")[0] == 0
    assert run(capsys, "plot", script, "--kinematics", "--samples", "37")[0] == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "crank_rocker-kinematics.png", "crank_rocker.png"]


@pytest.mark.parametrize("argv, name", [
    (["trace", SIXBAR, "--derivative"], "--derivative"), (["--vers"], "--vers"),
    (["plot", SIXBAR, "--kinem"], "--kinem")])
def test_an_abbreviated_option_is_refused(capsys, argv, name):
    status, out, err = run(capsys, *argv)
    assert status == 2 and out == ""
    assert f"has no option '{name}'; did you mean" in err


def test_the_kinematics_heading_says_how_many_samples_it_leaves_out():
    from geokin import plotting
    from geokin.kinematics import motion

    s = geokin.circuit(geokin.load(CONSTRUCTIONS / "triple_rocker_crank.toml"))
    m = motion(s)
    assert m.flagged.any()  # through its toggles
    fig, axes = plotting.figure_kinematics(m)
    heading = fig._suptitle.get_text()
    assert heading.endswith(f"(rates not drawn at {int(m.flagged.sum())} flagged samples)")
    angle, rate = (axes[i].get_lines()[1].get_ydata() for i in (0, 1))  # the coupler's
    # the angle is drawn wherever the circuit assembles; its rate not where flagged
    assert np.isfinite(angle).sum() == len(angle) and np.isnan(rate).sum() == m.flagged.sum()
    import matplotlib.pyplot as plt

    plt.close(fig)


FIVE_BAR = """
[construction]
name = "five-bar"

[inputs.t1]

[inputs.t2]
range = [90, 450]

[points]
O1 = { op = "fixed", at = [0, 0] }
O2 = { op = "fixed", at = [50, 0] }
A = { op = "polar", origin = "O1", distance = 20, angle = "t1" }
B = { op = "polar", origin = "O2", distance = 20, angle = "t2" }
C = { op = "circle_circle", centers = ["A", "B"], radii = [50, 50], branch = "left" }
"""


def test_circuit_refuses_several_inputs_rather_than_hold_all_but_one(capsys, tmp_path):
    script = tmp_path / "five_bar.toml"
    script.write_text(FIVE_BAR)
    for command in (["trace", script, "--circuit"], ["plot", script, "--circuit", "-o",
                                                      tmp_path / "x.png"]):
        status, out, err = run(capsys, *command)
        assert (status, out) == (2, "")
        assert err == ("geokin: error: --circuit moves one input through its toggles; this "
                       "construction has 2 inputs ('t1', 't2'), which a sweep moves together: "
                       "leave out --circuit\n")
    status, _, err = run(capsys, "analyze", script, "--start", 3)
    assert status == 2 and "--start picks the circuit of an input; this construction has 2 " \
                           "inputs, swept together" in err


def test_a_range_for_the_first_of_several_inputs_warns_that_the_pairing_changes(
        capsys, tmp_path, monkeypatch):
    script = tmp_path / "five_bar.toml"
    script.write_text(FIVE_BAR)
    status, out, err = run(capsys, "trace", script, "--range", 0, 180, "--samples", 3)
    assert status == 0
    warning = ("geokin: warning: --range moves input 't1' alone; the other inputs keep "
                   "their declared ranges ('t2' from 90 deg to 450 deg) over as many samples, "
                   "so the inputs pair up differently than in the declared sweep\n")
    assert err == warning
    rows = [line.split(",") for line in out.splitlines()[1:]]
    header = out.splitlines()[0].split(",")
    t1, t2 = header.index("t1"), header.index("t2")
    assert [(float(r[t1]), float(r[t2])) for r in rows] == [(0, 90), (90, 270), (180, 450)]
    # once, also where a long trace is written block by block
    monkeypatch.setattr(geokin.cli, "TRACE_BLOCK_SAMPLES", 4)
    status, _, err = run(capsys, "trace", script, "--range", 0, 180, "--samples", 9, "-o",
                         tmp_path / "t.csv")
    assert status == 0 and err == warning + f"wrote {tmp_path / 't.csv'}: 9 samples, 13 columns\n"
    # the declared sweep, or only its sampling changed: the inputs pair as declared, silently
    for options in ([], ["--samples", 5]):
        status, _, err = run(capsys, "trace", script, *options)
        assert (status, err) == (0, "")


@pytest.mark.parametrize("at, drawn", [(60, 60), (420, 420), (780, 60), (1120, 400),
                                       (-40, 680), (-300, 420)])
def test_at_on_a_circuit_of_two_turns_is_the_angle_in_the_motion_it_repeats(capsys, tmp_path,
                                                                          monkeypatch, at,
                                                                          drawn):
    """A change-point crank-rocker's circuit makes two turns, each angle met in two poses:
    an angle the circuit reaches is drawn there, another as many circuits away (two turns
    each) as it is, the pose the mechanism is in there."""
    import geokin.cli as cli

    script = tmp_path / "change_point.toml"
    script.write_text((CONSTRUCTIONS / "crank_rocker.toml").read_text()
                      .replace("l1 = { value = 40", "l1 = { value = 10")
                      .replace("l2 = { value = 10", "l2 = { value = 4")
                      .replace("l3 = { value = 35", "l3 = { value = 9")
                      .replace("l4 = { value = 30", "l4 = { value = 5"))
    shown = []
    draw_at = cli._circuit_at
    monkeypatch.setattr(cli, "_circuit_at", lambda result, value: (
        shown.append(np.degrees(value)) or draw_at(result, value)))
    status, _, err = run(capsys, "plot", script, "--circuit", "--at", at, "-o", tmp_path / "x.png")
    assert (status, err) == (0, f"wrote {tmp_path / 'x.png'}\n")
    assert shown == [pytest.approx(drawn, abs=1e-9)]


def test_circuit_values_copied_from_analyze_or_turns_away_are_taken(capsys, tmp_path):
    """The double rocker's limits to six decimals, and -60 deg for 300, are in its circuits."""
    script = tmp_path / "double_rocker.toml"
    script.write_text(DOUBLE_ROCKER)
    (first, _), (second_low, second_high) = (
        (f"{lo:.6f}", f"{hi:.6f}") for lo, hi in double_rocker_intervals())
    for start, at in ((first, first), (second_high, second_high), ("-60", "-50")):
        status, out, err = run(capsys, "trace", script, "--circuit", "--start", start,
                               "--samples", 5)
        assert status == 0 and err == ""
        status, _, err = run(capsys, "plot", script, "--circuit", "--start", start, "--at",
                             at, "-o", tmp_path / "x.png")
        assert status == 0 and err == f"wrote {tmp_path / 'x.png'}\n"
    status, _, err = run(capsys, "plot", script, "--circuit", "--start", 300, "--at", 323.14,
                         "-o", tmp_path / "x.png")
    assert status == 2 and (f"--at 323.14 is outside the circuit of input 'theta': "
                            f"{second_low} to {second_high} deg") in err
