#!/usr/bin/python3
"""Free rigid bodies that rotate (issue 41): a solid sphere thrown with backspin onto a held
floor with friction slides, then rolls without slipping at v = (5 v0 - 2 R w0)/7 (w0 the
backspin), and alike on a floor cut in two contact entries; a spinning box struck off its
centre of mass by a prestressed sheet keeps its energy (rotation included) with
generalized-alpha rho_inf = 1 and central differences; bad `inertia` input is exit 1 with the
file, line and key named.

usage: rigid_rotation_cases.py VELUM WORK_DIR
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

VELUM, WORK = sys.argv[1], sys.argv[2]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)

# A floor 0.4 m x 0.06 m of 5 mm quads, held normal to itself (z) and at its edges.
NX, NY, S = 80, 12, 0.005
nodes, elems, edge = [], [], []
for j in range(NY + 1):
    for i in range(NX + 1):
        nid = j * (NX + 1) + i + 1
        nodes.append([nid, -0.05 + S * i, -0.03 + S * j, 0.0])
        if i in (0, NX) or j in (0, NY):
            edge.append(nid)
for j in range(NY):
    for i in range(NX):
        a = j * (NX + 1) + i + 1
        elems.append([a, a + 1, a + NX + 2, a + NX + 1])

M, R, V0, W0, MU = 1.0, 0.1, 1.0, 10.0, 0.3  # W0: backspin (about -y for motion along +x)
BASE = {
    "mesh": {"nodes": nodes, "elements": [{"set": "floor", "type": "quad4",
                                           "connectivity": elems}]},
    "materials": {"pvc": {"type": "isotropic", "E": 1.0e9, "nu": 0.3, "density": 1000}},
    "sections": [{"elements": "floor", "material": "pvc", "thickness": 0.001}],
    "boundary": [{"nodes": edge, "fix": ["x", "y", "z"]},
                 {"nodes": list(range(1, len(nodes) + 1)), "fix": ["z"]}],
    "rigid_bodies": [{"name": "ball", "shape": "sphere", "center": [0, 0, R], "radius": R,
                      "mass": M, "inertia": 0.4 * M * R * R, "velocity": [V0, 0, 0],
                      "angular_velocity": [0, -W0, 0]}],
    "contact": [{"surfaces": ["floor", "ball"], "friction": MU, "thickness": 0.0,
                 "penalty_scale": 0.01}],
    "loads": [{"type": "gravity", "acceleration": [0, 0, -9.81]}],
    "analysis": {"type": "dynamic", "time": {"end": 0.3, "step": 1.0e-3},
                 "integrator": {"scheme": "generalized-alpha", "rho_inf": 0.9}},
    "output": {"fields": False, "interval": 1.0e-2, "history": [
        {"name": "vx", "quantity": "rigid_velocity", "body": "ball", "component": "x"},
        {"name": "x", "quantity": "rigid_position", "body": "ball", "component": "x"},
        {"name": "z", "quantity": "rigid_position", "body": "ball", "component": "z"},
        {"name": "wy", "quantity": "rigid_angular_velocity", "body": "ball", "component": "y"},
        {"name": "angle", "quantity": "rigid_rotation", "body": "ball", "component": "magnitude"},
        {"name": "fx", "quantity": "contact_force", "body": "ball", "component": "x"}]},
}
failures = []


def run(name, m):
    path = os.path.join(WORK, name + ".yaml")
    with open(path, "w") as f:
        yaml.safe_dump(m, f, default_flow_style=None, sort_keys=False)
    out = os.path.join(WORK, name)
    p = subprocess.run([VELUM, "run", path, "-o", out, "--quiet", "--threads", "1"],
                       capture_output=True,
                       text=True, timeout=200)
    return p, out, path


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


for kind in ("implicit",):
    m = copy.deepcopy(BASE)
    p, out, _ = run("rolling_" + kind, m)
    check(p.returncode == 0, f"{kind}: the ball slides and rolls (exit {p.returncode}: "
                             f"{p.stderr.strip()[-300:]})")
    if p.returncode != 0:
        continue
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
    last = rows[-1]
    v, w = float(last["vx"]), float(last["wy"])
    # Rolling radius: the centre's height over the floor (the penalty lets it sink a little).
    r = float(last["z"])
    v_rolling = (5 * V0 - 2 * R * W0) / 7
    print(f"{kind}: v = {v:.5f} m/s against (5 v0 - 2 R w0)/7 = {v_rolling:.5f} "
          f"({(v - v_rolling) / v_rolling:+.3%}); slip v - r w = {v - r * w:.2e} m/s; "
          f"centre {r:.6f} m; angle {float(last['angle']):.4f} rad")
    check(abs(v - v_rolling) < 0.01 * v_rolling, f"{kind}: rolling speed within 1%")
    check(abs(v - r * w) < 0.01 * v_rolling, f"{kind}: rolls without slipping at the end")
    first_slide = float(rows[1]["vx"]) - R * float(rows[1]["wy"])
    check(first_slide > 0.5, f"{kind}: it slides at first ({first_slide:.3f} m/s)")


def slab_msh(path, lo, hi):
    """The box lo..hi, each face two triangles, normals out of the box (MSH 2.2 ASCII)."""
    pts = [(x, y, z) for z in (lo[2], hi[2]) for y in (lo[1], hi[1]) for x in (lo[0], hi[0])]
    quads = [(4, 5, 7, 6), (0, 2, 3, 1), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(pts))
        for i, q in enumerate(pts):
            f.write("%d %.17g %.17g %.17g\n" % (i + 1, *q))
        f.write("$EndNodes\n$Elements\n%d\n" % len(tris))
        for i, t in enumerate(tris):
            f.write("%d 2 2 1 1 %d %d %d\n" % (i + 1, t[0] + 1, t[1] + 1, t[2] + 1))
        f.write("$EndElements\n")


# A box (a slab 1.4 m x 1.4 m x 0.1 m of twelve triangles, wider than the sheet below it) with
# its centre of mass 0.25 m off its middle, spinning about z at 2 rad/s and falling at 1 m/s
# onto a prestressed sheet 1 m square held at its edges: the sheet pushes on the slab's middle,
# off the centre of mass, so the slab also turns about y, and it bounces off. No gravity, no
# damping, generalized-alpha rho_inf = 1 (and central differences): the kinetic energy (the
# nodes' and the rotation's) plus the strain energy stay what they were, within the
# integrator's error.
N, A = 10, 1.0
snodes, selems, sedge = [], [], []
for j in range(N + 1):
    for i in range(N + 1):
        nid = j * (N + 1) + i + 1
        snodes.append([nid, A * i / N - A / 2, A * j / N - A / 2, 0.0])
        if i in (0, N) or j in (0, N):
            sedge.append(nid)
for j in range(N):
    for i in range(N):
        a = j * (N + 1) + i + 1
        selems.append([a, a + 1, a + N + 2, a + N + 1])
slab_msh(os.path.join(WORK, "slab.msh"), (-0.7, -0.7, 0.0105), (0.7, 0.7, 0.1105))
MB, VB, J, WZ, OFF = 5.0, 1.0, [0.3, 0.4, 0.5], 2.0, 0.25
BOX = {
    "mesh": {"nodes": snodes, "elements": [{"set": "sheet", "type": "quad4",
                                            "connectivity": selems}]},
    "materials": {"pvc": {"type": "isotropic", "E": 1.0e9, "nu": 0.3, "density": 100}},
    "sections": [{"elements": "sheet", "material": "pvc", "thickness": 0.001,
                  "prestress": [2.0e6, 2.0e6, 0]}],
    "boundary": [{"nodes": sedge, "fix": ["x", "y", "z"]}],
    "rigid_bodies": [{"name": "box", "shape": "mesh", "file": "slab.msh", "mass": MB,
                      "center_of_mass": [OFF, 0, 0.0605], "inertia": J,
                      "velocity": [0, 0, -VB], "angular_velocity": [0, 0, WZ]}],
    "contact": [{"surfaces": ["sheet", "box"]}],
    "analysis": {"type": "dynamic", "time": {"end": 0.04, "step": 2.0e-4},
                 "integrator": {"scheme": "generalized-alpha", "rho_inf": 1.0}},
    "output": {"fields": False, "history": [
        {"name": "ke", "quantity": "kinetic_energy"},
        {"name": "vz", "quantity": "rigid_velocity", "body": "box", "component": "z"},
        {"name": "fz", "quantity": "contact_force", "body": "box", "component": "z"},
        {"name": "wx", "quantity": "rigid_angular_velocity", "body": "box", "component": "x"},
        {"name": "wy", "quantity": "rigid_angular_velocity", "body": "box", "component": "y"},
        {"name": "wz", "quantity": "rigid_angular_velocity", "body": "box", "component": "z"},
        {"name": "rx", "quantity": "rigid_rotation", "body": "box", "component": "x"},
        {"name": "ry", "quantity": "rigid_rotation", "body": "box", "component": "y"},
        {"name": "rz", "quantity": "rigid_rotation", "body": "box", "component": "z"}]},
}


def rotation_energy(row):
    """1/2 w.I(R) w with I(R) = R J0 R^T from the history's rotation vector."""
    w = [float(row[k]) for k in ("wx", "wy", "wz")]
    r = [float(row[k]) for k in ("rx", "ry", "rz")]
    t = math.sqrt(sum(c * c for c in r))
    k = [c / t for c in r] if t > 0 else [0.0, 0.0, 1.0]
    c, s_ = math.cos(t), math.sin(t)
    K = [[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]]
    R = [[c * (i == j) + (1 - c) * k[i] * k[j] + s_ * K[i][j] for j in range(3)]
         for i in range(3)]
    wb = [sum(R[m][i] * w[m] for m in range(3)) for i in range(3)]  # R^T w: body axes at t = 0
    return 0.5 * sum(J[i] * wb[i] * wb[i] for i in range(3))


errors = []
for h, scheme in ((1.0e-4, "generalized-alpha"), (5.0e-5, "generalized-alpha"),
                  (1.0e-4, "central-difference")):
    box = copy.deepcopy(BOX)
    box["analysis"]["time"]["step"] = h
    if scheme == "central-difference":  # the step then capped at the stable one
        box["analysis"]["integrator"] = {"scheme": scheme}
    p, out, _ = run(f"spinning_box_{h:g}_{scheme}", box)
    check(p.returncode == 0 and "warning" not in p.stderr,
          f"spinning box, {scheme}, h = {h:g}: runs (exit {p.returncode}: "
          f"{p.stderr.strip()[-300:]})")
    if p.returncode != 0:
        continue
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
    summary = json.load(open(os.path.join(out, "summary.json")))
    e0 = 0.5 * MB * VB * VB + 0.5 * J[2] * WZ * WZ
    first, last = rows[0], rows[-1]
    energy = summary["energy"]
    held = energy["kinetic"] + energy["strain"]
    rot0, rot1 = rotation_energy(first), rotation_energy(last)
    if scheme == "generalized-alpha":
        errors.append((held - e0, held - e0 - energy["external_work"]))
    print(f"spinning box, {scheme}, h = {h:g}: kinetic energy at the start {float(first['ke']):.6f} J "
          f"against 1/2 m v^2 + 1/2 w.Jw = {e0:.6f} J (rotation {rot0:.6f} J); at the end "
          f"kinetic {energy['kinetic']:.6f} J + strain {energy['strain']:.6f} J = {held:.6f} J "
          f"({(held - e0) / e0:+.2e}), of which rotation {rot1:.6f} J (w = "
          f"{float(last['wx']):.4f}, {float(last['wy']):.4f}, {float(last['wz']):.4f} rad/s); "
          f"rebound {float(last['vz']):.4f} m/s, peak force "
          f"{max(float(r['fz']) for r in rows):.1f} N; work booked {energy['external_work']:.3e} J")
    check(abs(float(first["ke"]) - e0) < 1e-9 * e0,
          "spinning box: the kinetic energy at the start counts the rotation")
    check(float(last["fz"]) == 0 and float(last["vz"]) > 0, "spinning box: it bounces off")
    check(abs(float(last["wy"])) > 0.1, "spinning box: struck off its centre, it turns about y")
    check(abs(rot1 - rot0) > 1e-2 * e0, "spinning box: the strike changed the rotation's energy")
    check(abs(held - e0) < 2e-3 * e0, f"spinning box: energy kept ({(held - e0) / e0:+.2e})")
# The integrator's error: it falls (second order) with the step, the energy's and the
# balance's (held minus the booked work: the contact's work on the nodes and on the rotation).
if len(errors) == 2:
    (e1, b1), (e2, b2) = errors
    print(f"spinning box: energy error {e1:.3e} J, then {e2:.3e} J with half the step; balance "
          f"{b1:.3e} J, then {b2:.3e} J")
    check(abs(e2) < abs(e1) / 3 and abs(b2) < abs(b1) / 3,
          "spinning box: the energy error and the balance fall with the step")


# Central difference's nonlinear resonances (docs/performance.md, "Nonlinear resonance"): with a
# soft penalty the sheet alone sets the step, and the strike rings it. At safety 0.9 (h ω = 1.80
# for its stiffest mode, by the third-order resonance at √3) its energy grows within 10 ms of the
# strike though h ω < 2; the default (0.6, h ω = 1.20) keeps it. Either way a run that gains
# energy must say so: never "converged" with the energy created.
default_safety = None  # the default run's, which the blow-up's hint must name
for safety in (None, 0.9):
    box = copy.deepcopy(BOX)
    box["contact"][0]["penalty_scale"] = 0.01
    box["analysis"]["integrator"] = {"scheme": "central-difference"}
    if safety:
        box["analysis"]["integrator"]["safety"] = safety
    p, out, _ = run(f"rung_sheet_{safety or 'default'}", box)
    summary = json.load(open(os.path.join(out, "summary.json")))
    energy, step = summary["energy"], summary["explicit_step"]
    if safety is None:
        default_safety = step["safety"]
    held = energy["kinetic"] + energy["strain"]
    e0 = 0.5 * MB * VB * VB + 0.5 * J[2] * WZ * WZ
    print(f"rung sheet, safety {step['safety']}: exit {p.returncode}, status {summary['status']}, "
          f"step {step['largest_step']:.4e} ({step['largest_step'] / step['stable_step_start']:.3f}"
          f" of the stable one), kinetic + strain {held:.6f} J against {e0:.6f} J at "
          f"t = {summary['final_time']:.4g}")
    kept = p.returncode == 0 and abs(held - e0) < 2e-3 * e0
    said = (p.returncode == 2 and "implausible" in p.stderr and summary["status"] == "failed"
            and f"analysis.integrator.safety {default_safety:g}" in p.stderr)
    if safety is None:
        check(step["safety"] == 0.6 and kept,
              f"rung sheet, default safety: runs with the energy kept ({(held - e0) / e0:+.2e})")
    else:
        check(kept or said, "rung sheet, safety 0.9: the energy kept, or the blow-up reported "
                            "with the safety to take")
# Bad input: exit 1, the file, the line and the key named.
BAD = [
    ("inertia_without_mass", lambda b: (b.pop("mass"), b.pop("velocity"),
                                        b.pop("angular_velocity")),
     "needs a 'mass'", "rigid_bodies[0].inertia"),
    ("negative_inertia", lambda b: b.update(inertia=[1, -1, 1]), "positive",
     "rigid_bodies[0].inertia"),
    ("no_body", lambda b: b.update(inertia=[1, 1, 3]), "no body has these",
     "rigid_bodies[0].inertia"),
    ("unsymmetric", lambda b: b.update(inertia=[[1, 0.1, 0], [0, 1, 0], [0, 0, 1]]),
     "not symmetric", "rigid_bodies[0].inertia"),
    ("bad_shape", lambda b: b.update(inertia=[[1, 0], [0, 1]]), "expected a number",
     "rigid_bodies[0].inertia"),
    ("spin_without_inertia", lambda b: b.pop("inertia"), "needs an 'inertia'",
     "rigid_bodies[0].angular_velocity"),
    ("plane_turns", lambda b: (b.update(shape="plane", point=[0, 0, -1], normal=[0, 0, 1]),
                               b.pop("center"), b.pop("radius")),
     "only a sphere or a mesh turns", "rigid_bodies[0].inertia"),
]
for name, change, message, key in BAD:
    m = copy.deepcopy(BASE)
    change(m["rigid_bodies"][0])
    p, _, path = run(name, m)
    said = p.stderr
    check(p.returncode == 1 and message in said and key in said and os.path.basename(path) in said,
          f"{name}: exit {p.returncode}, message {said.strip()[-200:]!r}")
# A rotating body in two contact entries: the floor cut across x = 0.08 into two halves with
# nodes of their own (the cut's line of nodes doubled), the ball rolling across the cut. One
# entry over both halves and one entry per half turn the ball alike (one rotation, moved on by
# the sum of the entries' moments): the histories agree to round-off.
CUT = 26
cut_nodes, halves, cut_edge = [], ([], []), []
ids = {}
for h, cols in enumerate((range(0, CUT + 1), range(CUT, NX + 1))):
    for j in range(NY + 1):
        for i in cols:
            ids[(h, i, j)] = len(cut_nodes) + 1
            cut_nodes.append([len(cut_nodes) + 1, -0.05 + S * i, -0.03 + S * j, 0.0])
            if i in (0, NX) or j in (0, NY):
                cut_edge.append(len(cut_nodes))
    for j in range(NY):
        for i in list(cols)[:-1]:
            halves[h].append([ids[(h, i, j)], ids[(h, i + 1, j)], ids[(h, i + 1, j + 1)],
                              ids[(h, i, j + 1)]])
one = copy.deepcopy(BASE)
one["mesh"] = {"nodes": cut_nodes, "elements": [
    {"set": "floor", "type": "quad4", "connectivity": halves[0] + halves[1]}]}
one["boundary"] = [{"nodes": cut_edge, "fix": ["x", "y", "z"]},
                   {"nodes": list(range(1, len(cut_nodes) + 1)), "fix": ["z"]}]
one["analysis"]["time"]["end"] = 0.15  # across the cut (at t = 0.095) and on
two = copy.deepcopy(one)
two["mesh"]["elements"] = [{"set": "near", "type": "quad4", "connectivity": halves[0]},
                           {"set": "far", "type": "quad4", "connectivity": halves[1]}]
two["sections"] = [dict(two["sections"][0], elements=e) for e in ("near", "far")]
two["contact"] = [dict(two["contact"][0], surfaces=[e, "ball"]) for e in ("near", "far")]
p1, out1, _ = run("cut_one_entry", one)
p2, out2, _ = run("cut_two_entries", two)
check(p1.returncode == 0 and p2.returncode == 0,
      f"rotating ball, cut floor: both run ({p1.stderr.strip()[-200:]} {p2.stderr.strip()[-200:]})")
if p1.returncode == 0 and p2.returncode == 0:
    r1 = list(csv.DictReader(open(os.path.join(out1, "history.csv"))))
    r2 = list(csv.DictReader(open(os.path.join(out2, "history.csv"))))
    keys = ("vx", "x", "z", "wy", "angle", "fx")
    worst = max(abs(float(a[k]) - float(b[k])) / max(abs(float(r[k])) for r in r1)
                for a, b in zip(r1, r2) for k in keys)
    crossed = float(r1[0]["x"]) < -0.05 + S * CUT < float(r1[-1]["x"])
    print(f"rotating ball, cut floor: x {float(r1[-1]['x']):.4f} m, w {float(r1[-1]['wy']):.4f} "
          f"rad/s at the end; two entries against one: largest difference {worst:.3g} of each "
          f"column")
    check(crossed, "rotating ball, cut floor: the ball rolls across the cut")
    check(len(r1) == len(r2) and worst < 1e-9,
          f"rotating ball, cut floor: two entries turn it as one ({worst:.3g})")

if failures:
    print(f"{len(failures)} failed")
    sys.exit(1)
