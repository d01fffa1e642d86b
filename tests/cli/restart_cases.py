#!/usr/bin/python3
"""Restart (issue 14, item 6): a run stopped at a checkpoint and continued with --restart writes
the same history.csv and steps.csv, byte for byte, as the run that was never stopped; dynamic
(the hanging cable: generalized-alpha, damping, step control) and static (the truss reversal:
the predictor's history of three states).

The stop is the end of a first run (its end halfway, an output time, so that nothing before
it changes); the restarted run is the full model, continuing in the first run's folder.

usage: restart_cases.py VELUM EXAMPLES_DIR TRUST_DATA_DIR WORK_DIR
"""
import os
import re
import shutil
import subprocess
import sys

VELUM, EXAMPLES, DATA, WORK = sys.argv[1:5]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def velum(*args):
    return subprocess.run([VELUM, "run", *args, "--threads", "1", "--quiet"], capture_output=True,
                          text=True, timeout=300)


def case(name, text, end, half, checkpoint):
    full = os.path.join(WORK, name + ".yaml")
    text = re.sub(r"output:\n", f"output:\n  checkpoint: {checkpoint}\n", text, count=1)
    with open(full, "w") as f:
        f.write(text)
    first = os.path.join(WORK, name + "-first.yaml")
    with open(first, "w") as f:
        f.write(text.replace(f"end: {end}", f"end: {half}", 1))
    a, b = os.path.join(WORK, name + "-whole"), os.path.join(WORK, name + "-restarted")
    for args in ([full, "-o", a], [first, "-o", b], [full, "--restart", b]):
        p = velum(*args)
        check(p.returncode == 0, f"{name}: velum run {' '.join(args)}: exit {p.returncode}: {p.stderr}")
        if p.returncode:
            return
    for f in ["history.csv", "steps.csv"]:
        wa, wb = open(os.path.join(a, f), "rb").read(), open(os.path.join(b, f), "rb").read()
        check(wa == wb, f"{name}: {f} differs after the restart ({len(wa)} against {len(wb)} bytes)")
    check(open(os.path.join(b, "history.csv")).read().count("\n") > 3, f"{name}: empty history")


cable = os.path.join(EXAMPLES, "hanging-cable", "model.yaml")
case("dynamic", open(cable).read().replace("file: ", "file: " + os.path.dirname(cable) + "/"),
     "4.0", "2.0", "{steps: 7}")
case("static", open(os.path.join(DATA, "truss-reversal.yaml")).read(), "3", "1.5",
     "{interval: 0.5}")

# No checkpoint in the folder: exit 1, and the message says why.
p = velum(cable, "--restart", os.path.join(WORK, "nowhere"))
check(p.returncode == 1 and "no checkpoint" in p.stderr, f"no checkpoint: {p.returncode} {p.stderr}")

print(f"{len(failures)} failed" if failures else "restart cases passed")
sys.exit(1 if failures else 0)
