#!/usr/bin/python3
"""Issue 43 item 4: a law with a history per integration point through the whole program. An
ETFE strip (elastoplastic, bilinear hardening) pulled by an end load past yield and unloaded:
the support's reaction against the closed form of uniaxial stress (S22 = 0) on the
Green-Lagrange strain E11 = u + u²/2 and the 2nd PK stress, R = S11 (1 + u) A0 (loading:
S = (σ_y0 + H E)/(1 + H/E_mod) past yield; unloading elastic from the peak, so that with no
load left the strip keeps E11 = the plastic strain of the peak). The history is kept
across a restart from a checkpoint (byte-identical history.csv) and across the steps of a
staged run (the same reactions as one run).

usage: plastic_cases.py VELUM WORK_DIR
"""
import csv
import os
import xml.etree.ElementTree as ET
import shutil
import subprocess
import sys

VELUM, WORK = sys.argv[1:3]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def check(cond, what):
    print(("ok:   " if cond else "FAIL: ") + what)
    if not cond:
        failures.append(what)


E, NU, SY, H = 1.1e9, 0.45, 16e6, 6e7
W, T0, UMAX = 0.1, 2e-4, 0.04


def gl(u):
    return u + 0.5 * u * u


def loading(e):
    return E * e if e <= SY / E else (SY + H * e) / (1 + H / E)


EMAX = gl(UMAX)
SMAX = loading(EMAX)
ERES = EMAX - SMAX / E  # the plastic strain at the peak: no stress left there
URES = -1 + (1 + 2 * ERES) ** 0.5


FPEAK = SMAX * (1 + UMAX) * W * T0 / W  # first guess; the peak is read from the run


def stress(u, unloading):
    e = gl(u)
    return SMAX - E * (EMAX - e) if unloading else loading(e)


nodes = [[i + 1 + 5 * j, 0.25 * i, W * j, 0] for j in range(2) for i in range(5)]
MESH = ("mesh:\n  nodes: " + str(nodes) + "\n"
        "  elements:\n    - {set: strip, type: quad4, connectivity: [[1, 2, 7, 6], [2, 3, 8, 7], "
        "[3, 4, 9, 8], [4, 5, 10, 9]]}\n"
        "  node_sets:\n    left: [1, 6]\n    right: [5, 10]\n    all: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n")
HEAD = f"""title: ETFE strip pulled past yield and unloaded
{MESH}materials:
  etfe: {{type: elastoplastic, E: {E}, nu: {NU}, yield_stress: {SY}, hardening_modulus: {H}, density: 1750}}
sections:
  - {{elements: strip, material: etfe, thickness: {T0}}}
functions:
  pull: {{type: table, points: [[0, 0], [1, 1], [2, 0]]}}
loads:
  - {{type: edge, nodes: right, force_per_length: [{FPEAK!r}, 0, 0], function: pull}}
"""
BOUNDARY = """boundary:
  - {nodes: left, fix: [x]}
  - {nodes: 1, fix: [y]}
  - {nodes: all, fix: [z]}
"""
OUTPUT = """output:
  directory: out
  interval: 0.125
  fields: false
  history:
    - {name: R, quantity: reaction, nodes: left, component: x}
    - {name: ux, quantity: displacement, node: 5, component: x}
"""
ANALYSIS = """analysis:
  type: static
  time: {end: 2.0, step: 0.0625}
  newton: {tolerance: 1.0e-10, max_iterations: 30}
"""


def run(name, text, *args):
    model = os.path.join(WORK, name + ".yaml")
    open(model, "w").write(text)
    out = os.path.join(WORK, name)
    p = subprocess.run([VELUM, "run", model, "-o", out, "--threads", "1", "--quiet", *args],
                       capture_output=True, text=True, timeout=120)
    check(p.returncode == 0, f"{name}: exit {p.returncode} {p.stderr.strip()[-300:]}")
    return out


def history(out):
    return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open(os.path.join(out, "history.csv")))]


whole = run("whole", HEAD + BOUNDARY + ANALYSIS + OUTPUT.replace("fields: false", "fields: true"))
rows = history(whole)
# The peak strain the load reached (the load is given, the strain found): the unloading branch
# and the strain left start from there.
EMAX = gl(rows[8]["ux"])
SMAX = loading(EMAX)
ERES = EMAX - SMAX / E
URES = -1 + (1 + 2 * ERES) ** 0.5


def stress_at(u, unloading):
    e = gl(u)
    return SMAX - E * (EMAX - e) if unloading else loading(e)


worst = 0
for r in rows:
    u = r["ux"]
    expect = stress_at(u, r["time"] > 1 + 1e-9) * (1 + u) * W * T0
    worst = max(worst, abs(abs(r["R"]) - abs(expect)) / (SMAX * (1 + UMAX) * W * T0))
check(len(rows) == 17 and worst < 1e-6, f"reaction against the closed form: worst {worst:.2e} of "
      f"the peak over {len(rows)} rows")
check(abs(rows[-1]["ux"] - URES) < 1e-9, f"unloaded: the strip keeps the elongation "
      f"{rows[-1]['ux']:.9f} (closed form {URES:.9f})")
print(f"peak reaction {rows[8]['R']:.6g} N; residual elongation {URES:.6f} (the plastic strain "
      f"{ERES:.6f})")

# The frames' cell field plastic_strain: the equivalent plastic strain α of the committed
# history, e − σ/E on the loading branch past yield (0 before), the peak's on unloading.
import meshio  # noqa: E402  (Debian's python3-meshio; only this part needs it)

frames = ET.parse(os.path.join(whole, "results.pvd")).getroot().findall("./Collection/DataSet")
worst_alpha = 0
for d, r in zip(frames, rows):
    mesh = meshio.read(os.path.join(whole, d.get("file")))
    alpha = mesh.cell_data["plastic_strain"][0]
    e = gl(r["ux"])
    expect = ERES if r["time"] > 1 + 1e-9 else max(0.0, e - loading(e) / E)
    worst_alpha = max(worst_alpha, max(abs(a - expect) for a in alpha) / ERES)
check(len(frames) == len(rows) and worst_alpha < 1e-6,
      f"cell field plastic_strain against the closed form: worst {worst_alpha:.2e} of the "
      f"residual plastic strain {ERES:.6f} over {len(frames)} frames")

# Restart from a checkpoint written while loaded: the same history, byte for byte.
first = run("first", HEAD + BOUNDARY + ANALYSIS.replace("end: 2.0", "end: 1.25") +
            OUTPUT.replace("output:\n", "output:\n  checkpoint: {interval: 0.25}\n"))
run("restarted", HEAD + BOUNDARY + ANALYSIS + OUTPUT.replace(
    "output:\n", "output:\n  checkpoint: {interval: 0.25}\n"), "--restart", first)
a = open(os.path.join(whole, "history.csv"), "rb").read()
b = open(os.path.join(first, "history.csv"), "rb").read()
check(a == b, f"restart: history.csv the same as the whole run's ({len(a)} and {len(b)} bytes)")

# Two analysis steps, loading then unloading: the history carried from the first to the second.
staged = HEAD + BOUNDARY + OUTPUT + """steps:
  - {name: load, analysis: {type: static, time: {end: 1.0, step: 0.0625}, newton: {tolerance: 1.0e-10}}}
  - name: unload
    analysis: {type: static, time: {end: 1.0, step: 0.0625}, newton: {tolerance: 1.0e-10}}
    loads: [{type: edge, nodes: right, force_per_length: [%r, 0, 0], function: down}]
""" % FPEAK
staged = staged.replace("functions:\n", "functions:\n  down: {type: table, points: [[0, 1], [1, 0]]}\n")
srows = history(run("staged", staged))
check(srows and abs(srows[-1]["ux"] - rows[-1]["ux"]) < 1e-12,
      f"staged: unloaded to the elongation {srows[-1]['ux'] if srows else None} as in one run")

print(f"{len(failures)} failed" if failures else "plastic cases passed")
sys.exit(1 if failures else 0)
