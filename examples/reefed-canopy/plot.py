#!/usr/bin/python3
"""Draws skirt_diameter.png: the reefed C9 canopy's skirt diameter over time (twice the first
ring's radius) against the diameter the reefing line allows (its material length over pi,
the polygon through the rings aside) and an unreefed run's skirt diameter.
Usage: plot.py REEFED_OUT [UNREEFED_OUT]"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def history(directory):
    rows = list(csv.DictReader(open(os.path.join(directory, "history.csv"))))
    return {k.strip(): [float(r[k]) for r in rows] for k in rows[0]}


def reef(t):  # the model's `reef` table
    points = [(0, 1), (0.3, 0.4), (1.5, 0.4), (2.0, 1.0)]
    for (t0, g0), (t1, g1) in zip(points, points[1:]):
        if t <= t1:
            return g0 + (g1 - g0) * (t - t0) / (t1 - t0)
    return points[-1][1]


h = history(sys.argv[1])
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(h["time"], [2 * x for x in h["ring_first_x"]], label="skirt (reefed, disreefed)")
ax.plot(h["time"], [28.0 * reef(t) for t in h["time"]], "--", label="line length / π")
if len(sys.argv) > 2:
    u = history(sys.argv[2])
    ax.plot(u["time"], [2 * x for x in u["skirt_x"]], ":", label="unreefed canopy")
ax.set_xlabel("time [s]")
ax.set_ylabel("skirt diameter [ft]")
ax.set_title("C9 canopy: reefed to 0.4, disreefed from 1.5 s to 2.0 s")
ax.grid(True, alpha=0.3)
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(os.path.dirname(os.path.abspath(__file__)), "skirt_diameter.png"),
            dpi=110)
