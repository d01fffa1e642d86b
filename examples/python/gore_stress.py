#!/usr/bin/python3
"""Post-processing from Python: the principal true stresses along a gore centreline of a C9
canopy, from the last frame of a run.

The cells of the gore's element set that touch its centreline (the two either side for an even
number of elements across, the middle one for an odd number) are found from their reference
centroids, ordered from the vent to the skirt, and their cell stresses (true_stress_max,
true_stress_min, at the element centre) plotted against the reference distance from the vent;
pairs either side are averaged. The history's stress samples at the centreline's nodes
(columns smax_NN and smin_NN of models written by tools/c9-parachute) are drawn as well, when
present: they differ from the cell values where the stress changes across an element (at the
vent and the skirt). Units: the model's
(lbf, ft for the C9).

usage: gore_stress.py RESULTS_DIR MODEL.yaml [--gore SET] [--out FIG.png]
   e.g. gore_stress.py out/c9/isotropic out/c9/isotropic.yaml      (after `make demo`)
"""
import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import velum  # noqa: E402


def centreline_stress(results, gore):
    """(distance from the vent, max, min stress) of the cells along the gore's centreline in
    the last frame, its time and the centreline's length (reference)."""
    f = results.frame(-1)
    cells = results.cells(gore)
    centroids = np.array([f.points[f.connectivity[c]].mean(axis=0) for c in cells])
    r = np.hypot(centroids[:, 0], centroids[:, 1])
    phi = np.arctan2(centroids[:, 1], centroids[:, 0])
    off = np.abs(phi - phi.mean())  # the gore's cells lie symmetric about its centreline
    near = off <= off.min() + 1e-6 * (off.max() - off.min() + 1e-300) + 1e-12
    cells, r = cells[near], r[near]
    # Rows from the vent out: cells either side of the centreline share a radius.
    rows = np.unique(np.round(r / r.max(), 9))
    dist, smax, smin = [], [], []
    for row in rows:
        sel = np.isclose(r / r.max(), row, atol=1e-8)
        dist.append(r[sel].mean())
        smax.append(f.true_stress_max[cells[sel]].mean())
        smin.append(f.true_stress_min[cells[sel]].mean())
    # The centreline's nodes, vent to skirt: the gore's nodes on its mid-angle.
    nodes = np.unique(np.concatenate([f.connectivity[c] for c in results.cells(gore)]))
    on_line = nodes[np.abs(np.arctan2(f.points[nodes, 1], f.points[nodes, 0]) - phi.mean())
                    < 1e-9]
    radius = np.hypot(f.points[on_line, 0], f.points[on_line, 1])
    vent, skirt = radius.min(), radius.max()
    return np.array(dist) - vent, np.array(smax), np.array(smin), f.time, skirt - vent


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("results", type=Path)
    p.add_argument("model", type=Path)
    p.add_argument("--gore", help="element set of the gore (default: the middle gore)")
    p.add_argument("--out", type=Path, help="figure (default: RESULTS_DIR/gore_stress.png)")
    a = p.parse_args()
    r = velum.open_results(a.results, model=a.model)
    gores = sorted({b.set for b in r.blocks if b.set.startswith("gore")},
                   key=lambda s: int(s[4:]) if s[4:].isdigit() else s)
    gore = a.gore or gores[len(gores) // 2]
    s, smax, smin, t, length = centreline_stress(r, gore)

    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(s, smax, "o-", label="max principal (cells)")
    ax.plot(s, smin, "s-", label="min principal (cells)")
    h = r.history
    for tag, marker in (("smax_", "+"), ("smin_", "x")):
        cols = sorted(k for k in h if k.startswith(tag))
        if cols:
            # tools/c9-parachute samples at the centreline's nodes, evenly spaced.
            ax.plot(np.linspace(0, length, len(cols)), [h[c][-1] for c in cols], marker,
                    color="k",
                    label=f"{tag[:-1]} history samples (nodes)")
    ax.set_xlabel("reference distance from the vent along the centreline [ft]")
    ax.set_ylabel("principal true stress [lbf/ft²]")
    ax.set_title(f"{gore}, t = {t:.2f} s ({r.status})")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    out = a.out or a.results / "gore_stress.png"
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(f"{gore} at t = {t:.3f} s: distance from the vent [ft], max and min principal true "
          "stress [lbf/ft²]")
    for row in zip(s, smax, smin):
        print("  {:7.3f}  {:10.1f}  {:10.1f}".format(*row))
    print(f"figure: {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
