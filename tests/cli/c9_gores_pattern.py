#!/usr/bin/python3
"""Issue 45 item 7: the C9 canopy's gores flattened. The paper's gores are flat by construction
(each a trapezoid between two radial seams, from the vent to the skirt, quad9 elements), so
`velum pattern` must give each one back with no strain: its area, its seam lengths and its
vent and skirt chords as built, to round-off.

usage: c9_gores_pattern.py VELUM TOOLS_DIR WORK_DIR
"""
import json
import math
import os
import shutil
import subprocess
import sys

import yaml

VELUM, TOOLS, WORK = sys.argv[1:4]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


model = os.path.join(WORK, "c9.yaml")
subprocess.run(["/usr/bin/python3", os.path.join(TOOLS, "c9-parachute"), "-o", model], check=True)
m = yaml.safe_load(open(model))
gores = [e["set"] for e in m["mesh"]["elements"] if e["set"].startswith("gore")]
check(len(gores) == 7, f"the quarter has 7 gores ({len(gores)})")
with open(model, "a") as f:
    f.write(f"patterns:\n  panels: [{', '.join(gores)}]\n")
out = os.path.join(WORK, "patterns")
p = subprocess.run([VELUM, "pattern", model, "-o", out], capture_output=True, text=True, timeout=120)
check(p.returncode == 0, f"velum pattern: exit {p.returncode}: {p.stderr.strip()}")
result = json.load(open(os.path.join(out, "patterns.json")))

# The constructed gore: 28 gores of a 28 ft canopy with an 18 in vent; straight chords.
R, rv, n = 14.0, 0.75, 28
half = math.pi / n
chord = lambda r: 2 * r * math.sin(half)  # noqa: E731
area = 0.5 * (chord(rv) + chord(R)) * (R - rv) * math.cos(half)
X = {int(row[0]): row[1:] for row in m["mesh"]["nodes"]}
worst = 0.0
for panel in result["panels"]:
    check(panel["max_strain"] < 1e-12, f"{panel['name']}: strain left {panel['max_strain']:.2e}")
    check(abs(panel["area_flat"] - area) < 1e-9 * area,
          f"{panel['name']}: flat area {panel['area_flat']!r} against {area!r}")
    flat = {int(r[0]): r[1:] for r in panel["nodes"]}
    # The corners: the flat nodes at the vent and skirt radii on the gore's two seams.
    radius = {k: math.hypot(X[k][0], X[k][1]) for k in flat}
    for r_ring, what in ((rv, "vent"), (R, "skirt")):
        ring = sorted((k for k in flat if abs(radius[k] - r_ring) < 1e-9),
                      key=lambda k: math.atan2(X[k][1], X[k][0]))
        a, b = flat[ring[0]], flat[ring[-1]]
        width = math.hypot(a[0] - b[0], a[1] - b[1])
        err = abs(width - chord(r_ring)) / chord(r_ring)
        worst = max(worst, err)
        check(err < 1e-9, f"{panel['name']}: {what} chord {width!r} against {chord(r_ring)!r}")
    # A seam from vent to skirt keeps its length R − rv.
    seam = sorted((k for k in flat if abs(math.atan2(X[k][1], X[k][0]) -
                                         math.atan2(X[min(flat)][1], X[min(flat)][0])) < 1e-9),
                  key=lambda k: radius[k])
    a, b = flat[seam[0]], flat[seam[-1]]
    length = math.hypot(a[0] - b[0], a[1] - b[1])
    check(abs(length - (R - rv)) < 1e-9 * R, f"{panel['name']}: seam {length!r} against {R - rv}")
print(f"{len(result['panels'])} gores: area {area:.6f} ft², worst chord error {worst:.1e}")
if failures:
    sys.exit(1)
print("C9 gores flattened as built: all checks passed")
