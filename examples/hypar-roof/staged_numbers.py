#!/usr/bin/python3
"""Numbers and a figure of the staged hypar roof (hypar-staged.yaml: form finding, prestress,
snow, gust as analysis steps of one run), beside those of the chained runs when present.
usage: staged_numbers.py out   (reads out/staged and out/snow; writes out/staged.png)"""
import sys
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from plot import EDGES, N_EDGE, N_QUADS, results, sheet_stress


def frame_at(r, t):
    i = int(np.argmin(np.abs(np.asarray(r.times) - t)))
    return r.frame(i)


def main(out):
    out = Path(out)
    r = results.Results(out / "staged")
    s = r.summary
    steps = {a["name"]: a for a in s["analysis_steps"]}
    print(f"staged run: {s['status']}, {s['steps']} steps, {s['newton_iterations']} Newton "
          f"iterations, {s['cpu_seconds']:.1f} s CPU")
    for a in s["analysis_steps"]:
        print(f"  step {a['name']}: {a['type']}, t = {a['start_time']:.6g} .. {a['end_time']:.6g},"
              f" {a['status']}, {a['steps']} steps, {a['newton_iterations']} iterations"
              + (f", form finding {a['form_finding']}" if "form_finding" in a else ""))
    t_pre, t_snow = steps["prestress"]["end_time"], steps["snow"]["end_time"]
    found, pre, snow = frame_at(r, steps["form"]["end_time"]), frame_at(r, t_pre), \
        frame_at(r, t_snow)
    sr = r.steps
    first = [float(np.atleast_1d(x)[0]) for x, k in zip(sr["residuals"], sr["analysis_step"])
             if k == 2]
    print(f"prestress: largest displacement of the found shape under its prestress alone "
          f"{np.abs(pre.displacement).max():.3e} m"
          + (f", residual on it {first[0]:.3e} N" if first else ""))
    dz = snow.position[:, 2] - pre.position[:, 2]
    st = sheet_stress(snow) * 1e-6
    force = snow.cell_data["force"][N_QUADS:].reshape(4, N_EDGE) * 1e-3
    print(f"snow: largest downward deflection {-dz.min():.4f} m; warp {st[:, 0].min():.3f} .. "
          f"{st[:, 0].max():.3f} kN/m, fill {st[:, 1].min():.3f} .. {st[:, 1].max():.3f} kN/m; "
          f"cable force {force.min():.2f} .. {force.max():.2f} kN")
    h = r.history
    k = int(np.argmin(np.abs(h["time"] - t_snow)))
    for c in ("low_sw", "high_se", "low_ne", "high_nw"):
        print(f"  reaction {c} under snow: " +
              " ".join(f"{h[f'R_{c}_{x}'][k] * 1e-3:.2f}" for x in "xyz") + " kN")
    chained = out / "snow"
    if (chained / "summary.json").exists():
        c = results.Results(chained)
        cf = c.frame(-1)
        base = frame_at(c, 0.0)
        cdz = cf.position[:, 2] - base.position[:, 2]
        print(f"  chained runs (form.yaml, then snow): deflection {-cdz.min():.4f} m, "
              f"difference of the snowed positions {np.abs(cf.position - snow.position).max():.2e} m")
    g = h["analysis_step"] == 4
    uz = h["centre_uz"]
    t_gust = steps["gust"]["start_time"]
    moved = max(np.linalg.norm(r.frame(i).position - snow.position, axis=1).max()
                for i, t in enumerate(r.times) if t > t_gust + 1e-9)
    print(f"gust: centre uz from {uz[k]:.4f} m (snow) to {uz[g].max():.4f} m (highest) and "
          f"{uz[g].min():.4f} m (lowest); largest motion of a node from the snowed shape "
          f"{moved:.4f} m")
    k1 = int(np.argmin(np.abs(h["time"] - t_pre)))  # the account from the prestress check on
    held = h["kinetic"][-1] + h["strain"][-1] - (h["kinetic"][k1] + h["strain"][k1])
    work = h["work"][-1] - h["work"][k1]
    gk = np.where(g)[0][0] - 1
    gheld = h["kinetic"][-1] + h["strain"][-1] - (h["kinetic"][gk] + h["strain"][gk])
    gwork = h["work"][-1] - h["work"][gk]
    print(f"energy, prestress to end: kinetic + strain change {held:.2f} J, external work "
          f"{work:.2f} J; in the gust (dynamic) step: {gheld:.3f} J held, {gwork:.3f} J work, "
          f"imbalance {abs(gheld - gwork) / max(abs(gwork), 1e-30):.2e} of the work")

    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.plot(h["time"], uz * 1e3, ".-", ms=3)
    for a in s["analysis_steps"]:
        ax.axvline(a["end_time"], color="grey", lw=0.5)
        ax.text(0.5 * (a["start_time"] + a["end_time"]), ax.get_ylim()[1], a["name"],
                ha="center", va="top", fontsize=8)
    ax.set_xlabel("total time (s; load levels in the static steps)")
    ax.set_ylabel("centre displacement z (mm)")
    ax.set_title("hypar roof, one staged run: form, prestress, snow, gust")
    fig.tight_layout()
    fig.savefig(out / "staged.png", dpi=120)


if __name__ == "__main__":
    main(*sys.argv[1:])
