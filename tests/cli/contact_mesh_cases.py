#!/usr/bin/python3
"""Rigid meshes read from Gmsh files (issue 41, shape: mesh): a prestressed sheet pressed onto
the top of a box of quads equals the same sheet pressed onto the plane of that top (fixed, and
turned and moved by a prescribed motion), a free box of triangles bounces off the sheet, and
bad meshes are refused naming the file, the line and the key.

usage: contact_mesh_cases.py VELUM WORK_DIR
"""
import copy
import csv
import os
import re
import shutil
import subprocess
import sys

import yaml

VELUM, WORK = sys.argv[1], sys.argv[2]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def write_msh(path, points, elements):
    """MSH 2.2 ASCII: points [(x, y, z)], elements [(gmsh type, [node indices from 0])]."""
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(points))
        for i, p in enumerate(points):
            f.write("%d %.17g %.17g %.17g\n" % (i + 1, *p))
        f.write("$EndNodes\n$Elements\n%d\n" % len(elements))
        for i, (t, conn) in enumerate(elements):
            f.write("%d %d 2 1 1 %s\n" % (i + 1, t, " ".join(str(c + 1) for c in conn)))
        f.write("$EndElements\n")


def box_msh(path, lo, hi, n, triangles=False):
    """The box lo..hi, each face n x n quads (or triangles), normals out of the box."""
    dx, dy, dz = (hi[k] - lo[k] for k in range(3))
    ex, ey, ez = (dx, 0, 0), (0, dy, 0), (0, 0, dz)
    faces = [((lo[0], lo[1], hi[2]), ex, ey), ((lo[0], lo[1], lo[2]), ey, ex),
             ((hi[0], lo[1], lo[2]), ey, ez), ((lo[0], lo[1], lo[2]), ez, ey),
             ((lo[0], hi[1], lo[2]), ez, ex), ((lo[0], lo[1], lo[2]), ex, ez)]
    index, points, elements = {}, [], []

    def node(p):
        key = tuple(round(c, 12) for c in p)
        if key not in index:
            index[key] = len(points)
            points.append(p)
        return index[key]

    for o, u, v in faces:
        g = [[node(tuple(o[k] + u[k] * i / n + v[k] * j / n for k in range(3)))
              for j in range(n + 1)] for i in range(n + 1)]
        for i in range(n):
            for j in range(n):
                q = [g[i][j], g[i + 1][j], g[i + 1][j + 1], g[i][j + 1]]
                if triangles:
                    elements += [(2, [q[0], q[1], q[2]]), (2, [q[0], q[2], q[3]])]
                else:
                    elements.append((3, q))
    write_msh(path, points, elements)


N, A = 10, 1.0
nodes, elems, edge = [], [], []
for j in range(N + 1):
    for i in range(N + 1):
        nid = j * (N + 1) + i + 1
        nodes.append([nid, A * i / N - A / 2, A * j / N - A / 2, 0.0])
        if i in (0, N) or j in (0, N):
            edge.append(nid)
for j in range(N):
    for i in range(N):
        a = j * (N + 1) + i + 1
        elems.append([a, a + 1, a + N + 2, a + N + 1])
middle = (N // 2) * (N + 1) + N // 2 + 1
TOP = -0.03
BASE = {
    "mesh": {"nodes": nodes, "elements": [{"set": "sheet", "type": "quad4",
                                           "connectivity": elems}]},
    "materials": {"pvc": {"type": "isotropic", "E": 1.0e9, "nu": 0.3, "density": 1000}},
    "sections": [{"elements": "sheet", "material": "pvc", "thickness": 0.001,
                  "prestress": [2.0e6, 2.0e6, 0]}],
    "boundary": [{"nodes": edge, "fix": ["x", "y", "z"]}],
    "functions": {"ramp": {"type": "ramp", "duration": 1.0}},
    "loads": [{"type": "pressure", "elements": "sheet", "value": 10000.0,
               "direction": [0, 0, -1], "function": "ramp"}],
    "rigid_bodies": [{"name": "floor", "shape": "plane", "point": [0, 0, TOP],
                      "normal": [0, 0, 1]}],
    "contact": [{"surfaces": ["sheet", "floor"], "friction": 0.2}],
    "analysis": {"type": "static", "time": {"end": 1.0, "step": 0.2}},
    "output": {"fields": False, "history": [
        {"name": "fz", "quantity": "contact_force", "body": "floor", "component": "z"},
        {"name": "fx", "quantity": "contact_force", "body": "floor", "component": "x"},
        {"name": "area", "quantity": "contact_area", "body": "floor"},
        {"name": "uz", "quantity": "displacement", "node": middle, "component": "z"},
        {"name": "ux", "quantity": "displacement", "node": middle + 2, "component": "x"}]},
}
box_msh(os.path.join(WORK, "box.msh"), (-0.7, -0.7, -0.5), (0.7, 0.7, TOP), 4)


def run(name, m):
    path = os.path.join(WORK, name + ".yaml")
    with open(path, "w") as f:
        yaml.safe_dump(m, f, default_flow_style=None, sort_keys=False)
    out = os.path.join(WORK, name)
    p = subprocess.run([VELUM, "run", path, "-o", out, "--quiet"], capture_output=True,
                       text=True, timeout=120)
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv")))) \
        if p.returncode == 0 else []
    return p, rows, path


def as_mesh(m):
    b = m["rigid_bodies"][0]
    motion = b.get("motion")
    m["rigid_bodies"][0] = {"name": "floor", "shape": "mesh", "file": "box.msh"}
    if motion:
        m["rigid_bodies"][0]["motion"] = motion
    return m


# The sheet draped onto the box's top equals the sheet on the plane there: fixed, and with
# the body turned about x and lifted by a prescribed motion.
motion = {"displacement": [0.01, 0, 0.005], "rotation": [0.02, 0, 0.1], "point": [0, 0, TOP],
          "function": "ramp"}
for kind in ("fixed", "moved"):
    plane = copy.deepcopy(BASE)
    if kind == "moved":
        plane["rigid_bodies"][0]["motion"] = motion
    mesh = as_mesh(copy.deepcopy(plane))
    p1, r1, _ = run(f"plane_{kind}", plane)
    p2, r2, _ = run(f"mesh_{kind}", mesh)
    check(p1.returncode == 0 and p2.returncode == 0,
          f"{kind}: both run ({p1.stderr.strip()[-200:]} {p2.stderr.strip()[-200:]})")
    if not (r1 and r2):
        continue
    worst = 0.0
    for a, b in zip(r1, r2):
        for k in ("fz", "fx", "area", "uz", "ux"):
            scale = max(abs(float(r["fz" if k == "fx" else k])) for r in r1) or 1.0
            worst = max(worst, abs(float(a[k]) - float(b[k])) / scale)
    last = r2[-1]
    print(f"{kind}: force {float(last['fz']):.6g} N, area {float(last['area']):.4g} m2, "
          f"middle {float(last['uz']):.6g} m; largest difference {worst:.3g} of each column")
    check(float(last["area"]) > 0.1 and float(last["fz"]) < 0,
          f"{kind}: the sheet rests on the body")
    check(len(r1) == len(r2) and worst < 1e-9,
          f"{kind}: the box's top gives the plane's answer (largest difference {worst:.3g})")

# Edge contact with the box (edges: true): the sheet lies on the box's top, which is wider than
# it, so no side of the sheet crosses a ridge: the same answer as without (the ridges at the
# box's base, which the sheet's sides pass over far above, push nothing).
plane = copy.deepcopy(BASE)
mesh = as_mesh(copy.deepcopy(plane))
mesh["contact"][0]["edges"] = True
p1, r1, _ = run("plane_fixed", plane)
p2, r2, _ = run("mesh_fixed_edges", mesh)
check(p1.returncode == 0 and p2.returncode == 0,
      f"edges: both run ({p1.stderr.strip()[-200:]} {p2.stderr.strip()[-200:]})")
if r1 and r2:
    # (fx is round-off about zero: measured against fz.)
    worst = max(abs(float(a[k]) - float(b[k])) /
                (max(abs(float(r["fz" if k == "fx" else k])) for r in r1) or 1.0)
                for a, b in zip(r1, r2) for k in ("fz", "fx", "area", "uz", "ux"))
    check(len(r1) == len(r2) and worst < 1e-9,
          f"edges: the box's top still gives the plane's answer (largest difference {worst:.3g})")

# The same with friction (edges: true and friction 0.3): no side crosses a ridge, so the
# plane's answer with the same friction; a friction below 0 with edges is refused.
plane = copy.deepcopy(BASE)
plane["contact"][0]["friction"] = 0.3
mesh = as_mesh(copy.deepcopy(plane))
mesh["contact"][0]["edges"] = True
p1, r1, _ = run("plane_fixed_friction", plane)
p2, r2, _ = run("mesh_fixed_edges_friction", mesh)
check(p1.returncode == 0 and p2.returncode == 0,
      f"edges with friction: both run ({p1.stderr.strip()[-200:]} {p2.stderr.strip()[-200:]})")
if r1 and r2:
    worst = max(abs(float(a[k]) - float(b[k])) /
                (max(abs(float(r["fz" if k == "fx" else k])) for r in r1) or 1.0)
                for a, b in zip(r1, r2) for k in ("fz", "fx", "area", "uz", "ux"))
    check(len(r1) == len(r2) and worst < 1e-9,
          f"edges with friction: the plane's answer (largest difference {worst:.3g})")
mesh["contact"][0]["friction"] = -0.1
p, _, path = run("edges_negative_friction", mesh)
check(p.returncode == 1 and "contact[0].friction" in p.stderr
      and re.search(re.escape(os.path.basename(path)) + r":\d+: ", p.stderr) is not None,
      f"bad input edges_negative_friction: {p.stderr.strip()[:200]}")

# A free box of triangles wider than the sheet (5 kg, 1 m/s down, no gravity) bounces off it
# (and its held edges) as a free plane of the same mass does. (Node to surface: a box
# narrower than the sheet would cut the coarse sheet between nodes with its edges.)
cube = copy.deepcopy(BASE)
box_msh(os.path.join(WORK, "slab.msh"), (-0.7, -0.7, 0.0105), (0.7, 0.7, 0.1105), 2, True)
cube["materials"]["pvc"]["density"] = 100
cube.pop("loads")
cube["rigid_bodies"] = [{"name": "slab", "shape": "mesh", "file": "slab.msh", "mass": 5.0,
                         "velocity": [0, 0, -1.0]}]
cube["contact"] = [{"surfaces": ["sheet", "slab"]}]
cube["analysis"] = {"type": "dynamic", "time": {"end": 0.03, "step": 2.0e-4},
                    "integrator": {"scheme": "generalized-alpha", "rho_inf": 1.0}}
cube["output"] = {"fields": False, "history": [
    {"name": "vz", "quantity": "rigid_velocity", "body": "slab", "component": "z"},
    {"name": "fz", "quantity": "contact_force", "body": "slab", "component": "z"}]}
plane = copy.deepcopy(cube)
plane["rigid_bodies"] = [{"name": "slab", "shape": "plane", "point": [0, 0, 0.0105],
                          "normal": [0, 0, -1], "mass": 5.0, "velocity": [0, 0, -1.0]}]
p1, r1, _ = run("free_slab", cube)
p2, r2, _ = run("free_plane", plane)
check(p1.returncode == 0 and p2.returncode == 0,
      f"free slab and plane run ({p1.stderr.strip()[-300:]} {p2.stderr.strip()[-300:]})")
if r1 and r2:
    v_out = float(r1[-1]["vz"])
    worst = max(abs(float(a[k]) - float(b[k])) / max(abs(float(r[k])) for r in r2)
                for a, b in zip(r1, r2) for k in ("vz", "fz"))
    print(f"free slab: rebound {v_out:.4f} m/s of 1, peak force "
          f"{max(float(r['fz']) for r in r1):.1f} N; largest difference from the plane {worst:.3g}")
    check(v_out > 0.9 and float(r1[-1]["fz"]) == 0 and max(float(r["fz"]) for r in r1) > 0,
          f"free slab: pushed up, rebounds at {v_out:.4f} m/s")
    check(len(r1) == len(r2) and worst < 1e-9, f"free slab: as the free plane ({worst:.3g})")

# Bad meshes.
write_msh(os.path.join(WORK, "lines.msh"), [(0, 0, 0), (1, 0, 0)], [(1, [0, 1])])
write_msh(os.path.join(WORK, "flat.msh"), [(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 1, 0)],
          [(2, [0, 1, 2]), (2, [0, 1, 3])])
BAD = [
    ("missing_file", "nothere.msh", "nothere.msh", "rigid_bodies[0].file"),
    ("no_surface", "lines.msh", "no triangles or quads", "rigid_bodies[0].file"),
    ("degenerate", "flat.msh", "degenerate", "rigid_bodies[0].file"),
]
for name, file, message, key in BAD:
    m = as_mesh(copy.deepcopy(BASE))
    m["rigid_bodies"][0]["file"] = file
    p, _, path = run(name, m)
    err = p.stderr
    check(p.returncode == 1 and message in err and key in err
          and re.search(re.escape(os.path.basename(path)) + r":\d+: ", err) is not None,
          f"bad input {name}: {err.strip()[:200]}")
m = as_mesh(copy.deepcopy(BASE))
m["rigid_bodies"][0].pop("file")
p, _, path = run("no_file", m)
check(p.returncode == 1 and "file" in p.stderr, f"bad input no_file: {p.stderr.strip()[:200]}")

if failures:
    print(f"{len(failures)} failures")
    sys.exit(1)
print("all rigid mesh cases passed")
