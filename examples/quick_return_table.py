"""Seed 001's table of unknowns, read from the shipped quick-return script.

The script places the lever's pivot O1 at the origin, so the seed's
unknowns come straight from the traced points A (the crank pin) and B (the
ram's pin): r3 = |O1 A|, theta3 = the direction of O1 A, r4 = |O1 B| and
r5 = C B along the ram's guide. At theta2 = 30 degrees the seed's table
gives r3 = 87.17, r4 = 130.75, r5 = 51.96 and theta3 = 66.58 degrees,
truncated; its own Newton-Raphson run, like the loop equations, gives
r4 = 130.767.

Run: python examples/quick_return_table.py
"""

import pathlib

import numpy as np

import geokin

SCRIPT = pathlib.Path(__file__).resolve().parent.parent / "constructions" / "quick_return.toml"


def main():
    construction = geokin.load(SCRIPT)
    theta2 = np.arange(0, 361, 30)
    motion = geokin.sweep(construction, np.radians(theta2))
    a, b, c = motion["A"], motion["B"], motion["C"]
    r3, r4 = np.hypot(*a.T), np.hypot(*b.T)
    r5 = b[:, 0] - c[:, 0]
    theta3 = np.degrees(np.arctan2(a[:, 1], a[:, 0]))
    print(f"{'theta2':>7} {'r3':>8} {'r4':>8} {'r5':>8} {'theta3':>7}   (mm, degrees)")
    table = np.round(np.column_stack([theta2, r3, r4, r5, theta3]), 2) + 0.0  # no -0.00
    for row in table:
        print("{:7.0f} {:8.2f} {:8.2f} {:8.2f} {:7.2f}".format(*row))


if __name__ == "__main__":
    main()
