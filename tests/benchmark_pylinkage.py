"""Benchmark geokin's motion against pylinkage's compiled analytic kinematics.

Both run in one process on the benchmark four-bar (``mechanisms.coupler_fourbar``:
pivots O2 = (0, 0) and O4 = (40, 0), crank 10, coupler 35, rocker 30, B on
the left branch, coupler point P at 20 from A, 30 degrees off A->B), over N
samples of one crank turn, theta = 2 pi k / N, at 2 pi rad/s. Timed calls:

- hand: ``benchmark_engine.hand_motion``, positions, velocities and
  accelerations of A, B and P in closed form, vectorized numpy;
- motion: ``geokin.motion`` on a sweep made beforehand, velocities and
  accelerations of every point by finite differences (the construction
  evaluated again at perturbed inputs), with their error estimates and flags;
- sweep+motion: ``geokin.sweep`` then ``geokin.motion``;
- pylinkage: ``Linkage.step_fast_with_kinematics`` (numba-compiled
  ``solver.simulation.simulate_with_kinematics``), positions, velocities and
  accelerations of every joint by analytic differentiation, stepping the
  crank sample by sample; its linkage is put back at the start of the turn
  first (``set_coords``), so every call does the same work.

The script first checks that the three agree, then prints CPU times (the
least over interleaved rounds, ``benchmark_engine.interleaved_cpu``), each
as a multiple of the hand closed form in the same run, and geokin's times
over pylinkage's. Figures are measured, never asserted.

Run with ``python tests/benchmark_pylinkage.py`` (``... quick`` to stop at
360,000 samples). It needs pylinkage and numba, which geokin does not depend
on; without them it says so and exits.
"""

import importlib.util
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from benchmark_engine import hand_motion, interleaved_cpu  # noqa: E402
from mechanisms import coupler_fourbar  # noqa: E402

from geokin import motion, sweep  # noqa: E402

try:
    from pylinkage import Crank, FixedDyad, Ground, Linkage, RRRDyad

    HAS_NUMBA = importlib.util.find_spec("numba") is not None  # compiled, not plain Python
except ImportError:
    Linkage, HAS_NUMBA = None, False

SPEED = 2 * np.pi  # rad/s
JOINTS = {"A": 2, "B": 3, "P": 4}  # pylinkage component index of each point


def pylinkage_fourbar(n, b_start):
    """The benchmark four-bar as a pylinkage ``Linkage`` turning once in ``n`` steps.

    Parameters
    ----------
    n : int
        Steps per crank turn; the crank starts one step before 0, so the
        samples are theta = 2 pi k / n, k = 0 ... n - 1.
    b_start : array_like
        A point near B's position at theta = 0, which picks the branch.

    Returns
    -------
    tuple
        The compiled linkage and its starting coordinates.
    """
    step = 2 * np.pi / n
    o2, o4 = Ground(0.0, 0.0, name="O2"), Ground(40.0, 0.0, name="O4")
    crank = Crank(o2, 10.0, angular_velocity=step, initial_angle=-step, name="A")
    b = RRRDyad(crank.output, o4, 35.0, 30.0, x=b_start[0], y=b_start[1], name="B")
    p = FixedDyad(crank.output, b, 20.0, np.radians(30), name="P")
    linkage = Linkage([o2, o4, crank, b, p], name="benchmark four-bar")
    linkage.set_input_velocity(crank, SPEED)
    linkage.compile()
    return linkage, linkage.get_coords()


def pylinkage_run(linkage, start, n):
    """Positions, velocities and accelerations of every joint over one turn, (n, 5, 2) each."""
    linkage.set_coords(start)
    return linkage.step_fast_with_kinematics(iterations=n)


def relative(a, b):
    """Largest difference of two (N, 2) arrays over the largest magnitude of ``b``."""
    return float(np.abs(np.asarray(a) - np.asarray(b)).max() / np.abs(b).max())


def check(fourbar, n):
    """Compare geokin, pylinkage and the closed form at ``n`` samples; print the worst.

    Returns
    -------
    float
        The largest relative difference of any velocity or acceleration.
    """
    theta = np.arange(n) * (2 * np.pi / n)
    swept = sweep(fourbar, theta)
    m = motion(swept, speed=SPEED)
    linkage, start = pylinkage_fourbar(n, swept.points["B"][0])
    pos, vel, acc = pylinkage_run(linkage, start, n)
    velocity, acceleration = hand_motion(theta)
    worst = 0.0
    print(f"agreement at {n:,} samples (largest |difference| / largest |value|):")
    for name, j in JOINTS.items():
        where = relative(pos[:, j], swept.points[name])
        hv, ha = np.c_[velocity[name]], np.c_[acceleration[name]]
        pairs = {"geokin-hand": (m.velocity[name], m.acceleration[name], hv, ha),
                 "pylinkage-hand": (vel[:, j], acc[:, j], hv, ha),
                 "geokin-pylinkage": (m.velocity[name], m.acceleration[name], vel[:, j],
                                      acc[:, j])}
        text = []
        for label, (v, a, v0, a0) in pairs.items():
            dv, da = relative(v, v0), relative(a, a0)
            worst = max(worst, dv, da)
            text.append(f"{label} v {dv:.1e} a {da:.1e}")
        print(f"  {name}: position {where:.1e}; " + "; ".join(text))
        assert where < 1e-9, f"pylinkage assembled {name} elsewhere than geokin"
    assert worst < 1e-6, f"velocities or accelerations differ by {worst:.1e}"
    return worst


def compile_seconds(fourbar):
    """Wall time of pylinkage's first kinematic call: numba compiles, or loads its cache."""
    theta = np.zeros(1)
    b_start = sweep(fourbar, theta).points["B"][0]
    linkage, start = pylinkage_fourbar(360, b_start)
    begin = time.perf_counter()
    pylinkage_run(linkage, start, 360)
    return time.perf_counter() - begin


def main(sizes):
    """Check agreement, then print the timing table for each N in ``sizes``."""
    if Linkage is None or not HAS_NUMBA:
        print("pylinkage with numba is not installed: nothing to compare against")
        return
    import numba
    import pylinkage

    fourbar = coupler_fourbar()
    fourbar.compile()
    print(f"pylinkage {pylinkage.__version__}, numba {numba.__version__}, "
          f"numpy {np.__version__}")
    print(f"pylinkage first call (numba compile or cache load): "
          f"{compile_seconds(fourbar):.2f} s wall")
    check(fourbar, 360)
    check(fourbar, 36_000)
    print("CPU time per call, least over interleaved rounds (x: multiple of hand)")
    print(f"{'N':>9} {'hand':>10} {'geokin motion':>20} {'geokin sweep+motion':>20} "
          f"{'pylinkage':>20} {'motion/pl':>9} {'s+m/pl':>7}")
    for n in sizes:
        theta = np.arange(n) * (2 * np.pi / n)
        swept = sweep(fourbar, theta)
        linkage, start = pylinkage_fourbar(n, swept.points["B"][0])
        times = interleaved_cpu({
            "hand": lambda theta=theta: hand_motion(theta),
            "motion": lambda swept=swept: motion(swept, speed=SPEED),
            "sweep+motion": lambda theta=theta: motion(sweep(fourbar, theta), speed=SPEED),
            "pylinkage": lambda linkage=linkage, start=start, n=n: pylinkage_run(
                linkage, start, n)},
            rounds=15 if n <= 36_000 else 7 if n <= 360_000 else 3)
        hand = times["hand"]
        cells = [f"{times[k] * 1e3:>11.3f} ms {times[k] / hand:>4.1f}x"
                 for k in ("motion", "sweep+motion", "pylinkage")]
        print(f"{n:>9,} {hand * 1e3:>7.3f} ms " + " ".join(cells) +
              f" {times['motion'] / times['pylinkage']:>9.2f}"
              f" {times['sweep+motion'] / times['pylinkage']:>7.2f}")


if __name__ == "__main__":
    quick = sys.argv[1:] == ["quick"]
    main((360, 3_600, 36_000, 360_000) + (() if quick else (3_600_000,)))
