#!/usr/bin/python3
"""Issue 43 (VERIFICATION.md F7): spherical rubber balloons inflated through their limit
points by arc length (tools/balloon-model: an octant of quad9, follower pressure p = t with
t = p R0/(mu H) or p R0/(C1 H)). The pressure-stretch path against the closed forms
  neo-Hookean:             t = 2 (1/l - 1/l^7), maximum 1.239463 at l = 7^(1/6) = 1.383088;
  Mooney-Rivlin C2/C1=0.1: t = 4 (1/l - 1/l^7)(1 + 0.1 l^2), maximum 2.98124 at l = 1.4761,
                           minimum 2.52724 at l = 3.1426;
  Mooney-Rivlin C2/C1=0.25 (>= 0.2145): no limit point, the path rises all the way.
The extremes of the computed path are located by a parabola through the three rows around
the discrete extreme.

usage: balloon_cases.py VELUM TOOLS_DIR WORK_DIR
"""
import csv
import json
import os
import shutil
import subprocess
import sys

VELUM, TOOLS, WORK = sys.argv[1:4]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def check(cond, what):
    print(("ok:   " if cond else "FAIL: ") + what)
    if not cond:
        failures.append(what)


def run(name, *model_args):
    model = os.path.join(WORK, name + ".yaml")
    subprocess.run(["/usr/bin/python3", os.path.join(TOOLS, "balloon-model"), "--interval",
                    "0.001", "--no-fields", "-o", model, *model_args], check=True)
    out = os.path.join(WORK, name)
    p = subprocess.run([VELUM, "run", model, "-o", out, "--threads", "1", "--quiet"],
                       capture_output=True, text=True, timeout=120)
    rows = []
    if os.path.exists(os.path.join(out, "history.csv")):
        rows = [(float(t), 1 + float(u))
                for t, u in list(csv.reader(open(os.path.join(out, "history.csv"))))[1:]]
    return p, out, rows


def extreme(rows, i):
    """(stretch, t) of the vertex of the parabola t(l) through rows i-1, i, i+1."""
    (t0, l0), (t1, l1), (t2, l2) = rows[i - 1], rows[i], rows[i + 1]
    d01, d12 = (t1 - t0) / (l1 - l0), (t2 - t1) / (l2 - l1)
    a = (d12 - d01) / (l2 - l0)
    b = d01 - a * (l0 + l1)
    lv = -b / (2 * a)
    return lv, t1 + d01 * (lv - l1) + a * (lv - l0) * (lv - l1)


def local_extremes(rows):
    out = []
    for i in range(1, len(rows) - 1):
        if (rows[i][0] - rows[i - 1][0]) * (rows[i + 1][0] - rows[i][0]) < 0:
            out.append(extreme(rows, i))
    return out


def nh(l):
    return 2 * (1 / l - l ** -7)


def mr(ratio):
    return lambda l: 4 * (1 / l - l ** -7) * (1 + ratio * l * l)


def along_curve(name, rows, f, scale, tol):
    worst = max(abs(t - f(l)) for t, l in rows[1:]) / scale
    check(worst < tol, f"{name}: the path stays within {worst:.2e} of the closed form "
                       f"(relative to the maximum; limit {tol})")


# Neo-Hookean: the pressure falls for ever after its maximum, so the path never comes back to
# an end above it: the run stops at max_steps (exit 2, the documented end) far past the limit.
p, out, rows = run("neo_hookean", "--law", "neo_hookean", "--end", "1.3", "--max-steps", "90")
check(p.returncode == 2 and "max_steps = 90" in p.stderr, f"neo-Hookean: exit {p.returncode}, "
      f"{p.stderr.strip()[-200:]}")
check(rows and rows[-1][1] > 2.5, f"neo-Hookean: followed to stretch {rows[-1][1] if rows else 0}")
ext = local_extremes(rows)
check(len(ext) == 1, f"neo-Hookean: one limit point ({ext})")
if ext:
    lm, tm = ext[0]
    ep, el = abs(tm / 1.239463 - 1), abs(lm / 1.383088 - 1)
    print(f"neo-Hookean maximum: t = {tm:.6f} at stretch {lm:.5f}; errors {ep:.2e} in p, "
          f"{el:.2e} in stretch")
    check(ep < 3e-3 and el < 2e-2, "neo-Hookean maximum within 0.3% in p and 2% in stretch")
along_curve("neo-Hookean", rows, nh, 1.239463, 3e-3)
steps = list(csv.DictReader(open(os.path.join(out, "steps.csv"))))
check("1" in {r["negative_pivots"] for r in steps}, "neo-Hookean: the descending branch is "
      "unstable under pressure (a negative pivot)")

# Mooney-Rivlin C2/C1 = 0.1: a maximum and a minimum, then up to the end t = 3.2.
p, out, rows = run("mooney_rivlin", "--law", "mooney_rivlin", "--ratio", "0.1", "--end", "3.2")
check(p.returncode == 0, f"Mooney-Rivlin 0.1: exit {p.returncode}: {p.stderr.strip()[-200:]}")
ext = local_extremes(rows)
check(len(ext) == 2, f"Mooney-Rivlin 0.1: a maximum and a minimum ({ext})")
if len(ext) == 2:
    for (l, t), (lx, tx), what in zip(ext, [(1.4761, 2.98124), (3.1426, 2.52724)],
                                      ["maximum", "minimum"]):
        ep, el = abs(t / tx - 1), abs(l / lx - 1)
        print(f"Mooney-Rivlin {what}: t = {t:.6f} at stretch {l:.5f}; errors {ep:.2e} in p, "
              f"{el:.2e} in stretch")
        check(ep < 5e-3 and el < 5e-3, f"Mooney-Rivlin {what} within 0.5%")
along_curve("Mooney-Rivlin 0.1", rows, mr(0.1), 2.98124, 3e-3)
summary = json.load(open(os.path.join(out, "summary.json")))
check(len(summary["warnings"]) == 2 and summary["warnings"][0].startswith("unstable"),
      f"Mooney-Rivlin 0.1: unstable between the limit points ({summary['warnings']})")

# Mooney-Rivlin C2/C1 = 0.25: no limit point; the pressure rises monotonically.
p, out, rows = run("mooney_rivlin_stiff", "--law", "mooney_rivlin", "--ratio", "0.25", "--end",
                   "5.0")
check(p.returncode == 0, f"Mooney-Rivlin 0.25: exit {p.returncode}: {p.stderr.strip()[-200:]}")
check(not local_extremes(rows) and all(b[0] > a[0] for a, b in zip(rows, rows[1:])),
      "Mooney-Rivlin 0.25: the pressure rises monotonically")
check(rows and rows[-1][1] > 2, f"Mooney-Rivlin 0.25: stretch {rows[-1][1] if rows else 0}")
along_curve("Mooney-Rivlin 0.25", rows, mr(0.25), 5.0, 3e-3)

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("all balloon cases passed")
