#!/usr/bin/python3
"""Issue 43 item 7: the two-layer ETFE cushion of examples/etfe-cushion (its generator,
make_model.py) inflated, loaded by snow and unloaded, in three analysis steps with wrinkling.

- An elastic foil (the same law with a yield stress out of reach) comes back to its inflated
  state: apex displacements, gas pressure and volume as before the snow (elastic recovery).
- The yielding foil keeps a residual deformation: after unloading the bottom foil hangs lower
  than after inflation and the cushion holds more volume at a lower pressure; the unloading
  recovers most of the snow's deflection but not all of it (0 < residual < half the snow's
  deflection of the bottom apex), and up to the first yield the two runs agree.
- One analysis run with the same load history (time functions instead of steps) ends in the
  same state as the staged run (the history per point carried across the steps).

usage: etfe_cushion_cases.py VELUM EXAMPLE_DIR WORK_DIR
"""
import csv
import os
import shutil
import subprocess
import sys

VELUM, EXAMPLE, WORK = sys.argv[1:4]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def check(cond, what):
    print(("ok:   " if cond else "FAIL: ") + what)
    if not cond:
        failures.append(what)


def run(name, *options):
    model = os.path.join(WORK, name + ".yaml")
    subprocess.run([sys.executable, os.path.join(EXAMPLE, "make_model.py"), "-o", model,
                    "--wrinkling", *options], check=True, capture_output=True)
    text = open(model).read().replace("fields: true", "fields: false")
    open(model, "w").write(text)
    out = os.path.join(WORK, name)
    p = subprocess.run([VELUM, "run", model, "-o", out, "--threads", "1", "--quiet"],
                       capture_output=True, text=True, timeout=120)
    check(p.returncode == 0, f"{name}: exit {p.returncode} {p.stderr.strip()[-300:]}")
    rows = [{k: float(v) for k, v in r.items()}
            for r in csv.DictReader(open(os.path.join(out, "history.csv")))]
    return {round(r["time"], 9): r for r in rows}


plastic = run("plastic", "--staged")
elastic = run("elastic", "--staged", "--yield-stress", "1e12")
single = run("single")
if failures:
    sys.exit(1)

inflated, snow, unloaded = 1.0, 2.0, 3.0
ATM = 101325.0


def gauge(r):
    return r["p"] - ATM


# Elastic recovery: the same state before and after the snow.
e0, e1 = elastic[inflated], elastic[unloaded]
worst = max(abs(e1[k] - e0[k]) for k in ("top", "bottom"))
check(worst < 1e-9 and abs(gauge(e1) - gauge(e0)) < 1e-6 * gauge(e0),
      f"elastic foil: back to the inflated state (apex {worst:.1e} m, pressure "
      f"{gauge(e1) - gauge(e0):.1e} Pa)")

# The yielding foil.
p0, p1, p2 = plastic[inflated], plastic[snow], plastic[unloaded]
sag = p0["bottom"] - p2["bottom"]  # how much lower the bottom apex hangs
deflection = p0["bottom"] - p1["bottom"]
check(all(abs(plastic[t][k] - elastic[t][k]) < 1e-12 for t in (0.25, inflated, 1.75)
          for k in ("top", "bottom", "p")),
      "before the first yield the yielding and the elastic foil agree")
check(p1["bottom"] < elastic[snow]["bottom"],
      f"under snow the yielding bottom foil sags more ({-p1['bottom']:.5f} m) than the elastic "
      f"one ({-elastic[snow]['bottom']:.5f} m)")
check(1e-3 < sag < 0.5 * deflection,
      f"residual sag of the bottom apex {sag * 1e3:.2f} mm, between 1 mm and half the snow's "
      f"deflection ({deflection * 1e3:.2f} mm): recovery {1 - sag / deflection:.1%}")
check(p2["V"] > p0["V"] and gauge(p2) < gauge(p0),
      f"unloaded: more volume ({p2['V']:.6f} > {p0['V']:.6f} m3, quarter) at a lower pressure "
      f"({gauge(p2):.1f} < {gauge(p0):.1f} Pa)")
check(p2["top"] < p0["top"], f"the top apex ends lower too ({(p0['top'] - p2['top']) * 1e3:.2f} mm)")

# One run with time functions against the three steps.
s2 = single[unloaded]
diff = max(abs(s2[k] - p2[k]) for k in ("top", "bottom"))
check(diff < 1e-9 and abs(s2["p"] - p2["p"]) < 1e-6,
      f"one run and the staged run end in the same state (apex {diff:.1e} m)")

print(f"inflated {gauge(p0):.1f} Pa, snow peak {gauge(p1):.1f} Pa, unloaded {gauge(p2):.1f} Pa; "
      f"bottom apex {p0['bottom'] * 1e3:.2f} / {p1['bottom'] * 1e3:.2f} / {p2['bottom'] * 1e3:.2f} mm, "
      f"top {p0['top'] * 1e3:.2f} / {p1['top'] * 1e3:.2f} / {p2['top'] * 1e3:.2f} mm")
print(f"{len(failures)} failed" if failures else "ETFE cushion cases passed")
sys.exit(1 if failures else 0)
