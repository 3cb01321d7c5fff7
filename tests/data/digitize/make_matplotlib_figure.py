"""Test figure for `geardyn digitize` drawn by another tool (matplotlib 3, Agg backend), in its
default style: a box frame, outward ticks, tick labels and a legend inside the plot.

Run: python3 make_matplotlib_figure.py   (writes matplotlib_resonance.png and
matplotlib_truth.csv beside this script; both are committed, so the tests need no matplotlib).

The curve is a damped resonance, y = 2 + 6 / sqrt((1 - r^2)^2 + (0.25 r)^2) with r = x / 3400,
drawn as a red line over 1500..5500 and as blue square markers at the 21 speeds of the truth
file. The axes are x 1500..5500 (ticks every 500) and y 0..30 (ticks every 5).
"""
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def curve(x):
    r = x / 3400.0
    return 2.0 + 6.0 / np.sqrt((1.0 - r**2) ** 2 + (0.25 * r) ** 2)


x_line = np.linspace(1500.0, 5500.0, 2001)
x_mark = np.linspace(1500.0, 5500.0, 21)
fig, ax = plt.subplots(figsize=(8, 5), dpi=100)
ax.plot(x_line, curve(x_line), color="#d62728", linewidth=1.5, label="model")
ax.plot(x_mark, curve(x_mark), "s", color="#1f77b4", markersize=6, label="measured")
ax.set_xlim(1300, 5700)
ax.set_ylim(-1, 31)
ax.set_xticks(np.arange(1500, 5501, 500))
ax.set_yticks(np.arange(0, 31, 5))
ax.set_xlabel("speed (rpm)")
ax.set_ylabel("pp DTE (um)")
ax.set_title("A figure geardyn did not draw")
ax.legend(loc="upper right")
fig.savefig(os.path.join(HERE, "matplotlib_resonance.png"))

with open(os.path.join(HERE, "matplotlib_truth.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["speed_rpm", "dte_pp_um"])
    for x in x_mark:
        w.writerow([f"{x:.1f}", f"{curve(x):.6f}"])
