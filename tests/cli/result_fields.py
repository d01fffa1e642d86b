#!/usr/bin/python3
"""Issue 20: every frame field, the legend and the summary's extremes against closed-form
values, read back with meshio.

The model: a 2 x 1 orthotropic sheet (4 x 2 quad4, thickness t0) pulled by a dead edge load
q(t) = q t per reference length on its right edge, its left edge held in x (one node in y), all
nodes in z: a homogeneous uniaxial state. The left half has sheet axes m1 = x, the right half
m1 = y with the same material written with E1, E2 swapped (the same sheet in other axes). A
separate straight cable (cable2), fixed at one end, carries a dead point load F(t) = F t.
Closed form (Saint Venant-Kirchhoff, Green-Lagrange E, 2nd PK S): S11 = E1 E11, E22 = -nu12 E11,
the 1st PK stress lam1 S11 = q / t0 fixes lam1; lam2 = sqrt(1 + 2 E22); true stress
sigma = lam1 S11 / lam2 (thickness held); force per current length t0 sigma; reactions sum to
-q W; cable force F.

usage: result_fields.py VELUM WORK_DIR
"""
import csv
import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np

VELUM, WORK = sys.argv[1:3]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)

L, W, NX, NY = 2.0, 1.0, 4, 2
E1, E2, NU12, G12, T0 = 1000.0, 500.0, 0.3, 200.0, 0.01
Q, F_CABLE, EA = 1.0, 2.0, 100.0
TIMES = [0.0, 0.25, 0.5, 0.75, 1.0]  # the initial state is a frame too


def nid(i, j):
    return 1 + i + (NX + 1) * j


nodes = [[nid(i, j), L * i / NX, W * j / NY, 0.0] for j in range(NY + 1) for i in range(NX + 1)]
nodes += [[101, 0.0, -1.0, 0.0], [102, 0.5, -1.0, 0.0], [103, 1.0, -1.0, 0.0]]
left, right = [], []
for j in range(NY):
    for i in range(NX):
        quad = [nid(i, j), nid(i + 1, j), nid(i + 1, j + 1), nid(i, j + 1)]
        (left if i < NX // 2 else right).append(quad)
corner = nid(NX, NY)  # (L, W): the largest displacement
model = f"""title: uniaxial orthotropic sheet and a cable (issue 20 fields)
mesh:
  nodes: {json.dumps(nodes)}
  elements:
    - {{set: left, type: quad4, ids: {json.dumps(list(range(1, len(left) + 1)))}, connectivity: {json.dumps(left)}}}
    - {{set: right, type: quad4, ids: {json.dumps(list(range(11, 11 + len(right))))}, connectivity: {json.dumps(right)}}}
    - {{set: cord, type: cable2, ids: [21, 22], connectivity: [[101, 102], [102, 103]]}}
  node_sets:
    x0: {json.dumps([nid(0, j) for j in range(NY + 1)])}
    xL: {json.dumps([nid(NX, j) for j in range(NY + 1)])}
    sheet: {json.dumps([n[0] for n in nodes[:-3]])}
    cord_free: [102, 103]
materials:
  ortho: {{type: orthotropic, E1: {E1}, E2: {E2}, nu12: {NU12}, G12: {G12}, density: 1}}
  ortho90: {{type: orthotropic, E1: {E2}, E2: {E1}, nu12: {NU12 * E2 / E1}, G12: {G12}, density: 1}}
  line: {{type: cable, E: {EA / 0.01}, density: 1}}
sections:
  - {{elements: left, material: ortho, thickness: {T0}}}
  - {{elements: right, material: ortho90, thickness: {T0}, axes: {{points: [[0, 0, 0], [0, 1, 0], [-1, 0, 0]]}}}}
  - {{elements: cord, material: line, area: 0.01}}
boundary:
  - {{nodes: x0, fix: [x]}}
  - {{nodes: {nid(0, 0)}, fix: [y]}}
  - {{nodes: sheet, fix: [z]}}
  - {{nodes: 101, fix: [x, y, z]}}
  - {{nodes: cord_free, fix: [y, z]}}
loads:
  - {{type: edge, nodes: xL, force_per_length: [{Q}, 0, 0], function: ramp}}
  - {{type: point, nodes: 103, force: [{F_CABLE}, 0, 0], function: ramp}}
functions:
  ramp: {{type: ramp, duration: 1.0}}
analysis:
  type: static
  time: {{end: 1.0, step: 0.25}}
  newton: {{tolerance: 1.0e-12, max_iterations: 30}}
output:
  interval: 0.25
  history:
    - {{name: Rx, quantity: reaction, nodes: x0, component: x}}
    - {{name: Rc, quantity: reaction, nodes: 101, component: x}}
    - {{name: ux, quantity: displacement, node: {corner}, component: x}}
    - {{name: uy, quantity: displacement, node: {corner}, component: y}}
    - {{name: s11_left, quantity: stress, point: [0.5, 0.5, 0], component: s11}}
    - {{name: s22_right, quantity: stress, point: [1.5, 0.5, 0], component: s22}}
"""
path = os.path.join(WORK, "model.yaml")
open(path, "w").write(model)


def run(path, out):
    p = subprocess.run([VELUM, "run", path, "-o", out, "--threads", "1", "--quiet"],
                       capture_output=True, text=True)
    assert p.returncode == 0, f"velum failed ({p.returncode}):\n{p.stdout}{p.stderr}"


out = os.path.join(WORK, "out")
run(path, out)


def closed_form(t):
    # lam1 E1 (lam1^2 - 1) / 2 = q t / t0
    r = np.roots([E1 / 2, 0.0, -E1 / 2, -Q * t / T0])
    lam1 = max(x.real for x in r if abs(x.imag) < 1e-12)
    e11 = 0.5 * (lam1**2 - 1)
    e22 = -NU12 * e11
    lam2 = np.sqrt(1 + 2 * e22)
    sigma = lam1 * E1 * e11 / lam2
    return lam1, lam2, e11, e22, sigma


rows = list(csv.reader(open(os.path.join(out, "history.csv"))))
head, hist = rows[0], np.array([[float(v) for v in r] for r in rows[1:]])
col = {n: i for i, n in enumerate(head)}
frames = ET.parse(os.path.join(out, "results.pvd")).getroot().findall("./Collection/DataSet")
assert len(frames) == len(hist), (len(frames), len(hist))
legend = json.load(open(os.path.join(out, "legend.json")))
assert legend == {"element_set": ["left", "right", "cord"],
                  "material": ["ortho", "ortho90", "line"]}, legend

tol = 1e-9
checked = 0
for k, d in enumerate(frames):
    t = float(d.get("timestep"))
    mesh = meshio.read(os.path.join(out, d.get("file")))
    row = hist[k]
    assert abs(row[0] - t) < 1e-12
    types = [c.type for c in mesh.cells for _ in c.data]  # meshio joins blocks of one type
    assert types == ["quad"] * (NX * NY) + ["line"] * 2, types
    for name, blocks in mesh.cell_data.items():  # scalars (n,) as before issue 20; vectors (n, 3)
        assert all(b.ndim == 1 or b.shape[1] == 3 for b in blocks), (name, blocks[0].shape)
    for name, arr in mesh.point_data.items():
        assert arr.ndim == 1 or arr.shape[1] == 3, (name, arr.shape)
    cd = {name: np.concatenate([np.asarray(b, dtype=float) for b in blocks])
          for name, blocks in mesh.cell_data.items()}
    pd = mesh.point_data
    nm = NX * NY  # membrane cells first, then the two cables
    memb, cab = slice(0, nm), slice(nm, nm + 2)
    lam1, lam2, e11, e22, sigma = closed_form(t)
    half = NX * NY // 2
    L_, R_ = slice(0, half), slice(half, nm)

    def near(name, cells, expected, scale=1.0):
        v = cd[name][cells]
        assert np.all(np.abs(v - expected) <= tol * scale), (name, t, v, expected)

    # membranes
    near("true_stress_max", memb, sigma, sigma)
    near("true_stress_min", memb, 0.0, sigma)
    near("stress_11", L_, sigma, sigma)
    near("stress_22", L_, 0.0, sigma)
    near("stress_11", R_, 0.0, sigma)
    near("stress_22", R_, sigma, sigma)
    near("stress_12", memb, 0.0, sigma)
    near("force_per_length_max", memb, T0 * sigma, T0 * sigma)
    near("force_per_length_min", memb, 0.0, T0 * sigma)
    near("force_per_length_11", L_, T0 * sigma, T0 * sigma)
    near("force_per_length_22", R_, T0 * sigma, T0 * sigma)
    near("force_per_length_12", memb, 0.0, T0 * sigma)
    near("strain_11", L_, e11)
    near("strain_22", L_, e22)
    near("strain_11", R_, e22)
    near("strain_22", R_, e11)
    near("strain_12", memb, 0.0)
    near("stretch_max", memb, lam1)
    near("stretch_min", memb, lam2)
    near("fiber_angle_change", memb, 0.0)
    for name, left_dir, right_dir in [("sheet_axis_1", [1, 0, 0], [0, 1, 0]),
                                      ("sheet_axis_2", [0, 1, 0], [-1, 0, 0]),
                                      ("fiber_dir_1", [1, 0, 0], [0, 1, 0]),
                                      ("fiber_dir_2", [0, 1, 0], [-1, 0, 0]),
                                      ("sheet_normal", [0, 0, 1], [0, 0, 1])]:
        near(name, L_, np.array(left_dir))
        near(name, R_, np.array(right_dir))
    if t > 0:
        assert np.allclose(np.abs(cd["stress_dir_max"][memb]), [1, 0, 0], atol=1e-9)
    # cables: membrane fields absent (NaN), force = F t; membranes: force absent
    near("force", cab, F_CABLE * t, F_CABLE)
    assert np.all(np.isnan(cd["force"][memb]))
    for name, arr in cd.items():
        if name in ("force", "element_set", "material", "element_id"):
            continue
        assert np.all(np.isnan(arr[cab])), f"{name} is not NaN on cables"
        assert np.all(np.isfinite(arr[memb])), f"{name} is not finite on membranes"
    assert list(cd["element_set"].astype(int)) == [0] * half + [1] * half + [2, 2]
    assert list(cd["material"].astype(int)) == [0] * half + [1] * half + [2, 2]
    assert list(cd["element_id"].astype(int)) == list(range(1, half + 1)) + \
        list(range(11, 11 + half)) + [21, 22]
    # points: ids, reactions, averages
    ids = np.asarray(pd["node_id"]).astype(int)
    assert sorted(ids) == sorted(n[0] for n in nodes)
    at = {int(i): n for n, i in enumerate(ids)}
    R = pd["reaction"]
    x0 = [at[nid(0, j)] for j in range(NY + 1)]
    assert abs(R[x0, 0].sum() + Q * W * t) <= 1e-9, (R[x0, 0].sum(), -Q * W * t)
    h = W / NY  # a homogeneous state: each node carries its share of the edge, h/2 at corners
    assert np.allclose(R[x0, 0], -Q * t * h * np.array([0.5] + [1] * (NY - 1) + [0.5]),
                       rtol=0, atol=1e-12), R[x0, 0]
    assert abs(R[x0, 0].sum() - row[col["Rx"]]) <= 1e-9
    assert abs(R[at[101], 0] + F_CABLE * t) <= 1e-9 and abs(R[at[101], 0] - row[col["Rc"]]) <= 1e-9
    free = [at[nid(i, j)] for i in range(1, NX + 1) for j in range(1, NY + 1)]
    assert np.all(R[free, :2] == 0), "reaction at a free component"
    assert np.all(np.abs(R[:, 2]) <= 1e-9), "out-of-plane reaction in an in-plane problem"
    U = pd["displacement"]
    c = at[corner]
    assert abs(U[c, 0] - (lam1 - 1) * L) <= 1e-9 and abs(U[c, 1] - (lam2 - 1) * W) <= 1e-9
    assert abs(U[c, 0] - row[col["ux"]]) <= 1e-12 and abs(U[c, 1] - row[col["uy"]]) <= 1e-12
    assert abs(row[col["s11_left"]] - sigma) <= tol * sigma
    assert abs(row[col["s22_right"]] - sigma) <= tol * sigma
    sheet_nodes = [at[n[0]] for n in nodes[:-3]]
    cable_only = [at[102], at[103], at[101]]
    for name, expected in [("true_stress_max", sigma), ("force_per_length_max", T0 * sigma),
                           ("strain_11", None), ("stretch_max", lam1), ("stretch_min", lam2)]:
        v = np.asarray(pd[name])
        assert np.all(np.isnan(v[cable_only])), f"point {name} not NaN off the membranes"
        if expected is not None:
            assert np.all(np.abs(v[sheet_nodes] - expected) <= 1e-9 * abs(expected) + 1e-15), name
    # the averaged strain_11 mixes the left (E11) and right (E22) halves at the middle column
    mid = [at[nid(NX // 2, j)] for j in range(NY + 1)]
    assert np.allclose(np.asarray(pd["strain_11"])[mid], 0.5 * (e11 + e22), atol=1e-12)
    checked += 1

assert checked == len(TIMES), checked
s = json.load(open(os.path.join(out, "summary.json")))
for key in ["status", "steps", "wall_seconds", "linear_solver", "warnings", "energy",
            "cpu_seconds", "peak_memory_mb", "threads", "extremes"]:
    assert key in s, key
assert s["threads"] == 1 and s["cpu_seconds"] > 0 and s["peak_memory_mb"] > 1, s
x = s["extremes"]
lam1, lam2, e11, e22, sigma = closed_form(1.0)
assert abs(x["max_principal_stress"]["value"] - sigma) <= 1e-9 * sigma, x
assert x["max_principal_stress"]["element"] in list(range(1, 5)) + list(range(11, 15)), x
assert x["max_principal_stress"]["time"] == 1.0
assert abs(x["max_force_per_length"]["value"] - T0 * sigma) <= 1e-9 * T0 * sigma, x
assert x["max_displacement"]["node"] == corner and x["max_displacement"]["time"] == 1.0, x
assert abs(x["max_displacement"]["value"] - np.hypot((lam1 - 1) * L, (lam2 - 1) * W)) < 1e-9
# the initial state (t = 0, unloaded) is not part of the extremes
assert abs(x["min_cable_force"]["value"] - F_CABLE * TIMES[1]) <= 1e-9, x
assert x["min_cable_force"]["time"] == TIMES[1] and x["min_cable_force"]["element"] in (21, 22)
assert abs(x["max_cable_force"]["value"] - F_CABLE) <= 1e-9 and x["max_cable_force"]["time"] == 1
print(f"checked {checked} frames: sigma = {sigma:.6g}, lam1 = {lam1:.6g}, lam2 = {lam2:.6g}")

# Without frames (output.fields: false) the cells are evaluated for the extremes alone: the
# summary's extremes must be the same, to the bit.
quiet_model = model.replace("output:\n  interval: 0.25", "output:\n  interval: 0.25\n  fields: false")
assert quiet_model != model
quiet_path = os.path.join(WORK, "model-no-fields.yaml")
open(quiet_path, "w").write(quiet_model)
quiet_out = os.path.join(WORK, "out-no-fields")
run(quiet_path, quiet_out)
written = os.listdir(quiet_out)
assert "frames" not in written and "results.pvd" not in written, written
q = json.load(open(os.path.join(quiet_out, "summary.json")))
assert q["extremes"] == x, (q["extremes"], x)
print("the extremes without frames are the same")
