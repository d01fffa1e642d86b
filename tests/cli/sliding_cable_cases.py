"""Sliding cable (VERIFICATION F8): a ring hanging on a nearly inextensible cable between
supports at different heights finds the point of equal angles; its position against the
closed form (1e-3 m) and the cable tension W / (2 cos a) from the support reaction (0.1%).
Between supports at equal height (the ring starting off the middle, so it slides there): sag
sqrt((L/2)^2 - (s/2)^2) and tension W L / (4 sag), against the inextensible closed form (the
cable's stretch, 1e-4, bounds it) and the same with the cable's Green strain (1e-8)."""
import csv
import math
import os
import subprocess
import sys

velum, data, out = sys.argv[1:4]
model = os.path.join(data, "sliding", "ring_uneven.yaml")
subprocess.run([velum, "run", model, "-o", out, "--threads", "1", "--quiet"], check=True)
rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
last = {k.strip(): float(v) for k, v in rows[-1].items()}
A, B, P0, W = (0.0, 0.0), (4.0, 1.0), (2.0, -1.5), 1000.0
L = math.dist(A, P0) + math.dist(P0, B)
s = B[0] - A[0]
sa = s / L
ca = math.sqrt(1 - sa * sa)
a = (L + (A[1] - B[1]) / ca) / 2  # length on A's side: (a - b) cos a = zA - zB
x, z = A[0] + a * sa, A[1] - a * ca
T = W / (2 * ca)
Tv = math.hypot(last["rx"], last["rz"])
# The history quantity `force` (element 1, the chain) against the same closed form.
errors = [abs(last["x"] - x), abs(last["z"] - z), abs(Tv - T) / T, abs(last["T"] - T) / T]
print(f"ring: dx {errors[0]:.2e} m, dz {errors[1]:.2e} m, tension {errors[2]:.2e} (rel), "
      f"history force {errors[3]:.2e} (rel)")
# Supports at equal height: the ring slides to the middle.
model_eq = os.path.join(data, "sliding", "ring_equal.yaml")
subprocess.run([velum, "run", model_eq, "-o", out + "-equal", "--threads", "1", "--quiet"],
               check=True)
eq = {k.strip(): float(v)
      for k, v in list(csv.DictReader(open(os.path.join(out + "-equal", "history.csv"))))[-1].items()}
s, L0, EA = 4.0, math.dist((0, 0), (1.6, -1.6)) + math.dist((1.6, -1.6), (4, 0)), 2.0e11 * 1e-4
sag0 = math.sqrt((L0 / 2) ** 2 - (s / 2) ** 2)
T0 = W * L0 / (4 * sag0)
def excess(l):  # the cable's force (Green strain) less the force the ring's weight needs
    return EA * 0.5 * (l * l / L0 / L0 - 1) * l / L0 - W * l / (4 * math.sqrt(l * l - s * s) / 2)
lo, hi = L0 * (1 + 1e-12), L0 * 1.01
for _ in range(200):
    mid = 0.5 * (lo + hi)
    lo, hi = (mid, hi) if excess(mid) < 0 else (lo, mid)
l = 0.5 * (lo + hi)
sag1, T1 = math.sqrt(l * l - s * s) / 2, W * l / (4 * math.sqrt(l * l - s * s) / 2)
eq_err = [abs(eq["x"] - 2.0), abs(-eq["z"] - sag0) / sag0, abs(eq["T"] - T0) / T0,
          abs(-eq["z"] - sag1) / sag1, abs(eq["T"] - T1) / T1]
print(f"ring, equal heights: x - s/2 {eq_err[0]:.2e} m; against the inextensible closed form: "
      f"sag {eq_err[1]:.2e}, tension {eq_err[2]:.2e} (rel); with the stretch: sag "
      f"{eq_err[3]:.2e}, tension {eq_err[4]:.2e} (rel)")
eq_ok = eq_err[0] < 1e-9 and max(eq_err[1:3]) < 2e-4 and max(eq_err[3:]) < 1e-8
# `force` of an element that does not exist: bad input naming the file, line and key.
bad = os.path.join(os.path.dirname(out.rstrip("/")) or ".", "ring_bad_force.yaml")
text = open(model).read().replace("quantity: force, element: 1", "quantity: force, element: 9")
open(bad, "w").write(text)
run = subprocess.run([velum, "run", bad, "-o", out + "-bad", "--quiet"], capture_output=True,
                     text=True)
named = run.returncode == 1 and "element: no cable element has the id 9" in run.stderr
print("bad element id:", "named" if named else f"NOT named (exit {run.returncode}): {run.stderr}")
# Chains that are not chains: a node repeated consecutively, a single segment.
for chain, says in (("[1, 2, 2, 3]", "node 2 is repeated consecutively"),
                    ("[1, 3]", "a sliding_cable chain runs through at least 3 nodes")):
    open(bad, "w").write(open(model).read().replace("[[1, 2, 3]]", f"[{chain}]"))
    run = subprocess.run([velum, "run", bad, "-o", out + "-bad", "--quiet"],
                         capture_output=True, text=True)
    ok = run.returncode == 1 and says in run.stderr and "connectivity" in run.stderr
    print(f"chain {chain}:", "named" if ok else f"NOT named (exit {run.returncode}): {run.stderr}")
    named = named and ok
# A chain longer than the largest element (quad9's 9 nodes) in dynamics: 12 nodes through 10
# fixed rings along a line, pulled at its free end. The element scatter refused such chains
# ("more than 9 nodes") before; the support's reaction is the chain's one force at every time.
long_nodes = [[k + 1, 0.5 * k, 0, 0] for k in range(12)]
long_model = f"""title: a 12-node sliding chain through fixed rings, pulled in dynamics
mesh:
  nodes: {long_nodes}
  elements:
    - {{set: rope, type: sliding_cable, connectivity: [{list(range(1, 13))}]}}
materials:
  steel: {{type: cable, E: 2.0e11, density: 7850}}
sections:
  - {{elements: rope, material: steel, area: 1.0e-4}}
boundary:
  - {{nodes: [1], fix: [x, y, z]}}
  - {{nodes: {list(range(2, 12))}, fix: [x, y, z]}}
  - {{nodes: [12], fix: [y, z]}}
loads:
  - {{type: point, nodes: [12], force: [1000.0, 0, 0]}}
analysis: {{type: dynamic, time: {{end: 2.0e-3, step: 1.0e-4}}}}
output:
  interval: 5.0e-4
  history:
    - {{name: rx, quantity: reaction, nodes: [1], component: x}}
    - {{name: T, quantity: force, element: 1}}
"""
long_path = os.path.join(os.path.dirname(out.rstrip("/")) or ".", "long_chain.yaml")
open(long_path, "w").write(long_model)
run = subprocess.run([velum, "run", long_path, "-o", out + "-long", "--threads", "1", "--quiet"],
                     capture_output=True, text=True)
long_ok = run.returncode == 0
if long_ok:
    lrows = list(csv.DictReader(open(os.path.join(out + "-long", "history.csv"))))
    worst = max(abs(abs(float(r["rx"])) - float(r["T"])) for r in lrows[1:])
    top = max(float(r["T"]) for r in lrows)
    long_ok = top > 0 and worst < 1e-8 * top
    print(f"12-node chain in dynamics: {len(lrows)} rows, force up to {top:.4g} N, support "
          f"reaction against it {worst:.2e} N")
else:
    print(f"12-node chain in dynamics: exit {run.returncode}: {run.stderr.strip()}")
sys.exit(0 if long_ok and eq_ok and named and errors[0] < 1e-3 and errors[1] < 1e-3 and errors[2] < 1e-3 and errors[3] < 1e-3 else 1)
