#!/usr/bin/python3
"""Gas flow through the command line (issue 42): a rigid vessel (every wall held) runs, its gas
fed by an inflator and emptied by a vent opening at a pressure, the first law closing to
round-off in summary.json; a restart from a checkpoint goes on with the same gas history; bad
gas-flow input is exit 1 with a message naming the file, the line and the key.

usage: gas_flow_cases.py VELUM WORK_DIR
"""
import copy
import csv
import json
import os
import shutil
import subprocess
import sys

import yaml

VELUM, WORK = sys.argv[1], sys.argv[2]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)

BASE = {
    "mesh": {
        "nodes": [[1, 0, 0, 0], [2, 0.2, 0, 0], [3, 0.2, 0.2, 0], [4, 0, 0.2, 0],
                  [5, 0, 0, 0.25], [6, 0.2, 0, 0.25], [7, 0.2, 0.2, 0.25], [8, 0, 0.2, 0.25]],
        "elements": [{"set": "box", "type": "quad4",
                      "connectivity": [[1, 4, 3, 2], [5, 6, 7, 8], [1, 2, 6, 5], [2, 3, 7, 6],
                                       [3, 4, 8, 7], [4, 1, 5, 8]]}],
    },
    "materials": {"steel": {"type": "isotropic", "E": 2.0e11, "nu": 0.3, "density": 7800}},
    "sections": [{"elements": "box", "material": "steel", "thickness": 0.002}],
    "boundary": [{"nodes": [1, 2, 3, 4, 5, 6, 7, 8], "fix": ["x", "y", "z"]}],
    "functions": {"mdot": {"type": "table", "points": [[0, 0.2], [0.05, 0.2], [0.06, 0.0],
                                                        [0.2, 0.0]]}},
    "loads": [{"type": "gas", "elements": "box", "initial_pressure": 101325.0,
               "ambient": 101325.0, "gamma": 1.4, "temperature": 300.0, "gas_constant": 287.0,
               "inflator": {"mass_flow": "mdot", "temperature": 600.0},
               "vents": [{"area": 1.0e-4, "discharge": 0.7, "open_pressure": 50000.0}]}],
    "analysis": {"type": "dynamic", "time": {"end": 0.2, "step": 1.0e-3}},
    "output": {"interval": 0.01, "fields": False, "history": [
        {"name": "p", "quantity": "gas_pressure", "load": 0},
        {"name": "m", "quantity": "gas_mass", "load": 0},
        {"name": "vent", "quantity": "gas_mass_flow", "load": 0, "vent": 0}]},
}
failures = []


def run(name, m, *extra):
    path = os.path.join(WORK, name + ".yaml")
    with open(path, "w") as f:
        yaml.safe_dump(m, f, default_flow_style=None, sort_keys=False)
    out = os.path.join(WORK, name)
    p = subprocess.run([VELUM, "run", path, "-o", out, "--quiet", *extra], capture_output=True,
                       text=True, timeout=120)
    return p, out, path


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


# The rigid vessel runs; the vent opens once the gauge pressure passes 50 kPa; the accounts close.
p, out, _ = run("vessel", BASE)
check(p.returncode == 0, f"a rigid vessel runs (exit {p.returncode}: {p.stderr.strip()})")
if p.returncode == 0:
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
    first_open = next(float(r["p"]) - 101325 for r in rows if float(r["vent"]) > 0)
    check(first_open >= 50000, f"the vent opens past its pressure ({first_open:.0f} Pa gauge)")
    gas = json.load(open(os.path.join(out, "summary.json")))["gas"][0]
    e = gas["energy"]
    scale = max(e["enthalpy_in"], e["internal_final"])
    check(abs(e["first_law_residual"]) < 1e-12 * scale,
          f"first law closes ({e['first_law_residual']:.3g} J of {scale:.3g})")
    check(abs(gas["mass"]["residual"]) < 1e-14 * gas["mass"]["final"], "mass account closes")

# A restart from a checkpoint goes on with the gas state it left.
m = copy.deepcopy(BASE)
m["output"]["checkpoint"] = {"steps": 70}
p, out, path = run("restart", m)
if p.returncode == 0:
    full = open(os.path.join(out, "history.csv")).read()
    os.remove(os.path.join(out, "summary.json"))
    # Cut the files back to the checkpoint and go on from it.
    p2 = subprocess.run([VELUM, "run", path, "-o", out, "--restart", out, "--quiet"],
                        capture_output=True, text=True, timeout=120)
    again = open(os.path.join(out, "history.csv")).read()
    check(p2.returncode == 0 and again == full,
          f"a restart repeats the gas history (exit {p2.returncode}: {p2.stderr.strip()[:200]})")
else:
    check(False, f"the checkpointed run (exit {p.returncode}: {p.stderr.strip()[:200]})")

# Bad input: exit 1, the file, the line and the key.
def bad(name, change, key, words):
    m = copy.deepcopy(BASE)
    change(m)
    p, _, path = run(name, m)
    msg = p.stderr
    good = p.returncode == 1 and os.path.basename(path) + ":" in msg and key in msg and words in msg
    check(good, f"{name}: exit {p.returncode}, {msg.strip()[:160]!r}")


gas = lambda m: m["loads"][0]  # noqa: E731
bad("negative_area", lambda m: gas(m)["vents"][0].update(area=-1e-4), "vents[0].area", "")
bad("discharge", lambda m: gas(m)["vents"][0].update(discharge=1.5), "vents[0].discharge",
    "(0, 1]")
bad("temperature", lambda m: gas(m).update(temperature=0.0), "temperature", "")
bad("orifice", lambda m: gas(m).update(orifices=[{"chamber": 3, "area": 1e-4}]),
    "orifices[0].chamber", "no gas load 3")
bad("short_table", lambda m: m["functions"]["mdot"].update(points=[[0, 0.2], [0.1, 0]]),
    "inflator.mass_flow", "cover the run")
bad("no_walls", lambda m: gas(m).update(elements=[]), "elements", "")
bad("amount_and_flow", lambda m: gas(m).update(amount="mdot"), "amount", "")
sys.exit(1 if failures else 0)
