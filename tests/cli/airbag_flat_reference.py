#!/usr/bin/python3
"""Issue 45: a sheet started from a shrunk mesh with its flat reference equals the run started
flat. The square airbag of examples/airbag-flat-reference (its generator, make_model.py): two
flat panels (one eighth, 12 x 12 quad4, nylon, wrinkling) given as mesh.reference_positions,
inflated by gas by `static`, once from a shrunk, bulged mesh (model.yaml: in-plane 0.85, 6 cm
bulge), once from the flat panels lifted by a 2 mm bulge (flat-start.yaml, so that the bag
encloses gas). Each chamber's gas fills its start volume at ambient pressure and its amount
rises to the same content (0.006 m^3 at ambient), so both must end in one equilibrium.

The bound: both runs end converged (Newton's last residuals ~1e-9 N), which leaves their
shapes within ~1e-11 m of the one equilibrium; a change of the gas content by 1e-6 moves the
nodes by 1.9e-8 m. The nodal displacements must agree within 1e-7 of the apex height
(1.5e-8 m), volume and pressure within 1e-8 relative: a bag started shrunk that held other
gas, or reached another equilibrium, fails it. Also: each run starts at its own volume and
ambient pressure, with gas flow the initial mass is p0 V_start / (R T), and the flat panels as
the start are refused (no gas enclosed).

usage: airbag_flat_reference.py VELUM EXAMPLE_DIR WORK_DIR
"""
import csv
import importlib.util
import json
import os
import shutil
import subprocess
import sys

import meshio
import numpy as np

VELUM, EXAMPLE, WORK = sys.argv[1:4]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
spec = importlib.util.spec_from_file_location("make_model", os.path.join(EXAMPLE, "make_model.py"))
mm = importlib.util.module_from_spec(spec)
spec.loader.exec_module(mm)
N = 12
failures = []


def check(cond, what):
    print(("ok:   " if cond else "FAIL: ") + what)
    if not cond:
        failures.append(what)


def run(name):
    text = mm.model(N, name)
    with open(os.path.join(EXAMPLE, name + ".yaml")) as f:
        check(f.read() == text, f"{name}.yaml in the example is what make_model.py writes")
    path = os.path.join(WORK, name + ".yaml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(WORK, name)
    p = subprocess.run([VELUM, "run", path, "-o", out, "--threads", "1", "--quiet"],
                       capture_output=True, text=True, timeout=120)
    check(p.returncode == 0, f"{name}: exit {p.returncode} {p.stderr.strip()[-300:]}")
    if p.returncode:
        sys.exit(1)
    summary = json.load(open(os.path.join(out, "summary.json")))
    check(summary["status"] == "converged" and summary["final_time"] == 1,
          f"{name}: {summary['status']} at t = {summary['final_time']} in {summary['steps']} steps")
    rows = [{k: float(v) for k, v in r.items()}
            for r in csv.DictReader(open(os.path.join(out, "history.csv")))]
    with open(os.path.join(out, "results.pvd")) as f:
        last = f.read().rsplit('file="', 1)[1].split('"', 1)[0]
    frame = meshio.read(os.path.join(out, last))
    order = np.argsort(frame.point_data["node_id"])
    return {"first": rows[0], "last": rows[-1], "u": frame.point_data["displacement"][order],
            "X": frame.points[order], "wrinkled": frame.cell_data["wrinkle_state"][0]}


flat, shrunk = run("flat-start"), run("model")
for name, r in (("flat-start", flat), ("model", shrunk)):
    shrink, bulge = mm.STARTS[name]
    v0 = mm.volume(N, mm.grid(N, shrink, bulge))
    f = r["first"]
    check(abs(f["V"] - v0) < 1e-10 * v0 and abs(f["p"] - mm.P0) < 1e-9,
          f"{name} starts where its mesh is: V {f['V']:.8g} (its start volume {v0:.8g}), "
          f"p {f['p']:.8g}; seam middle at x {f['seam_mid']:.6g} ({shrink * mm.A:.6g})")
    check(abs(f["seam_mid"] - shrink * mm.A) < 1e-12, f"{name}: the seam starts at its mesh position")
    check(np.abs(r["X"][:, 2]).max() == 0.0, f"{name}: the reference is flat")
a, b = flat["last"], shrunk["last"]
gauge = a["p"] - mm.P0
check(gauge > 5e3, f"the bag is taut at the end: {gauge:.1f} Pa gauge, apex {a['apex']:.6f} m")
check(bool((flat["wrinkled"] > 0).any()), f"wrinkled at the end: {int((flat['wrinkled'] > 0).sum())} of "
      f"{flat['wrinkled'].size} elements")
d = np.abs(flat["u"] - shrunk["u"]).max()
check(d < 1e-7 * a["apex"], f"end shapes: largest nodal distance {d:.2e} m (apex {a['apex']:.6f} m, "
      f"bound {1e-7 * a['apex']:.1e})")
for key in ("V", "p", "apex", "seam_mid", "corner", "mid_z"):
    base = gauge if key == "p" else abs(a[key])
    err = abs(a[key] - b[key]) / base
    check(err < 1e-8 if key in ("V", "p") else err < 1e-7,
          f"{key}: shrunk start {b[key]:.10g}, flat start {a[key]:.10g} (relative {err:.1e})")

# With gas flow (mass and temperature tracked) the initial mass is the start volume's too.
text = mm.model(N, "model").replace("gamma: 1.0, amount: fill}",
                                    "gamma: 1.4, temperature: 300.0, gas_constant: 287.0}")
text = text.replace("- {name: p, quantity: gas_pressure, load: 0}",
                    "- {name: p, quantity: gas_pressure, load: 0}\n    - {name: m, quantity: gas_mass, load: 0}")
text = text.replace("end: 1.0, step: 0.125", "end: 0.1, step: 0.1")
path = os.path.join(WORK, "flow.yaml")
with open(path, "w") as f:
    f.write(text)
p = subprocess.run([VELUM, "run", path, "-o", os.path.join(WORK, "flow"), "--threads", "1", "--quiet"],
                   capture_output=True, text=True, timeout=60)
check(p.returncode == 0, f"gas flow: exit {p.returncode} {p.stderr.strip()[-300:]}")
if p.returncode == 0:
    row = next(csv.DictReader(open(os.path.join(WORK, "flow", "history.csv"))))
    m0 = mm.P0 * mm.volume(N, mm.grid(N, *mm.STARTS["model"])) / (287.0 * 300.0)
    check(abs(float(row["m"]) - m0) < 1e-10 * m0,
          f"gas flow: initial mass {float(row['m']):.10g} kg, p0 V_start / (R T) = {m0:.10g}")

# The flat panels as the start too: no gas enclosed, refused naming the load's line.
bad = os.path.join(WORK, "flat.yaml")
with open(bad, "w") as f:
    f.write(mm.model(N, "model", 1.0, 0.0))
p = subprocess.run([VELUM, "run", bad, "-o", os.path.join(WORK, "flat"), "--quiet"],
                   capture_output=True, text=True, timeout=60)
check(p.returncode != 0 and "flat.yaml:" in p.stderr and "zero to round-off" in p.stderr,
      f"a bag started flat is refused: exit {p.returncode}, {p.stderr.strip()[:200]}")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
