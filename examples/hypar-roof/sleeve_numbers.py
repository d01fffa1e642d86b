#!/usr/bin/python3
"""Numbers and a figure of the hypar roof with its edge cables in sleeves (sleeve_model.py)
beside the same roof with fixed edge cables: the found edges, the snow's deflection, the edge's
sag and the cable force along it.
usage: sleeve_numbers.py out   (reads out/sleeve, out/sleeve-friction, out/fixed; writes
out/sleeve.png)"""
import sys
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True  # no __pycache__ in the example folder
import make_model  # noqa: E402
from plot import EDGES, N_EDGE, N_QUADS, results  # noqa: E402
from sleeve_model import VARIANTS  # noqa: E402

N = make_model.N
# Each edge's nodes in chain order (corner to corner), as sleeve_model.py's chains run.
EDGE_NODES = {e: [segs[0][0] - 1] + [b - 1 for _, b in segs]
              for e, segs in zip(EDGES, make_model.edge_segments().values())}


def frame_at(r, t):
    return r.frame(int(np.argmin(np.abs(np.asarray(r.times) - t))))


def sag(p, nodes):
    """The edge's mid node's distance from the chord between its corners, split into its part
    normal to the chord in the horizontal plane (the arc in plan) and the vertical drop."""
    a, b, m = p[nodes[0]], p[nodes[-1]], p[nodes[len(nodes) // 2]]
    d = m - 0.5 * (a + b)
    chord = (b - a) / np.linalg.norm(b - a)
    d -= d.dot(chord) * chord
    return float(np.hypot(d[0], d[1])), float(d[2])


def variant(out, name):
    """The numbers of one model's run."""
    r = results.Results(Path(out) / name)
    s = r.summary
    steps = {a["name"]: a for a in s["analysis_steps"]}
    found, pre, snow = (frame_at(r, steps[k]["end_time"]) for k in ("form", "prestress", "snow"))
    force = {}
    for key, f in (("found", found), ("snow", snow)):
        cells = f.cell_data["force"][N_QUADS:]
        # fixed: N_EDGE segments per edge; sleeves: one chain per edge
        force[key] = (cells.reshape(4, N_EDGE) if len(cells) == 4 * N_EDGE
                      else np.repeat(cells[:, None], N_EDGE, axis=1))
    return {
        "name": name, "status": s["status"], "form_finding": steps["form"].get("form_finding"),
        "iterations": {k: a["newton_iterations"] for k, a in steps.items()},
        "prestress_moved": float(np.abs(pre.position - found.position).max()),
        "deflection": float(-(snow.position[:, 2] - pre.position[:, 2]).min()),
        "sag_found": {e: sag(found.position, n) for e, n in EDGE_NODES.items()},
        "sag_snow": {e: sag(snow.position, n) for e, n in EDGE_NODES.items()},
        "drop": float(below_chord(snow.position[EDGE_NODES["south"]]).max()),
        "force": force, "snow": snow, "found": found,
        "slip": {e: float(r.history[f"slip_{e}"][-1]) for e in EDGES
                 if f"slip_{e}" in r.history},
    }


def report(v):
    ff = v["form_finding"]
    print(f"{v['name']}: {v['status']}; form finding {ff['updates']} updates (residual "
          f"{ff['residual']:.2g}), Newton iterations {v['iterations']}; the found shape moves "
          f"{v['prestress_moved']:.2e} m under its prestress alone")
    e = "south"
    print(f"  found: south edge sag in plan {v['sag_found'][e][0]:.4f} m; cable force "
          f"{v['force']['found'].min() * 1e-3:.3f} .. {v['force']['found'].max() * 1e-3:.3f} kN")
    f = v["force"]["snow"] * 1e-3
    print(f"  snow: centre deflection {v['deflection']:.4f} m; south edge sag in plan "
          f"{v['sag_snow'][e][0]:.4f} m, at most {v['drop']:.4f} m below the corners' chord"
          + ("; cable force (the chain's mean) kN " if v["name"] == "sleeve-friction"
             else "; cable force kN ") + ", ".join(f"{k} {f[i].min():.2f}..{f[i].max():.2f}"
                                          for i, k in enumerate(EDGES))
          + (f"; slip at mid-edge {v['slip'][e] * 1e3:.1f} mm" if v["slip"] else ""))


def below_chord(x):
    """Each edge node's height below the straight line between the edge's corners (at its x)."""
    a, b = x[0], x[-1]
    return a[2] + (x[:, 0] - a[0]) / (b[0] - a[0]) * (b[2] - a[2]) - x[:, 2]


def figure(vs, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    nodes = EDGE_NODES["south"]
    style = {"fixed": "-", "sleeve": "-", "sleeve-friction": "--"}
    for v in vs:
        x = v["snow"].position[nodes]
        s = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(x, axis=0), axis=1))])
        label = dict((n, w) for n, w, _ in VARIANTS)[v["name"]]
        mean = " (mean)" if v["name"] == "sleeve-friction" else ""
        ax[0].step(s, np.append(v["force"]["snow"][0], v["force"]["snow"][0][-1]) * 1e-3,
                   style[v["name"]], where="post", label=f"{label}{mean}")
        ax[1].plot(x[:, 0], below_chord(x) * 1e3, style[v["name"]], marker=".", ms=3,
                   label=f"snow, {label}")
    found = vs[0]["found"].position[nodes]
    ax[1].plot(found[:, 0], below_chord(found) * 1e3, ":", color="grey", label="found shape")
    ax[0].axhline(40, color="grey", lw=0.5)
    ax[0].set_xlabel("along the south edge (m)")
    ax[0].set_ylabel("cable force under snow (kN)")
    ax[0].set_title("edge cable force: sleeve one value, fixed varies")
    ax[0].legend(fontsize=7)
    ax[1].set_xlabel("x (m)")
    ax[1].set_ylabel("below the corners' chord (mm)")
    ax[1].set_title("south edge: vertical sag under 0.5 kN/m² snow")
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main(out):
    vs = [variant(out, name) for name, _, _ in VARIANTS]
    for v in vs:
        report(v)
    figure(vs, Path(out) / "sleeve.png")


if __name__ == "__main__":
    main(*sys.argv[1:])
