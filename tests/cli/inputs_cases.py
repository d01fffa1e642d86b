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
        print("FAIL:", what[:600])


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


def check_model(name, model):
    d = os.path.join(WORK, name)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "model.yaml")
    with open(path, "w") as f:
        yaml.safe_dump(model, f, sort_keys=False)
    return subprocess.run([VELUM, "check", path], capture_output=True, text=True, timeout=60)


def square_bag(n=4, L=0.3, bulge=0.0):
    """One eighth of a square cushion: the top sheet over [0, L]^2, its seam held on z = 0,
    lifted by `bulge` in the middle (0: flat, no volume)."""
    nodes, els = [], []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = L * i / n, L * j / n
            nodes.append([1 + i + j * (n + 1), x, y,
                          bulge * (1 - (x / L) ** 2) * (1 - (y / L) ** 2)])
    for j in range(n):
        for i in range(n):
            a = 1 + i + j * (n + 1)
            els.append([a, a + 1, a + n + 2, a + n + 1])

    def ids(f):
        return [q[0] for q in nodes if f(q[1], q[2])]

    return {
        "title": "square bag",
        "mesh": {"nodes": nodes, "elements": [{"set": "sheet", "type": "quad4",
                                                 "connectivity": els}],
                 "node_sets": {"plane_x": ids(lambda x, y: x == 0),
                               "plane_y": ids(lambda x, y: y == 0),
                               "seam": ids(lambda x, y: abs(x - L) < 1e-12
                                           or abs(y - L) < 1e-12)}},
        "materials": {"fabric": {"type": "isotropic", "E": 5e8, "nu": 0.4, "density": 1000.0}},
        "sections": [{"elements": "sheet", "material": "fabric", "thickness": 0.6e-3}],
        "boundary": [{"nodes": "plane_x", "symmetry": {"normal": [1, 0, 0]}},
                     {"nodes": "plane_y", "symmetry": {"normal": [0, 1, 0]}},
                     {"nodes": "seam", "symmetry": {"normal": [0, 0, 1]}}],
        "loads": [{"type": "gas", "elements": "sheet", "initial_pressure": 101325.0,
                   "ambient": 101325.0, "gamma": 1.0, "amount": "fill"}],
        "functions": {"fill": {"type": "table", "points": [[0, 1], [1, 2]]}},
        "analysis": {"type": "static", "time": {"end": 1.0, "step": 0.25}},
    }


# A flat chamber (V = 0) is flat, not inside out; with a bulge it is accepted.
p = check_model("flat-bag", square_bag())
check(p.returncode == 1 and "zero to round-off" in p.stderr and "flat or degenerate" in p.stderr
      and "bulge" in p.stderr and "reverse the node order" not in p.stderr,
      f"flat bag: exit {p.returncode}: {p.stderr}")
p = check_model("bulged-bag", square_bag(bulge=0.03))
check(p.returncode == 0, f"bulged bag: exit {p.returncode}: {p.stderr}")


def sine_sheet(prestress, n=12, A=0.02, max_updates=60):
    """Form finding of a sheet over the unit square, its edges fixed, two of them curved
    (w = A sin(pi x) on y = 0 and y = 1): warp = fill has a shape, warp != fill none."""
    nodes, els, edge = [], [], []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = i / n, j / n
            nodes.append([1 + i + j * (n + 1), x, y,
                          A * math.sin(math.pi * x) if j in (0, n) else 0.0])
            if i in (0, n) or j in (0, n):
                edge.append(1 + i + j * (n + 1))
    for j in range(n):
        for i in range(n):
            a = 1 + i + j * (n + 1)
            els.append([a, a + 1, a + n + 2, a + n + 1])
    return {
        "title": "sine sheet",
        "mesh": {"nodes": nodes, "elements": [{"set": "sheet", "type": "quad4",
                                                 "connectivity": els}],
                 "node_sets": {"edge": edge}},
        "materials": {"fabric": {"type": "isotropic", "E": 1000.0, "nu": 0.3, "density": 1.0}},
        "sections": [{"elements": "sheet", "material": "fabric", "thickness": 1.0,
                      "prestress": prestress}],
        "boundary": [{"nodes": "edge", "fix": ["x", "y", "z"]}],
        "analysis": {"type": "form_finding", "time": {"end": 1.0, "step": 1.0},
                     "form_finding": {"max_updates": max_updates}},
    }


# Form finding of a warp != fill prestress with no equilibrium shape says why, and does not
# send the user to max_updates.
p, out = run("form-warp-fill", sine_sheet([4.0, 1.0, 0.0]))
check(p.returncode == 2 and "differs between warp and fill" in p.stderr
      and "more updates only slide the mesh" in p.stderr
      and "raise analysis.form_finding.max_updates" not in p.stderr,
      f"form finding warp != fill: exit {p.returncode}: {p.stderr}")

# form.yaml names its mesh file relative to itself: the folder moved, it still runs.
model = sine_sheet([1.0, 1.0, 0.0])
lines = ["*NODE"] + [f"{q[0]}, {q[1]!r}, {q[2]!r}, {q[3]!r}" for q in model["mesh"]["nodes"]]
lines += ["*ELEMENT, TYPE=M3D4, ELSET=SHEET"]
lines += [f"{k + 1}, " + ", ".join(map(str, e))
          for k, e in enumerate(model["mesh"]["elements"][0]["connectivity"])]
lines += ["*NSET, NSET=EDGE", ", ".join(map(str, model["mesh"]["node_sets"]["edge"]))]
model["mesh"] = {"file": "sheet.inp"}
model["sections"][0]["elements"] = "SHEET"
model["boundary"][0]["nodes"] = "EDGE"
here = os.path.join(WORK, "form-portable")
os.makedirs(here)
with open(os.path.join(here, "sheet.inp"), "w") as f:
    f.write("\n".join(lines) + "\n")
p, out = run("form-portable", model)
check(p.returncode == 0, f"form finding for form.yaml: exit {p.returncode}: {p.stderr}")
if p.returncode == 0:
    form = yaml.safe_load(open(os.path.join(out, "form.yaml")))
    check(form["mesh"]["file"] == "../sheet.inp",
          f"form.yaml names its mesh {form['mesh']['file']!r}, not ../sheet.inp")
    moved = os.path.join(WORK, "form-moved")
    shutil.move(here, moved)
    q = subprocess.run([VELUM, "run", os.path.join(moved, "out", "form.yaml"), "-o",
                        os.path.join(moved, "again"), "--threads", "1", "-q"],
                       capture_output=True, text=True, timeout=60)
    check(q.returncode == 0, f"form.yaml in a moved folder: exit {q.returncode}: {q.stderr}")


def staged(static_step):
    """A sheet shaken dynamically for 0.01 s, then a static step; output.interval 2 ms."""
    model = copy.deepcopy(sine_sheet([1.0, 1.0, 0.0], n=2, A=0.0))
    model["sections"][0].pop("prestress")
    model["mesh"]["node_sets"]["right"] = [3, 6, 9]
    model["boundary"] = [{"nodes": [1, 4, 7], "fix": ["x", "y", "z"]},
                         {"nodes": "sheet", "fix": ["z"]}]
    model["boundary"][1]["nodes"] = [q[0] for q in model["mesh"]["nodes"]]
    model["loads"] = [{"type": "edge", "nodes": "right", "force_per_length": [8.0, 0, 0],
                       "function": "ramp"}]
    model["functions"] = {"ramp": {"type": "ramp", "duration": 1.0}}
    del model["analysis"]
    model["steps"] = [
        {"name": "shake", "analysis": {"type": "dynamic", "time": {"end": 0.01, "step": 0.001}}},
        {"name": "settle", "analysis": {"type": "static",
                                        "time": {"end": 1.0, "step": static_step}}}]
    model["output"] = {"interval": 0.002}
    return model


# A global output interval does not cut the load steps of a static step.
for step, expected in [(1.0, 1), (0.25, 4)]:
    p, out = run(f"stage-static-{step}", staged(step))
    check(p.returncode == 0, f"staged, static step {step}: exit {p.returncode}: {p.stderr}")
    if p.returncode:
        continue
    s = json.load(open(os.path.join(out, "summary.json")))
    steps = [a["steps"] for a in s["analysis_steps"]]
    with open(os.path.join(out, "history.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["analysis_step"] == "2"]
    print(f"staged, static step {step}: load steps {steps[1]}, history rows {len(rows)}")
    check(steps == [10, expected] and len(rows) == expected,
          f"staged, static step {step}: steps {steps}, {len(rows)} rows of the static step")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("all inputs cases passed")
