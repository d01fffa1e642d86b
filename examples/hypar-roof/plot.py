#!/usr/bin/python3
"""Figures and numbers of the hypar roof (run.sh): the found shape and the shape under snow,
warp and fill stresses, cable forces along the edges and the corner reactions.
usage: plot.py out   (reads out/form, out/snow, out/snow-wrinkling; writes PNGs into out)"""
import importlib.util
import sys
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PolyCollection
import numpy as np

HERE = Path(__file__).resolve().parent
spec = importlib.util.spec_from_file_location("results", HERE / "../../python/velum/results.py")
results = importlib.util.module_from_spec(spec)
spec.loader.exec_module(results)

N_QUADS, N_EDGE = 400, 20  # the mesh of make_model.py: roof first, then 4 cable sets
EDGES = ["south", "east", "north", "west"]


def last(run):
    r = results.Results(run)
    return r, r.frame(-1)


def quads(frame):
    xy = frame.position[:, :2]
    return [xy[c] for c in frame.connectivity[:N_QUADS]]


def plan_view(fig, ax, frame, cell_values, cmap, title):
    """The roof's cells seen from above, coloured by one value per cell."""
    pc = PolyCollection(quads(frame), array=cell_values, cmap=cmap, edgecolor="k", linewidth=0.2)
    ax.add_collection(pc)
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_title(title)
    fig.colorbar(pc, ax=ax)


def sheet_stress(frame):
    """True stress (warp, fill, shear) in the deformed sheet axes of the roof's cells."""
    c = frame.cell_data
    return np.column_stack([c["stress_11"], c["stress_22"], c["stress_12"]])[:N_QUADS]


def main(out):
    out = Path(out)
    form_r, form = last(out / "form")
    snow_r, snow = last(out / "snow")
    wr_r, wr = last(out / "snow-wrinkling")
    z_form = form.position[:, 2]
    dz = snow.position[:, 2] - z_form
    print(f"form finding: {form_r.summary.get('form_finding')}")
    print(f"snow: largest downward deflection {-dz.min():.4f} m (wrinkling: "
          f"{-(wr.position[:, 2] - z_form).min():.4f} m)")
    for name, f in (("elastic", snow), ("wrinkling", wr)):
        s = sheet_stress(f) * 1e-6  # N/m^2 x 0.001 m thickness, in kN/m
        smin = f.cell_data["true_stress_min"][:N_QUADS]
        share = np.mean(smin < -1e-6 * np.abs(smin).max())
        line = (f"snow, {name}: warp {s[:, 0].min():.3f} .. {s[:, 0].max():.3f} kN/m, fill "
                f"{s[:, 1].min():.3f} .. {s[:, 1].max():.3f} kN/m; elements with a compressive "
                f"principal stress {100 * share:.1f}%")
        if "wrinkle_state" in f.cell_data:
            ws = f.cell_data["wrinkle_state"][:N_QUADS]
            line += f", wrinkled {100 * np.mean(ws == 1):.1f}%, slack {100 * np.mean(ws == 2):.1f}%"
        print(line)
        force = f.cell_data["force"][N_QUADS:].reshape(4, N_EDGE) * 1e-3
        print("  cable force kN: " + ", ".join(
            f"{e} {force[i].min():.2f}..{force[i].max():.2f}" for i, e in enumerate(EDGES)))
    h = snow_r.history
    for c in ("low_sw", "high_se", "low_ne", "high_nw"):
        print(f"  reaction {c}: form " + " ".join(
            f"{form_r.history[f'R_{c}_{k}'][-1] * 1e-3:.2f}" for k in "xyz") + " kN; snow " +
            " ".join(f"{h[f'R_{c}_{k}'][-1] * 1e-3:.2f}" for k in "xyz") + " kN")

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.6))
    for a, values, title in ((ax[0], z_form, "found shape: height z (m)"),
                             (ax[1], dz * 1e3, "snow 0.5 kN/m²: deflection (mm)")):
        cells = np.array([values[c].mean() for c in form.connectivity[:N_QUADS]])
        plan_view(fig, a, form, cells, "viridis", title)
    fig.tight_layout()
    fig.savefig(out / "shape.png", dpi=120)

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.6))
    s = sheet_stress(snow) * 1e-6
    for a, k, title in ((ax[0], 0, "warp stress under snow (kN/m)"),
                        (ax[1], 1, "fill stress under snow (kN/m)")):
        plan_view(fig, a, snow, s[:, k], "coolwarm", title)
    fig.tight_layout()
    fig.savefig(out / "stresses.png", dpi=120)

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for name, f, style in (("found (prestress)", form, "--"), ("snow", snow, "-")):
        force = f.cell_data["force"][N_QUADS:].reshape(4, N_EDGE) * 1e-3
        for i, e in enumerate(EDGES):
            ax[0].plot(np.arange(N_EDGE) + 0.5, force[i], style, label=f"{e}, {name}")
    ax[0].set_xlabel("segment along the edge")
    ax[0].set_ylabel("cable force (kN)")
    ax[0].legend(fontsize=7)
    ax[0].set_title("edge cable forces")
    corners = ["low_sw", "high_se", "low_ne", "high_nw"]
    width = 0.2
    for k, comp in enumerate("xyz"):
        ax[1].bar(np.arange(4) + (k - 1) * width, [h[f"R_{c}_{comp}"][-1] * 1e-3 for c in corners],
                  width, label=f"R{comp}")
    ax[1].set_xticks(range(4), corners)
    ax[1].set_ylabel("reaction under snow (kN)")
    ax[1].legend()
    ax[1].set_title("corner reactions")
    fig.tight_layout()
    fig.savefig(out / "cables_reactions.png", dpi=120)


if __name__ == "__main__":
    main(*sys.argv[1:])
