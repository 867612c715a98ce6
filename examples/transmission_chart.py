"""Seed 000's transmission-angle design chart, as a PNG.

For a four-bar with ground L0, crank L1, coupler L2 and follower L3, take the
ratios alpha = L0 / L1, R2 = L2 / L1 and R3 = L3 / L1. With the crank at
theta2 = 0 the diagonal from the crank pin to the follower's pivot is
alpha - 1, so the minimum transmission angle mu_min satisfies

    R2**2 + R3**2 - 2 R2 R3 cos(mu_min) = (alpha - 1)**2,

an ellipse in the (R3, R2) plane: every coupler/follower pair on it gives the
same minimum transmission angle. The chart draws it for the example of seed
000's design chart (fixed 7, crank 4, coupler 5, rocker 5: alpha = 1.75,
mu_min = 34.92 degrees; the seed's triple rocker, analysed in
constructions/triple_rocker_*.toml, is another four-bar: 7, 5, 6, 5)
and for neighbouring angles, over the Grashof class of every (R3, R2) from
geokin.analysis.grashof, with the seed's three Grashof boundary lines

    R2 + R3 = alpha + 1,   R2 - R3 = alpha - 1,   R3 - R2 = alpha - 1.

Below the first line the maximum transmission angle is 180 degrees: the
coupler and follower stretch into a line before the crank reaches
theta2 = 180 degrees, as in the seed's triple rocker.

Run: python examples/transmission_chart.py [PATH] (default transmission_chart.png)
"""

import argparse

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from geokin.analysis import fourbar_transmission_extremes, grashof  # noqa: E402

SEED = dict(ground=7.0, input_link=4.0, coupler=5.0, output_link=5.0)
REGIONS = [  # kind, colour, label
    ("crank-rocker", "#cfe8cf", "crank-rocker (Grashof, crank shortest)"),
    ("triple-rocker RRR1", "#fde0c5", "triple rocker RRR1 (ground longest)"),
    ("triple-rocker RRR3", "#f6d3e4", "triple rocker RRR3 (coupler longest)"),
    ("triple-rocker RRR4", "#d6dcf5", "triple rocker RRR4 (follower longest)"),
    ("other", "#e3e3e3", "other classes (crank not the shortest link)"),
    ("unassemblable", "#ffffff", "cannot be assembled"),
]


def ellipse(alpha, mu, samples=721):
    """Points (R3, R2) with R2**2 + R3**2 - 2 R2 R3 cos(mu) = (alpha - 1)**2."""
    # rotate by 45 degrees: u = (R2 + R3) / sqrt 2, v = (R2 - R3) / sqrt 2
    t = np.linspace(0, 2 * np.pi, samples)
    k = (alpha - 1) ** 2
    u = np.sqrt(k / (1 - np.cos(mu))) * np.cos(t)
    v = np.sqrt(k / (1 + np.cos(mu))) * np.sin(t)
    r2, r3 = (u + v) / np.sqrt(2), (u - v) / np.sqrt(2)
    keep = (r2 > 0) & (r3 > 0)
    return np.where(keep, r3, np.nan), np.where(keep, r2, np.nan)


def classes(alpha, r3, r2):
    index = {kind: i for i, (kind, _, _) in enumerate(REGIONS)}
    grid = np.empty(r2.shape, dtype=int)
    for pos in np.ndindex(r2.shape):
        kind = grashof(ground=alpha, input_link=1.0, coupler=r2[pos], output_link=r3[pos]).kind
        grid[pos] = index.get(kind, index["other"])
    return grid


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("path", nargs="?", default="transmission_chart.png")
    args = parser.parse_args(argv)

    alpha = SEED["ground"] / SEED["input_link"]
    mu_min, mu_max = fourbar_transmission_extremes(**SEED)
    r3_seed = SEED["output_link"] / SEED["input_link"]
    r2_seed = SEED["coupler"] / SEED["input_link"]
    top = 4.0

    fig, ax = plt.subplots(figsize=(9, 8.4), constrained_layout=True)
    cells = np.linspace(0, top, 401)
    centres = 0.5 * (cells[1:] + cells[:-1])
    r3, r2 = np.meshgrid(centres, centres)
    ax.pcolormesh(cells, cells, classes(alpha, r3, r2), shading="flat",
                  cmap=ListedColormap([c for _, c, _ in REGIONS]), vmin=-0.5,
                  vmax=len(REGIONS) - 0.5, rasterized=True)

    x = np.array([0.0, top])
    lines = [  # boundary, label, where along R3, rotation
        (alpha + 1 - x, r"$R_2 + R_3 = \alpha + 1$", 0.3, -45),
        (alpha - 1 + x, r"$R_2 - R_3 = \alpha - 1$", 2.3, 45),
        (x - (alpha - 1), r"$R_3 - R_2 = \alpha - 1$", 2.75, 45),
    ]
    for y, label, at, rotation in lines:
        ax.plot(x, y, color="0.25", lw=1.2, ls="--")
        ax.text(at, np.interp(at, x, y) + 0.07, label, fontsize=9, color="0.15",
                rotation=rotation, rotation_mode="anchor", ha="left", va="bottom",
                transform_rotates_text=True)

    for degrees in (20, 30, 40, 50, 60):
        ex, ey = ellipse(alpha, np.radians(degrees))
        ax.plot(ex, ey, color="0.45", lw=0.9)
        i = np.nanargmax(ey)
        ax.annotate(f"{degrees}°", (ex[i], ey[i]), xytext=(2, 3), textcoords="offset points",
                    fontsize=8, color="0.35")
    ex, ey = ellipse(alpha, mu_min)
    ax.plot(ex, ey, color="#b2182b", lw=2.4,
            label=rf"$\mu_{{min}}$ = {np.degrees(mu_min):.2f}° (seed 000)")

    ax.plot(r3_seed, r2_seed, "o", color="k", ms=7, zorder=5)
    ax.annotate(f"seed 000's chart example: fixed 7, crank 4, coupler 5, rocker 5\n"
                rf"$\mu_{{min}}$ = {np.degrees(mu_min):.2f}°, "
                rf"$\mu_{{max}}$ = {np.degrees(mu_max):.0f}°",
                (r3_seed, r2_seed), xytext=(1.9, 0.45), fontsize=9,
                arrowprops=dict(arrowstyle="->", color="k"),
                bbox=dict(boxstyle="round", fc="white", ec="0.6"))

    handles = [Patch(facecolor=c, edgecolor="0.6", label=label) for _, c, label in REGIONS]
    handles.insert(0, ax.get_legend_handles_labels()[0][0])
    handles.insert(1, plt.Line2D([], [], color="0.45", lw=0.9,
                                 label=r"other $\mu_{min}$ (degrees, labelled)"))
    handles.insert(2, plt.Line2D([], [], color="0.25", lw=1.2, ls="--",
                                 label="Grashof boundaries $s + l = p + q$;\n"
                                       r"below $R_2 + R_3 = \alpha + 1$: $\mu_{max}$ = 180°"))
    ax.legend(handles=handles, loc="upper left", fontsize=8.5, framealpha=0.95)
    ax.set(xlim=(0, top), ylim=(0, top), aspect="equal",
           xlabel=r"$R_3 = L_3 / L_1$  (follower / crank)",
           ylabel=r"$R_2 = L_2 / L_1$  (coupler / crank)")
    ax.set_title("Transmission-angle design chart: curves of equal minimum transmission angle\n"
                 rf"ground / crank $\alpha = L_0 / L_1 = {alpha:g}$; "
                 r"$\mu_{min}$ at crank angle $\theta_2 = 0$", fontsize=11)
    ax.grid(alpha=0.3)
    fig.savefig(args.path, dpi=130)
    print(f"wrote {args.path}: alpha = {alpha:g}, mu_min = {np.degrees(mu_min):.2f} deg, "
          f"mu_max = {np.degrees(mu_max):.2f} deg")


if __name__ == "__main__":
    main()
