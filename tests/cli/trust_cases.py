#!/usr/bin/python3
"""Issue 14 through the command line: a static truss reversal stays on the stable branch with
the inertia in steps.csv, a shallow truss snaps through by arc length with warnings where its
equilibrium is unstable, path keys are checked, and an implausible run fails with exit 2.

usage: trust_cases.py VELUM DATA_DIR WORK_DIR
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys

VELUM, DATA, WORK = sys.argv[1:4]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def run(name, text):
    model = os.path.join(WORK, name + ".yaml")
    with open(model, "w") as f:
        f.write(text)
    out = os.path.join(WORK, name)
    p = subprocess.run([VELUM, "run", model, "-o", out, "--threads", "1"], capture_output=True,
                       text=True, timeout=120)
    return p, out


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def history(out):
    rows = list(csv.reader(open(os.path.join(out, "history.csv"))))
    return [[float(v) for v in r] for r in rows[1:]]


def stable_stretch(P):  # the largest root of λ³ − λ − 2P = 0, |P| < 1/(3√3)
    return 2 / math.sqrt(3) * math.cos(math.acos(3 * math.sqrt(3) * P) / 3)


truss = open(os.path.join(DATA, "truss-reversal.yaml")).read()
loads = {1: -0.19, 2: -0.058, 3: 0.074}
for predictor in ["extrapolate", "none"]:
    text = truss.replace("  type: static\n", f"  type: static\n  predictor: {predictor}\n")
    p, out = run("reversal-" + predictor, text)
    check(p.returncode == 0, f"reversal {predictor}: exit {p.returncode}: {p.stderr}")
    if p.returncode:
        continue
    for t, u in history(out):
        if round(t) == t and t > 0:
            lam = 1 + u
            check(abs(lam - stable_stretch(loads[round(t)])) < 1e-6,
                  f"reversal {predictor}: stretch {lam} at t = {t}")
    steps = list(csv.DictReader(open(os.path.join(out, "steps.csv"))))
    check(all(r["negative_pivots"] == "0" for r in steps),
          f"reversal {predictor}: negative pivots {[r['negative_pivots'] for r in steps]}")
    summary = json.load(open(os.path.join(out, "summary.json")))
    check(summary["status"] == "converged" and summary["warnings"] == [],
          f"reversal {predictor}: {summary}")

# The snap-through: P(y) = E A y (h² − y²)/L0³ along the whole path, one negative pivot
# between the limit points, a warning on entering and on leaving that stretch.
p, out = run("shallow", open(os.path.join(DATA, "shallow-truss.yaml")).read())
check(p.returncode == 0, f"shallow truss: exit {p.returncode}: {p.stderr}")
if p.returncode == 0:
    h, L0 = 0.2, math.sqrt(1.04)
    rows = history(out)
    worst = max(abs(t - 1000 * (h + v) * (h * h - (h + v) ** 2) / L0 ** 3) for t, v in rows)
    check(worst < 1e-6, f"shallow truss: {worst} off the analytic curve")
    check(min(h + v for t, v in rows) < -h, "shallow truss: did not pass the inverted position")
    check(abs(rows[-1][0] - 4.3549) < 1e-9, f"shallow truss ends at t = {rows[-1][0]}")
    summary = json.load(open(os.path.join(out, "summary.json")))
    w = summary["warnings"]
    check(len(w) == 2 and w[0].startswith("unstable equilibrium") and
          w[1].startswith("stable again"), f"shallow truss warnings {w}")
    check("warning: unstable equilibrium" in p.stderr, "no warning on the console")
    steps = list(csv.DictReader(open(os.path.join(out, "steps.csv"))))
    check({r["negative_pivots"] for r in steps} == {"0", "1"}, "shallow truss inertia")

shallow = open(os.path.join(DATA, "shallow-truss.yaml")).read()
displacement = shallow.replace(
    "path: {method: arc_length, constraint: cylindrical}",
    "path: {method: displacement, node: 3, component: y, displacement: -0.5}").replace(
    "end: 4.3549, step: 0.29", "end: 1, step: 0.02")
p, out = run("displacement", displacement)
check(p.returncode == 0, f"displacement control: exit {p.returncode}: {p.stderr}")
if p.returncode == 0:
    rows = history(out)
    check(len(rows) == 51 and abs(rows[-1][1] + 0.5) < 1e-12, "displacement control rows")

# Bad path keys: exit 1 with the key named.
bad = {
    "path-dynamic": (shallow.replace("type: static", "type: dynamic"), "needs type: static"),
    "path-fixed": (displacement.replace("node: 3, component: y", "node: 3, component: x"),
                   "displacement control needs a free component"),
    "path-method": (shallow.replace("method: arc_length", "method: arclength"),
                    "did you mean 'arc_length'"),
    "path-mixed": (shallow.replace("constraint: cylindrical", "constraint: riks, node: 3"),
                   "node belongs to method: displacement"),
    "predictor": (truss.replace("  type: static\n", "  type: static\n  predictor: linear\n"),
                  "unknown predictor 'linear'"),
}
for name, (text, message) in bad.items():
    p, out = run(name, text)
    check(p.returncode == 1 and message in p.stderr,
          f"{name}: exit {p.returncode}, wanted 1 with '{message}': {p.stderr}")

# E a million times too small in the truss (a material in other units than the load): it
# stretches to 22 times its length in the first step, and the run fails as implausible.
soft = truss.replace("E: 1.0,", "E: 1.0e-6,").replace(
    "points: [[0, 0], [1, -0.19], [2, -0.058], [3, 0.074]]", "points: [[0, 0], [3, 0.074]]")
p, out = run("soft-truss", soft)
summary = json.load(open(os.path.join(out, "summary.json"))) if p.returncode != 1 else {}
check(p.returncode == 2 and "implausible" in p.stderr and summary.get("status") == "failed" and
      "times the model's size" in summary.get("reason", ""),
      f"soft truss: exit {p.returncode}: {p.stderr[-500:]}")

print(f"{len(failures)} failed" if failures else "all trust cases passed")
sys.exit(1 if failures else 0)
