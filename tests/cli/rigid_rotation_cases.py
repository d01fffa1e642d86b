#!/usr/bin/python3
"""Free rigid bodies that rotate (issue 41): a solid sphere thrown with backspin onto a held
floor with friction slides, then rolls without slipping at v = (5 v0 - 2 R w0)/7 (w0 the
backspin); bad `inertia` input is exit 1 with the file, line and key named.

usage: rigid_rotation_cases.py VELUM WORK_DIR
"""
import copy
import csv
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
    p = subprocess.run([VELUM, "run", path, "-o", out, "--quiet"], capture_output=True,
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
m = copy.deepcopy(BASE)
m["contact"].append(copy.deepcopy(m["contact"][0]))
p, _, _ = run("two_entries", m)
check(p.returncode == 1 and "one contact entry only" in p.stderr and "contact[1]" in p.stderr,
      f"two contact entries on a rotating body: exit {p.returncode}: {p.stderr.strip()[-200:]}")

if failures:
    print(f"{len(failures)} failed")
    sys.exit(1)
