#!/usr/bin/python3
"""A parametric study from Python: the C9 canopy with two fibre families at ±angle from each
gore's centreline, angle from 0° (both families radial) to 90° (both along the hoop), in a
light coating.

Two fibre families alone have no stiffness across them: at 0° a gore cannot carry hoop stress
and the canopy is a mechanism. The coating is three more families of a fraction of the fibres'
modulus at 0°, 60° and 120° (equal families 60° apart are in-plane isotropic, ν = 1/3), which
gives every angle some stiffness in every direction. With --coating 0 the canopy is the
paper's two-family weave: ±60° and ±30° are then `make demo`'s "anisotropic" and
"anisotropic30".

For each angle the model is edited in memory and run in this process; the settled skirt
diameter (2 × the skirt node's x, history column skirt_x) and the largest maximum principal
true stress of the canopy (last frame) are collected, tabulated and plotted against the angle.
tools/c9-parachute writes the model (as `make demo` does; ±60° is its "anisotropic" material
and ±30° its "anisotropic30"). Units: lbf, ft, s (the model's).

A run that needs more than --max-steps time steps is stopped from the progress callback and
kept with the state it reached (status "stopped", drawn apart); --reuse takes the results of
an angle that a previous study already wrote into DIR instead of running it again.

usage: c9_fibre_study.py [--angles 0 15 ... 90] [--out DIR] [--small] [--threads N]
                         [--max-steps N] [--reuse]
"""
import argparse
import csv
import math
import subprocess
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import velum  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
# A coarse, short version for the test suite: 8 gores (2 in the quarter), 1 x 3 quad9 per gore,
# 1 s of inflation.
SMALL = ["--gores", "8", "--across", "1", "--along", "3", "--line-elements", "2", "--end", "1.0",
         "--step", "0.05", "--interval", "0.5"]


def parse():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--angles", type=float, nargs="+", default=list(range(0, 91, 15)),
                   help="fibre angles from the gore centreline [deg]")
    p.add_argument("--out", type=Path, default=Path("out/python/c9-fibre-study"))
    p.add_argument("--coating", type=float, default=0.05,
                   help="modulus of each of the coating's three families / the fibres' modulus")
    p.add_argument("--small", action="store_true", help="a coarse, short model (for tests)")
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--max-steps", type=int, default=4000,
                   help="stop a run after this many time steps (it is kept, marked stopped)")
    p.add_argument("--reuse", action="store_true",
                   help="take an angle's converged results from DIR when they are there")
    return p.parse_args()


def write_model(out, small):
    """The C9 model with fibre families (tools/c9-parachute --material anisotropic)."""
    path = out / "c9.yaml"
    cmd = [sys.executable, str(ROOT / "tools" / "c9-parachute"), "--material", "anisotropic",
           "-o", str(path)] + (SMALL if small else [])
    subprocess.run(cmd, check=True)
    return path


def run_angle(base, angle, coating, out, threads, max_steps=0, reuse=False):
    m = base.copy()
    fibers = m["materials"]["canopy"]["fibers"]
    fibers[0]["angle"], fibers[1]["angle"] = angle, -angle
    if coating > 0:
        fibers += [{"E": coating * fibers[0]["E"], "angle": a} for a in (0, 60, 120)]
    m["title"] = f"C9 parachute, fibres at ±{angle:g}°, coating {coating:g}"
    directory = out / f"angle_{angle:g}"
    started = time.process_time()
    if reuse and (directory / "summary.json").exists() and \
            velum.open_results(directory).status == "converged":
        r, cpu = velum.open_results(directory, model=m), float("nan")
    else:
        try:
            r = velum.run(m, output=directory, threads=threads, quiet=True,
                          progress=lambda t, step, iterations: not max_steps or step < max_steps)
        except velum.SolveError as e:  # keep the study going; the partial results say how far
            print(f"  ±{angle:g}°: {e}", file=sys.stderr)
            r = e.results
        cpu = time.process_time() - started
    diameter = 2 * r.history["skirt_x"][-1]
    f = r.frame(-1)
    canopy = np.concatenate([r.cells(b.set) for b in r.blocks if b.set.startswith("gore")])
    smax = f.true_stress_max[canopy].max()
    return dict(angle=angle, status="stopped" if r.stopped else r.status,
                final_time=r.summary["final_time"],
                skirt_diameter=diameter, max_stress=smax, steps=r.summary["steps"],
                newton_iterations=r.summary["newton_iterations"], cpu_seconds=cpu)


def plot(rows, path, title):
    ok = [r for r in rows if r["status"] == "converged"]
    bad = [r for r in rows if r["status"] != "converged"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, key, label in ((a1, "skirt_diameter", "settled skirt diameter [ft]"),
                           (a2, "max_stress", "largest max. principal true stress [lbf/ft²]")):
        ax.plot([r["angle"] for r in ok], [r[key] for r in ok], "o-", label="converged")
        for r in bad:  # no settled value to draw: mark the angle and say how far it got
            ax.axvline(r["angle"], color="C3", linestyle=":",
                       label=f"{r['angle']:g}°: {r['status']} at t = {r['final_time']:.2f} s, "
                             "not settled")
        if bad:
            ax.legend(fontsize=8)
        ax.set_xlabel("fibre angle ± from the gore centreline [deg]")
        ax.set_ylabel(label)
        ax.set_xticks(sorted({r["angle"] for r in rows}))
        ax.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    a = parse()
    a.out.mkdir(parents=True, exist_ok=True)
    base = velum.load(write_model(a.out, a.small))
    rows = []
    for angle in a.angles:
        rows.append(run_angle(base, angle, a.coating, a.out, a.threads, a.max_steps, a.reuse))
        r = rows[-1]
        print(f"  ±{angle:4g}°  {r['status']:<9}  t = {r['final_time']:.3g} s  skirt diameter {r['skirt_diameter']:7.3f} ft  "
              f"max stress {r['max_stress']:9.0f} lbf/ft²  {r['newton_iterations']} iterations, "
              f"{r['cpu_seconds']:.1f} s CPU", flush=True)
    with open(a.out / "study.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    plot(rows, a.out / "fibre_angle.png",
         f"C9 canopy: fibre families at ±angle, E = {base['materials']['canopy']['fibers'][0]['E']:g}"
         f" lbf/ft² each, coating {a.coating:g} E")
    print(f"table: {a.out / 'study.csv'}; figure: {a.out / 'fibre_angle.png'}")
    return 0 if all(math.isfinite(r["skirt_diameter"]) for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
