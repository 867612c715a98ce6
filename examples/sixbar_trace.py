"""Seed 003's six-bar: the coupler curve of M, drawn to a PNG.

Loads the shipped construction script, sweeps the crank over the script's
range (theta = 0 to 1800 degrees in steps of 16, as the seed's MATLAB
program) and draws the mechanism at theta = 100 degrees with the path of M.

Run: python examples/sixbar_trace.py [PATH] (default sixbar_trace.png)
"""

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

import geokin  # noqa: E402
from geokin.plotting import plot_mechanism  # noqa: E402

SCRIPT = pathlib.Path(__file__).resolve().parent.parent / "constructions" / "sixbar.toml"


def main(path="sixbar_trace.png"):
    construction = geokin.load(SCRIPT)
    motion = geokin.sweep(construction)
    m = motion["M"]
    print(f"{construction.name}: {len(motion)} samples, all assembled: {motion.valid.all()}")
    print(f"M moves within x {m[:, 0].min():.2f}..{m[:, 0].max():.2f}, "
          f"y {m[:, 1].min():.2f}..{m[:, 1].max():.2f} mm")
    fig = Figure(figsize=(8, 6), layout="constrained")
    at = int(np.argmin(np.abs(np.degrees(motion.input_values) - 96)))  # theta = 96 degrees
    plot_mechanism(motion, at, ax=fig.add_subplot(), title="six-bar (seed 003): path of M")
    fig.savefig(path)
    print(f"wrote {path}")


if __name__ == "__main__":
    main(*sys.argv[1:])
