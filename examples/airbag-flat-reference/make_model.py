#!/usr/bin/env python3
"""Writes the square airbag sewn from two flat panels (README.md): model.yaml starts it from a
shrunk, bulged mesh, flat-start.yaml from its flat panels lifted by a minimal bulge; both give
the flat panels as mesh.reference_positions and hold the same gas at the end.

usage: make_model.py [DIR] [--n N]   (DIR defaults to this folder, N to 12 cells a side)"""
import argparse
import math
import os

A = 0.3                       # half the bag's side (m): the eighth is the quarter [0, A]^2 of the top panel
P0 = 101325.0                 # initial and ambient pressure (Pa)
GAS = 0.0060                  # gas held at the end, as its volume at P0 (m^3, the eighth's)
STARTS = {                    # in-plane scale, bulge at the centre (m)
    "flat-start": (1.0, 0.002),
    "model": (0.85, 0.06),
}


def grid(n, shrink=1.0, bulge=0.0):
    nodes = []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = A * i / n, A * j / n
            z = bulge * math.cos(math.pi * x / (2 * A)) * math.cos(math.pi * y / (2 * A))
            nodes.append([j * (n + 1) + i + 1, round(shrink * x, 12), round(shrink * y, 12), round(z, 12)])
    return nodes


def quads(n):
    return [[j * (n + 1) + i + 1, j * (n + 1) + i + 2, (j + 1) * (n + 1) + i + 2, (j + 1) * (n + 1) + i + 1]
            for j in range(n) for i in range(n)]


def volume(n, nodes):
    """The eighth's volume closed by the planes x = 0, y = 0, z = 0: (1/3) the integral of
    x . (g1 x g2) over each bilinear quad, which 2 x 2 Gauss points integrate exactly."""
    at = {p[0]: p[1:] for p in nodes}
    g = 1 / math.sqrt(3)
    V = 0.0
    for e in quads(n):
        c = [at[k] for k in e]
        for xi in (-g, g):
            for eta in (-g, g):
                N = [(1 - xi) * (1 - eta) / 4, (1 + xi) * (1 - eta) / 4, (1 + xi) * (1 + eta) / 4, (1 - xi) * (1 + eta) / 4]
                dxi = [-(1 - eta) / 4, (1 - eta) / 4, (1 + eta) / 4, -(1 + eta) / 4]
                deta = [-(1 - xi) / 4, -(1 + xi) / 4, (1 + xi) / 4, (1 - xi) / 4]
                x, g1, g2 = ([sum(w[a] * c[a][k] for a in range(4)) for k in range(3)] for w in (N, dxi, deta))
                V += (x[0] * (g1[1] * g2[2] - g1[2] * g2[1]) + x[1] * (g1[2] * g2[0] - g1[0] * g2[2])
                      + x[2] * (g1[0] * g2[1] - g1[1] * g2[0])) / 3
    return V


def model(n, name, shrink=None, bulge=None):
    """The model text of start `name` (STARTS), or of the given in-plane scale and bulge."""
    if shrink is None:
        shrink, bulge = STARTS[name]
    start = grid(n, shrink, bulge)
    v0 = volume(n, start)
    amount = GAS / v0 if v0 > 0 else 1.0  # a flat start encloses nothing: refused by velum
    seam = sorted({j * (n + 1) + n + 1 for j in range(n + 1)} | {n * (n + 1) + i + 1 for i in range(n + 1)})
    mid = (n // 2) * (n + 1) + n // 2 + 1
    rows = lambda rs: "\n".join(f"    - {r}" for r in rs)
    return f"""# Written by make_model.py: a square airbag sewn from two flat panels, one eighth, {n} x {n} quad4,
# started {'from a shrunk and bulged mesh' if name == 'model' else 'from its flat panels lifted by a minimal bulge'}
# (in-plane scale {shrink}, bulge {bulge} m; {v0:.6g} m^3), its stress-free flat panels given
# as reference_positions. The gas fills the start volume at ambient pressure; its amount rises
# to {GAS} / V_start = {amount:.6g}, so the bag ends holding {GAS} m^3 of gas at {P0} Pa.
title: square airbag from flat panels, started {'shrunk' if name == 'model' else 'flat'}
mesh:
  nodes:
{rows(start)}
  reference_positions:
{rows(grid(n))}
  elements:
    - set: bag
      type: quad4
      connectivity:
{rows(quads(n)).replace('    - ', '        - ')}
  node_sets:
    seam: {seam}
    plane_x: {[j * (n + 1) + 1 for j in range(n + 1)]}
    plane_y: {[i + 1 for i in range(n + 1)]}
materials:
  nylon: {{type: isotropic, E: 5.88e8, nu: 0.4, density: 1000.0}}
sections:
  - {{elements: bag, material: nylon, thickness: 0.6e-3, wrinkling: true}}
boundary:
  - {{nodes: plane_x, symmetry: {{normal: [1, 0, 0]}}}}
  - {{nodes: plane_y, symmetry: {{normal: [0, 1, 0]}}}}
  - {{nodes: seam, symmetry: {{normal: [0, 0, 1]}}}}
loads:
  - {{type: gas, elements: bag, initial_pressure: {P0}, ambient: {P0}, gamma: 1.0, amount: fill}}
functions:
  fill: {{type: table, points: [[0, 1], [1, {amount!r}]]}}
analysis:
  type: static
  time: {{end: 1.0, step: 0.125, min_step: 1.0e-6, adaptive: true}}
output:
  directory: out
  interval: 1.0
  history:
    - {{name: V, quantity: gas_volume, load: 0}}
    - {{name: p, quantity: gas_pressure, load: 0}}
    - {{name: apex, quantity: position, node: 1, component: z}}
    - {{name: seam_mid, quantity: position, node: {n + 1}, component: x}}
    - {{name: corner, quantity: position, node: {(n + 1) ** 2}, component: x}}
    - {{name: mid_z, quantity: position, node: {mid}, component: z}}
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", nargs="?", default=os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--n", type=int, default=12)
    a = ap.parse_args()
    os.makedirs(a.dir, exist_ok=True)
    for name in STARTS:
        with open(os.path.join(a.dir, name + ".yaml"), "w") as f:
            f.write(model(a.n, name))


if __name__ == "__main__":
    main()
