#!/usr/bin/python3
"""Issue 47, items 2 to 6, through the command line: SIGINT and SIGTERM inside the loops that run
long (a relaxation level, form-finding updates, path steps) end the run within seconds with
"interrupted"; the per-level time budgets fail the level; a long fixed-step run keeps its output
times; a fully prescribed truss gives its reaction path; a limit point under load control is
named; path following announces itself, honours output.interval and max_steps and starts from
a state out of equilibrium; the steps of a staged model are limited together.

usage: loop_cases.py VELUM WORK_DIR [CASE_NAME_SUBSTRING]
"""
import csv
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time

import yaml

VELUM, WORK = sys.argv[1], sys.argv[2]
ONLY = sys.argv[3] if len(sys.argv) > 3 else ""


def square(n, analysis, pressure=5.0, prestress=None):
    """A flat n x n quad4 square, edges fixed, under a follower pressure."""
    nodes, els, edge = [], [], []
    for j in range(n + 1):
        for i in range(n + 1):
            k = j * (n + 1) + i + 1
            nodes.append([k, i / n, j / n, 0.0])
            if i in (0, n) or j in (0, n):
                edge.append(k)
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i + 1
            els.append([a, a + 1, a + n + 2, a + n + 1])
    section = {"elements": "sheet", "material": "fabric", "thickness": 0.01}
    if prestress:
        section["prestress"] = prestress
    centre = (n // 2) * (n + 1) + n // 2 + 1
    return {
        "mesh": {"nodes": nodes, "elements": [{"set": "sheet", "type": "quad4",
                                               "connectivity": els}],
                 "node_sets": {"edge": edge}},
        "materials": {"fabric": {"type": "isotropic", "E": 1.0e5, "nu": 0.3, "density": 1.0}},
        "sections": [section],
        "boundary": [{"nodes": "edge", "fix": ["x", "y", "z"]}],
        "loads": [{"type": "pressure", "elements": "sheet", "value": pressure}],
        "analysis": analysis,
        "output": {"fields": False, "history": [
            {"name": "uz", "quantity": "displacement", "node": centre, "component": "z"}]},
    }


TRUSS = {  # the shallow two-bar truss: P(y) = E A y (h² − y²) / L0³ with y the apex height
    "mesh": {"nodes": [[1, -1, 0, 0], [2, 1, 0, 0], [3, 0, 0.2, 0]],
             "elements": [{"set": "bars", "type": "cable2", "connectivity": [[1, 3], [2, 3]]}]},
    "materials": {"svk": {"type": "cable", "E": 1000.0, "density": 1.0, "compression": True}},
    "sections": [{"elements": "bars", "material": "svk", "area": 1.0}],
    "boundary": [{"nodes": [1, 2], "fix": ["x", "y", "z"]}, {"nodes": 3, "fix": ["x", "z"]}],
    "loads": [{"type": "point", "nodes": 3, "force": [0, -1.0, 0], "function": "linear"}],
    "functions": {"linear": {"type": "table", "points": [[-1000, -1000], [1000, 1000]]}},
    "analysis": {"type": "static", "time": {"end": 4.3549, "step": 0.29},
                 "path": {"method": "arc_length", "constraint": "cylindrical"}},
    "output": {"fields": False, "history": [
        {"name": "v", "quantity": "displacement", "node": 3, "component": "y"},
        {"name": "R", "quantity": "reaction", "nodes": [3], "component": "y"}]},
}
H, L0 = 0.2, math.sqrt(1.04)


def truss_force(y):
    return 1000 * y * (H * H - y * y) / L0 ** 3


def truss(**changes):
    m = json.loads(json.dumps(TRUSS))
    for path, value in changes.items():
        node = m
        keys = path.split("__")
        for k in keys[:-1]:
            node = node[k]
        if value is None:
            node.pop(keys[-1], None)
        else:
            node[keys[-1]] = value
    return m


def case_dir(name, model):
    d = os.path.join(WORK, name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    with open(os.path.join(d, "model.yaml"), "w") as f:
        f.write(model if isinstance(model, str) else yaml.safe_dump(model))
    return d


def cmd(d):
    return [VELUM, "run", os.path.join(d, "model.yaml"), "--threads", "1", "-o",
            os.path.join(d, "out")]


def run(name, model):
    d = case_dir(name, model)
    p = subprocess.run(cmd(d), capture_output=True, text=True, timeout=300)
    return p, d


def summary(d):
    try:
        return json.load(open(os.path.join(d, "out", "summary.json")))
    except (OSError, ValueError) as e:
        return {"status": f"unreadable: {e}"}


def history(d):
    rows = list(csv.reader(open(os.path.join(d, "out", "history.csv"))))
    return rows[0], [[float(v) for v in r] for r in rows[1:]]


def check(cond, what, problems):
    if not cond:
        problems.append(what)


def interrupted_inside(model, sig, wait=1.0, deadline=5.0, end=1.0):
    """Starts the run, signals it `wait` s after it has started (summary.json "running", its
    pid), and checks that it ends within `deadline` s, interrupted, its files consistent."""
    def case(name):
        d = case_dir(name, model)
        p = subprocess.Popen(cmd(d), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        problems = []
        t0 = time.time()
        while summary(d).get("pid") != p.pid and time.time() - t0 < 60:
            time.sleep(0.02)
        check(summary(d).get("status") == "running", f"not running: {summary(d)}", problems)
        time.sleep(wait)
        p.send_signal(sig)
        sent = time.time()
        out, err = p.communicate(timeout=120)
        took = time.time() - sent
        want = 130 if sig == signal.SIGINT else 143
        check(p.returncode == want, f"exit {p.returncode}, expected {want}: {err[-400:]!r}",
              problems)
        check(took < deadline, f"ended {took:.2f} s after the signal (limit {deadline} s)",
              problems)
        s = summary(d)
        check(s.get("status") == "interrupted", f"summary.json status {s.get('status')}",
              problems)
        check(s.get("final_time", end) < end, f"the run finished anyway: {s}", problems)
        header, rows = history(d)
        check(all(len(r) == len(header) for r in rows), "history.csv is ragged", problems)
        check(not rows or rows[-1][0] <= s.get("final_time", -1) + 1e-12,
              "history.csv goes past final_time", problems)
        check(b"converged" not in err, "the console says converged", problems)
        print(f"     {name}: ended {took:.2f} s after the signal")
        return problems
    return case


# One relaxation level of a 100 x 100 square takes seconds: signalled within it.
RELAX_LONG = square(100, {"type": "relaxation", "time": {"end": 1, "step": 1},
                          "relaxation": {"newton_switch": 1e-6}})
# Form finding that cannot meet its tolerance: reference updates until max_updates.
FORM_LONG = square(30, {"type": "form_finding", "time": {"end": 1, "step": 1},
                        "form_finding": {"tolerance": 1e-14, "max_updates": 1000000}},
                   pressure=0.5, prestress=[1000.0, 1000.0, 0.0])
# Arc length in tiny steps: many path steps.
PATH_LONG = truss(analysis__path={"method": "arc_length", "arc_length": 1e-6,
                                  "max_steps": 100000000}, analysis__time={"end": 4, "step": 0.1})


def budget(model, key, deadline):
    def case(name):
        t0 = time.time()
        p, d = run(name, model)
        took = time.time() - t0
        problems = []
        s = summary(d)
        check(p.returncode == 2, f"exit {p.returncode}: {p.stderr[-400:]!r}", problems)
        check(s.get("status") == "failed" and key in s.get("reason", ""),
              f"summary {s.get('status')}: {s.get('reason')}", problems)
        check(took < deadline, f"took {took:.1f} s", problems)
        return problems
    return case


RELAX_BUDGET = square(40, {"type": "relaxation", "time": {"end": 1, "step": 1},
                           "relaxation": {"newton_switch": 1e-6, "max_seconds": 0.02}})
FORM_BUDGET = square(30, {"type": "form_finding", "time": {"end": 1, "step": 1},
                          "form_finding": {"tolerance": 1e-14, "max_updates": 1000000,
                                           "max_seconds": 0.5}},
                     pressure=0.5, prestress=[1000.0, 1000.0, 0.0])


def long_fixed_step(name):
    """2 quad4 + 2 cables, generalized-α, fixed step 0.005, output every 50: failed at t = 100
    (a sliver step of 2.6e-11 short of the output time)."""
    m = {
        "mesh": {"nodes": [[1, 0, 0, 0], [2, 1, 0, 0], [3, 2, 0, 0], [4, 0, 1, 0], [5, 1, 1, 0],
                           [6, 2, 1, 0]],
                 "elements": [{"set": "sheet", "type": "quad4",
                               "connectivity": [[1, 2, 5, 4], [2, 3, 6, 5]]},
                              {"set": "ropes", "type": "cable2", "connectivity": [[2, 5], [3, 6]]}]},
        "materials": {"iso": {"type": "isotropic", "E": 1000.0, "nu": 0.3, "density": 1.0},
                      "rope": {"type": "cable", "E": 1000.0, "density": 1.0}},
        "sections": [{"elements": "sheet", "material": "iso", "thickness": 0.1},
                     {"elements": "ropes", "material": "rope", "area": 0.01}],
        "boundary": [{"nodes": [1, 4], "fix": ["x", "y", "z"]}],
        "loads": [{"type": "edge", "nodes": [3, 6], "force_per_length": [1.0, 0, 0]}],
        "analysis": {"type": "dynamic", "time": {"end": 150, "step": 0.005, "adaptive": False}},
        "output": {"interval": 50, "fields": False, "history": [
            {"name": "ux", "quantity": "displacement", "node": 6, "component": "x"}]},
    }
    p, d = run(name, m)
    problems = []
    s = summary(d)
    check(p.returncode == 0 and s.get("status") == "converged",
          f"exit {p.returncode}: {s.get('reason')}", problems)
    check(s.get("steps") == 30000, f"{s.get('steps')} steps, not 30000", problems)
    _, rows = history(d)
    check([r[0] for r in rows] == [0, 50, 100, 150], f"output times {[r[0] for r in rows]}",
          problems)
    check(not any("energy" in w for w in s.get("warnings", [])),
          f"a balanced run warned: {s.get('warnings')}", problems)
    return problems


def prescribed_truss(analysis_type):
    """Kratos' displacement-controlled snap-through: every component of the truss held, the
    apex driven down by 0.5; the reaction path against the closed form."""
    def case(name):
        m = truss(analysis__path=None, loads=None, functions={"ramp": {"type": "table",
                                                                         "points": [[0, 0], [1, 1]]}},
                  analysis__type=analysis_type, analysis__time={"end": 1, "step": 0.025})
        m["boundary"].append({"nodes": 3, "displacement": [0, -0.5, 0], "function": "ramp"})
        p, d = run(name, m)
        problems = []
        check(p.returncode == 0, f"exit {p.returncode}: {p.stderr[-400:]!r}", problems)
        if p.returncode:
            return problems
        _, rows = history(d)
        check(len(rows) == 41, f"{len(rows)} rows", problems)
        worst = max(abs(-r[2] - truss_force(H + r[1])) for r in rows)
        check(worst < 1e-6 * 10, f"reaction {worst:.3g} off the closed form", problems)
        check(abs(rows[-1][1] + 0.5) < 1e-12, f"apex at {rows[-1][1]}", problems)
        # The reaction passes through both limit points and back to tension.
        R = [-r[2] for r in rows]
        check(max(R) > 2.8 and min(R) < -2.8, f"reaction range {min(R)} .. {max(R)}", problems)
        print(f"     {name}: reaction within {worst:.2e} of E A y (h² − y²) / L0³")
        return problems
    return case


def limit_point(name):
    m = truss(analysis__path=None, analysis__predictor="none",
              analysis__time={"end": 4, "step": 0.1})
    p, d = run(name, m)
    problems = []
    check(p.returncode == 2, f"exit {p.returncode}", problems)
    reason = summary(d).get("reason", "")
    check("passes a limit point near t = 2.90" in reason and "analysis.path" in reason,
          f"reason {reason!r}", problems)
    check("give a smaller step" not in reason, "still asks for a smaller step", problems)
    return problems


def path_announced(name):
    m = truss(output__interval=1.0)
    p, d = run(name, m)
    problems = []
    s = summary(d)
    check(p.returncode == 0 and s.get("status") == "converged", f"exit {p.returncode}", problems)
    check("path following (arc length, cylindrical)" in p.stderr and
          "static load stepping" not in p.stderr, f"announced as {p.stderr[:400]!r}", problems)
    check(not any("analysis.path" in w for w in s.get("warnings", [])),
          f"told to follow the path: {s.get('warnings')}", problems)
    _, rows = history(d)
    # Every unit of load travelled along the path (out and back through the limit points),
    # not every one of its steps.
    check(10 <= len(rows) < s.get("steps", 0) / 2, f"{len(rows)} rows for {s.get('steps')} steps",
          problems)
    check(abs(rows[-1][0] - 4.3549) < 1e-9, "the end is not written", problems)
    worst = max(abs(r[0] - truss_force(H + r[1])) for r in rows)
    check(worst < 1e-6, f"{worst} off the closed form", problems)
    return problems


def path_max_steps(name):
    m = truss(analysis__path={"method": "arc_length", "max_steps": 10})
    p, d = run(name, m)
    problems = []
    s = summary(d)
    check(p.returncode == 2 and s.get("status") == "failed", f"exit {p.returncode}: {s}",
          problems)
    check("max_steps = 10" in s.get("reason", ""), f"reason {s.get('reason')!r}", problems)
    return problems


def path_from_imbalance(name):
    """A constant load at t0 with nothing yet to hold it: the start is brought to equilibrium
    before the path is followed (the stable branch then holds P = 0.5 + t)."""
    m = truss()
    m["loads"].append({"type": "point", "nodes": 3, "force": [0, -0.5, 0]})
    m["analysis"]["time"] = {"end": 2.0, "step": 0.29}
    p, d = run(name, m)
    problems = []
    check(p.returncode == 0, f"exit {p.returncode}: {p.stderr[-400:]!r}", problems)
    if p.returncode:
        return problems
    _, rows = history(d)
    worst = max(abs(0.5 + r[0] - truss_force(H + r[1])) for r in rows[1:])
    check(worst < 1e-6, f"{worst} off the closed form", problems)
    return problems


def staged_limits(name):
    step = {"name": "s", "analysis": {"type": "dynamic", "time": {"end": 1, "step": 1e-6}}}
    m = {k: v for k, v in truss(analysis=None).items()}
    m["steps"] = [dict(step, name=f"s{i}") for i in range(20)]
    p, d = run(name, m)
    problems = []
    check(p.returncode == 1 and "the steps together take 2e+07 steps" in p.stderr,
          f"exit {p.returncode}: {p.stderr[-400:]!r}", problems)
    return problems


CASES = [
    ("sigterm_in_relaxation_level", interrupted_inside(RELAX_LONG, signal.SIGTERM)),
    ("sigint_in_form_finding", interrupted_inside(FORM_LONG, signal.SIGINT)),
    ("sigterm_in_path_following", interrupted_inside(PATH_LONG, signal.SIGTERM, wait=0.5, end=4.0)),
    ("relaxation_max_seconds", budget(RELAX_BUDGET, "analysis.relaxation.max_seconds", 30)),
    ("form_finding_max_seconds", budget(FORM_BUDGET, "analysis.form_finding.max_seconds", 30)),
    ("long_fixed_step_run", long_fixed_step),
    ("prescribed_truss_static", prescribed_truss("static")),
    ("prescribed_truss_dynamic", prescribed_truss("dynamic")),
    ("limit_point_named", limit_point),
    ("path_following_announced_and_interval", path_announced),
    ("path_following_max_steps", path_max_steps),
    ("path_following_from_imbalance", path_from_imbalance),
    ("staged_total_steps_limited", staged_limits),
]


def main():
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    failed = 0
    cases = [c for c in CASES if not ONLY or ONLY in c[0]]
    for name, case in cases:
        try:
            problems = case(name)
        except Exception as e:  # a timeout or a missing file is a failure too
            problems = [f"{type(e).__name__}: {e}"]
        if problems:
            failed += 1
            print(f"FAIL {name}: {'; '.join(problems)}")
        else:
            print(f"ok   {name}")
    print(f"{len(cases) - failed}/{len(cases)} loop cases passed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
