#!/usr/bin/env python3
"""Issue 45 item 5: the round trip of a cutting pattern. A hypar with straight fixed edges is
form-found under an isotropic prestress (a minimal surface), cut into strip panels along the
warp, flattened and compensated by the strain of that prestress; velum pattern writes
roundtrip.yaml (the flat panels as mesh.panel_references, seams joined, no prestress) and its
static run must bring every panel back to the designed prestress: the mean of each stress
component within 0.5 % of it (documented in docs/patterns.md), every element's within what the
flattening strain leaves (E max_strain / (1 - nu), plus 1 %). Triangles: the flattening's
own elements; quad4 panels (flattened for their Gauss points' strain) come back within 1.5 %
at 12 x 12 as the cells report it, the error falling by a quarter at 24 x 24 (quad_checks).
Bad panel references are refused.
Usage: pattern_roundtrip.py VELUM WORKDIR."""
import json
import math
import os
import re
import subprocess
import sys

import meshio

L, H, N, PANELS = 4.0, 0.8, 12, 4
E, NU, T = 6.0e8, 0.3, 1.0e-3
S0 = 3.0e6  # prestress, Pa (3 kN/m over 1 mm)


def node(i, j):
    return 1 + j * (N + 1) + i


def compensation():
    # The flat panel shrunk by c stretches by 1 / (1 - c) when sewn: its Green strain must be
    # the equal biaxial prestress strain S0 (1 - nu) / E.
    g = S0 * (1 - NU) / E
    return 1 - 1 / math.sqrt(1 + 2 * g)


def model(extra_mesh="", quads=False):
    nodes = []
    for j in range(N + 1):
        for i in range(N + 1):
            u, v = i / N, j / N
            nodes.append(f"[{node(i, j)}, {L * u:.6g}, {L * v:.6g}, {H * (u * (1 - v) + v * (1 - u)) - H / 2:.6g}]")
    strips = []
    per = N // PANELS
    for p in range(PANELS):
        tris = [t for j in range(p * per, (p + 1) * per) for i in range(N)
                for t in ([node(i, j), node(i + 1, j), node(i + 1, j + 1)],
                          [node(i, j), node(i + 1, j + 1), node(i, j + 1)])]
        if quads:
            cells = [[node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)]
                     for j in range(p * per, (p + 1) * per) for i in range(N)]
            strips.append(f"    - {{set: panel_{p + 1}, type: quad4, connectivity: {cells}}}")
            continue
        strips.append(f"    - {{set: panel_{p + 1}, type: tri3, connectivity: {tris}}}")
    edge = sorted({node(i, 0) for i in range(N + 1)} | {node(i, N) for i in range(N + 1)} |
                  {node(0, j) for j in range(N + 1)} | {node(N, j) for j in range(N + 1)})
    sections = "\n".join(f"  - {{elements: panel_{p + 1}, material: pvc, thickness: {T}, "
                         f"prestress: [{S0}, {S0}, 0.0]}}" for p in range(PANELS))
    c = compensation()
    names = ", ".join(f"panel_{p + 1}" for p in range(PANELS))
    return f"""title: hypar cut in {PANELS} strips, round trip
mesh:
  nodes: [{", ".join(nodes)}]
  elements:
{chr(10).join(strips)}
  node_sets:
    edge: {edge}
{extra_mesh}materials:
  pvc: {{type: isotropic, E: {E}, nu: {NU}, density: 1000.0}}
sections:
{sections}
boundary:
  - {{nodes: edge, fix: [x, y, z]}}
analysis:
  type: form_finding
  time: {{end: 1.0, step: 1.0}}
patterns:
  panels: [{names}]
  compensation: [{c:.9g}, {c:.9g}]
  seam_allowance: 0.02
"""


def velum(args, timeout=300):
    return subprocess.run(args, capture_output=True, text=True, timeout=timeout)


def last_vtu(folder):
    frames = re.findall(r'file="([^"]+)"', open(os.path.join(folder, "results.pvd")).read())
    return os.path.join(folder, frames[-1])


def quad_round_trip(exe, work, n):
    """The hypar of n x n quad4 through form finding, velum pattern and the round trip: per
    panel the mean of the cells' stress_11 and stress_22 (sampled at the cell centres) relative
    to the prestress."""
    global N
    keep, N = N, n
    try:
        text = model(quads=True)
    finally:
        N = keep
    d = os.path.join(work, f"quad4_{n}")
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "hypar.yaml")
    with open(path, "w") as f:
        f.write(text)
    for args in (["run", path, "-q", "-o", os.path.join(d, "form")],
                 ["pattern", os.path.join(d, "form"), "-o", os.path.join(d, "patterns")],
                 ["run", os.path.join(d, "patterns", "roundtrip.yaml"), "-q", "-o", os.path.join(d, "rt")]):
        p = velum([exe] + args)
        if p.returncode != 0:
            raise SystemExit(f"quad4 {n}: velum {args[0]}: exit {p.returncode}: {p.stderr}")
    mesh = meshio.read(last_vtu(os.path.join(d, "rt")))
    names = json.load(open(os.path.join(d, "rt", "legend.json")))["element_set"]
    cell = lambda k: [v for block in mesh.cell_data[k] for v in block]
    sets = [names[int(i)] for i in cell("element_set")]
    s = {k: cell(k) for k in ("stress_11", "stress_22")}
    errors = []
    for name in sorted(set(sets)):
        idx = [i for i, m in enumerate(sets) if m == name]
        errors += [sum(s[c][i] for i in idx) / len(idx) / S0 - 1 for c in ("stress_11", "stress_22")]
    return errors


def quad_checks(exe, work):
    """Quadrilateral panels: flattened for the strain quad4 measures (at its Gauss points on the
    twisted bilinear surface), the round trip's stress comes back; the cell outputs, sampled
    at the element centres, stay low by a second-order discretisation error (the centre's
    metric of a twisted quad against its Gauss points'): 1.3 % at 12 x 12, a quarter of it at
    24 x 24 (docs/patterns.md). Before, flattened as split triangles: 3.8 % and 0.95 %."""
    failures = []
    e12, e24 = (quad_round_trip(exe, work, n) for n in (12, 24))
    w12, w24 = max(map(abs, e12)), max(map(abs, e24))
    print(f"quad4 round trip, worst panel mean stress error: 12 x 12 {w12:.3%}, 24 x 24 {w24:.3%} "
          f"(ratio {w12 / w24:.2f})")
    if not (all(e < 0 for e in e12 + e24) and w12 < 0.015):
        failures.append(f"quad4 12 x 12: mean stress errors {e12}, beyond 1.5 % or not low")
    if not 3.5 < w12 / w24 < 4.5:
        failures.append(f"quad4: the error falls from {w12:.3%} to {w24:.3%}, not by a quarter")
    return failures


def main():
    exe, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    failures = []
    path = os.path.join(work, "hypar.yaml")
    with open(path, "w") as f:
        f.write(model())
    p = velum([exe, "run", path, "-q", "-o", os.path.join(work, "form")])
    if p.returncode != 0:
        raise SystemExit(f"form finding: exit {p.returncode}: {p.stderr}")
    p = velum([exe, "pattern", os.path.join(work, "form"), "-o", os.path.join(work, "patterns")])
    print(p.stdout.strip())
    if p.returncode != 0:
        raise SystemExit(f"velum pattern: exit {p.returncode}: {p.stderr}")
    data = json.load(open(os.path.join(work, "patterns", "patterns.json")))
    strain = {q["name"]: q["max_strain"] for q in data["panels"]}
    rt = os.path.join(work, "patterns", "roundtrip.yaml")
    p = velum([exe, "run", rt, "-q", "-o", os.path.join(work, "roundtrip")])
    if p.returncode != 0:
        raise SystemExit(f"round trip: exit {p.returncode}: {p.stderr}")
    out = os.path.join(work, "roundtrip")
    mesh = meshio.read(last_vtu(out))
    names = json.load(open(os.path.join(out, "legend.json")))["element_set"]
    cell = lambda k: [v for block in mesh.cell_data[k] for v in block]
    sets = [names[int(i)] for i in cell("element_set")]
    s = {k: cell(k) for k in ("stress_11", "stress_22", "stress_12")}
    for name in sorted(strain):
        idx = [i for i, n in enumerate(sets) if n == name]
        if len(idx) != 2 * N * (N // PANELS):
            raise SystemExit(f"round trip: panel {name} has {len(idx)} cells")
        mean = [sum(s[c][i] for i in idx) / len(idx) for c in ("stress_11", "stress_22", "stress_12")]
        spread = max(abs(s[c][i] - S0) for c in ("stress_11", "stress_22") for i in idx)
        err = [abs(mean[0] - S0) / S0, abs(mean[1] - S0) / S0, abs(mean[2]) / S0]
        bound = S0 * 0.01 + E * strain[name] / (1 - NU)
        print(f"{name}: mean stress [{mean[0]:.5g}, {mean[1]:.5g}, {mean[2]:.4g}] Pa against "
              f"[{S0:g}, {S0:g}, 0]: errors {err[0]:.2%} {err[1]:.2%} {err[2]:.2%}; largest "
              f"deviation {spread / S0:.2%} (flattening strain {strain[name]:.2e}, bound "
              f"{bound / S0:.1%})")
        if not max(err) < 0.005:
            failures.append(f"{name}: mean stress {mean} off the prestress {S0} by {max(err):.2%}")
        if not spread < bound:
            failures.append(f"{name}: a stress {spread / S0:.2%} off the prestress, beyond {bound / S0:.1%}")

    failures += quad_checks(exe, work)

    # Bad input: a panel reference missing a node, an unknown set.
    text = open(rt).read()
    bad = {"missing": (re.sub(r"(panel_references:\n(?:.*\n)*?\s+positions:\n)\s+- \[\d+, [^\]]*\]\n", r"\1", text, count=1),
                       "give every node of the panel"),
           "unknown": (text.replace("elements: panel_1\n", "elements: panel_9\n", 1), "undefined element set 'panel_9'")}
    for name, (t, want) in bad.items():
        bp = os.path.join(work, f"bad_{name}.yaml")
        with open(bp, "w") as f:
            f.write(t)
        p = velum([exe, "check", bp], timeout=60)
        msg = p.stderr.strip()
        print(f"bad {name}: exit {p.returncode}: {msg.splitlines()[0] if msg else ''}")
        if p.returncode == 0 or want not in msg or not re.search(r"\.yaml:\d+", msg):
            failures.append(f"bad {name}: exit {p.returncode}, {msg!r}")
    for f in failures:
        print("FAIL:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
