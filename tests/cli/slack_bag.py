#!/usr/bin/env python3
"""Issue 47: a square bag inflated by an enclosed gas from a slack (bulged) start, with
wrinkling, by `static` (load steps on the gas amount) and by `relaxation`, reaches the shape
the follower pressure gives at the gas's final gauge pressure.

The bag: 0.6 m side, one eighth (a quarter of the top sheet, [0, 0.3]^2, 8 x 8 quad4, seams
held in the mid-plane), nylon 0.6 mm (E 588 MPa, nu 0.4), a 3 cm bulge of stress-free sheet;
the gas amount rises to 5.6 times the initial one (the bag first unfolds at ambient pressure,
then pressurises to about 10 kPa gauge). Usage: slack_bag.py VELUM WORKDIR."""
import ast
import csv
import json
import math
import os
import subprocess
import sys
import time

N, A, BULGE, AMOUNT = 8, 0.3, 0.03, 5.6


def model(kind, load, step, pressure=0.0, out="out"):
    nodes = []
    for j in range(N + 1):
        for i in range(N + 1):
            x, y = A * i / N, A * j / N
            z = BULGE * math.cos(math.pi * x / (2 * A)) * math.cos(math.pi * y / (2 * A))
            nodes.append([j * (N + 1) + i + 1, round(x, 12), round(y, 12), round(z, 12)])
    elems = []
    for j in range(N):
        for i in range(N):
            k = j * (N + 1) + i + 1
            elems.append([k, k + 1, k + N + 2, k + N + 1])
    plane_x = [j * (N + 1) + 1 for j in range(N + 1)]
    plane_y = [i + 1 for i in range(N + 1)]
    seam = sorted({j * (N + 1) + N + 1 for j in range(N + 1)} | {N * (N + 1) + i + 1 for i in range(N + 1)})
    if load == "gas":
        loads = ("  - {type: gas, elements: sheet, initial_pressure: 101325.0, ambient: 101325.0,"
                 " gamma: 1.0, amount: fill}\n"
                 f"functions:\n  fill: {{type: table, points: [[0, 1], [1, {AMOUNT}]]}}\n")
        hist = ("    - {name: V, quantity: gas_volume, load: 0}\n"
                "    - {name: p, quantity: gas_pressure, load: 0}\n")
    else:
        loads = (f"  - {{type: pressure, elements: sheet, value: {pressure!r}}}\n")
        hist = ""
    return f"""title: slack square bag, one eighth, {N}x{N} quad4, {kind}, {load}
mesh:
  nodes: {nodes}
  elements:
    - {{set: sheet, type: quad4, connectivity: {elems}}}
  node_sets:
    seam: {seam}
    plane_x: {plane_x}
    plane_y: {plane_y}
materials:
  nylon: {{type: isotropic, E: 5.88e8, nu: 0.4, density: 1000.0}}
sections:
  - {{elements: sheet, material: nylon, thickness: 0.6e-3, wrinkling: true}}
boundary:
  - {{nodes: plane_x, symmetry: {{normal: [1, 0, 0]}}}}
  - {{nodes: plane_y, symmetry: {{normal: [0, 1, 0]}}}}
  - {{nodes: seam, symmetry: {{normal: [0, 0, 1]}}}}
loads:
{loads}analysis:
  type: {kind}
  time: {{end: 1.0, step: {step}, min_step: 1.0e-6, adaptive: true}}
output:
  directory: {out}
  interval: 1.0
  fields: false
  history:
{hist}    - {{name: w0, quantity: displacement, node: 1, component: z}}
    - {{name: ux, quantity: displacement, node: {N + 1}, component: x}}
"""


def run(velum, work, name, text, budget):
    d = os.path.join(work, name)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "model.yaml")
    with open(path, "w") as f:
        f.write(text)
    t0 = time.monotonic()
    p = subprocess.run([velum, "run", path, "-q", "--threads", "1", "-o", os.path.join(d, "out")],
                       capture_output=True, text=True, timeout=budget)
    seconds = time.monotonic() - t0
    if p.returncode != 0:
        raise SystemExit(f"{name}: exit {p.returncode}: {p.stderr.strip()}")
    with open(os.path.join(d, "out", "history.csv")) as f:
        last = list(csv.DictReader(f))[-1]
    print(f"{name}: {seconds:.2f} s, " + ", ".join(f"{k} {float(v):.6g}" for k, v in last.items()))
    return {k: float(v) for k, v in last.items()}


def dynamic_route(velum, work, static):
    """Implicit dynamics from the bulge (step 1e-3): with generalized-alpha's default rho_inf
    0.8 the in-plane modes of the sheet going taut gain energy and the run stops on the energy
    balance with a hint naming rho_inf; with rho_inf 0 it inflates, its energy within the gas's
    work, to about the static shape (still moving a little at t = 1: within 2%)."""
    failures = []
    text = model("dynamic", "gas", 0.001)
    d = os.path.join(work, "gas_dynamic_default")
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "model.yaml"), "w") as f:
        f.write(text)
    p = subprocess.run([velum, "run", os.path.join(d, "model.yaml"), "-q", "--threads", "1", "-o", os.path.join(d, "out")],
                       capture_output=True, text=True, timeout=120)
    print(f"gas dynamic, rho_inf 0.8: exit {p.returncode}: {p.stderr.strip()[-160:]}")
    if p.returncode != 2 or "rho_inf: 0" not in p.stderr:
        failures.append(f"dynamic with rho_inf 0.8: exit {p.returncode}, no rho_inf hint: {p.stderr}")
    damped = text.replace("  type: dynamic\n",
                          "  type: dynamic\n  integrator: {scheme: generalized-alpha, rho_inf: 0.0}\n")
    r = run(velum, work, "gas_dynamic", damped, 120)
    with open(os.path.join(work, "gas_dynamic", "out", "summary.json")) as f:
        e = json.load(f)["energy"]
    held = e["kinetic"] + e["strain"] + e["damping"]
    print(f"gas dynamic, rho_inf 0: held {held:.4g} J against the gas's work {e['external_work']:.4g} J")
    if not held <= e["external_work"]:
        failures.append(f"dynamic: held {held} J beyond the work {e['external_work']} J")
    if static:
        for key in ("V", "w0", "ux"):
            err = abs(r[key] - static[key]) / abs(static[key])
            print(f"gas dynamic vs static: {key} {r[key]:.6f} against {static[key]:.6f} (relative {err:.1e})")
            limit = 0.05 if key == "ux" else 0.02  # the seam corner swings most
            if not err < limit:
                failures.append(f"dynamic: {key} {r[key]} against the static route's {static[key]}")
    return failures


def slack_everywhere(velum, work):
    """Relaxation of a sheet slack everywhere at the start: a quarter of the E1 airbag (4 x 4
    quad4, 5 kPa, seams held out of plane) whose section has wrinkling and a compressive
    prestress (-1e5 Pa both ways: stress-free only once stretched by 1.7e-4). Every point's
    stiffness starts at the residual κ Q, so the fictitious masses start far too light and the
    relaxation's guard must make them heavier; it made them four times the tangent's again
    each time, the same masses, and the level never ended. It inflates as the sheet without
    prestress does (the centre within 1e-3)."""
    failures = []
    n, half = 4, 0.6 / math.sqrt(2)
    nodes = [[j * (n + 1) + i + 1, round(half * i / n, 12), round(half * j / n, 12), 0.0]
             for j in range(n + 1) for i in range(n + 1)]
    elems = [[k, k + 1, k + n + 2, k + n + 1]
             for k in (j * (n + 1) + i + 1 for j in range(n) for i in range(n))]
    seam = sorted({j * (n + 1) + n + 1 for j in range(n + 1)} | {n * (n + 1) + i + 1 for i in range(n + 1)})
    results = {}
    for name, extra in (("free", ""), ("compressed", ", prestress: [-1.0e5, -1.0e5, 0]")):
        text = f"""title: E1 airbag quarter, slack everywhere at the start ({name})
mesh:
  nodes: {nodes}
  elements:
    - {{set: sheet, type: quad4, connectivity: {elems}}}
  node_sets:
    seam: {seam}
    px: {[j * (n + 1) + 1 for j in range(n + 1)]}
    py: {[i + 1 for i in range(n + 1)]}
materials:
  nylon: {{type: isotropic, E: 5.88e8, nu: 0.4, density: 1000.0}}
sections:
  - {{elements: sheet, material: nylon, thickness: 0.6e-3, wrinkling: true{extra}}}
boundary:
  - {{nodes: px, symmetry: {{normal: [1, 0, 0]}}}}
  - {{nodes: py, symmetry: {{normal: [0, 1, 0]}}}}
  - {{nodes: seam, fix: [z]}}
loads:
  - {{type: pressure, elements: sheet, value: 5000.0}}
analysis:
  type: relaxation
  time: {{end: 1.0, step: 1.0}}
  relaxation: {{max_seconds: 30}}
output:
  directory: out
  fields: false
  history:
    - {{name: w0, quantity: displacement, node: 1, component: z}}
"""
        results[name] = run(velum, work, f"e1_{name}", text, 60)
    a, b = results["compressed"]["w0"], results["free"]["w0"]
    print(f"slack everywhere: centre {a:.6f} m against {b:.6f} m without the prestress")
    if not abs(a - b) < 1e-3 * b:
        failures.append(f"slack everywhere: centre {a} against {b}")
    return failures


def other_equilibrium(velum, work, kind, gauge):
    """Whether the gas route's shape (its last frame), where it differs from the pressure
    route's, is another stable equilibrium of the same follower pressure: a static step
    started there (mesh positions, the bulge as reference) meets the tolerance at once and
    its tangent has no negative pivot. The 15 x 15 bag has two such shapes near 9.35 kPa."""
    import meshio  # Debian's python3-meshio; only this check needs it
    out = os.path.join(work, f"gas_{kind}", "out")
    with open(os.path.join(out, "results.pvd")) as f:
        last = f.read().rsplit('file="', 1)[1].split('"', 1)[0]
    frame = meshio.read(os.path.join(out, last))
    ids, d = frame.point_data["node_id"], frame.point_data["displacement"]
    text = model("static", "pressure", 1.0, gauge)
    line = next(l for l in text.splitlines() if l.startswith("  nodes: "))
    reference = ast.literal_eval(line[len("  nodes: "):])  # the bulge: the list model() wrote
    where = {n[0]: n[1:] for n in reference}
    start = [[int(i)] + [where[int(i)][c] + float(d[k][c]) for c in range(3)] for k, i in enumerate(ids)]
    text = text.replace(line, f"  nodes: {start}\n  reference_positions: {reference}")
    r = run(velum, work, f"pressure_from_gas_{kind}", text, 120)
    with open(os.path.join(work, f"pressure_from_gas_{kind}", "out", "steps.csv")) as f:
        rows = list(csv.DictReader(f))
    first = float(rows[0]["residuals"].split()[0])
    pivots = int(rows[-1]["negative_pivots"])
    moved = max(abs(r[k] - float(v)) for k, v in (("w0", d[0][2]), ("ux", d[N][0])))
    print(f"gas {kind}'s shape under the pressure alone: first residual {first:.2e}, moved "
          f"{moved:.1e} m, {pivots} negative pivots")
    return len(rows) == 1 and moved < 1e-8 and pivots == 0


def main():
    # Optional: the mesh size and the analysis types (static,relaxation). At 15 x 15 the
    # wrinkled bag has two equilibria near 9.35 kPa (the seam corner's ux -0.0864 and -0.0822):
    # gas by static and pressure by relaxation reach the first, the other two routes the second.
    global N
    velum, work = sys.argv[1], sys.argv[2]
    if len(sys.argv) > 3:
        N = int(sys.argv[3])
    kinds = sys.argv[4].split(",") if len(sys.argv) > 4 else ["static", "relaxation", "dynamic"]
    os.makedirs(work, exist_ok=True)
    failures = []
    steps = {"static": 0.1, "relaxation": 1.0}
    gas = {kind: run(velum, work, f"gas_{kind}",
                     model(kind, "gas", steps[kind]).replace("fields: false", "fields: true"), 120)
           for kind in kinds if kind in steps}
    for kind, r in gas.items():
        gauge = r["p"] - 101325.0
        if not gauge > 1e3:  # taut at the end: the amount exceeds what the unfolded bag holds
            failures.append(f"gas {kind}: gauge pressure {gauge:.1f} Pa, the bag never went taut")
            continue
        ref = run(velum, work, f"pressure_{kind}", model("relaxation", "pressure", 1.0, gauge), 120)
        other = None  # whether the gas's shape is another equilibrium, asked once
        for key in ("w0", "ux"):
            err = abs(r[key] - ref[key]) / abs(ref[key])
            print(f"gas {kind} vs pressure {gauge:.1f} Pa: {key} {r[key]:.6f} against {ref[key]:.6f} "
                  f"(relative {err:.1e})")
            if not err < 1e-4 and other is None:
                other = other_equilibrium(velum, work, kind, gauge)
            if not err < 1e-4 and not other:
                failures.append(f"gas {kind}: {key} {r[key]} against the pressure route's {ref[key]}")
    if "relaxation" in kinds and N == 8:
        failures += slack_everywhere(velum, work)
    if "dynamic" in kinds:
        failures += dynamic_route(velum, work, gas.get("static"))
    if "static" in gas and "relaxation" in gas:
        a, b = gas["static"], gas["relaxation"]
        if not abs(a["V"] - b["V"]) < 1e-4 * b["V"]:
            failures.append(f"volumes differ: static {a['V']}, relaxation {b['V']}")
    for f in failures:
        print("FAIL:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
