"""Tolerance studies: draws, figures against independent computations, the command line."""

import json
import math
import os
import pathlib
import sys

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from mechanisms import offset_slider_crank
from PIL import Image

import geokin
from geokin import AnalysisError, ConstructionError, GeokinError, load, tolerance
from geokin.analysis.measures import refine_extreme
from geokin.analysis.tolerance import BLOCK_VARIANTS, draw_variants
from geokin.cli import main, usable_cores

CONSTRUCTIONS = pathlib.Path(__file__).resolve().parent.parent / "constructions"
FOURBAR = str(CONSTRUCTIONS / "fourbar_open.toml")
NOMINAL = {"a": 10.55, "b": 25.0, "c": 14.0, "d": 24.0}  # seed 004
PLUS_MINUS_3 = dict.fromkeys(NOMINAL, 3.0)


def fourbar():
    return geokin.load(FOURBAR)


def assembles(a, b, c, d):
    """Seed 004's four-bar assembles over a whole turn: |b - c| <= |A - O4| <= b + c.

    |A - O4| runs from |d - a| (crank along the ground, a sample) to d + a (a
    sample too, at 180 degrees), for a crank pivoted at O2 = (0, 0) and O4 = (d, 0).
    """
    return (np.abs(b - c) <= np.abs(d - a)) & (np.abs(d + a) <= b + c)


def margin(a, b, c, d):
    return np.minimum(np.abs(d - a) - np.abs(b - c), b + c - np.abs(d + a))


# -- the draws ----------------------------------------------------------------------


def test_variant_i_depends_on_the_seed_and_i_alone():
    whole = draw_variants(NOMINAL, PLUS_MINUS_3, 11, 0, 5000)
    cuts = [0, 1, 7, 1024, 1025, 3333, 5000]
    pieces = [draw_variants(NOMINAL, PLUS_MINUS_3, 11, lo, hi) for lo, hi in
              zip(cuts[:-1], cuts[1:], strict=True)]
    for name in NOMINAL:
        assert np.array_equal(np.concatenate([p[name] for p in pieces]), whole[name])
    # another parameter in the study leaves the others' draws as they were
    fewer = draw_variants(NOMINAL, {"a": 3.0, "c": 3.0}, 11, 0, 5000)
    assert np.array_equal(fewer["a"], whole["a"]) and np.array_equal(fewer["c"], whole["c"])
    # another seed, other draws; each parameter its own
    assert not np.array_equal(draw_variants(NOMINAL, PLUS_MINUS_3, 12, 0, 10)["a"],
                              whole["a"][:10])
    assert abs(np.corrcoef(whole["a"], whole["b"])[0, 1]) < 0.06


@pytest.mark.parametrize("distribution, std", [("normal", 1.0), ("uniform", 3 / math.sqrt(3))])
def test_the_draws_have_the_distribution_asked_for(distribution, std):
    n = 200_000
    values = draw_variants({"a": 10.0}, {"a": 3.0}, 5, 0, n, distribution)["a"]
    # mean within 5 standard errors; standard deviation within 2%
    assert abs(values.mean() - 10) < 5 * std / math.sqrt(n)
    assert values.std() == pytest.approx(std, rel=0.02)
    if distribution == "uniform":
        assert values.min() >= 7 and values.max() <= 13
        counts, _ = np.histogram(values, bins=10, range=(7, 13))
        assert counts.min() > 0.95 * n / 10
    else:
        # the 3-sigma convention: about 0.27% outside +-T
        outside = np.mean(np.abs(values - 10) > 3)
        assert outside == pytest.approx(0.0027, abs=0.0006)


# -- the figures --------------------------------------------------------------------


def test_assemblable_fraction_against_an_independent_monte_carlo():
    t = tolerance(fourbar(), PLUS_MINUS_3, n=4000, seed=4)
    # the same draws: every variant assembles exactly where the closed condition says
    d = t.draws()
    args = [d[k] for k in "abcd"]
    clear = np.abs(margin(*args)) > 1e-9
    assert np.array_equal(t.assembled[clear], assembles(*args)[clear])
    # and the same distribution drawn by numpy's own generator, within binomial error
    rng = np.random.default_rng(2024)
    m = 400_000
    draws = [NOMINAL[k] + rng.normal(0, 1.0, m) for k in "abcd"]
    expected = assembles(*draws).mean()
    assert expected == pytest.approx(0.88, abs=0.01)
    error = math.sqrt(expected * (1 - expected) / t.variants + expected * (1 - expected) / m)
    assert abs(t.assemblable_fraction - expected) < 4 * error
    assert t.assemblable_error == pytest.approx(
        math.sqrt(t.assemblable_fraction * (1 - t.assemblable_fraction) / 4000))
    assert t.failures == {"B": int((~t.assembled).sum())}


def test_uniform_draws_against_the_closed_condition():
    t = tolerance(fourbar(), PLUS_MINUS_3, n=3000, seed=9, distribution="uniform")
    rng = np.random.default_rng(7)
    m = 400_000
    expected = assembles(*[NOMINAL[k] + rng.uniform(-3, 3, m) for k in "abcd"]).mean()
    error = math.sqrt(expected * (1 - expected) / t.variants)
    assert abs(t.assemblable_fraction - expected) < 4.5 * error


def placed_extreme(values, sign, closed):
    """The largest (sign 1) or least (-1) value, by the parabola through the extreme sample.

    Its neighbours; over a ``closed`` sweep (whole turns) values that end
    where they began have their ends as each other's neighbours.
    """
    i, n = int(np.argmax(sign * values)), len(values)
    back = closed and abs(values[0] - values[-1]) <= 1e-12 * max(1.0, abs(values[0]))
    if 0 < i < n - 1:
        around = values[i - 1:i + 2]
    elif back:
        around = np.array([values[n - 2], values[i], values[1]])
    else:
        return values[i]
    top = refine_extreme([-1.0, 0.0, 1.0], around)[1]
    return top if sign * top > sign * values[i] else values[i]


def test_path_statistics_and_strokes_are_those_of_the_variants_swept_one_by_one():
    c = fourbar()
    t = tolerance(c, {"a": 1.0, "c": 1.0, "d": 1.0}, n=1500, seed=3)
    draws = t.draws()
    nominal = geokin.sweep(c)["B"]
    deviations = []
    for i in range(t.variants):
        s = geokin.sweep(c.compile().with_parameters({k: v[i] for k, v in draws.items()}))
        assert bool(s.valid.all()) == t.assembled[i]
        if s.valid.all():
            deviations.append(np.hypot(*(s["B"] - nominal).T))
    deviations = np.array(deviations)
    spread = t.paths["B"]
    assert np.allclose(spread.mean, deviations.mean(axis=0), rtol=1e-9, atol=1e-12)
    assert np.allclose(spread.std, deviations.std(axis=0), rtol=1e-7, atol=1e-12)
    assert np.allclose(spread.worst, deviations.max(axis=0), rtol=1e-9, atol=1e-12)
    assert np.allclose(spread.envelope, np.percentile(deviations, 95, axis=0), rtol=1e-9,
                       atol=1e-12)
    assert np.allclose(spread.median, np.median(deviations, axis=0), rtol=1e-9, atol=1e-12)
    worst = int(np.argmax(deviations.max(axis=1)))
    assert spread.worst_variant == np.flatnonzero(t.assembled)[worst]
    # the rocker's swing in closed form: it turns back where crank and coupler lie in
    # line, stretched (O2 to B is a + b) and folded (b - a); placed between the samples
    # one degree apart, not at a sample, which would be up to 1e-4 rad short
    a, b, rocker, ground = draws["a"], NOMINAL["b"], draws["c"], draws["d"]

    def at_rocker(reach):
        return np.arccos((ground**2 + rocker**2 - reach**2) / (2 * ground * rocker))

    swing = np.abs(at_rocker(a + b) - at_rocker(b - a))[t.assembled]
    np.testing.assert_allclose(t.strokes["rocker.angle"].assembled, swing, rtol=0, atol=1e-5)
    assert t.valid_fraction.max() <= 1 and t.valid_fraction.min() >= t.assemblable_fraction


def graze_and_gap():
    """A four-bar that cannot be assembled near theta = 0 and whose roots meet at pi.

    Crank a, ground 30, coupler b, rocker a + 30 - b: every variant of a and b
    is stretched straight at theta = pi, where B changes branch, and with b
    near 32 none reaches theta = 0.
    """
    c = geokin.Construction("graze and gap")
    c.parameter("a", 10.0)
    c.parameter("b", 32.0)
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 30, 0)
    c.polar("A", "O2", "a", "theta")
    c.circle_circle("B", ("A", "O4"), ("b", "a + 30 - b"), branch="left")
    return c


def test_the_paths_drawn_are_those_of_the_variants_swept_one_by_one():
    # the study tracks branches only along the variants that assemble everywhere: the
    # variants it draws are swept again whole, those that cannot be assembled too
    c = graze_and_gap()
    values = np.linspace(0, 2 * np.pi, 145)
    t = tolerance(c, {"a": 0.3, "b": 0.3}, n=50, seed=2, values=values)
    draws = t.draws()
    drawn = t.sample_paths["B"]
    assert not t.assembled.any()
    for i in range(len(drawn)):
        alone = geokin.sweep(c.compile().with_parameters({k: v[i] for k, v in draws.items()}),
                             values)
        assert alone.events  # B changes branch at pi: its first branch held would differ
        np.testing.assert_allclose(drawn[i], alone["B"], rtol=0, atol=1e-12)


def test_where_variants_fail_is_where_each_fails_alone():
    # an intersection with a segment is missing where its root is off the segment:
    # its branch decides that, so it is tracked along every variant
    c = fourbar()
    c.segment_circle("C", ("A", "B"), "O4", "c", branch="second")
    values = np.linspace(0, 4 * np.pi, 181)
    t = tolerance(c, PLUS_MINUS_3, n=300, seed=1, values=values)
    draws = t.draws()
    failures: dict[str, int] = {}
    valid = np.zeros(len(values))
    for i in range(t.variants):
        s = geokin.sweep(c.compile().with_parameters({k: v[i] for k, v in draws.items()}),
                         values)
        valid += s.valid
        if not s.valid.all():
            node = c.compile().steps[s.failed_step[np.argmin(s.valid)] - 1].node.name
            failures[node] = failures.get(node, 0) + 1
    assert failures and t.failures == failures
    np.testing.assert_array_equal(t.valid_fraction, valid / t.variants)


def test_the_figures_do_not_depend_on_how_the_variants_are_cut():
    c = fourbar()
    n = 2 * BLOCK_VARIANTS + 300
    one = tolerance(c, PLUS_MINUS_3, n=n, seed=8, chunk_size=BLOCK_VARIANTS)
    other = tolerance(c, PLUS_MINUS_3, n=n, seed=8, chunk_size=10 * BLOCK_VARIANTS)
    assert_same(one, other)


def assert_same(one, other):
    assert np.array_equal(one.assembled, other.assembled)
    assert np.array_equal(one.valid_fraction, other.valid_fraction)
    assert one.failures == other.failures
    for p in one.paths:
        for field in ("mean", "std", "median", "envelope", "worst"):
            assert np.array_equal(getattr(one.paths[p], field), getattr(other.paths[p], field),
                                  equal_nan=True), field
        assert one.paths[p].worst_variant == other.paths[p].worst_variant
        assert np.array_equal(one.sample_paths[p], other.sample_paths[p], equal_nan=True)
    for k in one.strokes:
        assert np.array_equal(one.strokes[k].values, other.strokes[k].values, equal_nan=True)
    assert one.to_dict() == other.to_dict()


def rocker_stroke(a, b, c, d):
    """The rocker's swing between its two limit positions (crank and coupler in line)."""
    def angle(length):
        return np.arccos((d ** 2 + c ** 2 - length ** 2) / (2 * d * c))
    return angle(b + a) - angle(b - a)


def test_sensitivity_is_the_derivative_times_the_tolerance():
    t = tolerance(fourbar(), {"a": 0.5, "b": 0.2, "c": 0.1, "d": 0.3}, n=10, seed=0)
    ranked = dict(t.sensitivity["rocker.angle"])
    for k, tol in t.tolerances.items():
        h = 1e-6
        up, down = dict(NOMINAL), dict(NOMINAL)
        up[k] += h
        down[k] -= h
        exact = (rocker_stroke(**up) - rocker_stroke(**down)) / (2 * h) * tol
        # the sampled stroke's extremes lie on samples, within a degree of the true ones
        assert ranked[k] == pytest.approx(exact, rel=0.03, abs=1e-4)
    sizes = [abs(v) for _, v in t.sensitivity["rocker.angle"]]
    assert sizes == sorted(sizes, reverse=True)
    # a crank pin moves by exactly the change of the crank's length: |dA/da| = 1
    c = geokin.Construction("crank")
    c.parameter("r", 10)
    c.parameter("unused", 1)
    c.input("theta")
    c.fixed("O", 0, 0)
    c.polar("A", "O", "r", "theta")
    c.trace("A")
    crank = tolerance(c, {"r": 0.4, "unused": 2.0}, n=5)
    assert crank.sensitivity["A.path"] == (("r", pytest.approx(0.4, rel=1e-9)), ("unused", 0.0))


def test_a_study_reads_back_as_json_and_pickles():
    import pickle

    t = tolerance(fourbar(), {"c": 0.5}, n=50, seed=2)
    data = json.loads(json.dumps(t.to_dict(degrees=True), allow_nan=False))
    assert data["variants"] == 50 and data["assemblable_fraction"] == 1.0
    assert len(data["paths"]["B"]["mean"]) == 361 and data["inputs"]["theta2"][-1] == 360
    stroke = data["strokes"]["rocker.angle"]
    assert stroke["unit"] == "deg"
    assert stroke["nominal"] == pytest.approx(math.degrees(rocker_stroke(**NOMINAL)), abs=0.05)
    assert sum(stroke["histogram"]["counts"]) == 50
    copy = pickle.loads(pickle.dumps(t))
    assert_same(t, copy)
    assert repr(t).startswith("<Tolerance of 'four-bar, open': 50 variants, 100.0% assemble")


@pytest.mark.parametrize("tolerances, kwargs, error, message", [
    ({"e": 1}, {}, ConstructionError, r"cannot tolerance 'e': no such parameter "
                                      r"\(parameters: a, b, c, d\)"),
    ({"B": 1}, {}, ConstructionError, r"'B' \(it is a point\)"),
    ({"theta2": 1}, {}, ConstructionError, r"\(it is an input\)"),
    ({}, {}, AnalysisError, "at least one parameter"),
    ({"a": 0}, {}, AnalysisError, "tolerance of 'a' must be a positive number"),
    ({"a": float("nan")}, {}, AnalysisError, "positive number"),
    ({"a": "1"}, {}, AnalysisError, "tolerance of 'a' must be a number, got '1'"),
    ({"a": True}, {}, AnalysisError, "tolerance of 'a' must be a number, got True"),
    ({"a": np.True_}, {}, AnalysisError, "tolerance of 'a' must be a number"),
    ({"a": b"1"}, {}, AnalysisError, "tolerance of 'a' must be a number"),
    ({"a": 1}, {"n": 0}, AnalysisError, "number of variants"),
    ({"a": 1}, {"seed": -1}, AnalysisError, "seed"),
    ({"a": 1}, {"distribution": "gauss"}, AnalysisError, "unknown distribution 'gauss'"),
    ({"a": 1}, {"points": ["Q"]}, ConstructionError, "no point 'Q'"),
])
def test_bad_arguments_say_what_is_wrong(tolerances, kwargs, error, message):
    with pytest.raises(error, match=message):
        tolerance(fourbar(), tolerances, **kwargs)


def test_a_cluster_without_dask_names_the_extra(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    with pytest.raises(GeokinError, match=r"pip install 'geokin\[dask\]'"):
        tolerance(fourbar(), {"a": 1}, n=10, client=object())
    status = main(["tolerance", FOURBAR, "--tol", "a=1", "-n", "10", "--workers", "1"])
    assert status == 2 and "pip install 'geokin[dask]'" in capsys.readouterr().err


def test_a_real_local_cluster_gives_the_figures_found_in_process():
    distributed = pytest.importorskip("dask.distributed")
    c = fourbar()
    n = 2 * BLOCK_VARIANTS + 100
    here = tolerance(c, PLUS_MINUS_3, n=n, seed=5)
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        there = tolerance(c, PLUS_MINUS_3, n=n, seed=5, client=client,
                          chunk_size=BLOCK_VARIANTS)
    assert_same(here, there)


def test_a_local_cluster_is_quiet_has_geokin_and_leaves_dask_as_it_was():
    dask = pytest.importorskip("dask")
    pytest.importorskip("dask.distributed")
    from geokin.analysis.tolerance import QUIET_CLUSTER, local_cluster

    before = {key: dask.config.get(key) for key in QUIET_CLUSTER}

    def seen():
        return ({key: dask.config.get(key) for key in QUIET_CLUSTER},
                "geokin.analysis.tolerance" in sys.modules)

    with local_cluster(1) as client:
        on_workers = list(client.run(seen).values())
    assert on_workers == [(QUIET_CLUSTER, True)]
    assert {key: dask.config.get(key) for key in QUIET_CLUSTER} == before != QUIET_CLUSTER


@pytest.mark.skipif(usable_cores() < 2, reason="--workers 2 needs two cores")
def test_the_command_runs_on_two_local_workers(capsys):
    pytest.importorskip("dask.distributed")
    argv = ["tolerance", FOURBAR, "--tol", "c=2", "--tol", "d=2", "-n", "1200", "--json"]
    status, here, _ = run(capsys, *argv)
    status_there, there, err = run(capsys, *argv, "--workers", "2")
    assert status == status_there == 0 and err == ""
    assert json.loads(here) == json.loads(there)


# -- pictures and the command line ----------------------------------------------------


def run(capsys, *argv):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return status, out, err


def test_the_command_prints_json_with_the_figures(capsys):
    status, out, err = run(capsys, "tolerance", FOURBAR, "--tol", "a=3", "--tol", "b=3",
                           "--tol", "c=3", "--tol", "d=3", "-n", "1500", "--seed", "4",
                           "--json")
    assert status == 0 and err == ""
    data = json.loads(out)
    python = tolerance(fourbar(), PLUS_MINUS_3, n=1500, seed=4).to_dict(degrees=True)
    assert data["variants"] == 1500
    assert data["assemblable_fraction"] == python["assemblable_fraction"]
    for key in ("paths", "strokes", "sensitivity", "failures", "valid_fraction"):
        assert data[key] == python[key], key
    assert data["inputs"]["theta2"][:3] == [0, 1, 2]


def test_the_command_prints_text_and_draws_a_picture(capsys, tmp_path):
    path = tmp_path / "spread.png"
    status, out, err = run(capsys, "tolerance", FOURBAR, "--tol", "c=0.5", "--tol", "d=0.5",
                           "-n", "300", "--distribution", "uniform", "-o", path)
    assert status == 0 and err == f"wrote {path}\n"
    assert "300 variants, uniform (anywhere in +-T), seed 0" in out
    assert "assemble at every sample: 300 of 300 (100.00% +- 0.00%)" in out
    assert "stroke of crank.angle: 360 deg in every variant" in out
    assert "rocker.angle: " in out
    image = np.asarray(Image.open(path).convert("L"), dtype=float)
    assert image.shape[0] > 300 and image.std() > 10  # drawn, not blank


def test_the_histogram_counts_whole_variants():
    import matplotlib.pyplot as plt

    from geokin.plotting.tolerance import plot_histogram

    t = tolerance(fourbar(), {"c": 0.5}, n=30, seed=2)
    fig, ax = plt.subplots()
    plot_histogram(t, "rocker.angle", ax=ax)
    ticks = ax.get_yticks()
    plt.close(fig)
    assert ticks.size >= 2 and np.array_equal(ticks, np.round(ticks))


def test_no_picture_is_drawn_of_a_study_where_nothing_assembles(capsys, tmp_path):
    path = tmp_path / "none.png"
    status, _, err = run(capsys, "tolerance", FOURBAR, "--set", "c=2", "--tol", "a=0.01",
                         "-n", "20", "-o", path)
    assert status == 1 and not path.exists()
    # c = 2 is shorter than the crank's reach: the nominal design misses at theta2 = 0
    assert err == (f"geokin: error: {FOURBAR}: no variant assembles at every sample, nor does "
                   "the nominal design (at theta2 = 0 deg, node 'B': no intersection: the "
                   "curves do not meet): sweep where it assembles with --range (geokin analyze "
                   "gives its limits); no picture is drawn\n")


@pytest.mark.parametrize("argv, message", [
    (["--tol", "a3"], "--tol 'a3': expected NAME=VALUE, such as --tol a=10.5"),
    (["--tol", "a=x"], "--tol 'a=x': expected a number after '=', got 'x'"),
    (["--tol", "a=-1"], "--tol a=-1: the tolerance must be a positive number"),
    (["--tol", "a=1", "--tol", "a=2"], "--tol gives 'a' twice"),
    (["--tol", "e=1"], "--tol e: no parameter 'e' (parameters: a, b, c, d)"),
    ([], "--tol NAME=T is required: the parameters to draw, with their tolerances"),
    (["--tol", "a=1", "--set", "bb=3"],
     "--set: no parameter 'bb'; did you mean 'b'? (parameters: a, b, c, d)"),
    (["--tol", "a=1", "--set", "b"], "--set 'b': expected NAME=VALUE, such as --set a=10.5"),
    (["--tol", "a=1", "--set", "b=inf"], "--set 'b=inf': expected a finite number"),
    (["--tol", "a=1", "--histogram", "rocker"],
     "--histogram: no stroke 'rocker'; did you mean 'rocker.angle'? (strokes: crank.angle, "
     "coupler.angle, rocker.angle)"),
    (["--tol", "a=1", "--percentile", "100"], "--percentile must be between 0 and 100, got 100"),
])
def test_bad_options_exit_2_with_one_line_naming_the_option(capsys, argv, message):
    status, out, err = run(capsys, "tolerance", FOURBAR, "-n", "20", *argv)
    assert status == 2 and out == ""
    assert err == f"geokin: error: {message}\n"


def test_set_overrides_a_parameter_in_every_command(capsys, tmp_path):
    status, out, _ = run(capsys, "trace", FOURBAR, "--set", "c=15", "--set", "b=24",
                         "--points", "B,O4")
    rows = np.array([line.split(",") for line in out.splitlines()[1:]], dtype=float)
    assert status == 0
    assert np.allclose(np.hypot(rows[:, 2] - rows[:, 4], rows[:, 3] - rows[:, 5]), 15)
    status, out, _ = run(capsys, "analyze", FOURBAR, "--set", "a=30", "--json")
    four_bar = json.loads(out)["four_bars"][0]
    assert status == 0 and four_bar["input"] == pytest.approx(30)
    assert four_bar["class"] == "rocker-crank"  # a crank of 30 no longer turns fully
    status, out, _ = run(capsys, "tolerance", FOURBAR, "--set", "d=26", "--tol", "a=0.1",
                         "-n", "20", "--json")
    data = json.loads(out)
    assert data["set"] == {"d": 26.0} and data["nominal"] == {"a": 10.55}
    assert data["strokes"]["rocker.angle"]["nominal"] == pytest.approx(
        math.degrees(rocker_stroke(10.55, 25, 14, 26)), abs=0.05)
    # a saved report says which design it studied
    status, out, _ = run(capsys, "tolerance", FOURBAR, "--set", "d=26", "--tol", "a=0.1",
                         "-n", "20")
    assert status == 0 and "\nset: d = 26\n" in out
    status, _, err = run(capsys, "plot", FOURBAR, "--set", "b=100", "-o", tmp_path / "x.png")
    # the fixed pivots are still drawn, with why nothing assembles
    assert status == 1 and "no sample can be assembled" in err
    assert (tmp_path / "x.png").exists()


def test_a_design_that_never_assembles_exits_1(capsys):
    status, out, err = run(capsys, "tolerance", FOURBAR, "--set", "b=100", "--tol", "a=1",
                           "-n", "10")
    assert status == 1 and out == ""
    assert "no sample can be assembled" in err


@given(st.integers(0, 2**32 - 1), st.floats(1e-4, 3.0), st.booleans())
def test_strokes_near_the_nominal_link_are_those_of_the_arctangent(seed, spread, rising):
    """Small turns from the nominal, larger ones, beyond a quarter turn; links that stretch.

    The nominal angle either rises (its extremes at the ends) or swings,
    coming near its extremes several times; some rows turn not at all, one
    exactly atan(0.5), where the way the extremes are picked changes.
    """
    from geokin.analysis.tolerance import FROM_REFERENCE, _stroke_from

    rng = np.random.default_rng(seed)
    n, count = 121, 40
    s = np.linspace(0, 6, n)
    base = (np.unwrap(np.linspace(0, 3, n) + 0.3 * np.sin(s)) if rising
            else 0.4 * np.sin(3 * s) + 2 * np.pi * rng.integers(-3, 4))
    turn = spread * rng.normal(size=(count, 1)) * np.sin(s + rng.normal())
    turn[1] = 0.0
    turn[2] = np.arctan(FROM_REFERENCE) * np.sign(np.sin(s + 0.5))
    radius = rng.uniform(0.5, 2, (count, n))  # the links stretch from sample to sample
    dx, dy = radius * np.cos(base + turn), radius * np.sin(base + turn)
    dx[0, rng.integers(n)] = np.nan
    ux, uy = np.cos(base), np.sin(base)
    # the links' own angles, continuous along the samples: a turn beyond half a
    # turn from the nominal is not cut there
    angle = base + turn
    expected = np.array([placed_extreme(row, 1, False) - placed_extreme(row, -1, False)
                         for row in angle])
    found = _stroke_from((ux, uy, base), dx, dy)
    np.testing.assert_allclose(found[1:], expected[1:], rtol=0, atol=1e-11)
    assert np.isnan(found[0])


def test_a_link_opposite_the_nominal_has_the_nominal_stroke():
    """A link pointing the other way (a negative length drawn) turns as the nominal does.

    Its difference from the nominal is half a turn, where rounding flips the
    arctangent between +pi and -pi from sample to sample: followed along the
    samples, the stroke is the nominal's, not a turn more.
    """
    from geokin.analysis.tolerance import _stroke_from

    base = np.linspace(0, 2 * np.pi, 361)
    ux, uy = np.cos(base), np.sin(base)
    found = _stroke_from((ux, uy, base), -0.5 * ux[None], -0.5 * uy[None])
    np.testing.assert_allclose(found, [2 * np.pi], rtol=0, atol=1e-12)


def test_a_study_where_no_variant_assembles_is_printed_then_exits_1(capsys):
    # the nominal design assembles at some samples only; none of its variants at all
    status, out, err = run(capsys, "tolerance", FOURBAR, "--set", "c=2", "--tol", "a=0.01",
                           "-n", "20")
    assert status == 1 and "no variant assembles at every sample" in out
    assert "stroke of rocker.angle: no variant assembles" in out
    assert err.count("\n") == 1 and "no variant assembles" in err


def test_set_on_an_input_says_it_is_swept(capsys):
    status, _, err = run(capsys, "trace", FOURBAR, "--set", "theta2=5")
    assert status == 2 and "'theta2' is an input, swept over its range" in err


def test_one_variant_prints_its_own_stroke_not_the_nominal(capsys):
    from geokin.analysis.tolerance import draw_variants

    status, out, _ = run(capsys, "tolerance", FOURBAR, "--tol", "a=1", "-n", "1", "--seed", "3")
    assert status == 0 and ": 1 variant, " in out
    a = float(draw_variants(geokin.load(FOURBAR).compile().parameters, {"a": 1.0}, 3, 0, 1,
                            "normal")["a"][0])
    line = next(x for x in out.splitlines() if x.startswith("stroke of rocker.angle"))
    own = float(line.split(": ")[1].split(" deg")[0])
    nominal = math.degrees(rocker_stroke(**NOMINAL))
    assert own == pytest.approx(math.degrees(rocker_stroke(**{**NOMINAL, "a": a})), abs=0.05)
    assert abs(own - nominal) > 0.1
    printed = float(line.split("(nominal ")[1].split(" deg)")[0])  # measured at the samples
    assert printed == pytest.approx(nominal, abs=0.05)


@pytest.mark.parametrize("tolerances", [("beta=0.5", "r=0.2"), ("beta=0.5", "r=1e-4")])
def test_a_parameter_that_changes_nothing_is_ranked_zero(capsys, tolerances):
    # turning the guide turns the whole slider-crank, its crank turning fully: the rod's
    # stroke does not change with the guide's angle, whatever rounding the differences
    # leave, and whatever the other parameter's tolerance
    script = str(CONSTRUCTIONS / "slider_crank_inclined.toml")
    status, out, _ = run(capsys, "tolerance", script, "--tol", tolerances[0], "--tol",
                         tolerances[1], "-n", "200")
    line = next(x for x in out.splitlines() if x.strip().startswith("rod.angle:"))
    assert status == 0 and line.strip().startswith("rod.angle: r +") and line.endswith(
        "beta 0")


def test_a_tiny_real_sensitivity_is_not_taken_for_rounding(capsys):
    # the rod swings between asin((e - r) / l) and asin((e + r) / l) from the guide: a
    # longer rod swings less, by little for 1e-9
    script = str(CONSTRUCTIONS / "slider_crank_inclined.toml")
    status, out, _ = run(capsys, "tolerance", script, "--tol", "r=0.2", "--tol", "l=1e-9",
                         "-n", "50")
    line = next(x for x in out.splitlines() if x.strip().startswith("rod.angle:"))
    assert status == 0 and " l -" in line and not line.endswith(" l 0")


def test_only_parameters_given_in_degrees_are_labelled_deg(capsys, tmp_path):
    # e and h are lengths inside an angle (asin of their ratio, in degrees); gam is an
    # angle inside a distance; a stands both for a length and an angle
    script = tmp_path / "mixed.toml"
    script.write_text("""
[construction]
name = "mixed"
units = "mm"
[parameters]
e = 10
h = 35
gam = 20
a = 5
[inputs.t]
kind = "angle"
range = [0, 90]
samples = 19
[points]
O = { op = "fixed", at = [0, 0] }
[points.G]
op = "polar"
origin = "O"
distance = "h * sin(radians(gam))"
angle = "degrees(asin(e / h))"
[points.A]
op = "polar"
origin = "G"
distance = "a"
angle = "t + a"
[links]
crank = ["G", "A"]
""")
    status, out, _ = run(capsys, "tolerance", str(script), "--tol", "e=0.1", "--tol", "h=0.1",
                         "--tol", "gam=0.5", "--tol", "a=0.1", "-n", "20")
    assert status == 0
    assert ("tolerances: e = 10 +- 0.1, h = 35 +- 0.1, gam = 20 +- 0.5 deg, a = 5 +- 0.1 "
            "(mm)\n") in out


def test_an_angle_parameters_tolerance_is_given_in_degrees(capsys):
    script = str(CONSTRUCTIONS / "slider_crank_inclined.toml")
    status, out, _ = run(capsys, "tolerance", script, "--tol", "beta=0.5", "-n", "20")
    assert status == 0 and "tolerances: beta = 30 +- 0.5 deg\n" in out
    status, out, _ = run(capsys, "tolerance", script, "--tol", "beta=0.5", "--tol", "r=0.2",
                         "-n", "20")
    assert "tolerances: beta = 30 +- 0.5 deg, r = 20 +- 0.2 (mm)\n" in out


def test_a_block_that_keeps_its_place_on_its_guide_has_no_stroke(capsys):
    """The seed six-bar's block does not slide: its stroke is the coordinates' rounding.

    It reads 0, no parameter changes it, and the picture's histogram shows a
    stroke that does spread.
    """
    from geokin.plotting.tolerance import spread_output

    six = load(CONSTRUCTIONS / "sixbar.toml")
    t = tolerance(six, {"l3": 1, "l4": 1}, n=200, seed=3)
    block = t.strokes["block.position"]
    assert block.nominal == 0 and not block.assembled.any()
    assert dict(t.sensitivity["block.position"]) == {"l3": 0.0, "l4": 0.0}
    assert spread_output(t) != "block.position"
    status, out, _ = run(capsys, "tolerance", str(CONSTRUCTIONS / "sixbar.toml"),
                         "--tol", "l3=1", "--tol", "l4=1", "-n", "200")
    assert status == 0
    assert "stroke of block.position: 0 mm in every variant" in out
    assert "block.position: none of the parameters changes it" in out


def test_a_tolerance_that_crosses_zero_is_warned_of(capsys):
    status, _, err = run(capsys, "tolerance", FOURBAR, "--tol", "a=100", "-n", "50")
    assert status == 0
    assert err == ("geokin: warning: --tol a=100: about 38% of the variants draw 'a' below "
                   "zero, where its nominal value is 10.55\n")
    status, _, err = run(capsys, "tolerance", FOURBAR, "--set", "a=-10.55", "--tol", "a=1e308",
                         "--distribution", "uniform", "-n", "50")
    assert err.startswith("geokin: warning: --tol a=1e+308: about 50% of the variants draw "
                          "'a' above zero, where its nominal value is -10.55\n")
    for argv in (["--tol", "a=3"], ["--tol", "a=10", "--distribution", "uniform"]):
        status, _, err = run(capsys, "tolerance", FOURBAR, *argv, "-n", "50")
        assert status == 0 and err == ""
    # a guide's angle in degrees may turn negative
    status, _, err = run(capsys, "tolerance", str(CONSTRUCTIONS / "slider_crank_inclined.toml"),
                         "--tol", "beta=40", "-n", "50")
    assert status == 0 and err == ""


def test_a_study_over_more_than_the_nominal_design_reaches_says_so_and_what_to_do(capsys):
    """The triple rocker turns its input within its limits only, not the declared full turn."""
    script = str(CONSTRUCTIONS / "triple_rocker_crank.toml")
    status, out, err = run(capsys, "tolerance", script, "--tol", "r2=0.05", "-n", "20",
                           "--range", 0, 360)
    assert status == 1 and "0 of 20" in out
    hi = float(geokin.limits(load(script)).intervals[0][1].value)
    # the first sample past the limit, with samples one degree apart from 0
    first = math.ceil(np.degrees(hi))
    assert err.endswith(f"no variant assembles at every sample, nor does the nominal design "
                        f"(at theta2 = {first} deg, node 'C': no intersection: the curves do not "
                        "meet): sweep where it assembles with --range (geokin analyze gives its "
                        "limits)\n")
    status, _, _ = run(capsys, "tolerance", script, "--tol", "r2=0.05", "-n", "20",
                       "--range", -130, 130)
    assert status == 0


def test_a_study_of_variants_that_never_assemble_says_so_in_one_line(capsys):
    status, _, err = run(capsys, "tolerance", FOURBAR, "--tol", "a=1e300", "-n", "50")
    assert status == 1
    # the sign warning and the error; no numpy warning, and no word of a picture
    assert err.splitlines()[1:] == [f"geokin: error: {FOURBAR}: no variant assembles at "
                                    "every sample"]
    assert err.splitlines()[0].startswith("geokin: warning: --tol a=1e+300: about 50%")


def test_more_workers_than_cores_are_refused_before_any_start(capsys, monkeypatch):
    import geokin.cli

    def no_start(workers):
        raise AssertionError("a cluster was started")

    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0}, raising=False)
    monkeypatch.setattr(os, "cpu_count", lambda: 1)
    monkeypatch.setattr(geokin.cli, "local_cluster", no_start)
    status, out, err = run(capsys, "tolerance", FOURBAR, "--tol", "a=1", "--workers", "2")
    assert status == 2 and out == ""
    assert err == ("geokin: error: --workers 2: more than the 1 core this machine gives the "
                   "program; to run on more, join a cluster with --scheduler\n")


def test_a_nominal_without_a_stroke_beside_variants_with_one(capsys, tmp_path):
    """A crank of 13.01 fails at a few samples; some variants assemble everywhere.

    The text says the nominal has no stroke (it raised a TypeError), and the
    picture's histogram is a stroke that spreads, not the crank's rounding.
    """
    from geokin.plotting.tolerance import spread_output

    path = tmp_path / "edge.png"
    status, out, err = run(capsys, "tolerance", FOURBAR, "--tol", "a=0.05", "--set", "a=13.01",
                           "-n", "300", "-o", path)
    assert status == 0 and path.exists() and err == f"wrote {path}\n"
    line = next(x for x in out.splitlines() if x.startswith("stroke of rocker.angle"))
    assert line.startswith("stroke of rocker.angle: nominal none (not assembled at every "
                           "sample), mean ")
    c = load(FOURBAR).compile().with_parameters({"a": 13.01})
    t = tolerance(c, {"a": 0.05}, n=300)
    assert spread_output(t) != "crank.angle"
    # the crank, found everywhere but turning a design that cannot, has no stroke either
    assert "crank.angle" in t.strokes
    assert all(math.isnan(spread.nominal) for spread in t.strokes.values())
    import matplotlib.pyplot as plt

    from geokin.plotting.tolerance import plot_histogram

    fig, ax = plt.subplots()
    plot_histogram(t, ax=ax)
    labels = ax.get_legend_handles_labels()[1]
    plt.close(fig)
    assert not any(label.startswith("nominal") for label in labels)  # no "nominal nan"


def test_a_slider_cranks_stroke_and_its_sensitivity_are_those_of_the_closed_form():
    """Stroke sqrt((rod + r)^2 - e^2) - sqrt((rod - r)^2 - e^2), and its derivative in e.

    Sampled a degree apart, the extremes fall between samples: taken at the
    samples, the stroke was 1.2e-3 short and its sensitivity to the offset 3%.
    """
    r, rod, e = 40.0, 120.0, 20.0
    t = tolerance(offset_slider_crank(r, rod, e), {"e": 1.0}, n=64, seed=2)
    stroke = np.sqrt((rod + r) ** 2 - e**2) - np.sqrt((rod - r) ** 2 - e**2)
    slope = -e / np.sqrt((rod + r) ** 2 - e**2) + e / np.sqrt((rod - r) ** 2 - e**2)
    assert t.strokes["slider.position"].nominal == pytest.approx(stroke, abs=1e-5)
    [(name, effect)] = t.sensitivity["slider.position"]
    assert name == "e" and effect == pytest.approx(slope * 1.0, rel=1e-4)
    # every variant's stroke, from its own offset
    drawn = t.draws()["e"][t.assembled]
    expected = np.sqrt((rod + r) ** 2 - drawn**2) - np.sqrt((rod - r) ** 2 - drawn**2)
    np.testing.assert_allclose(t.strokes["slider.position"].assembled, expected, atol=1e-5)


def test_an_open_sweeps_ends_are_not_each_others_neighbours():
    """x (1 - x)(1 + 2x) on [0, 1] is 0 at both ends and tops 0.528163 inside.

    Only a sweep that ends whole turns on from where it began may join its
    ends; this one, sampled every 0.1, is open, whatever its values do.
    """
    from geokin.analysis.tolerance import _closes, _range_between_samples

    x = np.linspace(0, 1, 11)
    f = (x * (1 - x) * (1 + 2 * x))[None]
    top = (2 + np.sqrt(28)) / 12  # where 1 + 2x - 6x^2 = 0
    assert _range_between_samples(f, False)[0] == pytest.approx(
        top * (1 - top) * (1 + 2 * top), abs=2e-4)
    c = fourbar()
    assert _closes(c.compile(), {"theta2": np.linspace(0, 2 * np.pi, 5)})
    assert not _closes(c.compile(), {"theta2": np.linspace(0, np.pi, 5)})
    assert not _closes(c.compile(), {"theta2": np.zeros(5)})
