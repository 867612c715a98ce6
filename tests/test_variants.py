"""Design variants swept at once: each variant exactly as it sweeps alone.

Every check compares a batch of variants with each variant swept, moved or
searched on its own (a construction holding that variant's values), or
with the four-bar's closed forms; branch tracking must never run from one
variant into the next.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import geokin
from geokin import Construction, ConstructionError
from geokin.circuits import limits
from geokin.kinematics import _variant_sizes, motion

NAMES = ("a", "b", "c", "d")


def named_fourbar(name, near=False, lengths=(10.0, 35.0, 30.0, 40.0)):
    """A four-bar whose lengths a, b, c, d are parameters: crank O2-A, dyad A-B-O4."""
    c = Construction(name)
    for key, value in zip(NAMES, lengths, strict=True):
        c.parameter(key, float(value))
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", "d", 0)
    c.polar("A", "O2", "a", "theta")
    if near:
        c.circle_circle("B", ("A", "O4"), ("b", "c"), near=(10, 30))
    else:
        c.circle_circle("B", ("A", "O4"), ("b", "c"), branch="left")
    return c


def parametric_fourbar(near=False, lengths=(10.0, 35.0, 30.0, 40.0)):
    """A four-bar with named lengths, a second dyad that folds, and a slider."""
    c = named_fourbar("four-bar variants", near, lengths)
    # roots that meet and part as the crank turns: a line through A and B cut by
    # a circle about O4
    c.line_circle("C", ("A", "B"), "O4", "c", branch="first")
    c.link("crank", "O2", "A")
    c.link("coupler", "A", "B")
    c.link("rocker", "O4", "B")
    c.slider("block", "C", ("A", "B"))
    return c


def sample_path(kind, rng):
    """Input values along a path of one kind: two turns, a random walk, or coarse steps."""
    return {"turns": np.linspace(0, 4 * np.pi, 181),
            "random walk": np.cumsum(rng.normal(0.3, 0.5, 60)),
            "coarse": np.linspace(0, 2 * np.pi, 9)}[kind]


def random_lengths(rng, count):
    """Lengths of which many cannot be assembled over a whole turn, some at change points."""
    a = rng.uniform(5, 15, count)
    d = rng.uniform(20, 40, count)
    b = rng.uniform(10, 40, count)
    c = np.where(rng.random(count) < 0.3, a + d - b, rng.uniform(5, 40, count))
    return {"a": a, "b": b, "c": np.where(c > 0, c, 10.0), "d": d}


def built_alone(lengths, near=False):
    """Return a function building variant i afresh, with its lengths as the parameters' values."""
    return lambda i: parametric_fourbar(near, [lengths[k][i] for k in NAMES])


def assert_same_as_alone(batch, construction_of, values):
    """Each variant of ``batch`` equals the sweep of its own construction, exactly."""
    for i in range(batch.variants):
        alone = geokin.sweep(construction_of(i), values)
        np.testing.assert_array_equal(batch.valid[i], alone.valid)
        np.testing.assert_array_equal(batch.failed_step[i], alone.failed_step)
        np.testing.assert_array_equal(batch.reason_code[i], alone.reason_code)
        for node in alone.branches:
            np.testing.assert_array_equal(batch.branches[node][i], alone.branches[node])
        for point in alone.points:
            np.testing.assert_allclose(batch[point][i], alone[point], rtol=0, atol=1e-12)
        mine = batch.variant(i).events
        assert [(e.node, e.index, e.before, e.after) for e in mine] == [
            (e.node, e.index, e.before, e.after) for e in alone.events]
        np.testing.assert_allclose([e.fraction for e in mine],
                                   [e.fraction for e in alone.events], rtol=0, atol=1e-9)


@pytest.mark.parametrize("path", ["turns", "random walk", "coarse"])
def test_300_variants_equal_their_own_sweeps(path):
    rng = np.random.default_rng({"turns": 1, "random walk": 2, "coarse": 3}[path])
    values = sample_path(path, rng)
    c = parametric_fourbar()
    lengths = random_lengths(rng, 300)
    batch = geokin.sweep(c, values, parameters=lengths)
    assert batch.valid.shape == (300, len(values)) and batch["C"].shape == (300, len(values), 2)
    # the batch holds what makes the test worth running: variants that cannot be
    # assembled somewhere, and branch changes
    assert 0 < batch.valid.all(axis=1).sum() < 300 and len(batch.events) > 50
    assert_same_as_alone(batch, built_alone(lengths), values)


def assert_untracked_only_where_incomplete(batch, tracked):
    """``batch`` (swept with ``track_incomplete=False``) is ``tracked`` but for the
    positions, branches and events of variants that cannot be assembled everywhere."""
    np.testing.assert_array_equal(batch.valid, tracked.valid)
    np.testing.assert_array_equal(batch.failed_step, tracked.failed_step)
    np.testing.assert_array_equal(batch.reason_code, tracked.reason_code)
    for i in np.flatnonzero(tracked.valid.all(axis=1)):
        for node in tracked.branches:
            np.testing.assert_array_equal(batch.branches[node][i], tracked.branches[node][i])
        for point in tracked.points:
            np.testing.assert_array_equal(batch[point][i], tracked[point][i])
        assert batch.variant(i).events == tracked.variant(i).events


@pytest.mark.parametrize("path", ["turns", "random walk", "coarse"])
def test_variants_untracked_where_incomplete_keep_what_decides_validity(path):
    # B's branch decides where C (a line through A and B cut by a circle) is found:
    # it is tracked along every variant; C's, which decides nothing, only along the
    # variants found everywhere
    rng = np.random.default_rng({"turns": 1, "random walk": 2, "coarse": 3}[path])
    values = sample_path(path, rng)
    c = parametric_fourbar()
    lengths = random_lengths(rng, 300)
    tracked = geokin.sweep(c, values, parameters=lengths)
    batch = geokin.sweep(c, values, parameters=lengths, track_incomplete=False)
    assert_untracked_only_where_incomplete(batch, tracked)
    # C's branches along the incomplete variants are its first ones held, which is what
    # spares the work: not tracked, they differ from tracking somewhere
    incomplete = ~tracked.valid.all(axis=1)
    held = batch.branches["C"][incomplete]
    assert (held == held[:, :1]).all()
    if path != "coarse":
        assert (held != tracked.branches["C"][incomplete]).any()


def test_a_branch_that_decides_where_a_later_point_is_found_is_tracked_along_every_variant():
    # crank 10, ground 30, coupler 32, rocker 8: B cannot be assembled within 45 degrees
    # of theta = 0, and its roots meet at theta = pi (a + d = b + c), where its branch
    # changes. D, built on B, is found where |B - O2| <= 2 e, which differs from one
    # root of B to the other after pi
    c = Construction("graze and gap")
    c.parameter("e", 13.0)
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 30, 0)
    c.polar("A", "O2", 10, "theta")
    c.circle_circle("B", ("A", "O4"), (32, 8), branch="left")
    c.circle_circle("D", ("B", "O2"), ("e", "e"), branch="left")
    values = np.linspace(0, 2 * np.pi, 145)
    sizes = {"e": [11.5, 12.0, 13.0, 14.0, 30.0]}
    tracked = geokin.sweep(c, values, parameters=sizes)
    assert not tracked.valid.all(axis=1).any()
    assert [e.node for e in tracked.variant(0).events] == ["B"]
    batch = geokin.sweep(c, values, parameters=sizes, track_incomplete=False)
    assert_untracked_only_where_incomplete(batch, tracked)
    np.testing.assert_array_equal(batch.branches["B"], tracked.branches["B"])
    # what makes this worth checking: B held on its first branch, D would be found
    # at other samples
    held = geokin.engine.evaluate(c, {"theta": values}, len(values), held={"B": 0})
    alone = geokin.sweep(c.compile().with_parameters({"e": 13.0}), values)
    assert (held.valid != alone.valid).any()


def test_a_coupler_point_leaves_the_dyad_untracked_where_it_folds():
    # a point in the frame of A and B is missing only where they coincide, which B's
    # branch cannot decide (both roots are b from A): B itself is then left untracked
    c = named_fourbar("coupler point")
    c.local("P", "A", "B", (20, 8))
    rng = np.random.default_rng(11)
    lengths = random_lengths(rng, 200)
    values = np.linspace(0, 4 * np.pi, 181)
    tracked = geokin.sweep(c, values, parameters=lengths)
    batch = geokin.sweep(c, values, parameters=lengths, track_incomplete=False)
    assert_untracked_only_where_incomplete(batch, tracked)
    incomplete = ~tracked.valid.all(axis=1)
    held = batch.branches["B"][incomplete]
    assert (held == held[:, :1]).all()
    assert (held != tracked.branches["B"][incomplete]).any()


def test_a_frame_on_a_point_one_root_can_reach_keeps_the_root_tracked():
    # O4 and A = (s, -3) are B's centres, F = (4, -3) is not: at s = -4 one root of B
    # is exactly F, where the frame F -> B has no direction. B's roots meet at s = 0
    # (|A - O4| = 8 - 5), where its branch changes, and it cannot be assembled beyond
    # s = -12.4: which root is F at s = -4 is the tracked branch's business
    for branch in ("left", "right"):
        c = Construction("frame on a point a root passes through")
        c.parameter("k", 1.0)
        c.input("s", kind="length", range=(-14, 3))
        c.fixed("O4", 0, 0)
        c.fixed("A", "s", -3)
        c.fixed("F", 4, -3)
        c.circle_circle("B", ("A", "O4"), (8, 5), branch=branch)
        c.local("P", "F", "B", ("k", 0))
        values = np.arange(3.0, -14.5, -0.5)
        sizes = {"k": [1.0, 2.0]}
        tracked = geokin.sweep(c, values, parameters=sizes)
        assert not tracked.valid.all(axis=1).any()
        # held on its first branch, B would be found elsewhere than F at s = -4
        at = int(np.flatnonzero(values == -4)[0])
        held = geokin.engine.evaluate(c, {"s": values}, len(values),
                                      held={"B": ("left", "right").index(branch)})
        assert held.valid[at] != tracked.valid[0, at]
        assert_untracked_only_where_incomplete(
            geokin.sweep(c, values, parameters=sizes, track_incomplete=False), tracked)


def test_a_pause_at_a_change_point_among_variants_that_fold():
    # the crank stops at pi, where a + 30 = b + c for the first variant: its roots
    # meet at two samples in a row, looked into among the samples of the variants the
    # quick test leaves open (the second folds)
    c = Construction("change point")
    for name, value in {"a": 10.0, "b": 32.0, "c": 8.0}.items():
        c.parameter(name, value)
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 30, 0)
    c.polar("A", "O2", "a", "theta")
    c.circle_circle("B", ("A", "O4"), ("b", "c"), branch="left")
    values = np.concatenate([np.linspace(np.pi / 2, np.pi, 46),
                             np.linspace(np.pi, 3 * np.pi / 2, 46)])
    sizes = {"b": [32.0, 25.0], "c": [8.0, 20.0]}
    batch = geokin.sweep(c, values, parameters=sizes)
    assert_same_as_alone(batch, lambda i: c.compile().with_parameters(
        {k: v[i] for k, v in sizes.items()}), values)


DEPENDENTS = {
    # points in frames of B and one of its centres, A or O4: blind to B's branch
    "coupler point": lambda c: c.local("P", "A", "B", (12, 5)),
    "along B-O4": lambda c: c.along("R", ("B", "O4"), 3),
    "polar off A-B": lambda c: c.polar("T", "O4", 6, 0.5, reference=("A", "B")),
    # in the frame of O2 and B, which B's roots are not equally far from
    "point on O2-B": lambda c: c.local("Q", "O2", "B", (5, 2)),
    # a second dyad on B, found on one root of B where not on the other
    "dyad on B": lambda c: c.circle_circle("D", ("B", "O2"), ("e", "e"), branch="left"),
    # roots off the segment A..B are missing: its own branch decides where it is found
    "segment cut": lambda c: c.segment_circle("S", ("A", "B"), "O4", "c", branch="first"),
}


@given(st.lists(st.floats(-3, 3), min_size=2, max_size=25), st.integers(0, 2**32 - 1),
       st.lists(st.sampled_from(sorted(DEPENDENTS)), unique=True, max_size=4),
       st.booleans())
def test_variants_untracked_where_incomplete_along_random_paths(steps, seed, dependents,
                                                                 dyad_on_point):
    values = np.cumsum(steps)
    rng = np.random.default_rng(seed)
    lengths = {**random_lengths(rng, 6), "e": rng.uniform(5, 30, 6)}
    c = parametric_fourbar()
    c.parameter("e", 10.0)
    for name in dependents:
        DEPENDENTS[name](c)
    if dyad_on_point and "coupler point" in dependents:
        c.circle_circle("F", ("P", "O4"), ("e", 25), branch="right")
    tracked = geokin.sweep(c, values, parameters=lengths)
    assert_untracked_only_where_incomplete(
        geokin.sweep(c, values, parameters=lengths, track_incomplete=False), tracked)


def test_each_variant_chooses_its_own_starting_root():
    c = parametric_fourbar(near=True)
    rng = np.random.default_rng(5)
    lengths = random_lengths(rng, 100)
    # with O4 on either side of O2, the root above the ground line is left of A -> O4
    # for some variants and right of it for the others
    lengths["d"] = lengths["d"] * np.where(rng.random(100) < 0.5, -1, 1)
    values = np.linspace(0, 2 * np.pi, 73)
    batch = geokin.sweep(c, values, parameters=lengths)
    assert_same_as_alone(batch, built_alone(lengths, near=True), values)
    # not all on one side: the sketch position chose per variant
    first = [batch.branches["B"][i][np.argmax(batch.valid[i])] for i in range(100)
             if batch.valid[i].any()]
    assert 0 < sum(first) < len(first)


@given(st.lists(st.floats(-3, 3), min_size=2, max_size=25),
       st.integers(0, 2**32 - 1))
def test_variants_along_random_paths(steps, seed):
    values = np.cumsum(steps)
    lengths = random_lengths(np.random.default_rng(seed), 5)
    c = parametric_fourbar()
    batch = geokin.sweep(c, values, parameters=lengths)
    assert_same_as_alone(batch, built_alone(lengths), values)


def test_variant_construction_holds_its_values():
    c = parametric_fourbar()
    batch = geokin.sweep(c, [0.0, 1.0], parameters={"a": [8.0, 9.0], "d": 41.0})
    one = batch.variant(1)
    assert one.construction.parameters["a"] == 9.0 and one.construction.parameters["d"] == 41.0
    assert one.construction.parameters["b"] == 35.0
    np.testing.assert_allclose(np.hypot(*one["A"].T), 9.0)
    np.testing.assert_array_equal(batch["O4"][:, :, 0], 41.0)
    assert batch.variant(-1).construction.parameters["a"] == 9.0
    with pytest.raises(IndexError):
        batch.variant(2)


def test_flat_and_back():
    c = parametric_fourbar()
    lengths = random_lengths(np.random.default_rng(7), 20)
    batch = geokin.sweep(c, np.linspace(0, 2 * np.pi, 37), parameters=lengths)
    flat = batch.flat()
    assert flat.variants is None and len(flat) == 20 * 37
    again = flat.as_variants(20)
    np.testing.assert_array_equal(again["C"], batch["C"])
    np.testing.assert_array_equal(again.valid, batch.valid)
    assert again.events == batch.events


@pytest.mark.parametrize("parameters, message", [
    ({"e": [1.0]}, "no parameter 'e'"),
    ({"theta": [1.0]}, "it is an input"),
    ({"a": [1.0, 2.0], "b": [1.0, 2.0, 3.0]}, "different numbers of values"),
    ({"a": [[1.0, 2.0]]}, "one-dimensional"),
    ({"a": []}, "at least one variant"),
    ({"a": ["x"]}, "not numbers"),
    ({"a": [10.0, np.nan]}, "must be finite numbers; variant 1 is nan"),
    ({"b": np.inf}, "must be finite numbers; it is inf"),
])
def test_bad_variants_are_refused(parameters, message):
    with pytest.raises(ConstructionError, match=message):
        geokin.sweep(parametric_fourbar(), [0.0, 1.0], parameters=parameters)


def test_motion_of_variants_equals_each_alone():
    c = parametric_fourbar()
    lengths = random_lengths(np.random.default_rng(11), 40)
    values = np.linspace(0, 2 * np.pi, 91)
    batch = motion(geokin.sweep(c, values, parameters=lengths), speed=3.0)
    assert batch.velocity["B"].shape == (40, 91, 2) and batch.flagged.shape == (40, 91)
    for i in range(40):
        alone = motion(geokin.sweep(built_alone(lengths)(i), values), speed=3.0)
        for point in ("A", "B", "C"):
            np.testing.assert_allclose(batch.velocity[point][i], alone.velocity[point],
                                       rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(batch.acceleration[point][i], alone.acceleration[point],
                                       rtol=1e-12, atol=1e-12)
        for link in ("crank", "coupler", "rocker"):
            np.testing.assert_allclose(batch.angle[link][i], alone.angle[link], atol=1e-12)
            np.testing.assert_allclose(batch.angular_velocity[link][i],
                                       alone.angular_velocity[link], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(batch.slider_velocity["block"][i],
                                   alone.slider_velocity["block"], rtol=1e-12, atol=1e-12)
        np.testing.assert_array_equal(batch.flagged[i], alone.flagged)


def closed_form_limits(a, b, c, d):
    """The crank angles where the coupler and rocker stretch out or fold (|b -+ c| from O4)."""
    found = []
    for reach in (b + c, abs(b - c)):
        cosine = (a * a + d * d - reach * reach) / (2 * a * d)
        if -1 < cosine < 1:
            found += [np.arccos(cosine), -np.arccos(cosine)]
    return sorted(found)


def test_limits_of_variants_against_the_closed_form_and_each_alone():
    rng = np.random.default_rng(13)
    count = 300
    lengths = {"a": rng.uniform(5, 15, count), "b": rng.uniform(10, 40, count),
               "c": rng.uniform(5, 40, count), "d": rng.uniform(20, 40, count)}

    def fourbar(lengths):
        c = Construction("four-bar")
        for name, value in zip(NAMES, lengths, strict=True):
            c.parameter(name, float(value))
        c.input("theta", range=(-np.pi, np.pi))
        c.fixed("O2", 0, 0)
        c.fixed("O4", "d", 0)
        c.polar("A", "O2", "a", "theta")
        c.circle_circle("B", ("A", "O4"), ("b", "c"), branch="left")
        return c

    found = limits(fourbar((1, 1, 1, 1)), parameters=lengths)
    assert isinstance(found, tuple) and len(found) == count
    checked = nowhere = 0
    for i, mine in enumerate(found):
        a, b, cc, d = (lengths[k][i] for k in NAMES)
        expected = closed_form_limits(a, b, cc, d)
        values = sorted(v for pair in mine.as_values() for v in pair
                        if not np.isclose(abs(v), np.pi))
        if not mine.intervals:
            nowhere += 1
            # O4 is never within the dyad's reach: |A - O4| runs over |d - a| .. d + a
            assert a + d < abs(b - cc) or abs(d - a) > b + cc
            continue
        if mine.full_turn:
            assert expected == []
            continue
        np.testing.assert_allclose(np.sort(np.mod(values, 2 * np.pi)),
                                   np.sort(np.mod(expected, 2 * np.pi)), atol=1e-9)
        alone = limits(fourbar([lengths[k][i] for k in NAMES]))
        assert alone.full_turn == mine.full_turn
        np.testing.assert_allclose(alone.as_values(), mine.as_values(), rtol=0, atol=1e-12)
        assert [(lo.node, lo.kind, hi.node, hi.kind) for lo, hi in alone.intervals] == [
            (lo.node, lo.kind, hi.node, hi.kind) for lo, hi in mine.intervals]
        checked += 1
    assert checked > 100 and nowhere > 0


def test_limits_take_a_sweep_of_variants():
    c = parametric_fourbar()
    lengths = random_lengths(np.random.default_rng(17), 5)
    batch = geokin.sweep(c, np.linspace(0, 2 * np.pi, 5), parameters=lengths)
    by_sweep = limits(batch)
    by_values = limits(c, parameters=lengths)
    assert [f.as_values() for f in by_sweep] == [f.as_values() for f in by_values]


def test_closure_group_variants_equal_each_alone():
    def grouped(lengths):
        c = Construction("four-bar with a group")
        for name, value in zip(NAMES, lengths, strict=True):
            c.parameter(name, float(value))
        c.input("theta")
        c.fixed("O2", 0, 0)
        c.fixed("O4", "d", 0)
        c.polar("A", "O2", "a", "theta")
        c.closure("group", ["B"], [("A", "B", "b"), ("O4", "B", "c")], near={"B": (20, 25)})
        return c

    values = np.linspace(0, 2 * np.pi, 37)
    lengths = {"a": [10.0, 9.0, 12.0], "b": [35.0, 36.0, 33.0], "c": [30.0] * 3,
               "d": [40.0] * 3}
    batch = geokin.sweep(grouped((10, 35, 30, 40)), values, parameters=lengths)
    assert batch["B"].shape == (3, 37, 2)
    assert_same_as_alone(batch, lambda i: grouped([lengths[k][i] for k in NAMES]), values)


def test_limits_of_closure_group_variants_equal_each_alone():
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "constructions" / "stephenson3.toml"
            ).read_text()
    c = geokin.loads(text)
    cranks = [1.0, 2.0, 2.5]
    found = limits(c, parameters={"GF": cranks})
    for crank, mine in zip(cranks, found, strict=True):
        alone = limits(geokin.loads(text.replace("\nGF = 1\n", f"\nGF = {crank}\n")))
        assert mine.full_turn == alone.full_turn
        np.testing.assert_allclose(mine.as_values(), alone.as_values(), rtol=0, atol=1e-12)
    assert found[0].full_turn and not found[1].full_turn


def test_a_sweep_of_variants_shows_itself_and_says_which_sample_to_explain():
    c = parametric_fourbar()
    batch = geokin.sweep(c, np.linspace(0, 2 * np.pi, 19),
                         parameters={"c": [5.0, 30.0, 31.0]})
    page = batch._repr_html_()
    assert "3 variants" in page and "2 assemble at every sample" in page
    assert "parameter c" in page and page.count("<polyline") >= 1
    assert "3 variants" in motion(batch)._repr_html_()
    with pytest.raises(ValueError, match=r"variant\(i\)\.explain\(4\)"):
        batch.explain(4)
    assert "assembled" in batch.variant(1).explain(4)


def test_variants_of_a_length_input_are_looked_into_at_their_own_scale():
    # a point sliding along y = h, held by two circles: small and large variants together
    def build(h, r1, r2):
        c = Construction("graze")
        for name, value in (("h", h), ("r1", r1), ("r2", r2)):
            c.parameter(name, value)
        c.input("s", kind="length", range=(-3, 3))
        c.fixed("O4", 0, 0)
        c.fixed("A", "s", "h")
        c.circle_circle("B", ("A", "O4"), ("r1", "r2"), branch="left")
        return c

    small, large = (2.0, 3.0, 1.0), (2.0, 3000.0, 2998.0)
    # the roots of the small one meet at s = 0, inside a step whose ends look alike
    path = np.array([-2.001, -2.0, 2.0, 2.001])
    batch = geokin.sweep(build(*small), path, parameters={
        name: [a, b] for name, a, b in zip(("h", "r1", "r2"), small, large, strict=True)})
    for i, lengths in enumerate((small, large)):
        alone = geokin.sweep(build(*lengths), path)
        np.testing.assert_array_equal(batch.branches["B"][i], alone.branches["B"])
    assert batch.branches["B"][0].tolist() == [0, 0, 1, 1]


def test_paths_must_repeat_the_same_inputs():
    from geokin.engine import evaluate

    c = parametric_fourbar()
    with pytest.raises(ConstructionError, match="same values of input 'theta'"):
        evaluate(c, {"theta": np.array([0, 0.5, 1, 2, 2.5, 3.0])}, 6, paths=2,
                 parameters={"a": np.array([1.0, 2.0])})
    with pytest.raises(ConstructionError, match="cannot be 4 paths"):
        evaluate(c, {"theta": np.zeros(6)}, 6, paths=4, parameters={"a": np.ones(4)})


def test_paths_given_once_are_the_paths_repeated():
    from geokin.engine import evaluate

    c = parametric_fourbar()
    theta = np.linspace(0, 2 * np.pi, 7)
    lengths = {"a": np.array([1.0, 2.0, 9.0])}
    once = evaluate(c, {"theta": theta}, 21, paths=3, parameters=lengths)
    repeated = evaluate(c, {"theta": np.tile(theta, 3)}, 21, paths=3, parameters=lengths)
    assert once.inputs["theta"].shape == (21,)
    np.testing.assert_array_equal(once.valid, repeated.valid)
    for name in repeated.points:
        np.testing.assert_array_equal(once[name], repeated[name])
    np.testing.assert_array_equal(once.branches["B"], repeated.branches["B"])


@given(st.lists(st.tuples(*[st.floats(1, 60)] * 3, st.floats(1, 90)), min_size=1, max_size=6))
def test_a_design_has_the_size_its_row_of_variants_gives_it(lengths):
    """One design's size, found on numbers, equals its row of the variants' sizes.

    The variants include designs that fold (NaN at some samples) and designs that
    assemble nowhere (the largest coordinate stands in).
    """
    values = {name: [row[k] for row in lengths] for k, name in enumerate(NAMES)}
    swept = geokin.sweep(parametric_fourbar(), np.linspace(0, 2 * np.pi, 37),
                         parameters=values)
    rows = _variant_sizes(swept)
    for i in range(len(lengths)):
        assert _variant_sizes(swept.variant(i)).tolist() == [rows[i]]
