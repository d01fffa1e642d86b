#!/usr/bin/env python3
"""Issue 45: `velum pattern` through the command line. A half cylinder cut into two panels
(developable: every flat edge and the area kept), its compensation, the files (patterns.json,
DXF layers CUT/SEAM/TEXT, SVG, flattening.vtu), and bad input: compensation out of range,
overlapping panels, a panel that is not a disc, an unknown set.
Usage: pattern_cases.py VELUM WORKDIR."""
import json
import math
import os
import re
import subprocess
import sys

NU, NV, R, H = 12, 6, 2.0, 3.0


def model(panels="[left, right]", compensation="[0.02, 0.01]", ring=False, overlap=False):
    span = 2 * math.pi if ring else math.pi
    cols = NU if ring else NU + 1
    nodes, left, right = [], [], []
    for j in range(NV + 1):
        for i in range(cols):
            phi = span * i / NU
            nodes.append([j * cols + i + 1, round(R * math.cos(phi), 12), round(R * math.sin(phi), 12),
                          round(H * j / NV, 12)])
    for j in range(NV):
        for i in range(NU):
            a, b = j * cols + i + 1, j * cols + (i + 1) % cols + 1
            q = [a, b, b + cols, a + cols]
            (left if i < NU // 2 else right).append(q)
    if overlap:
        right.append(left[0])
    els = (f"    - {{set: left, type: quad4, connectivity: {left}}}\n"
           f"    - {{set: right, type: quad4, connectivity: {right}}}\n")
    if ring:
        els = f"    - {{set: ring, type: quad4, connectivity: {left + right}}}\n"
    sections = ("  - {elements: ring, material: pvc, thickness: 1.0e-3}\n" if ring else
                "  - {elements: left, material: pvc, thickness: 1.0e-3}\n"
                "  - {elements: right, material: pvc, thickness: 1.0e-3}\n")
    return f"""title: half cylinder, two panels
mesh:
  nodes: {nodes}
  elements:
{els}materials:
  pvc: {{type: isotropic, E: 1.0e9, nu: 0.3, density: 1000.0}}
sections:
{sections}analysis:
  type: static
  time: {{end: 1.0, step: 1.0}}
patterns:
  panels: {panels}
  compensation: {compensation}
  seam_allowance: 0.02
"""


def pattern(velum, work, name, text):
    d = os.path.join(work, name)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "model.yaml")
    with open(path, "w") as f:
        f.write(text)
    p = subprocess.run([velum, "pattern", path, "-o", os.path.join(d, "patterns")],
                       capture_output=True, text=True, timeout=120)
    return p, os.path.join(d, "patterns")


def main():
    velum, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    failures = []
    p, out = pattern(velum, work, "cylinder", model())
    print(p.stdout.strip())
    if p.returncode != 0:
        raise SystemExit(f"velum pattern: exit {p.returncode}: {p.stderr}")
    data = json.load(open(os.path.join(out, "patterns.json")))
    by_id = {}
    text = open(os.path.join(work, "cylinder", "model.yaml")).read()
    nodes = json.loads(re.search(r"nodes: (\[\[.*?\]\])\n", text).group(1))
    xyz = {n[0]: n[1:] for n in nodes}
    for panel in data["panels"]:
        uv = {n[0]: n[1:] for n in panel["nodes"]}
        by_id[panel["name"]] = uv
        worst = 0.0
        for a in uv:
            for b in uv:  # neighbours on the grid: one step in i or j (ids a, a+1, a+cols)
                if b in (a + 1, a + NU + 1):
                    L3 = math.dist(xyz[a], xyz[b])
                    worst = max(worst, abs(math.dist(uv[a], uv[b]) - L3) / L3)
        area = math.pi * R * H / 2
        print(f"{panel['name']}: edges within {worst:.1e}, area 3-D {panel['area_3d']:.9g} "
              f"flat {panel['area_flat']:.9g}, cut {panel['area_cut']:.6g}")
        if not worst < 1e-6:
            failures.append(f"{panel['name']}: a flat edge is off by {worst:.2e}")
        if not abs(panel["area_flat"] - panel["area_3d"]) < 1e-6 * panel["area_3d"]:
            failures.append(f"{panel['name']}: flat area {panel['area_flat']} against {panel['area_3d']}")
        if not abs(panel["area_3d"] - area) < 0.01 * area:
            failures.append(f"{panel['name']}: 3-D area {panel['area_3d']} against {area}")
        # The cut line: the seam (shrunk by 2% and 1%) offset by 2 cm all round.
        seam = panel["area_flat"] * 0.98 * 0.99
        if not seam < panel["area_cut"] < seam + 0.02 * 2.1 * (math.pi * R + 2 * H):
            failures.append(f"{panel['name']}: cut area {panel['area_cut']} for a seam area {seam}")
        dxf = open(os.path.join(out, panel["name"] + ".dxf")).read()
        for layer in ("CUT", "SEAM", "TEXT"):
            if f"\n8\n{layer}\n" not in dxf:
                failures.append(f"{panel['name']}.dxf: no entity on layer {layer}")
        if not dxf.startswith("0\nSECTION\n2\nHEADER\n9\n$ACADVER\n1\nAC1009") or not dxf.endswith("EOF\n"):
            failures.append(f"{panel['name']}.dxf: not an R12 DXF")
        if "<path" not in open(os.path.join(out, panel["name"] + ".svg")).read():
            failures.append(f"{panel['name']}.svg: no outline")
    if "flattening_strain" not in open(os.path.join(out, "flattening.vtu")).read():
        failures.append("flattening.vtu: no flattening_strain field")

    bad = {"compensation": (model(compensation="[5, 0.01]"), "patterns.compensation", "plausible range"),
           "overlap": (model(overlap=True), "patterns.panels[1]", "overlaps panel 'left'"),
           "ring": (model(panels="[ring]", ring=True), "patterns.panels[0]", "Euler characteristic 0"),
           "unknown": (model(panels="[left, rigth]"), "patterns.panels[1]", "did you mean")}
    for name, (text, key, want) in bad.items():
        p, _ = pattern(velum, work, "bad_" + name, text)
        msg = p.stderr.strip()
        print(f"bad {name}: exit {p.returncode}: {msg.splitlines()[0] if msg else ''}")
        if p.returncode != 1 or key not in msg or want not in msg or not re.search(r"model\.yaml:\d+", msg):
            failures.append(f"bad {name}: exit {p.returncode}, {msg!r}")
    for f in failures:
        print("FAIL:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
