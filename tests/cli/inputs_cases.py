#!/usr/bin/python3
"""Issue 47 item 7 through the command line:
- a gas-filled sphere octant closed by its symmetry planes: the summed symmetry-plane reactions
  equal those of the same mesh under a follower pressure of the gas's final gauge pressure, and
  the closed form -p_g A_z (A_z: the area the deformed sheet projects on z = 0);
- the messages: a flat chamber (V = 0), form finding with no equilibrium, an output interval
  that would cap the steps of a static stage; form.yaml names its mesh relative to itself.

usage: inputs_cases.py VELUM WORK_DIR
"""
import copy
import csv
import json
import math
import os
import shutil
import subprocess
import sys

import yaml

VELUM, WORK = sys.argv[1:3]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def run(name, model, *extra):
    d = os.path.join(WORK, name)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "model.yaml")
    with open(path, "w") as f:
        yaml.safe_dump(model, f, sort_keys=False)
    out = os.path.join(d, "out")
    p = subprocess.run([VELUM, "run", path, "-o", out, "--threads", "1", *extra],
                       capture_output=True, text=True, timeout=120)
    return p, out


def last_row(out):
    with open(os.path.join(out, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: float(v) for k, v in rows[-1].items()}


def octant(n=4, R=0.3):
    """A sphere octant of quad4 (three patches of the cube's corner faces projected on the
    sphere), normals outward, node sets plane_x, plane_y, plane_z."""
    ids = {}

    def node(p):
        key = tuple(round(c, 9) for c in p)
        ids.setdefault(key, len(ids) + 1)
        return ids[key]

    elements = []
    for face in range(3):
        grid = {}
        for i in range(n + 1):
            for j in range(n + 1):
                q = [0.0, 0.0, 0.0]
                q[face], q[(face + 1) % 3], q[(face + 2) % 3] = 1.0, i / n, j / n
                s = math.sqrt(sum(c * c for c in q))
                p = [R * c / s for c in q]
                grid[i, j] = (node(p), p)
        for i in range(n):
            for j in range(n):
                c = [grid[i, j], grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1]]
                a = [c[1][1][k] - c[0][1][k] for k in range(3)]
                b = [c[3][1][k] - c[0][1][k] for k in range(3)]
                normal = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                          a[0] * b[1] - a[1] * b[0]]
                if sum(normal[k] * c[0][1][k] for k in range(3)) < 0:
                    c.reverse()  # outward: g1 x g2 points out of the gas
                elements.append([x[0] for x in c])
    nodes = [[i] + list(k) for k, i in sorted(ids.items(), key=lambda kv: kv[1])]
    sets = {f"plane_{a}": [x[0] for x in nodes if abs(x[1 + k]) < 1e-9]
            for k, a in enumerate("xyz")}
    return {
        "title": "sphere octant",
        "mesh": {"nodes": nodes, "elements": [{"set": "sheet", "type": "quad4",
                                                 "connectivity": elements}],
                 "node_sets": sets},
        "materials": {"fabric": {"type": "isotropic", "E": 5e8, "nu": 0.3, "density": 1000.0}},
        "sections": [{"elements": "sheet", "material": "fabric", "thickness": 0.6e-3}],
        "boundary": [{"nodes": f"plane_{a}",
                      "symmetry": {"normal": [1.0 if a == b else 0.0 for b in "xyz"]}}
                     for a in "xyz"],
        "functions": {"fill": {"type": "table", "points": [[0, 1], [1, 1.05]]},
                      "ramp": {"type": "ramp", "duration": 1.0}},
        "analysis": {"type": "static", "time": {"end": 1.0, "step": 0.25},
                     "newton": {"tolerance": 1e-10}},
        "output": {"history": [
            {"name": "Rz", "quantity": "reaction", "nodes": "plane_z", "component": "z"},
            {"name": "Rx", "quantity": "reaction", "nodes": "plane_x", "component": "x"}]},
    }


# The octant: gas against a follower pressure of its final gauge pressure and the closed form.
gas = octant()
gas["loads"] = [{"type": "gas", "elements": "sheet", "initial_pressure": 1e5, "ambient": 1e5,
                 "gamma": 1.0, "amount": "fill", "origin": [0, 0, 0]}]
gas["output"]["history"] += [{"name": "p", "quantity": "gas_pressure", "load": 0}]
arc = [n[0] for n in gas["mesh"]["nodes"] if abs(n[3]) < 1e-9]
for n in arc:
    for c in "xy":
        gas["output"]["history"].append({"name": f"{c}{n}", "quantity": "position", "node": n,
                                         "component": c})
p, out = run("octant-gas", gas)
check(p.returncode == 0, f"octant gas: exit {p.returncode}: {p.stderr}")
if p.returncode == 0:
    g = last_row(out)
    pg = g["p"] - 1e5
    # A_z: the polygon of the origin and the z = 0 edge (straight quad4 edges), by angle.
    pts = sorted(((g[f"x{n}"], g[f"y{n}"]) for n in arc), key=lambda q: math.atan2(q[1], q[0]))
    poly = [(0.0, 0.0)] + pts
    Az = 0.5 * abs(sum(poly[i][0] * poly[(i + 1) % len(poly)][1]
                       - poly[(i + 1) % len(poly)][0] * poly[i][1] for i in range(len(poly))))
    print(f"octant gas: p_g {pg:.6g} Pa, A_z {Az:.6g} m2, -p_g A_z {-pg * Az:.6g} N, "
          f"reactions z {g['Rz']:.6g} N, x {g['Rx']:.6g} N")
    check(abs(g["Rz"] + pg * Az) < 1e-6 * pg * Az,
          f"octant gas: summed z reaction {g['Rz']} against -p_g A_z = {-pg * Az}")
    check(abs(g["Rx"] - g["Rz"]) < 1e-6 * abs(g["Rz"]), f"octant gas: Rx {g['Rx']} != Rz")
    follower = octant()
    follower["loads"] = [{"type": "pressure", "elements": "sheet", "value": pg,
                          "function": "ramp"}]
    p, out = run("octant-pressure", follower)
    check(p.returncode == 0, f"octant pressure: exit {p.returncode}: {p.stderr}")
    if p.returncode == 0:
        f = last_row(out)
        print(f"octant follower pressure: reactions z {f['Rz']:.6g} N")
        check(abs(f["Rz"] - g["Rz"]) < 1e-6 * abs(f["Rz"]),
              f"octant: gas {g['Rz']} against follower pressure {f['Rz']}")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("all inputs cases passed")
