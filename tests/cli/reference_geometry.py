#!/usr/bin/env python3
"""Issue 45 (F10): a sheet started away from its stress-free reference (mesh.reference_positions)
reaches the state of the run started at the reference.

The bag of slack_bag.py (one eighth of a 0.6 m square bag, 8 x 8 quad4, nylon, wrinkling, a
3 cm stress-free bulge), inflated by gas to 5.6 times its initial amount by `static`: once
started at its reference, once from a shrunk mesh (in-plane 0.9, bulge 1.6 times) with the
reference given as mesh.reference_positions. A gas chamber's initial volume is measured where
the sheet starts (as an airbag's is its folded volume), so the shrunk run starts at the
initial pressure in its own volume and its amount ends at 5.6 V_reference / V_start: both runs
hold the same gas. Then bad input: an unknown node, a node given twice.
Usage: reference_geometry.py VELUM WORKDIR."""
import csv
import math
import os
import re
import subprocess
import sys

N, A, BULGE, AMOUNT = 8, 0.3, 0.03, 5.6


def grid(shrink=1.0, lift=1.0):
    nodes = []
    for j in range(N + 1):
        for i in range(N + 1):
            x, y = A * i / N, A * j / N
            z = BULGE * math.cos(math.pi * x / (2 * A)) * math.cos(math.pi * y / (2 * A))
            nodes.append([j * (N + 1) + i + 1, round(shrink * x, 12), round(shrink * y, 12),
                          round(lift * z, 12)])
    return nodes


def quads():
    elems = []
    for j in range(N):
        for i in range(N):
            k = j * (N + 1) + i + 1
            elems.append([k, k + 1, k + N + 2, k + N + 1])
    return elems


def volume(nodes):
    """The eighth's volume with the planes through the origin, (1/3) sum of the integral of
    x . (g1 x g2) over each bilinear quad: 2 x 2 Gauss points integrate it exactly."""
    at = {n[0]: n[1:] for n in nodes}
    g = 1 / math.sqrt(3)
    V = 0.0
    for e in quads():
        c = [at[n] for n in e]
        for xi in (-g, g):
            for eta in (-g, g):
                N4 = [(1 - xi) * (1 - eta) / 4, (1 + xi) * (1 - eta) / 4,
                      (1 + xi) * (1 + eta) / 4, (1 - xi) * (1 + eta) / 4]
                dxi = [-(1 - eta) / 4, (1 - eta) / 4, (1 + eta) / 4, -(1 + eta) / 4]
                deta = [-(1 - xi) / 4, -(1 + xi) / 4, (1 + xi) / 4, (1 - xi) / 4]
                x = [sum(N4[a] * c[a][k] for a in range(4)) for k in range(3)]
                g1 = [sum(dxi[a] * c[a][k] for a in range(4)) for k in range(3)]
                g2 = [sum(deta[a] * c[a][k] for a in range(4)) for k in range(3)]
                n = [g1[1] * g2[2] - g1[2] * g2[1], g1[2] * g2[0] - g1[0] * g2[2],
                     g1[0] * g2[1] - g1[1] * g2[0]]
                V += sum(x[k] * n[k] for k in range(3)) / 3
    return V


def model(start, reference=None, amount=AMOUNT):
    elems = quads()
    plane_x = [j * (N + 1) + 1 for j in range(N + 1)]
    plane_y = [i + 1 for i in range(N + 1)]
    seam = sorted({j * (N + 1) + N + 1 for j in range(N + 1)} | {N * (N + 1) + i + 1 for i in range(N + 1)})
    ref = f"  reference_positions: {reference}\n" if reference is not None else ""
    mid = (N // 2) * (N + 1) + N // 2 + 1
    return f"""title: slack square bag, one eighth, started {'shrunk' if reference else 'at its reference'}
mesh:
  nodes: {start}
{ref}  elements:
    - {{set: sheet, type: quad4, connectivity: {elems}}}
  node_sets:
    seam: {seam}
    plane_x: {plane_x}
    plane_y: {plane_y}
materials:
  nylon: {{type: isotropic, E: 5.88e8, nu: 0.4, density: 1000.0}}
sections:
  - {{elements: sheet, material: nylon, thickness: 0.6e-3, wrinkling: true}}
boundary:
  - {{nodes: plane_x, symmetry: {{normal: [1, 0, 0]}}}}
  - {{nodes: plane_y, symmetry: {{normal: [0, 1, 0]}}}}
  - {{nodes: seam, symmetry: {{normal: [0, 0, 1]}}}}
loads:
  - {{type: gas, elements: sheet, initial_pressure: 101325.0, ambient: 101325.0, gamma: 1.0, amount: fill}}
functions:
  fill: {{type: table, points: [[0, 1], [1, {amount!r}]]}}
analysis:
  type: static
  time: {{end: 1.0, step: 0.1, min_step: 1.0e-6, adaptive: true}}
output:
  directory: out
  interval: 1.0
  fields: false
  history:
    - {{name: V, quantity: gas_volume, load: 0}}
    - {{name: p, quantity: gas_pressure, load: 0}}
    - {{name: z0, quantity: position, node: 1, component: z}}
    - {{name: xc, quantity: position, node: {N + 1}, component: x}}
    - {{name: xm, quantity: position, node: {mid}, component: x}}
    - {{name: zm, quantity: position, node: {mid}, component: z}}
"""


def write(work, name, text):
    d = os.path.join(work, name)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "model.yaml")
    with open(path, "w") as f:
        f.write(text)
    return d, path


def run(velum, work, name, text):
    d, path = write(work, name, text)
    p = subprocess.run([velum, "run", path, "-q", "-o", os.path.join(d, "out")],
                       capture_output=True, text=True, timeout=120)
    if p.returncode != 0:
        raise SystemExit(f"{name}: exit {p.returncode}: {p.stderr.strip()}")
    with open(os.path.join(d, "out", "history.csv")) as f:
        rows = list(csv.DictReader(f))
    first, last = ({k: float(v) for k, v in r.items()} for r in (rows[0], rows[-1]))
    print(f"{name}: " + ", ".join(f"{k} {v:.6g}" for k, v in last.items()))
    return first, last


def main():
    velum, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    failures = []
    reference = grid()
    _, flat = run(velum, work, "at_reference", model(reference))
    start = grid(0.9, 1.6)
    v_ref, v_start = volume(reference), volume(start)
    first, shrunk = run(velum, work, "shrunk", model(start, reference, AMOUNT * v_ref / v_start))
    # The run starts where the mesh puts the sheet, not at its reference, and the gas fills
    # the volume there at its initial pressure.
    if not abs(first["xc"] - 0.9 * A) < 1e-9:
        failures.append(f"the shrunk run starts with node {N + 1} at x = {first['xc']}, not {0.9 * A}")
    print(f"start volumes: reference {v_ref:.8g}, shrunk {v_start:.8g}; "
          f"the shrunk run's first V {first['V']:.8g}, p {first['p']:.8g}")
    if not (abs(first["V"] - v_start) < 1e-12 * v_start and abs(first["p"] - 101325.0) < 1e-9):
        failures.append(f"the shrunk run starts at V {first['V']}, p {first['p']}: "
                        f"not its start volume {v_start} at the initial pressure")
    if not flat["p"] - 101325.0 > 1e3:
        failures.append(f"the bag never went taut: gauge {flat['p'] - 101325.0} Pa")
    for key in ("V", "p", "z0", "xc", "xm", "zm"):
        base = flat[key] - (101325.0 if key == "p" else 0.0)
        err = abs(shrunk[key] - flat[key]) / abs(base)
        print(f"{key}: shrunk start {shrunk[key]:.8g}, reference start {flat[key]:.8g} (relative {err:.1e})")
        if not err < 5e-3:
            failures.append(f"{key}: {shrunk[key]} from the shrunk start against {flat[key]}")

    # Bad input: file, line and key named, non-zero exit, no output folder run.
    bad = {"unknown": [[999, 0.0, 0.0, 0.0]] + reference[1:],
           "twice": reference + [reference[3]]}
    for name, ref in bad.items():
        d, path = write(work, "bad_" + name, model(start, ref))
        p = subprocess.run([velum, "run", path, "-q", "-o", os.path.join(d, "out")],
                           capture_output=True, text=True, timeout=60)
        msg = p.stderr.strip()
        print(f"bad {name}: exit {p.returncode}: {msg.splitlines()[0] if msg else ''}")
        want = "node 999 is not in the mesh" if name == "unknown" else "reference position twice"
        if p.returncode == 0 or "mesh.reference_positions[" not in msg or want not in msg \
                or not re.search(r"model\.yaml:\d+", msg):
            failures.append(f"bad {name}: exit {p.returncode}, message {msg!r}")
    for f in failures:
        print("FAIL:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
