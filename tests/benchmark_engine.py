"""Benchmark the engine against a hand-written numpy four-bar, in the same run.

Run with ``python tests/benchmark_engine.py`` (``... closure`` for the
closure group's lines only, ``... variants`` for design variants); it prints a table of times,
the engine-to-hand-written ratios and the peak memory per sample. The test
suite does not run it: figures here are measured, never asserted.
"""

import gc
import sys
import time
import timeit
import tracemalloc
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from mechanisms import coupler_fourbar, sixbar  # noqa: E402
from mechanisms import fourbar as four_bar  # noqa: E402

from geokin import load, motion, sweep  # noqa: E402
from geokin.engine import evaluate  # noqa: E402


def hand_joints(theta):
    """A, B and P - A of the benchmark four-bar in closed form, as x and y arrays."""
    ax, ay = 10 * np.cos(theta), 10 * np.sin(theta)
    dx, dy = 40 - ax, -ay
    d2 = dx * dx + dy * dy
    d = np.sqrt(d2)
    m = (d2 + 35**2 - 30**2) / (2 * d)
    h = np.sqrt(35**2 - m * m)
    ux, uy = dx / d, dy / d
    bx, by = ax + m * ux - h * uy, ay + m * uy + h * ux
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    k = 20 / 35
    qx, qy = k * (c * (bx - ax) - s * (by - ay)), k * (s * (bx - ax) + c * (by - ay))
    return ax, ay, bx, by, qx, qy


def hand_written(theta):
    """The benchmark four-bar in closed form: the fastest plain numpy we can write."""
    ax, ay, _, _, qx, qy = hand_joints(theta)
    return np.stack([ax + qx, ay + qy], axis=-1)


def hand_motion(theta, omega=2 * np.pi):
    """Closed-form velocity and acceleration of A, B and P of the benchmark four-bar.

    The vector loop vA + w3 x b = w4 x c (a = A - O2, b = B - A, c = B - O4,
    w x r = w (-ry, rx)), dotted with c and with b, gives each unknown rate;
    differentiated once more, each angular acceleration.
    """
    ax, ay, bx, by, qx, qy = hand_joints(theta)
    b1, b2, c1, c2 = bx - ax, by - ay, bx - 40, by
    vax, vay = -omega * ay, omega * ax
    cross = b1 * c2 - b2 * c1
    w3 = -(vax * c1 + vay * c2) / cross
    w4 = -(vax * b1 + vay * b2) / cross
    aax, aay = -omega * omega * ax, -omega * omega * ay
    kx = aax - w3 * w3 * b1 + w4 * w4 * c1
    ky = aay - w3 * w3 * b2 + w4 * w4 * c2
    al3 = -(kx * c1 + ky * c2) / cross
    al4 = -(kx * b1 + ky * b2) / cross
    velocity = {"A": (vax, vay), "B": (-w4 * c2, w4 * c1),
                "P": (vax - w3 * qy, vay + w3 * qx)}
    acceleration = {"A": (aax, aay), "B": (-al4 * c2 - w4 * w4 * c1, al4 * c1 - w4 * w4 * c2),
                    "P": (aax - al3 * qy - w3 * w3 * qx, aay + al3 * qx - w3 * w3 * qy)}
    return velocity, acceleration


def interleaved_cpu(candidates, rounds=15, seconds=0.1):
    """Return each candidate's least CPU time per call, over rounds run in turn.

    The candidates take turns (A B A B ...), so a busy machine slows them
    alike and their ratio holds within one run.
    """
    counts = {}
    for name, function in candidates.items():
        start = time.process_time()
        function()
        counts[name] = max(1, int(seconds / max(time.process_time() - start, 1e-6)))
    best = dict.fromkeys(candidates, float("inf"))
    for _ in range(rounds):
        for name, function in candidates.items():
            gc.collect()
            start = time.process_time()
            for _ in range(counts[name]):
                function()
            best[name] = min(best[name], (time.process_time() - start) / counts[name])
    return best


def best_time(function, repeat=7):
    number, elapsed = timeit.Timer(function).autorange()
    times = timeit.repeat(function, number=number, repeat=repeat)
    return min(times) / number


def peak_bytes(function):
    tracemalloc.start()
    function()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


def main():
    fourbar = coupler_fourbar()
    fourbar.compile()
    check = np.linspace(0, 2 * np.pi, 1000)
    assert np.allclose(sweep(fourbar, check)["P"], hand_written(check), atol=1e-12)
    print("four-bar with coupler point: engine (geokin.sweep) vs hand-written closed form (CPU)")
    print(f"{'N':>9} {'hand-written':>14} {'engine':>12} {'ratio':>7}")
    for n in (360, 36_000, 1_000_000):
        theta = np.linspace(0, 2 * np.pi, n)
        times = interleaved_cpu({
            "hand": lambda theta=theta: hand_written(theta),
            "engine": lambda theta=theta: sweep(fourbar, theta)["P"]},
            rounds=15 if n < 1_000_000 else 5)
        hand, engine = times["hand"], times["engine"]
        print(f"{n:>9} {hand * 1e3:>11.3f} ms {engine * 1e3:>9.3f} ms {engine / hand:>7.2f}")
    six = sixbar()
    six.compile()
    theta = np.linspace(0, np.radians(1800), 1_000_000)
    seconds = best_time(lambda: sweep(six, theta)["M"], 3)
    print(f"seed six-bar, 1,000,000 samples: {seconds:.3f} s")
    # branch tracking's cost where it has nothing to do: the same evaluation with and
    # without tracking, interleaved
    print("branch tracking's share of a sweep without grazes (tracked / untracked, CPU):")
    for n in (36_000, 360_000):
        inputs = {"theta": np.linspace(0, 2 * np.pi, n)}
        times = interleaved_cpu({
            "tracked": lambda inputs=inputs, n=n: evaluate(fourbar, inputs, n),
            "untracked": lambda inputs=inputs, n=n: evaluate(fourbar, inputs, n, track=False)})
        tracked, untracked = times["tracked"], times["untracked"]
        print(f"{n:>9} samples: {tracked * 1e3:.3f} ms / {untracked * 1e3:.3f} ms = "
              f"{tracked / untracked:.3f}")
    # branch tracking's cost where it has work to do: a parallelogram (ground 10,
    # crank 4, coupler 10, rocker 4) passes two change points in a turn, against the
    # benchmark four-bar (no graze) at the same N
    parallelogram = four_bar(10, 4, 10, 4)
    parallelogram.compile()
    theta = np.linspace(0.5, 0.5 + 2 * np.pi, 361)
    plain = best_time(lambda: sweep(fourbar, theta)["P"])
    grazing = best_time(lambda: sweep(parallelogram, theta)["B"])
    print(f"parallelogram through 2 change points, 361 samples: {grazing * 1e3:.3f} ms "
          f"({grazing / plain:.1f}x the benchmark four-bar's {plain * 1e3:.3f} ms)")
    # velocities and accelerations by finite differences, against the closed form
    theta = np.linspace(0, 2 * np.pi, 1000)
    m = motion(sweep(fourbar, theta), speed=2 * np.pi)
    velocity, acceleration = hand_motion(theta)
    for name in ("A", "B", "P"):
        assert np.allclose(m.velocity[name], np.c_[velocity[name]], rtol=0, atol=1e-7 * 500)
        assert np.allclose(m.acceleration[name], np.c_[acceleration[name]], rtol=0,
                           atol=1e-5 * 5000)
    print("velocity and acceleration: geokin.motion on a sweep vs the closed form (CPU)")
    print(f"{'N':>9} {'closed form':>14} {'motion':>12} {'ratio':>7}")
    for n in (360, 3600, 36_000, 360_000):
        theta = np.linspace(0, 2 * np.pi, n, endpoint=False)
        swept = sweep(fourbar, theta)
        times = interleaved_cpu({
            "hand": lambda theta=theta: hand_motion(theta),
            "motion": lambda swept=swept: motion(swept, speed=2 * np.pi)}, rounds=7)
        print(f"{n:>9} {times['hand'] * 1e3:>11.3f} ms {times['motion'] * 1e3:>9.3f} ms "
              f"{times['motion'] / times['hand']:>7.2f}")
    n = 360_000
    theta = np.linspace(0, 2 * np.pi, n, endpoint=False)
    peak = peak_bytes(lambda: motion(sweep(fourbar, theta), speed=2 * np.pi))
    print(f"peak memory of sweep + motion, {n:,} samples: {peak / n:.0f} bytes per sample")
    print("peak memory of a four-bar sweep (tracemalloc):")
    for n in (100_000, 200_000, 400_000):
        theta = np.linspace(0, 2 * np.pi, n)
        peak = peak_bytes(lambda theta=theta: sweep(fourbar, theta)["P"])
        print(f"{n:>9} samples: {peak / 2**20:7.1f} MiB, {peak / n:6.0f} bytes per sample")


FOLDED = {"GF": 1.1247, "FD": 2.5826, "FE": 2.5029, "DE": 2.5582, "CA": 2.2633, "CB": 1.8292,
          "AB": 2.4434, "DA": 2.7345, "EB": 2.8767}
"""Lengths of the Stephenson III whose triad folds within the turn."""


def closure_groups():
    """Print the Stephenson III (a closure group, continued) against the seed six-bar.

    Both at 36,000 samples of one turn, CPU time, interleaved: the sweep, and
    the sweep with its motion. Measured, not asserted.
    """
    stephenson = load(Path(__file__).resolve().parents[1] / "constructions" / "stephenson3.toml")
    six = sixbar()
    n = 36_000
    theta = np.linspace(0, 2 * np.pi, n)

    def against_sixbar(what, ours, sixbars, rounds):
        times = interleaved_cpu({"ours": ours, "sixbar": sixbars}, rounds=rounds)
        print(f"closure group: {what}, {n:,} samples: {times['ours'] * 1e3:.1f} ms vs the "
              f"seed six-bar's {times['sixbar'] * 1e3:.1f} ms "
              f"({times['ours'] / times['sixbar']:.0f}x)")

    assert sweep(stephenson, theta).valid.all()
    against_sixbar("Stephenson III sweep", lambda: sweep(stephenson, theta),
                   lambda: sweep(six, theta), 5)
    # lengths whose triad folds at theta = 0.929: the sweep stops there and takes the
    # assembly up again where the turn comes back to its start
    folded = stephenson.compile().with_parameters(FOLDED)
    assert not sweep(folded, theta).valid.all()
    against_sixbar("a folding Stephenson III sweep", lambda: sweep(folded, theta),
                   lambda: sweep(six, theta), 3)
    swept, six_swept = sweep(stephenson, theta), sweep(six, theta)
    against_sixbar("Stephenson III motion", lambda: motion(swept, speed=2 * np.pi),
                   lambda: motion(six_swept, speed=2 * np.pi), 3)


def hand_variants(lengths, theta):
    """The benchmark four-bar's coupler point P for many variants, by hand: lengths (V, 1)."""
    d, a, b, c, p = lengths
    ax, ay = a * np.cos(theta), a * np.sin(theta)
    dx, dy = d - ax, -ay
    d2 = dx * dx + dy * dy
    k = (d2 + b * b - c * c) / (2 * d2)
    h = np.sqrt(b * b / d2 - k * k)
    bx, by = ax + k * dx - h * dy, ay + k * dy + h * dx
    s, cs, sn = p / b, np.cos(np.radians(30)), np.sin(np.radians(30))
    ux, uy = bx - ax, by - ay
    return ax + s * (cs * ux - sn * uy), ay + s * (sn * ux + cs * uy)


def design_variants():
    """Print 10,000 variants x 360 samples of the benchmark four-bar against hand broadcasting.

    The lengths (ground, crank, coupler, rocker, coupler point) are drawn
    uniformly around the benchmark's (crank-rockers all), as parameters of one
    construction: ``geokin.sweep(..., parameters=...)`` against hand-written
    numpy broadcasting (V, 1) lengths against (N,) angles, CPU time,
    interleaved; and the peak memory per variant-sample.
    """
    from geokin import Construction

    c = Construction("four-bar variants")
    for name, value in (("d", 40), ("a", 10), ("b", 35), ("c", 30), ("p", 20)):
        c.parameter(name, value)
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", "d", 0)
    c.polar("A", "O2", "a", "theta")
    c.circle_circle("B", ("A", "O4"), ("b", "c"), branch="left")
    c.polar("P", "A", "p", np.radians(30), reference=("A", "B"))
    rng = np.random.default_rng(0)
    count, n = 10_000, 360
    lengths = np.column_stack([rng.uniform(38, 42, count), rng.uniform(8, 12, count),
                               rng.uniform(30, 40, count), rng.uniform(25, 35, count),
                               rng.uniform(15, 25, count)])
    values = {name: lengths[:, i] for i, name in enumerate("dabcp")}
    theta = np.arange(n) * (2 * np.pi / n)
    columns = [lengths[:, i:i + 1] for i in range(5)]
    swept = sweep(c, theta, parameters=values)
    px, py = hand_variants(columns, theta)
    assert swept.valid.all() and np.allclose(swept["P"][..., 0], px, rtol=0, atol=1e-10)
    times = interleaved_cpu({
        "hand": lambda: hand_variants(columns, theta),
        "engine": lambda: sweep(c, theta, parameters=values)}, rounds=7, seconds=0.5)
    print(f"design variants: {count:,} variants x {n} samples: engine "
          f"{times['engine'] * 1e3:.0f} ms vs hand-written broadcasting "
          f"{times['hand'] * 1e3:.0f} ms ({times['engine'] / times['hand']:.2f}x)")
    peak = peak_bytes(lambda: sweep(c, theta, parameters=values))
    print(f"peak memory of that sweep: {peak / (count * n):.0f} bytes per variant-sample")


if __name__ == "__main__":
    if sys.argv[1:] == ["closure"]:
        closure_groups()
    elif sys.argv[1:] == ["variants"]:
        design_variants()
    else:
        main()
        closure_groups()
        design_variants()
