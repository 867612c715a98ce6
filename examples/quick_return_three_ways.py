"""Seed 001's quick-return mechanism at theta2 = 30 degrees, solved three ways.

The crank (r2 = 40) turns about O2 = (0, r1) with r1 = 60; the slotted lever
turns about O1 at the origin through the crank pin A; the ram B slides on the
line y = r1 + r6 with r6 = 60. The unknowns are r3 = |O1 A|, the lever angle
theta3, r4 = |O1 B| and the ram's position r5 from the foot C = (0, r1 + r6).

1. analytically (the seed's formulas, with atan2 for the lever angle),
2. by Newton-Raphson on the seed's four loop equations, from the seed's
   starting guess (1, 1, 1, 1),
3. by a geometric construction: B is where the line O1 A meets the ram's line.

Lengths in mm, angles in degrees. Run: python examples/quick_return_three_ways.py
"""

import numpy as np

from geokin import Construction, sweep
from geokin.loops import quick_return_closed_form, quick_return_loop

R1, R2, R6 = 60.0, 40.0, 60.0
THETA2 = np.radians(30.0)
SEED = {"r3": 87.17, "r4": 130.75, "r5": 51.96, "theta3": 66.58}


def construction() -> Construction:
    c = Construction("quick return")
    c.parameter("r1", R1)
    c.parameter("r2", R2)
    c.parameter("r6", R6)
    c.input("theta2")
    c.fixed("O1", 0, 0)
    c.fixed("O2", 0, "r1")
    c.fixed("C", 0, "r1 + r6")
    c.fixed("E", 1, "r1 + r6")
    c.polar("A", "O2", "r2", "theta2")
    c.line_line("B", ("O1", "A"), ("C", "E"))
    return c


def main():
    analytic = {k: float(v) for k, v in quick_return_closed_form(R1, R2, R6, THETA2).items()}
    newton = quick_return_loop(R1, R2, R6, [THETA2], guess=(1, 1, 1, 1))
    numeric = {name: float(newton[name][0]) for name in newton.names}
    s = sweep(construction(), [THETA2])
    a, b, foot = s["A"][0], s["B"][0], s["C"][0]
    built = {"r3": float(np.hypot(*a)), "r4": float(np.hypot(*b)), "r5": float(b[0] - foot[0]),
             "theta3": float(np.arctan2(a[1], a[0]))}

    print(f"Quick return, r1 = {R1:g}, r2 = {R2:g}, r6 = {R6:g} mm, theta2 = 30 degrees")
    print(f"Newton-Raphson: {int(newton.iterations[0])} iterations from (1, 1, 1, 1), "
          f"residual {newton.residual[0]:.1e}\n")
    header = (f"{'':8}{'seed 001':>10}{'analytical':>16}{'Newton':>16}{'construction':>16}"
              f"{'Newton-anal.':>14}{'constr.-anal.':>15}")
    print(header)
    print("-" * len(header))
    for name in ("r3", "r4", "r5", "theta3"):
        scale = 180 / np.pi if name == "theta3" else 1.0
        unit = "deg" if name == "theta3" else "mm"
        x, n, c = analytic[name] * scale, numeric[name] * scale, built[name] * scale
        print(f"{name:>6} {unit:<3}{SEED[name]:>8.2f}{x:>16.10f}{n:>16.10f}{c:>16.10f}"
              f"{n - x:>14.1e}{c - x:>15.1e}")
    print("\nThe seed truncates to two decimals; its analytical r4 = 130.75 used the rounded\n"
          "r3 = 87.17 (120 * 87.17 / 80 = 130.755); its own Newton run gives 130.76696831.")


if __name__ == "__main__":
    main()
