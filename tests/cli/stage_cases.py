#!/usr/bin/python3
"""Staged analyses (`steps:`, docs/model-format.md "Analysis steps") through `velum run`:
- load A, then A + B in a second static step, ends where one static step with A + B ends;
- a support released in a second step (the loads held) ends where a run without it ends;
- the results: one history with an analysis_step column and continuing time, steps.csv with
  the same column, one frame series, summary.json's analysis_steps.

usage: stage_cases.py VELUM WORK_DIR
"""
import copy
import csv
import json
import os
import subprocess
import sys

import yaml

VELUM, WORK = sys.argv[1], sys.argv[2]
NX, NY = 4, 2  # quad4 cells of a 2 x 1 sheet in the x-y plane (z held)


def base():
    nodes, els = [], []
    for j in range(NY + 1):
        for i in range(NX + 1):
            nodes.append([1 + i + j * (NX + 1), 2.0 * i / NX, 1.0 * j / NY, 0.0])
    for j in range(NY):
        for i in range(NX):
            a = 1 + i + j * (NX + 1)
            els.append([a, a + 1, a + NX + 2, a + NX + 1])
    right = [1 + NX + j * (NX + 1) for j in range(NY + 1)]
    left = [1 + j * (NX + 1) for j in range(NY + 1)]
    history = []
    for n in nodes:
        for c in "xy":
            history.append({"name": f"u{c}{n[0]}", "quantity": "displacement", "node": n[0],
                            "component": c})
    return {
        "title": "staged sheet",
        "mesh": {"nodes": nodes, "elements": [{"set": "sheet", "type": "quad4",
                                                 "connectivity": els}],
                 "node_sets": {"left": left, "right": right, "all": [n[0] for n in nodes],
                               "corner": [right[-1]]}},
        "materials": {"iso": {"type": "isotropic", "E": 1000.0, "nu": 0.3, "density": 1.0}},
        "sections": [{"elements": "sheet", "material": "iso", "thickness": 0.1}],
        "functions": {"ramp": {"type": "ramp", "duration": 1.0}},
        "boundary": [{"nodes": "left", "fix": ["x", "y", "z"]}, {"nodes": "all", "fix": ["z"]}],
        "output": {"history": history},
    }


LOAD_A = {"type": "edge", "nodes": "right", "force_per_length": [8.0, 0, 0], "function": "ramp"}
LOAD_B = {"type": "point", "nodes": "corner", "force": [0, 3.0, 0], "function": "ramp"}
A_HELD = {k: v for k, v in LOAD_A.items() if k != "function"}  # constant: A at its end value
SUPPORT = {"nodes": "corner", "fix": ["y"]}


def static(end=1.0, step=0.25):
    return {"type": "static", "time": {"end": end, "step": step},
            "newton": {"tolerance": 1e-10}}


def run(name, model):
    d = os.path.join(WORK, name)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "model.yaml")
    with open(path, "w") as f:
        yaml.safe_dump(model, f, sort_keys=False)
    p = subprocess.run([VELUM, "run", path, "-o", os.path.join(d, "out"), "--threads", "1",
                        "--quiet"], capture_output=True, text=True, timeout=300)
    if p.returncode != 0:
        raise AssertionError(f"{name}: exit {p.returncode}\n{p.stderr}")
    with open(os.path.join(d, "out", "history.csv")) as f:
        rows = list(csv.DictReader(f))
    summary = json.load(open(os.path.join(d, "out", "summary.json")))
    return d, rows, summary


def final_u(rows):
    last = rows[-1]
    return {k: float(v) for k, v in last.items() if k.startswith("u")}


def max_diff(a, b):
    scale = max(abs(v) for v in b.values())
    return max(abs(a[k] - b[k]) for k in b) / scale, scale


def main():
    os.makedirs(WORK, exist_ok=True)
    failures = []

    def check(ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            failures.append(what)

    # 1. A, then A + B, against A + B in one step.
    one = base()
    one["loads"] = [LOAD_A, LOAD_B]
    one["analysis"] = static()
    _, rows1, _ = run("one_step", one)
    two = base()
    two["loads"] = [LOAD_A]
    two["steps"] = [{"name": "A", "analysis": static()},
                    {"name": "A+B", "analysis": static(), "loads": [A_HELD, LOAD_B]}]
    d2, rows2, s2 = run("two_steps", two)
    diff, scale = max_diff(final_u(rows2), final_u(rows1))
    print(f"     A then A+B vs A+B: largest displacement difference {diff:.3e} of {scale:.4g}")
    check(diff < 1e-7, "two static steps (A, then A+B) end where one step with A+B ends")
    check(scale > 0.05, "the loads move the sheet enough to be nonlinear (largest u > 0.05)")
    times = [float(r["time"]) for r in rows2]
    check(abs(times[-1] - 2.0) < 1e-12 and all(b > a for a, b in zip(times, times[1:])),
          "history time runs on through the steps to 2")
    check([r["analysis_step"] for r in rows2] == ["1"] * 5 + ["2"] * 4,
          "history.csv: analysis_step 1 for t = 0 .. 1 (5 rows), 2 after (4 rows, no repeat)")
    with open(os.path.join(d2, "out", "steps.csv")) as f:
        srows = list(csv.DictReader(f))
    check([r["analysis_step"] for r in srows] == ["1"] * 4 + ["2"] * 4,
          "steps.csv: an analysis_step column")
    steps = s2.get("analysis_steps", [])
    check([(a["name"], a["status"]) for a in steps] == [("A", "converged"), ("A+B", "converged")]
          and s2["status"] == "converged" and s2["steps"] == 8
          and abs(steps[1]["start_time"] - 1) < 1e-12 and abs(steps[1]["end_time"] - 2) < 1e-12,
          "summary.json: two converged analysis_steps, 8 steps in all, step 2 from t = 1 to 2")
    pvd = open(os.path.join(d2, "out", "results.pvd")).read()
    check(pvd.count("<DataSet") == 9 and s2["frames"] == 9, "results.pvd: 9 frames over both steps")

    # 2. A with an extra support, then the support released (loads held): as A without it.
    free = base()
    free["loads"] = [LOAD_A]
    free["analysis"] = static()
    _, rows3, _ = run("free", free)
    released = base()
    released["loads"] = [LOAD_A]
    released["boundary"] = released["boundary"] + [SUPPORT]
    released["steps"] = [{"name": "supported", "analysis": static()},
                         {"name": "released", "analysis": static(),
                          "boundary": base()["boundary"]}]
    _, rows4, s4 = run("released", released)
    diff, scale = max_diff(final_u(rows4), final_u(rows3))
    print(f"     support released vs never there: largest difference {diff:.3e} of {scale:.4g}")
    check(diff < 1e-7, "a support released in step 2 (loads held) ends as a run without it")
    mid = [r for r in rows4 if abs(float(r["time"]) - 1.0) < 1e-12][0]
    corner = str(1 + NX + NY * (NX + 1))
    check(abs(float(mid["uy" + corner])) < 1e-12 and abs(float(rows4[-1]["uy" + corner])) > 1e-3,
          "the corner is held in y in step 1 and moves in y once released")
    check(s4["status"] == "converged" and len(s4["analysis_steps"]) == 2, "summary: converged")
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print("all staged checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
