#!/usr/bin/python3
"""Issue 47 item 6: arc length through the collapse of a gas-filled tube.

A cantilevered membrane tube (half of it, by symmetry), closed by a stiff cap and filled with
an isothermal gas that starts pressurised and out of equilibrium, is bent by a tip load until
it kinks. Path following must first bring the pressurised start to equilibrium (its bordered
corrector alone overshot and failed with the tube without wrinkling), then follow the load
past its limit point with the gas chamber's low-rank term in every solve (Newton stays fast),
the gas obeying p V = p0 V0 at every point of the path.

usage: gas_tube_path.py VELUM WORK_DIR
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys

VELUM, WORK = sys.argv[1:3]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


R, L, T = 0.1, 0.6, 2e-4
NA, NL = 12, 12  # elements around the half circumference, along the tube


def tube(wrinkling, path, end):
    nodes, idx = [], {}

    def node(key, x):
        if key not in idx:
            idx[key] = len(nodes) + 1
            nodes.append([idx[key], *x])
        return idx[key]

    for i in range(NL + 1):
        for j in range(NA + 1):
            v = math.pi * j / NA
            node(("t", i, j), (L * i / NL, R * math.sin(v), R * math.cos(v)))
    quads = [[idx[("t", i, j)], idx[("t", i + 1, j)], idx[("t", i + 1, j + 1)],
              idx[("t", i, j + 1)]] for i in range(NL) for j in range(NA)]
    c = node("c", (L, 0, 0))
    ring = [idx[("t", NL, j)] for j in range(NA + 1)]
    fan = [[c, ring[k + 1], ring[k]] for k in range(NA)]
    spokes = [[c, n] for n in ring] + [[ring[k], ring[k + 1]] for k in range(NA)]
    root = [idx[("t", 0, j)] for j in range(NA + 1)]
    plane = [idx[("t", i, j)] for i in range(NL + 1) for j in (0, NA)] + [c]
    return f"""mesh:
  nodes: {nodes}
  elements:
    - {{set: tube, type: quad4, connectivity: {quads}}}
    - {{set: cap, type: tri3, connectivity: {fan}}}
    - {{set: spokes, type: cable2, connectivity: {spokes}}}
  node_sets: {{root: {root}, plane: {plane}, tip: [{c}]}}
materials:
  film: {{type: isotropic, E: 5.0e8, nu: 0.3, density: 1000.0}}
  stiff: {{type: isotropic, E: 5.0e11, nu: 0.3, density: 1000.0}}
  bar: {{type: cable, E: 1.0e12, density: 1.0, compression: true}}
sections:
  - {{elements: tube, material: film, thickness: {T}, wrinkling: {wrinkling}}}
  - {{elements: cap, material: stiff, thickness: {T}}}
  - {{elements: spokes, material: bar, area: 1.0e-4}}
boundary:
  - {{nodes: root, fix: [x, y, z]}}
  - {{nodes: plane, symmetry: {{normal: [0, 1, 0]}}}}
loads:
  - {{type: gas, elements: [tube, cap], initial_pressure: 1.0e4, ambient: 0.0, gamma: 1.0}}
  - {{type: point, nodes: tip, force: [0, 0, -10.0], function: ramp}}
functions:
  ramp: {{type: table, points: [[0, 0], [10, 10]]}}
analysis:
  type: static
  time: {{end: {end}, step: 0.1}}
  {path}
output:
  directory: out
  fields: false
  history:
    - {{name: w, quantity: displacement, node: {c}, component: z}}
    - {{name: p, quantity: gas_pressure, load: 0}}
    - {{name: V, quantity: gas_volume, load: 0}}
"""


def run(name, text):
    model = os.path.join(WORK, name + ".yaml")
    with open(model, "w") as f:
        f.write(text)
    out = os.path.join(WORK, name)
    p = subprocess.run([VELUM, "run", model, "-o", out, "-q", "--threads", "1"],
                       capture_output=True, text=True, timeout=300)
    rows = []
    if os.path.exists(os.path.join(out, "history.csv")):
        rows = [[float(v) for v in r]
                for r in list(csv.reader(open(os.path.join(out, "history.csv"))))[1:]]
    steps = []
    if os.path.exists(os.path.join(out, "steps.csv")):
        steps = list(csv.DictReader(open(os.path.join(out, "steps.csv"))))
    return p, out, rows, steps


ARC = "path: {method: arc_length, max_steps: 2000}"

# The start out of equilibrium, without wrinkling: before, path following's start-up Newton
# (the bordered corrector at a step of 0) stalled at a residual of 2.3e4 and the run ended at
# t = 0; a static load step from the same start equilibrates it.
p, out, rows, _ = run("plain", tube("false", ARC, 0.2))
check(p.returncode == 0, f"plain tube by arc length: exit {p.returncode}: {p.stderr.strip()}")
p_static, _, rows_static, _ = run("plain-static", tube("false", "", 0.2))
check(p_static.returncode == 0, f"plain tube by load steps: exit {p_static.returncode}")
if rows and rows_static:
    w_path = next((r[1] for r in rows if abs(r[0] - 0.1) < 1e-12), None)
    w_static = next((r[1] for r in rows_static if abs(r[0] - 0.1) < 1e-12), None)
    check(w_path is not None and w_static is not None
          and abs(w_path - w_static) <= 1e-6 * abs(w_static),
          f"the path's first point is the static one at t = 0.1: {w_path} against {w_static}")

# Through the kink: the load rises to a limit, falls back and rises again to the end.
p, out, rows, steps = run("collapse", tube("true", ARC, 3.6))
check(p.returncode == 0, f"collapse by arc length: exit {p.returncode}: {p.stderr.strip()}")
summary = json.load(open(os.path.join(out, "summary.json")))
check(summary.get("status") == "converged", f"status {summary.get('status')}")
t = [r[0] for r in rows]
check(rows and abs(t[-1] - 3.6) <= 1e-9, f"the path reaches t = 3.6 (ends at {t[-1] if t else None})")
peaks = [k for k in range(1, len(t) - 1) if t[k] > t[k - 1] and t[k] > t[k + 1]]
check(len(peaks) >= 1, "the load passes a limit point (t rises, then falls)")
if peaks:
    k = peaks[0]
    dip = min(t[k:])
    check(dip <= 0.97 * t[k], f"past the limit the load falls by 3 % or more: {t[k]} -> {dip}")
    w = [r[1] for r in rows]
    check(all(w[i + 1] < w[i] for i in range(len(w) - 1)),
          "the tip goes on moving down through the limit point (w falls at every point)")
    print(f"limit load parameter {t[k]:.6g} at w = {w[k]:.6g}; falls to {dip:.6g}")
# Isothermal gas: p V = p0 V0 along the whole path (the start's V0, p0 in row 0).
pv0 = rows[0][2] * rows[0][3]
worst = max(abs(r[2] * r[3] - pv0) / pv0 for r in rows)
check(worst <= 1e-9, f"p V = p0 V0 at every point (worst {worst:.2e})")
# The gas term in the corrector keeps Newton fast: few corrections per path step.
its = [int(s["iterations"]) for s in steps]
mean = sum(its) / max(1, len(its))
check(steps and mean <= 6, f"mean corrections per path step {mean:.2f} (at most 6)")
print(f"{len(its)} path steps, {mean:.2f} corrections each, p V within {worst:.1e}")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("gas tube path following: all checks passed")
