"""Measure the accuracy of velocities and accelerations against the loop equations.

Run with ``python tests/accuracy_kinematics.py``. For seed 000's four-bar with
the crank, the coupler and the follower driving in turn (both branches, 361
samples per turn), it prints the largest error of the angular velocities and
accelerations over the samples whose transmission angle is at least 10
degrees from 0 and 180, relative to the largest rate of any link. The test
suite asserts the targets (1e-7 and 1e-5); this prints the figures.
"""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from mechanisms import triple_rocker  # noqa: E402
from test_kinematics import loop_rates, node_angle  # noqa: E402

from geokin import sweep  # noqa: E402
from geokin.kinematics import motion  # noqa: E402

NODES = {"crank": ("C", "B", "D"), "coupler": ("B", "A", "Dp"), "follower": ("B", "A", "C")}


def main():
    print(f"{'driver':>9} {'velocity':>10} {'acceleration':>13}")
    for driver, node in NODES.items():
        worst_velocity = worst_acceleration = 0.0
        for branch in ("left", "right"):
            s = sweep(triple_rocker(driver, branch), np.linspace(-np.pi, np.pi, 361))
            m = motion(s, speed=1.0)
            angles = [np.arctan2(*(s[b] - s[a]).T[::-1])
                      for a, b in [("A", "B"), ("B", "C"), ("D", "C")]]
            omega, alpha = loop_rates(angles, 1.0, 0.0, driver)
            mu = node_angle(s, *node)
            good = s.valid & (mu >= 10) & (mu <= 170)
            scale_w = max(np.abs(w[good]).max() for w in omega.values())
            scale_a = max(np.abs(a[good]).max() for a in alpha.values())
            for link in omega:
                error_w = np.abs(m.angular_velocity[link][good] - omega[link][good]).max()
                error_a = np.abs(m.angular_acceleration[link][good] - alpha[link][good]).max()
                worst_velocity = max(worst_velocity, error_w / scale_w)
                worst_acceleration = max(worst_acceleration, error_a / scale_a)
        print(f"{driver:>9} {worst_velocity:>10.1e} {worst_acceleration:>13.1e}")


if __name__ == "__main__":
    main()
