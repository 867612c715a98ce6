import os
import tracemalloc

import numpy as np
import pytest

from geokin import Construction, sweep
from geokin.budgets import (
    MAX_EXPRESSION_DEPTH,
    MAX_EXPRESSION_LENGTH,
    MAX_NAME_LENGTH,
    MAX_SCRIPT_BYTES,
    check_memory,
    check_sweep_memory,
    memory_budget,
    physical_memory,
    sweep_bytes,
)
from geokin.errors import BudgetError, GeokinError


def test_the_limits_are_generous_for_real_scripts_and_stop_hostile_ones():
    # 40,000 parameters make a 0.6 MB script; a 10 MB expression is refused
    assert 2 * 2**20 <= MAX_SCRIPT_BYTES <= 64 * 2**20
    assert 1_000 <= MAX_EXPRESSION_LENGTH < 10 * 2**20
    assert 20 <= MAX_EXPRESSION_DEPTH <= 200  # printing recurses once per level
    assert 30 <= MAX_NAME_LENGTH <= 1_000


def test_physical_memory_is_what_the_system_reports_at_most():
    total = physical_memory()
    assert total > 2**26  # more than 64 MiB
    if hasattr(os, "sysconf"):
        assert total <= os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    assert 0 < memory_budget() < total


def test_the_sweep_estimate_grows_with_points_and_samples():
    assert sweep_bytes(10, 1000) == 1000 * (10 * 48 + 64)
    assert sweep_bytes(20, 1000) > sweep_bytes(10, 1000)
    assert sweep_bytes(10, 2000) == 2 * sweep_bytes(10, 1000)
    assert sweep_bytes(10, 1000, copies=3) == 3 * sweep_bytes(10, 1000)


def _chain(points):
    """A crank driving a chain of four-bar-like dyads: every point moves."""
    c = Construction("chain")
    c.input("t")
    c.fixed("O", 0, 0)
    c.fixed("Q", 40, 0)
    c.polar("A0", "O", 10, "t")
    for i in range(1, points - 2):
        c.circle_circle(f"A{i}", (f"A{i - 1}", "Q"), (35, 30), branch="left")
    return c


@pytest.mark.parametrize("points", [5, 30])
def test_the_estimate_bounds_the_memory_a_sweep_really_uses(points):
    """A sweep and reading every point stay within the estimate, and within 4 times of it."""
    c = _chain(points)
    c.compile()
    n = 20_000
    theta = np.linspace(0, 2 * np.pi, n)
    tracemalloc.start()
    try:
        s = sweep(c, theta)
        for name in s.points:
            s[name]
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    estimate = sweep_bytes(points, n)
    assert peak <= estimate
    assert peak >= estimate / 4


def test_a_sweep_too_large_is_refused_with_the_estimate_and_a_way_out():
    budget = 8 * 2**30
    with pytest.raises(BudgetError) as info:
        check_sweep_memory(2000, 1_000_000, budget=budget)
    message = str(info.value)
    assert "\n" not in message
    assert "2,000 points x 1,000,000 samples" in message and "96 GB" in message
    assert "fewer samples" in message and "fewer points" in message
    block = int(message.rsplit("at most ", 1)[1].split()[0].replace(",", ""))
    assert sweep_bytes(2000, block) <= budget < sweep_bytes(2000, 2 * block)
    assert info.value.needed == sweep_bytes(2000, 1_000_000) and info.value.budget == budget
    assert isinstance(info.value, GeokinError)


def test_a_sweep_that_fits_returns_its_estimate():
    assert check_sweep_memory(5, 361) == sweep_bytes(5, 361)
    assert check_sweep_memory(5, 361, budget=sweep_bytes(5, 361)) == sweep_bytes(5, 361)


def test_the_default_budget_is_this_machine_s_memory():
    with pytest.raises(BudgetError, match="of this machine's memory"):
        check_sweep_memory(1_000_000, 1_000_000)  # 48 TB


def test_no_block_fits_when_one_sample_is_too_large():
    with pytest.raises(BudgetError, match="not even one sample"):
        check_sweep_memory(10**9, 10, budget=10**6)


def test_check_memory_names_what_and_how():
    check_memory(10, what="a frame", advice="use fewer", budget=10)
    with pytest.raises(BudgetError, match=r"^an animation of 3 frames needs about 11 GB, more "
                                          r"than the 1 GB budget; stream the frames$"):
        check_memory(11 * 10**9, what="an animation of 3 frames", advice="stream the frames",
                     budget=10**9)


def test_the_readme_states_the_limits_as_they_are():
    from pathlib import Path

    from geokin.budgets import BYTES_PER_POINT_SAMPLE, MEMORY_FRACTION
    from geokin.primitives import SCALE_RANGE

    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")
    limits = readme.split("### Limits on size", 1)[1].split("\n## ", 1)[0]
    assert f"{MAX_SCRIPT_BYTES // 2**20} MiB (`MAX_SCRIPT_BYTES`)" in limits
    assert f"{MAX_EXPRESSION_LENGTH:,} characters (`MAX_EXPRESSION_LENGTH`)" in limits
    assert f"at most {MAX_EXPRESSION_DEPTH} levels" in limits
    assert f"{MAX_NAME_LENGTH} characters (`MAX_NAME_LENGTH`)" in limits
    assert f"about {BYTES_PER_POINT_SAMPLE} bytes per point and sample" in limits
    assert MEMORY_FRACTION == 0.5 and "half the machine's memory" in limits
    low, high = (f"{v:.0e}".replace("e+", "e").replace("e-0", "e-") for v in SCALE_RANGE)
    assert f"up to {high};" in limits and f"at least {low} |" in limits
