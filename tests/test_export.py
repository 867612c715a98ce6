"""Sweeps exported as tables: columns, CSV, JSON and NPZ, and the files written whole."""

import csv
import io
import json
import pathlib

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from mechanisms import fourbar_closed_form, slider_crank_closed_form

import geokin
from geokin import ConstructionError, circuit, load, motion, sweep
from geokin.cli import main
from geokin.io import (
    EXPORT_FORMATS,
    columns,
    export_sweep,
    shortest_text,
    write_csv,
    write_json,
    write_npz,
)

CONSTRUCTIONS = pathlib.Path(__file__).resolve().parent.parent / "constructions"
SIXBAR = CONSTRUCTIONS / "sixbar.toml"
CRANK = CONSTRUCTIONS / "triple_rocker_crank.toml"
FOURBAR = CONSTRUCTIONS / "fourbar_open.toml"
SLIDER_CRANK = CONSTRUCTIONS / "slider_crank_offset.toml"


def read_csv(path):
    rows = list(csv.reader(io.StringIO(pathlib.Path(path).read_text(encoding="utf-8"))))
    names, cells = rows[0], np.array(rows[1:], dtype=float).reshape(len(rows) - 1, len(rows[0]))
    return {name: cells[:, i] for i, name in enumerate(names)}


def read_json(path):
    data = json.loads(pathlib.Path(path).read_text(encoding="utf-8"))
    return {name: np.array([np.nan if v is None else v for v in values], dtype=float)
            for name, values in data.items()}


def read_npz(path):
    with np.load(path) as data:
        return {name: data[name] for name in data}


READ = {".csv": read_csv, ".json": read_json, ".npz": read_npz}


def a_crank(*names):
    """A crank driven by an input of each name, the first turning it."""
    c = geokin.Construction("crank")
    for name in names:
        c.input(name)
    c.fixed("O", 0, 0)
    c.polar("A", "O", 3, " + ".join(names))
    return c


@pytest.fixture(scope="module")
def rocker():
    """The triple rocker past its limits (NaN rows), with its rates: nothing round."""
    s = sweep(load(CRANK), np.radians(np.linspace(-140, 140, 281)))
    return s, motion(s)


# -- the table ---------------------------------------------------------------------


def test_columns_in_order_with_rates_and_the_sweeps_own_arrays(rocker):
    s, m = rocker
    table = columns(s, ["C", "B"], motion=m)
    assert list(table) == (["theta2", "valid", "time", "flagged"]
                           + [f"{p}.{k}" for p in "CB" for k in ("x", "y", "vx", "vy", "ax", "ay")])
    np.testing.assert_array_equal(table["theta2"], s.inputs["theta2"])  # radians
    np.testing.assert_array_equal(table["valid"], s.valid)
    np.testing.assert_array_equal(table["C.x"], s["C"][:, 0])
    np.testing.assert_array_equal(table["B.ay"], m.acceleration["B"][:, 1])
    np.testing.assert_array_equal(table["time"], m.time)
    assert table["valid"].dtype == bool and table["flagged"].dtype == bool
    assert not s.valid.all()


def test_every_point_by_default_and_branches_where_they_change_or_when_asked():
    c = load(CRANK)
    s = sweep(c)
    assert not s.events
    assert list(columns(s)) == ["theta2", "valid"] + [f"{p}.{xy}" for p in s.points
                                                      for xy in "xy"]
    assert "C.branch" in columns(s, [], branches=True)
    whole = circuit(c)
    assert whole.events and list(columns(whole, ["C"])) == ["theta2", "valid", "C.branch",
                                                            "C.x", "C.y"]
    assert "C.branch" not in columns(whole, ["C"], branches=False)
    assert set(columns(whole, [])["C.branch"]) == {0.0, 1.0}


def test_inputs_given_replace_the_sweeps_values():
    s = sweep(a_crank("theta"), [0.0, np.pi / 2])
    assert columns(s, [], inputs={"theta": [0, 90]})["theta"].tolist() == [0.0, 90.0]
    with pytest.raises(ValueError, match="inputs must give the sweep's inputs"):
        columns(s, inputs={"phi": [0, 90]})
    with pytest.raises(ValueError, match=r"must have shape \(2,\)"):
        columns(s, inputs={"theta": [0, 90, 180]})


def test_an_input_with_the_name_of_a_column_is_refused_not_overwritten():
    s = sweep(a_crank("valid"), [0.0, 1.0])
    with pytest.raises(ConstructionError, match="column 'valid' would be written twice"):
        columns(s)
    s = sweep(a_crank("time"), [0.0, 1.0])
    assert list(columns(s, [])) == ["time", "valid"]  # no clash without rates
    with pytest.raises(ConstructionError, match="column 'time'"):
        columns(s, [], motion=motion(s))


def test_a_motion_of_another_sweep_is_refused_and_of_the_same_sweep_made_twice_taken():
    c = a_crank("theta")
    s = sweep(c, [0.0, 1.0, 2.0])
    own = columns(s, motion=motion(s))
    again = columns(s, motion=motion(sweep(c, [0.0, 1.0, 2.0])))
    assert own.keys() == again.keys()
    for name in own:
        np.testing.assert_array_equal(own[name], again[name])
    for other in ([0.0, 1.0, 2.5], [0.0, 1.0]):
        with pytest.raises(ValueError, match="motion is of another sweep"):
            columns(s, motion=motion(sweep(c, other)))


def test_an_unknown_point_is_named():
    with pytest.raises(KeyError, match="did you mean 'A'"):
        columns(sweep(a_crank("theta"), [0.0]), ["AA"])


def a_four_bar(rocker_pivot_x, *, coupler=5.0, rocker=5.0):
    """A four-bar with ground pivots at (0, 0) and (rocker_pivot_x, 1/3), crank 10."""
    c = geokin.Construction("four-bar")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", rocker_pivot_x, 1 / 3)  # not a round number: exactness shows
    c.polar("A", "O2", 10, "theta")
    c.circle_circle("B", ("A", "O4"), (coupler, rocker), branch="left")
    return c


@pytest.mark.parametrize("pivot_x", [40.0, 15.0], ids=["never", "partly"])
def test_ground_points_are_known_at_every_sample_moving_ones_only_where_assembled(
        tmp_path, pivot_x):
    s = sweep(a_four_bar(pivot_x), np.linspace(0, 2 * np.pi, 73))
    assert not s.valid.all() and s.valid.any() == (pivot_x == 15.0)
    table = columns(s, motion=motion(s))
    assert (table["O4.x"] == pivot_x).all() and (table["O4.y"] == 1 / 3).all()
    assert (table["O2.x"] == 0).all() and (table["O2.y"] == 0).all()
    for rate in ("vx", "vy", "ax", "ay"):  # a ground point stands still
        assert (table[f"O4.{rate}"] == 0).all(), rate
    # a moving point is unknown where the mechanism cannot be assembled, even one found
    # there (the crank pin A, before B fails)
    for name in ("A.x", "A.y", "B.x", "B.vx"):
        assert np.isnan(table[name][~s.valid]).all(), name
        assert np.isfinite(table[name][s.valid]).all(), name
    for suffix in EXPORT_FORMATS:  # and every file says the same, exactly
        back = READ[suffix](export_sweep(s, tmp_path / f"four-bar{suffix}", ["O4", "B"]))
        assert (back["O4.y"] == 1 / 3).all(), suffix
        assert np.isnan(back["B.y"][~s.valid]).all(), suffix


def wrapped(angle):
    """Return angles wrapped to (-180, 180] degrees."""
    return np.degrees(np.angle(np.exp(1j * np.radians(angle))))


def test_link_angles_and_rates_match_the_four_bar_closed_form():
    """Seed 004's open four-bar over two turns: angles to 1e-9 deg, unwrapped; the rates
    as accurate as geokin.motion states at every unflagged sample."""
    s = sweep(load(FOURBAR), np.linspace(0, 4 * np.pi, 1441))
    m = motion(s, speed=2 * np.pi)
    links = ["crank", "coupler", "rocker"]
    radians = columns(s, [], motion=m, links=links)
    assert list(radians) == ["theta2", "valid", "time", "flagged"] + [
        f"{link}.{k}" for link in links for k in ("angle", "omega", "alpha")]
    table = columns(s, [], motion=m, links=links, degrees=True)
    for name, column in radians.items():
        if name.split(".")[-1] in ("theta2", "angle", "omega", "alpha"):
            np.testing.assert_array_equal(table[name], np.degrees(column), err_msg=name)
    t2 = s.inputs["theta2"]
    t3, t4, w3, w4, a3, a4 = fourbar_closed_form(t2, 10.55, 25, 14, 24, 2 * np.pi)
    # the crank runs on to 720 degrees; the others rock, each within one turn
    np.testing.assert_allclose(table["crank.angle"], np.degrees(t2), rtol=0, atol=1e-9)
    for link, theta in (("coupler", t3), ("rocker", t4)):
        angle = table[f"{link}.angle"]
        assert np.abs(wrapped(angle - np.degrees(theta))).max() <= 1e-9, link
        assert np.abs(np.diff(angle)).max() < 2 and np.ptp(angle) < 180, link
    ok = ~table["flagged"]
    assert ok.all()
    w = 2 * np.pi
    fastest = np.max(np.abs([w + 0 * t2, w3, w4]), axis=0)
    largest = np.fmax(np.max(np.abs([a3, a4]), axis=0), fastest**2)
    for link, omega, alpha in (("crank", w, 0), ("coupler", w3, a3), ("rocker", w4, a4)):
        assert (np.abs(radians[f"{link}.omega"] - omega) <= 1e-7 * fastest)[ok].all(), link
        assert (np.abs(radians[f"{link}.alpha"] - alpha) <= 1e-5 * largest)[ok].all(), link


def test_slider_columns_match_the_offset_slider_crank_closed_form():
    """Crank 20, rod 70, guide 10 above the crank's pivot from (0, 10) along +x."""
    s = sweep(load(SLIDER_CRANK))
    m = motion(s, speed=2 * np.pi)
    table = columns(s, [], motion=m, sliders=["slider"], degrees=True)
    assert list(table)[-3:] == ["slider.position", "slider.velocity", "slider.acceleration"]
    x, v, a = slider_crank_closed_form(s.inputs["theta"], 20, 70, 10, 2 * np.pi)
    np.testing.assert_allclose(table["slider.position"], x, rtol=0, atol=1e-12 * 70)
    ok = ~table["flagged"]
    assert ok.all()
    fastest = np.fmax(20 * 2 * np.pi, np.abs(v))
    largest = np.fmax(20 * (2 * np.pi) ** 2, np.abs(a))
    assert (np.abs(table["slider.velocity"] - v) <= 1e-7 * fastest).all()
    assert (np.abs(table["slider.acceleration"] - a) <= 1e-5 * largest).all()
    # lengths stay lengths in degrees; without a motion only the position
    assert list(columns(s, [], sliders=["slider"]))[-1] == "slider.position"


def test_links_and_sliders_are_named_and_given_only_when_asked():
    s = sweep(load(SLIDER_CRANK), np.linspace(0, np.pi, 5))
    assert not any(k.endswith((".angle", ".position")) for k in columns(s))
    with pytest.raises(KeyError, match="no link 'crnk'; did you mean 'crank'"):
        columns(s, [], links=["crnk"])
    with pytest.raises(KeyError, match="no slider 'crank'"):
        columns(s, [], sliders=["crank"])
    # degrees converts the angle inputs too, unless they are given
    assert columns(s, [], degrees=True)["theta"].tolist() == pytest.approx([0, 45, 90, 135, 180])
    given = columns(s, [], degrees=True, inputs={"theta": [0, 1, 2, 3, 4]})
    assert given["theta"].tolist() == [0, 1, 2, 3, 4]


# -- the formats round trip exactly --------------------------------------------------


@pytest.mark.parametrize("suffix", EXPORT_FORMATS)
def test_a_sweep_reads_back_exactly_from_every_format(tmp_path, rocker, suffix):
    s, m = rocker
    table = columns(s, motion=m, branches=True)
    path = export_sweep(s, tmp_path / f"rocker{suffix}", motion=m, branches=True)
    assert path == tmp_path / f"rocker{suffix}"
    back = READ[suffix](path)
    assert list(back) == list(table)
    for name, column in table.items():
        if suffix == ".npz":
            assert back[name].dtype == column.dtype, name
        # float equality, NaN where a sample cannot be assembled
        np.testing.assert_array_equal(back[name], column.astype(float), err_msg=name)


@given(hnp.arrays(np.float64, st.integers(0, 20), elements=st.floats(width=64)))
def test_any_float_reads_back_exactly_from_csv(values):
    text = io.StringIO()
    write_csv({"x": values}, text)
    lines = text.getvalue().splitlines()
    assert lines[0] == "x"
    back = np.array([float(v) for v in lines[1:]])
    np.testing.assert_array_equal(back, values)
    numbers = ~np.isnan(values)
    assert np.array_equal(np.signbit(back[numbers]), np.signbit(values[numbers]))  # -0 too


@given(hnp.arrays(np.float64, st.integers(0, 20), elements=st.floats(width=64)))
def test_any_float_reads_back_exactly_from_json_or_as_null(values):
    text = io.StringIO()
    write_json({"x": values}, text, values_per_write=3)
    back = json.loads(text.getvalue())["x"]
    assert [v if np.isfinite(v) else None for v in values.tolist()] == back


def test_csv_keeps_its_format():
    text = io.StringIO()
    write_csv({"theta": [0.0, 22.5, 1e16, 1e-320], "valid": np.array([True, False, True, True]),
               "x": [np.nan, -0.0, 0.1 + 0.2, 2.0 ** 70]}, text, rows_per_write=3)
    assert text.getvalue() == ("theta,valid,x\n0,1,nan\n22.5,0,-0\n1e+16,1,0.30000000000000004\n"
                               "1e-320,1,1.1805916207174113e+21\n")


def csv_cell_by_cell(table):
    """The CSV of a table written one value at a time with repr, the reference."""
    lines = [",".join(table)]
    for row in zip(*table.values(), strict=True):
        lines.append(",".join(("1" if v else "0") if isinstance(v, np.bool_)
                              else shortest_text(v) for v in row))
    return "\n".join(lines) + "\n"


def test_the_csv_of_a_sweep_is_the_text_of_repr_cell_by_cell_and_reads_back_bit_for_bit():
    # the six-bar past a turn with its rates and link angles: numbers of every length,
    # ground columns of one value, and samples that cannot be assembled (nan)
    s = sweep(load(SIXBAR), np.radians(np.linspace(-30, 400, 2001)))
    table = columns(s, motion=motion(s), links=[k.name for k in s.construction.links], degrees=True)
    table["far"] = np.where(np.arange(len(s)) % 3, 1e-9, 3e17) * table["theta"]  # by repr
    expected = csv_cell_by_cell(table)
    for rows in (500, 10_000):
        text = io.StringIO()
        write_csv(table, text, rows_per_write=rows)
        assert text.getvalue() == expected
    text = io.StringIO()
    write_csv({name: column[:40] for name, column in table.items()}, text, rows_per_write=3)
    assert text.getvalue() == "".join(expected.splitlines(keepends=True)[:41])
    binary = io.BytesIO()
    write_csv(table, binary, rows_per_write=300)
    assert binary.getvalue() == expected.encode("ascii")
    back = np.loadtxt(io.StringIO(expected), delimiter=",", skiprows=1)
    for i, column in enumerate(table.values()):
        np.testing.assert_array_equal(back[:, i], column.astype(float))
    # JSON writes repr's text too, with its .0, and null where not a finite number
    text = io.StringIO()
    write_json(table, text, values_per_write=700)
    assert text.getvalue() == "{" + ", ".join(
        json.dumps(name) + ": [" + ", ".join(
            ("true" if v else "false") if isinstance(v, np.bool_)
            else repr(float(v)) if np.isfinite(v) else "null" for v in column) + "]"
        for name, column in table.items()) + "}\n"


def test_trace_json_writes_null_for_what_is_not_a_finite_number():
    stream = io.StringIO()
    write_json({"t": np.arange(5.0), "valid": np.array([1, 0, 1, 1, 1], bool),
                "x": np.array([1.5, np.nan, np.inf, -np.inf, 1e300])}, stream,
               values_per_write=2)
    assert json.loads(stream.getvalue()) == {
        "t": [0, 1, 2, 3, 4], "valid": [True, False, True, True, True],
        "x": [1.5, None, None, None, 1e300]}


def test_a_name_that_csv_must_quote_reads_back():
    text = io.StringIO()
    names = ["a,b", 'say "x"', "line\nbreak", "plain"]
    write_csv({name: [1.0] for name in names}, text)
    assert list(csv.reader(io.StringIO(text.getvalue()))) == [names, ["1"] * 4]
    assert text.getvalue().endswith(",plain\n1,1,1,1\n")


# -- NPZ: any column name ---------------------------------------------------------------


CLASHING = ["file", "allow_pickle", "args", "kwds", "allow_zip64", "mmap_mode"]


def test_npz_takes_columns_named_as_the_arguments_of_savez_and_load(tmp_path):
    table = {name: np.arange(3.0) + i for i, name in enumerate(CLASHING)}
    table["valid"] = np.array([True, False, True])
    path = export_sweep(table, tmp_path / "clash.npz")
    back = read_npz(path)
    assert list(back) == list(table)
    for name, column in table.items():
        assert back[name].dtype == column.dtype
        np.testing.assert_array_equal(back[name], column)
    archive = io.BytesIO()
    write_npz(table, archive)
    assert archive.getvalue()[:2] == b"PK"


def test_a_sweep_whose_input_is_named_file_exports_to_npz_from_python_and_the_cli(
        tmp_path, capsys):
    names = ("file", "allow_pickle", "args")
    s = sweep(a_crank(*names), {name: np.linspace(0, 1, 4) for name in names})
    back = read_npz(export_sweep(s, tmp_path / "inputs.npz"))
    for name in names:
        np.testing.assert_array_equal(back[name], s.inputs[name])
    script = tmp_path / "inputs.toml"
    script.write_text(geokin.dump(a_crank(*names)))
    assert main(["trace", str(script), "-o", str(tmp_path / "cli.npz")]) == 0
    assert list(read_npz(tmp_path / "cli.npz"))[:4] == [*names, "valid"]
    assert "wrote" in capsys.readouterr().err


def test_npz_refuses_python_objects_rather_than_pickling_them():
    with pytest.raises(ValueError, match="pickle"):
        write_npz({"x": np.array([object()], dtype=object)}, io.BytesIO())


# -- files: by suffix, whole or not at all --------------------------------------------


def test_the_format_is_the_suffix_in_any_case(tmp_path):
    s = sweep(a_crank("theta"), [0.0, 1.0])
    for name in ("a.CSV", "b.Json", "c.NpZ"):
        assert export_sweep(s, str(tmp_path / name)) == tmp_path / name
    assert read_csv(tmp_path / "a.CSV")["A.x"].tolist() == s["A"][:, 0].tolist()
    assert read_json(tmp_path / "b.Json")["A.x"].tolist() == s["A"][:, 0].tolist()
    assert read_npz(tmp_path / "c.NpZ")["A.x"].tolist() == s["A"][:, 0].tolist()
    with pytest.raises(ValueError, match=r"use a \.csv, \.json or \.npz file"):
        export_sweep(s, tmp_path / "d.txt")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.CSV", "b.Json", "c.NpZ"]


def test_a_table_is_written_as_it_is_and_checked_first(tmp_path):
    path = tmp_path / "t.csv"
    export_sweep({"t": [1.0, 2.0], "u": np.array([True, False])}, path)
    assert path.read_text() == "t,u\n1,1\n2,0\n"
    with pytest.raises(TypeError, match="a table is written as it is"):
        export_sweep({"t": [1.0]}, path, ["A"])
    with pytest.raises(ValueError, match="columns of different lengths"):
        export_sweep({"t": [1.0], "u": [1.0, 2.0]}, path)
    with pytest.raises(ValueError, match="one-dimensional"):
        write_json({"t": [[1.0]]}, io.StringIO())
    assert path.read_text() == "t,u\n1,1\n2,0\n"


@pytest.mark.parametrize("suffix", EXPORT_FORMATS)
@pytest.mark.parametrize("error", [RuntimeError, KeyboardInterrupt])
def test_a_write_failing_midway_leaves_the_old_file(tmp_path, monkeypatch, suffix, error):
    path = tmp_path / f"old{suffix}"
    path.write_bytes(b"the old file")
    written = []

    def half_then_fail(columns, stream, **kwargs):
        stream.write(b"PK\x03\x04" if "b" in stream.mode else "theta,valid\n0,1\n")
        stream.flush()
        written.extend(p.stat().st_size for p in tmp_path.iterdir() if p != path)
        raise error("midway")

    for writer in ("write_csv", "write_json", "write_npz"):
        monkeypatch.setattr(f"geokin.io.export.{writer}", half_then_fail)
    with pytest.raises(error, match="midway"):
        export_sweep(sweep(a_crank("theta"), [0.0, 1.0]), path)
    assert written[0] > 0  # a temporary file was being written, and is gone
    assert path.read_bytes() == b"the old file"
    assert [p.name for p in tmp_path.iterdir()] == [path.name]


def test_an_npz_failing_on_a_later_column_leaves_the_old_file_or_none(tmp_path):
    table = {"x": np.arange(1000.0), "bad": np.array([object()] * 1000, dtype=object)}
    path = tmp_path / "old.npz"
    path.write_bytes(b"the old file")
    with pytest.raises(ValueError, match="pickle"):
        export_sweep(table, path)
    assert path.read_bytes() == b"the old file"
    path.unlink()
    with pytest.raises(ValueError, match="pickle"):
        export_sweep(table, path)
    assert list(tmp_path.iterdir()) == []


# -- units: radians in Python, degrees on the command line ------------------------------


def test_python_exports_radians_and_the_command_line_degrees(tmp_path, capsys):
    s = sweep(load(SIXBAR))
    python = read_csv(export_sweep(s, tmp_path / "python.csv", ["M"]))
    np.testing.assert_array_equal(python["theta"], s.inputs["theta"])
    assert python["theta"].max() == pytest.approx(np.radians(1792))
    assert main(["trace", str(SIXBAR), "--points", "M", "-o", str(tmp_path / "cli.csv")]) == 0
    capsys.readouterr()
    cli = read_csv(tmp_path / "cli.csv")
    # the degrees asked for, digit for digit, not converted back from radians
    np.testing.assert_array_equal(cli["theta"], np.arange(0, 1800, 16))
    np.testing.assert_allclose(np.radians(cli["theta"]), python["theta"], rtol=1e-15)
    np.testing.assert_array_equal(cli["M.x"], python["M.x"])
    degrees = columns(s, ["M"], inputs={"theta": np.degrees(s.inputs["theta"])})
    np.testing.assert_allclose(degrees["theta"], cli["theta"], rtol=1e-15)
