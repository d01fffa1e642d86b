#!/usr/bin/python3
"""The stress-map sheet law through the command line (docs/materials.md, "Stress maps"): a
square sheet under a biaxial dead load whose material is a grid CSV tabulated from a stiffening
fabric law converges by Newton in a few iterations per step, to the homogeneous state where
lambda_i S_ii(E11, E22) t = the edge load; with an unloading modulus, loaded and unloaded, it
keeps the strains of the unloading lines' closed form; bad grid files and moduli are rejected
naming file, line and key.

usage: stress_map_cases.py VELUM WORK_DIR [no-python]

(no-python: the build has no Python package, and `velum fit` must say so.)
"""
import csv
import json
import os
import shutil
import subprocess
import sys

import yaml

VELUM, WORK = sys.argv[1], sys.argv[2]
WITH_PYTHON = len(sys.argv) < 4 or sys.argv[3] != "no-python"
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def s11(e1, e2):
    return 600 * e1 + 9000 * e1 ** 3 + 150 * e2 + 4000 * e1 * e2 ** 2


def s22(e1, e2):
    return 400 * e2 + 20000 * e2 ** 3 + 150 * e1 + 3000 * e1 ** 2 * e2


AXIS = [-0.02 + 0.005 * k for k in range(25)]  # -0.02 ... 0.10, holds 0


def grid_rows():
    return [[e1, e2, s11(e1, e2), s22(e1, e2)] for e2 in AXIS for e1 in AXIS]


def write_grid(name, rows, header="strain_warp,strain_fill,stress_warp,stress_fill"):
    with open(os.path.join(WORK, name), "w") as f:
        f.write("# a test grid: Green-Lagrange strains, 2nd PK stress (kN/m with thickness 1)\n")
        f.write(header + "\n")
        for r in rows:
            f.write(",".join(repr(v) for v in r) + "\n")


N = 4  # a 4 x 4 quad4 sheet on the unit square
nodes = [[j * (N + 1) + i + 1, i / N, j / N, 0.0] for j in range(N + 1) for i in range(N + 1)]
quads = [[j * (N + 1) + i + 1, j * (N + 1) + i + 2, (j + 1) * (N + 1) + i + 2,
          (j + 1) * (N + 1) + i + 1] for j in range(N) for i in range(N)]
FX, FY = 12.0, 8.0  # edge loads per unit reference length


def model(grid="grid.csv", extra=None):
    mat = {"type": "stress_map", "map": grid, "G12": 30.0, "density": 1.0}
    mat.update(extra or {})
    return {
        "title": "stress map, biaxial",
        "mesh": {"nodes": nodes, "elements": [{"set": "sheet", "type": "quad4",
                                               "connectivity": quads}],
                 "node_sets": {
                     "left": {"box": [-0.01, -0.01, -0.01, 0.01, 1.01, 0.01]},
                     "bottom": {"box": [-0.01, -0.01, -0.01, 1.01, 0.01, 0.01]},
                     "right": {"box": [0.99, -0.01, -0.01, 1.01, 1.01, 0.01]},
                     "top": {"box": [-0.01, 0.99, -0.01, 1.01, 1.01, 0.01]},
                     "all": {"box": [-1, -1, -1, 2, 2, 1]}}},
        "materials": {"fab": mat},
        "sections": [{"elements": "sheet", "material": "fab", "thickness": 1.0}],
        "boundary": [{"nodes": "left", "fix": ["x"]}, {"nodes": "bottom", "fix": ["y"]},
                     {"nodes": "all", "fix": ["z"]}],
        "loads": [{"type": "edge", "nodes": "right", "force_per_length": [FX, 0, 0],
                   "function": "ramp"},
                  {"type": "edge", "nodes": "top", "force_per_length": [0, FY, 0],
                   "function": "ramp"}],
        "functions": {"ramp": {"type": "ramp", "duration": 1.0}},
        "analysis": {"type": "static", "time": {"end": 1.0, "step": 0.25},
                     "newton": {"tolerance": 1e-10, "max_iterations": 20}},
        "output": {"history": [
            {"name": "ux", "quantity": "displacement", "node": (N + 1) ** 2, "component": "x"},
            {"name": "uy", "quantity": "displacement", "node": (N + 1) ** 2, "component": "y"}]},
    }


def run(name, m):
    path = os.path.join(WORK, name + ".yaml")
    with open(path, "w") as f:
        yaml.safe_dump(m, f, sort_keys=False)
    out = os.path.join(WORK, name)
    return subprocess.run([VELUM, "run", path, "-o", out, "--threads", "1", "--quiet"],
                          capture_output=True, text=True), out


# --- Newton converges, to the homogeneous state of the tabulated law. ---
write_grid("grid.csv", grid_rows())
p, out = run("biaxial", model())
check(p.returncode == 0, f"biaxial: exit {p.returncode}: {p.stdout}{p.stderr}")
if p.returncode == 0:
    summary = json.load(open(os.path.join(out, "summary.json")))
    steps = list(csv.DictReader(open(os.path.join(out, "steps.csv"))))
    its = [int(r["iterations"]) for r in steps]
    print("Newton iterations per step:", its)
    check(summary["status"] == "converged", "biaxial: not converged")
    check(max(its) <= 6, f"biaxial: {its} iterations per step")
    res = [float(v) for v in steps[-1]["residuals"].split()]
    print("last step's residuals:", res)
    # Quadratic convergence at the end: each residual at most about the square of the last.
    check(len(res) >= 3 and res[-2] < 1e-3 * res[-3], f"biaxial: residuals {res}")
    rows = list(csv.reader(open(os.path.join(out, "history.csv"))))
    ux, uy = float(rows[-1][1]), float(rows[-1][2])
    l1, l2 = 1 + ux, 1 + uy
    E1, E2 = (l1 * l1 - 1) / 2, (l2 * l2 - 1) / 2
    r1, r2 = l1 * s11(E1, E2) / FX - 1, l2 * s22(E1, E2) / FY - 1
    print(f"E11 = {E1:.5f}, E22 = {E2:.5f}: lambda S against the load, {r1:.2e}, {r2:.2e}")
    check(abs(r1) < 2e-3 and abs(r2) < 2e-3, f"biaxial: equilibrium off by {r1}, {r2}")
    check(E1 > 0.01 and E2 > 0.01, f"biaxial: strains {E1}, {E2} too small to test the map")

# --- Unloading modulus: loaded to the same state, unloaded to zero load along the lines of
# slope K from the largest strains, S_ii = S_ii(map at E_ii = max) - K (max - E_ii) = 0: the
# strains left against that closed form (the map at the other strain as it is). ---
K = 3000.0  # above the grid's steepest slopes, 910 (warp) and 1030 (fill)
cycle = model(extra={"unloading_modulus": [K, K]})
cycle["functions"] = {"ramp": {"type": "table", "points": [[0, 0], [1, 1], [2, 0]]}}
cycle["analysis"]["time"] = {"end": 2.0, "step": 0.25}
p, out = run("unloading", cycle)
check(p.returncode == 0, f"unloading: exit {p.returncode}: {p.stdout}{p.stderr}")
if p.returncode == 0:
    rows = {float(r["time"]): r for r in csv.DictReader(open(os.path.join(out, "history.csv")))}
    def green(u):
        return ((1 + float(u)) ** 2 - 1) / 2
    m1, m2 = green(rows[1.0]["ux"]), green(rows[1.0]["uy"])
    E1, E2 = green(rows[2.0]["ux"]), green(rows[2.0]["uy"])
    # Newton on the two lines' roots (the polynomial the grid tabulates stands for the map).
    e1, e2 = m1, m2
    for _ in range(30):
        f1, f2 = s11(m1, e2) - K * (m1 - e1), s22(e1, m2) - K * (m2 - e2)
        d12 = 150 + 8000 * m1 * e2
        d21 = 150 + 6000 * e1 * m2
        det = K * K - d12 * d21
        e1, e2 = e1 - (K * f1 - d12 * f2) / det, e2 - (K * f2 - d21 * f1) / det
    print(f"unloading: peak E = ({m1:.5f}, {m2:.5f}), left ({E1:.6f}, {E2:.6f}), closed form "
          f"({e1:.6f}, {e2:.6f})")
    check(0 < E1 < m1 and 0 < E2 < m2, f"unloading: strains left {E1}, {E2}")
    check(abs(E1 - e1) < 1e-3 * m1 and abs(E2 - e2) < 1e-3 * m2,
          f"unloading: strains left ({E1}, {E2}) against ({e1}, {e2})")
    check(rows[1.0]["ux"] == list(csv.DictReader(open(os.path.join(WORK, "biaxial",
                                                                   "history.csv"))))[-1]["ux"],
          "unloading: loading as without the modulus")
for name, K_bad, phrase in [("soft", [500, K], "warp unloading modulus 500 is below the map's "
                             "steepest slope"),
                            ("negative", -1, "must not be negative")]:
    p, _ = run(name, model(extra={"unloading_modulus": K_bad}))
    check(p.returncode == 1 and "materials.fab.unloading_modulus" in p.stderr and
          phrase in p.stderr, f"{name}: {p.returncode} {p.stderr}")

# --- Bad grid files: file, line and key named; exit 1. ---
good = grid_rows()
n = len(AXIS)
bad = {
    "nonmonotone": (lambda r: r[:3] + [[r[3][0], r[3][1], r[2][2], r[3][3]]] + r[4:],
                    ["nonmonotone.csv:6: materials.fab.map", "stress_warp must increase"]),
    "hole": (lambda r: r[:n + 5] + r[n + 6:], ["hole.csv:", "materials.fab.map", "hole"]),
    "unsorted": (lambda r: r[:1] + [r[2], r[1]] + r[3:],
                 ["unsorted.csv:5: materials.fab.map", "strain_warp must increase"]),
    "text": (lambda r: r[:7] + [[r[7][0], "abc", 1, 2]] + r[8:],
             ["text.csv:10: materials.fab.map: strain_fill:", "is not a finite number"]),
}
for name, (edit, phrases) in bad.items():
    write_grid(name + ".csv", edit([list(x) for x in good]))
    p, _ = run(name, model(name + ".csv"))
    check(p.returncode == 1, f"{name}: exit {p.returncode}")
    for ph in phrases:
        check(ph in p.stderr, f"{name}: '{ph}' not in:\n{p.stderr}")
# A zero slope at the origin (E11 = 0 is the grid's first warp strain, S11 flat there).
flat = [[e1, e2, 1e3 * e1 ** 2 + 1e-3 * e1 ** 3, s22(e1, e2)]
        for e2 in AXIS[4:] for e1 in AXIS[4:]]
write_grid("flat.csv", flat)
p, _ = run("flat", model("flat.csv"))
check(p.returncode == 1 and "materials.fab.map" in p.stderr and
      "slopes at zero strain must be positive" in p.stderr, f"flat: {p.returncode} {p.stderr}")
write_grid("header.csv", good, header="e1,e2,s1,s2")
p, _ = run("header", model("header.csv"))
check(p.returncode == 1 and "header.csv:2: materials.fab.map: expected the header" in p.stderr,
      f"header: {p.stderr}")
p, _ = run("missing", model("nowhere.csv"))
check(p.returncode == 1 and "nowhere.csv" in p.stderr and "cannot open" in p.stderr,
      f"missing: {p.stderr}")
p, _ = run("both", model(extra={"shear": "s.csv"}))
check(p.returncode == 1 and "either `shear: FILE.csv` or `G12" in p.stderr, f"both: {p.stderr}")

# --- `velum fit`: the Python module velum.fit behind the command line. ---
with open(os.path.join(WORK, "biaxial.csv"), "w") as f:
    f.write("ratio,strain_warp,strain_fill,stress_warp,stress_fill\n")
    for ratio, (w, fl) in {"1:1": (1, 1), "2:1": (2, 1), "1:2": (1, 2), "1:0": (1, 0),
                           "0:1": (0, 1)}.items():
        for k in range(1, 9):  # an orthotropic law's strains under stresses in that ratio
            s1, s2 = 2.0 * k * w, 2.0 * k * fl
            f.write(f"{ratio},{s1 / 600 - 0.3 * s2 / 600!r},{-0.3 * s1 / 600 + s2 / 400!r},"
                    f"{s1!r},{s2!r}\n")
p = subprocess.run([VELUM, "fit", "biaxial.csv", "--green", "--name", "tab", "--no-png"],
                   cwd=WORK, capture_output=True, text=True)
if not WITH_PYTHON:  # a build without the Python package (the sanitizers' preset) says so
    check(p.returncode != 0 and "velum fit needs Velum's Python package" in p.stderr,
          f"velum fit without the package: exit {p.returncode}: {p.stderr}")
else:
    check(p.returncode == 0 and "type: orthotropic" in p.stdout and "E1: 600" in p.stdout and
          os.path.isfile(os.path.join(WORK, "tab-map.csv")),
          f"velum fit: exit {p.returncode}: {p.stdout[:400]}{p.stderr}")
    with open(os.path.join(WORK, "badfit.csv"), "w") as f:
        f.write("ratio,strain_warp,strain_fill,stress_warp,stress_fill\n1:1,0.01,x,1,1\n")
    p = subprocess.run([VELUM, "fit", "badfit.csv"], cwd=WORK, capture_output=True, text=True)
    check(p.returncode == 1 and "badfit.csv:2: strain_fill" in p.stderr,
          f"velum fit, bad CSV: exit {p.returncode}: {p.stderr}")

print("failures:", len(failures))
sys.exit(1 if failures else 0)
