#!/usr/bin/python3
"""The hypar roof's cutting-pattern round trip, per panel: the mean warp, fill and shear stress
the sewn panels reach (out/roundtrip) against the designed prestress, as a Markdown table.
Usage: pattern_numbers.py ROUNDTRIP_DIR PATTERNS_DIR [--check TOL] (with --check: exit 1 when
a panel's mean stress is off the prestress by more than TOL, a fraction)."""
import json
import os
import re
import sys

import meshio

from make_model import FILL, T, WARP


def panel_errors(out, pdir):
    frames = re.findall(r'file="([^"]+)"', open(os.path.join(out, "results.pvd")).read())
    mesh = meshio.read(os.path.join(out, frames[-1]))
    names = json.load(open(os.path.join(out, "legend.json")))["element_set"]
    cell = lambda k: [v for block in mesh.cell_data[k] for v in block]
    sets = [names[int(i)] for i in cell("element_set")]
    s = {k: cell(k) for k in ("stress_11", "stress_22", "stress_12")}
    s1, s2 = WARP / T, FILL / T
    rows = []
    for q in json.load(open(os.path.join(pdir, "patterns.json")))["panels"]:
        idx = [i for i, n in enumerate(sets) if n == q["name"]]
        mean = [sum(s[c][i] for i in idx) / len(idx) for c in ("stress_11", "stress_22", "stress_12")]
        err = [(mean[0] - s1) / s1, (mean[1] - s2) / s2, mean[2] / s1]
        rows.append((q["name"], len(idx), q["area_flat"], q["max_strain"], mean, err))
    return rows


def main():
    out, pdir = sys.argv[1], sys.argv[2]
    rows = panel_errors(out, pdir)
    print("| panel | triangles | flat area (m²) | largest flattening strain | mean warp, fill, "
          "shear stress (MPa) | error warp | error fill | shear / prestress |")
    print("|---|---|---|---|---|---|---|---|")
    for name, n, area, strain, mean, err in rows:
        print(f"| {name} | {n} | {area:.4f} | {strain:.2e} | {mean[0] / 1e6:.4f}, "
              f"{mean[1] / 1e6:.4f}, {mean[2] / 1e6:.4f} | {err[0]:+.3%} | {err[1]:+.3%} | "
              f"{err[2]:+.3%} |")
    if "--check" in sys.argv:
        tol = float(sys.argv[sys.argv.index("--check") + 1])
        bad = [r[0] for r in rows if max(abs(e) for e in r[5]) > tol]
        if bad or not rows:
            print(f"FAIL: panels off the prestress by more than {tol:.2%}: {bad}")
            sys.exit(1)


if __name__ == "__main__":
    main()
