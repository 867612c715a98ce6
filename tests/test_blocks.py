"""A long sweep evaluated block by block gives what one sweep of all samples gives.

Blocks are made small here, so that their boundaries fall on branch changes,
on samples where roots meet, on gaps and on the turns of random paths; every
block must agree with the sweep of the whole path, exactly.
"""

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from mechanisms import coupler_fourbar, fourbar, sixbar

import geokin
from geokin.engine import sweep_in_blocks


def assert_blocks_equal_whole(construction, values, block):
    whole = geokin.sweep(construction, values)
    n = len(values)
    blocks = list(sweep_in_blocks(construction, lambda i, j: {"theta": values[i:j]}, n,
                                  block_samples=block))
    sizes = [len(b) for b in blocks]
    # a block is at least as long as asked (longer where roots meet at its seam)
    assert sum(sizes) == n and all(size >= min(block, n) for size in sizes[:-1])
    offsets = np.cumsum([0, *sizes[:-1]])
    joined = {name: np.concatenate([np.broadcast_to(b.branches[name], (len(b),))
                                    for b in blocks]) for name in whole.branches}
    for name, labels in joined.items():
        np.testing.assert_array_equal(labels, whole.branches[name], err_msg=name)
    np.testing.assert_array_equal(np.concatenate([b.valid for b in blocks]), whole.valid)
    np.testing.assert_array_equal(np.concatenate([b.reason_code for b in blocks]),
                                  whole.reason_code)
    for point in whole.points:
        np.testing.assert_allclose(np.concatenate([b[point] for b in blocks]), whole[point],
                                   rtol=0, atol=1e-12, err_msg=point)
    events = [(e.node, e.index + lo, e.before, e.after)
              for lo, b in zip(offsets, blocks, strict=True) for e in b.events]
    assert events == [(e.node, e.index, e.before, e.after) for e in whole.events]
    fractions = [e.fraction for b in blocks for e in b.events]
    np.testing.assert_allclose(fractions, [e.fraction for e in whole.events], atol=1e-9)


@pytest.mark.parametrize("block", [1, 2, 3, 5, 8, 64])
def test_a_parallelogram_through_its_change_points_at_block_edges(block):
    # change points at 0 and 180 degrees fall on samples (roots meeting at a sample)
    values = np.radians(np.arange(0.0, 1081.0, 10.0))
    assert_blocks_equal_whole(fourbar(10, 4, 10, 4), values, block)


@pytest.mark.parametrize("block", [2, 7, 50])
def test_the_seed_six_bar_over_five_turns(block):
    values = np.radians(np.linspace(0, 1800, 451))
    assert_blocks_equal_whole(sixbar(), values, block)


@pytest.mark.parametrize("block", [1, 4, 9])
def test_gaps_and_toggles_of_a_triple_rocker(block):
    values = np.linspace(0, 6 * np.pi, 200)
    assert_blocks_equal_whole(fourbar(7, 5, 6, 5), values, block)


@given(st.lists(st.floats(-1.5, 1.5), min_size=2, max_size=60),
       st.sampled_from([(10, 4, 10, 4), (7, 5, 6, 5), (24, 10.55, 25, 14), (10, 8, 3, 9)]),
       st.integers(1, 12))
def test_blocks_along_random_paths(steps, lengths, block):
    values = np.cumsum(steps)
    assert_blocks_equal_whole(fourbar(*lengths), values, block)


def test_blocks_of_a_closure_group():
    script = Path(__file__).resolve().parents[1] / "constructions" / "stephenson3.toml"
    construction = geokin.load(script)
    values = np.linspace(0, 4 * np.pi, 301)
    whole = geokin.sweep(construction, values)
    blocks = list(sweep_in_blocks(construction, lambda i, j: {"theta": values[i:j]}, 301,
                                  block_samples=37))
    for point in whole.points:
        np.testing.assert_allclose(np.concatenate([b[point] for b in blocks]), whole[point],
                                   rtol=0, atol=1e-9, err_msg=point)


def test_a_block_of_the_benchmark_four_bar_is_a_view_of_the_same_numbers():
    values = np.linspace(0, 2 * np.pi, 1000)
    assert_blocks_equal_whole(coupler_fourbar(), values, 333)


@pytest.mark.parametrize("block", [1, 2, 3])
def test_a_run_of_meeting_samples_across_a_seam(block):
    # the parallelogram's change point held over repeated samples: one meeting, whose
    # branch change comes after its last sample
    values = np.radians([0.0, 90, 270, 360, 360, 360, 420, 500, 540, 540, 600])
    assert_blocks_equal_whole(fourbar(10, 4, 10, 4), values, block)


@pytest.mark.parametrize("block", range(1, 15))
def test_a_dyad_held_folded_across_a_seam(block):
    # two inputs hold a dyad folded (|OB| = 6 + 4) over six samples while the crank
    # turns on: the roots stay met, and part after the last of them
    c = geokin.Construction("folded dyad")
    c.input("s", kind="length", range=(0, 10))
    c.input("theta")
    c.fixed("O", 0, 0)
    c.polar("B", "O", "s", "theta")
    c.circle_circle("C", ("O", "B"), (6, 4), branch="left")
    s = np.r_[8, 9, 10, [10] * 6, 9.9, 9.8, 9.7, 9.6, 9.5]
    theta = np.r_[0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 2.6, 3.6, 4.6, 5.6, 6.6]
    whole = geokin.sweep(c, {"s": s, "theta": theta})
    assert whole.events  # the fold is left onto the other branch
    blocks = list(sweep_in_blocks(c, lambda i, j: {"s": s[i:j], "theta": theta[i:j]}, s.size,
                                  block_samples=block))
    np.testing.assert_array_equal(
        np.concatenate([np.broadcast_to(b.branches["C"], (len(b),)) for b in blocks]),
        whole.branches["C"])


@given(st.lists(st.sampled_from([-60, -30, 0, 0, 30, 60, 90, 180]), min_size=2, max_size=40),
       st.sampled_from([(10, 4, 10, 4), (7, 5, 6, 5), (10, 8, 3, 9)]),
       st.integers(1, 6))
def test_blocks_along_paths_that_stop_turn_and_land_on_change_points(steps, lengths, block):
    # steps of whole multiples of 30 degrees: samples on the parallelogram's change
    # points, repeated samples, and turns back at them
    values = np.radians(np.r_[0.0, np.cumsum(steps)])
    assert_blocks_equal_whole(fourbar(*lengths), values, block)


@pytest.mark.parametrize("block", range(1, 9))
def test_change_points_within_the_rounding_of_a_mechanism_far_from_the_origin(block):
    # 1e5 from the origin, the parallelogram's roots meet within 1e-5 of their scale
    # (their coordinates' rounding): samples 1e-5 rad past the change points, where
    # they are 2e-6 apart, are meeting samples, in every block as in the whole sweep
    c = geokin.Construction("parallelogram far from the origin")
    c.input("theta")
    c.fixed("O2", 1e5, 1e5)
    c.fixed("O4", 1e5 + 10, 1e5)
    c.polar("A", "O2", 4, "theta")
    c.circle_circle("B", ("A", "O4"), (10, 4), branch="left")
    # each change point held over three samples: one meeting, the branch changing after it
    degrees = np.repeat(np.arange(0.0, 1081.0, 30.0), np.where(
        np.arange(0.0, 1081.0, 30.0) % 180 == 0, 3, 1))
    values = np.radians(degrees) + np.where(degrees % 180 == 0, 1e-5, 0.0)
    whole = geokin.sweep(c, values)
    last = np.flatnonzero((degrees % 180 == 0) & (np.roll(degrees, -1) != degrees))
    assert [(e.index, e.fraction) for e in whole.events] == [(i + 1, 0.0) for i in last[1:-1]]
    assert_blocks_equal_whole(c, values, block)
