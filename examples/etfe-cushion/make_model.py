#!/usr/bin/python3
"""Writes the two-layer ETFE cushion of this example (README.md): a quarter of a square cushion
of side A on its clamped frame, the top and bottom foils bumps of rise F over the frame's
plane (their stress-free shapes: a soap film's under pressure), the air between them a closed
gas chamber inflated by raising its amount, snow on the top foil per plan area, then taken
away.

usage: make_model.py [-o model.yaml] [--n 8] [--snow 1200] [--yield-stress 16e6]
                     [--wrinkling] [--staged]
"""
import argparse
import math

P_ATM = 101325.0

ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
ap.add_argument("-o", "--out", default="model.yaml")
ap.add_argument("--n", type=int, default=8, help="quad4 elements along a quarter side")
ap.add_argument("--side", type=float, default=3.0, help="cushion side A (m)")
ap.add_argument("--rise", type=float, default=0.3, help="rise F of each foil (m)")
ap.add_argument("--thickness", type=float, default=1.5e-4, help="foil thickness (m)")
ap.add_argument("--amount", type=float, default=1.13,
                help="gas amount after inflation, relative to the stress-free volume's")
ap.add_argument("--snow", type=float, default=1200.0, help="snow per plan area (Pa)")
ap.add_argument("--yield-stress", type=float, default=16.0e6)
ap.add_argument("--hardening", type=float, default=6.0e7)
ap.add_argument("--wrinkling", action="store_true", help="sections with wrinkling: true")
ap.add_argument("--staged", action="store_true",
                help="three analysis steps (inflate, snow, unload) instead of one run")
ap.add_argument("--step", type=float, default=0.125, help="load step (time units)")
a = ap.parse_args()

n, half, F = a.n, 0.5 * a.side, a.rise
nodes, ids = [], {}


def bump(x, y):
    """The shape of a soap film under pressure on the square (|x|, |y| <= half): the solution
    of Laplace(w) = -1 with w = 0 on the frame (series in cos and cosh, odd terms)."""
    w = 0.5 * (half * half - x * x)
    for k in range(1, 60, 2):
        b = k * math.pi / (2 * half)
        w -= (16 * half * half / (math.pi ** 3 * k ** 3) * (-1) ** ((k - 1) // 2) *
              math.cosh(b * y) / math.cosh(b * half) * math.cos(b * x))
    return w


def node(i, j, layer):
    """Node at grid point (i, j) of a layer (+1 top, -1 bottom); the frame's nodes are shared."""
    key = (i, j, 0 if (i == n or j == n) else layer)
    if key not in ids:
        x, y = half * i / n, half * j / n
        z = layer * F * bump(x, y) / bump(0, 0)
        ids[key] = len(nodes) + 1
        nodes.append([ids[key], round(x, 12), round(y, 12), 0.0 if key[2] == 0 else round(z, 12)])
    return ids[key]


def layer_elements(layer):
    conn = []
    for j in range(n):
        for i in range(n):
            q = [node(i, j, layer), node(i + 1, j, layer), node(i + 1, j + 1, layer),
                 node(i, j + 1, layer)]
            conn.append(q if layer > 0 else q[::-1])  # normals out of the gas
    return conn


top, bottom = layer_elements(1), layer_elements(-1)
frame = sorted({v for k, v in ids.items() if k[2] == 0})
plane_x = sorted({v for k, v in ids.items() if k[0] == 0 and k[1] != n})
plane_y = sorted({v for k, v in ids.items() if k[1] == 0 and k[0] != n})
apex_top, apex_bottom = ids[(0, 0, 1)], ids[(0, 0, -1)]

wr = ", wrinkling: true" if a.wrinkling else ""
head = f"""title: two-layer ETFE cushion {a.side:g} m square, inflated, snow {a.snow:g} Pa, unloaded
# Written by make_model.py{' --wrinkling' if a.wrinkling else ''}{' --staged' if a.staged else ''}: \
a quarter (symmetry x = 0, y = 0), {n} x {n} quad4 per foil.
mesh:
  nodes: {nodes}
  elements:
    - {{set: top, type: quad4, connectivity: {top}}}
    - {{set: bottom, type: quad4, connectivity: {bottom}}}
  node_sets:
    frame: {frame}
    plane_x: {plane_x}
    plane_y: {plane_y}
materials:
  etfe: {{type: elastoplastic, E: 1.1e9, nu: 0.45, yield_stress: {a.yield_stress:g}, \
hardening_modulus: {a.hardening:g}, density: 1750}}
sections:
  - {{elements: top, material: etfe, thickness: {a.thickness:g}{wr}}}
  - {{elements: bottom, material: etfe, thickness: {a.thickness:g}{wr}}}
boundary:
  - {{nodes: frame, fix: [x, y, z]}}
  - {{nodes: plane_x, symmetry: {{normal: [1, 0, 0]}}}}
  - {{nodes: plane_y, symmetry: {{normal: [0, 1, 0]}}}}
"""
gas = (f"{{type: gas, elements: [top, bottom], initial_pressure: {P_ATM}, ambient: {P_ATM}, "
       f"gamma: 1, amount: inflate}}")
snow = (f"{{type: pressure, elements: top, value: {a.snow:g}, direction: [0, 0, -1], "
        f"per: projected, function: snow}}")
output = """output:
  directory: out
  interval: 0.25
  fields: true
  history:
    - {name: p, quantity: gas_pressure, load: 0}
    - {name: V, quantity: gas_volume, load: 0}
    - {name: top, quantity: displacement, node: %d, component: z}
    - {name: bottom, quantity: displacement, node: %d, component: z}
""" % (apex_top, apex_bottom)
newton = "newton: {tolerance: 1.0e-9, max_iterations: 30}"
if a.staged:
    # A step's loads replace the list and their functions run in step time: after the
    # inflation the gas is listed again with its amount held (else it would start from 1).
    held = gas.replace("amount: inflate", "amount: inflated")
    body = f"""functions:
  inflate: {{type: table, points: [[0, 1], [1, {a.amount!r}], [1000, {a.amount!r}]]}}
  inflated: {{type: table, points: [[0, {a.amount!r}], [1000, {a.amount!r}]]}}
  up: {{type: table, points: [[0, 0], [1, 1]]}}
  down: {{type: table, points: [[0, 1], [1, 0]]}}
loads:
  - {gas}
steps:
  - {{name: inflate, analysis: {{type: static, time: {{end: 1.0, step: {a.step}}}, {newton}}}}}
  - name: snow
    analysis: {{type: static, time: {{end: 1.0, step: {a.step}}}, {newton}}}
    loads: [{held}, {snow.replace('snow}', 'up}')}]
  - name: unload
    analysis: {{type: static, time: {{end: 1.0, step: {a.step}}}, {newton}}}
    loads: [{held}, {snow.replace('snow}', 'down}')}]
"""
else:
    body = f"""functions:
  inflate: {{type: table, points: [[0, 1], [1, {a.amount!r}], [1000, {a.amount!r}]]}}
  snow: {{type: table, points: [[0, 0], [1, 0], [2, 1], [3, 0], [1000, 0]]}}
loads:
  - {gas}
  - {snow}
analysis:
  type: static
  time: {{end: 3.0, step: {a.step}}}
  {newton}
"""
with open(a.out, "w") as f:
    f.write(head + body + output)
print(f"{a.out}: {len(nodes)} nodes, {len(top) + len(bottom)} elements; apex nodes top "
      f"{apex_top}, bottom {apex_bottom}")
