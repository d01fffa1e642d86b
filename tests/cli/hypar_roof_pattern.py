#!/usr/bin/env python3
"""Issue 45: the example hypar roof (examples/hypar-roof, pattern_model.py) cut into five
strip panels along the warp: form finding, velum pattern, the round trip's static run; every
panel's mean warp, fill and shear stress must come back within 0.5 % of the designed prestress
(the tolerance of docs/patterns.md); velum pattern must write each panel's DXF with its cut,
seam and text layers, and the example folder must carry one for every panel. Usage: hypar_roof_pattern.py VELUM WORKDIR."""
import os
import subprocess
import sys

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples",
                       "hypar-roof")
TOLERANCE = 0.005


def run(args):
    p = subprocess.run(args, capture_output=True, text=True, timeout=240)
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(args)}: exit {p.returncode}: {p.stderr}")
    return p.stdout


def main():
    exe, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    model = os.path.join(work, "hypar-pattern.yaml")
    form, pdir, rt = (os.path.join(work, d) for d in ("form", "patterns", "roundtrip"))
    py = sys.executable
    run([py, os.path.join(EXAMPLE, "pattern_model.py"), model, form])
    run([exe, "run", model, "-q"])
    print(run([exe, "pattern", form, "-o", pdir]).strip())
    run([exe, "run", os.path.join(pdir, "roundtrip.yaml"), "-q", "-o", rt])
    sys.dont_write_bytecode = True  # no __pycache__ in the example folder
    sys.path.insert(0, EXAMPLE)
    from pattern_numbers import panel_errors
    rows = panel_errors(rt, pdir)
    failures = []
    if len(rows) != 5:
        failures.append(f"{len(rows)} panels, expected 5")
    for name, n, area, strain, mean, err in rows:
        print(f"{name}: {n} triangles, errors warp {err[0]:+.3%} fill {err[1]:+.3%} "
              f"shear {err[2]:+.3%}")
        if n == 0 or not max(abs(e) for e in err) <= TOLERANCE:
            failures.append(f"{name}: mean stress off the prestress by {err} (tolerance {TOLERANCE})")
        written = os.path.join(pdir, f"{name}.dxf")
        text = open(written).read() if os.path.isfile(written) else ""
        for layer in ("CUT", "SEAM", "TEXT"):
            if layer not in text:
                failures.append(f"{written}: missing or without the {layer} layer")
        dxf = os.path.join(EXAMPLE, "patterns", f"{name}.dxf")
        if not os.path.isfile(dxf) or "CUT" not in open(dxf).read():
            failures.append(f"{dxf}: missing or without a CUT polyline")
    for f in failures:
        print("FAIL:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
