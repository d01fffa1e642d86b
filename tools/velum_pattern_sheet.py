#!/usr/bin/python3
"""The sheet of cutting patterns `velum pattern` writes (PDIR/patterns.png): every flat panel
of PDIR/patterns.json drawn to one scale, its warp (u, the roll's length) across the page,
the panels stacked one under the other, each with its seam line (the flat panel shrunk by the
compensation), its flat mesh outline and its name and areas. Run by velum pattern with
Debian's /usr/bin/python3; exit 3, with the reason, where matplotlib is missing.
Usage: velum_pattern_sheet.py PATTERNS.json OUT.png"""
import json
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as missing:
    print(f"velum pattern: note: {missing.name} is missing, patterns.png not written (Debian: "
          "apt-get install python3-matplotlib)", file=sys.stderr)
    sys.exit(3)


def main():
    if len(sys.argv) != 3:
        print(__doc__.splitlines()[-1], file=sys.stderr)
        sys.exit(2)
    data = json.load(open(sys.argv[1]))
    warp, fill = data["compensation"]
    panels = data["panels"]
    if not panels:
        print("velum pattern: error: no panels to draw", file=sys.stderr)
        sys.exit(1)
    shapes, width, gap = [], 0.0, 0.0
    for p in panels:
        uv = {n[0]: (n[1], n[2]) for n in p["nodes"]}
        ring = [uv[i] for i in p["outline"]] + [uv[p["outline"][0]]]
        u = [a * (1 - warp) for a, _ in ring]
        v = [b * (1 - fill) for _, b in ring]
        shapes.append((p, ring, u, v))
        width = max(width, max(u) - min(u))
        gap = max(gap, 0.08 * (max(v) - min(v)))
    fig_w = 10.0
    height = sum(max(v) - min(v) for _, _, _, v in shapes) + gap * (len(shapes) + 1)
    fig, ax = plt.subplots(figsize=(fig_w, min(60.0, max(3.0, fig_w * height / max(width, 1e-12)))))
    y = 0.0
    for p, ring, u, v in shapes:
        dv = y - max(v)  # stack downwards
        ax.plot([a for a, _ in ring], [b + dv for _, b in ring], color="0.7", lw=0.6)
        ax.fill([a for a in u], [b + dv for b in v], facecolor="#dbe8f5", edgecolor="#1f4e79",
                lw=1.0)
        cu = 0.5 * (min(u) + max(u))
        cv = 0.5 * (min(v) + max(v)) + dv
        ax.text(cu, cv, f"{p['name']}\nflat {p['area_flat']:.3f} m²\ncut {p['area_cut']:.3f} m²",
                ha="center", va="center", fontsize=8)
        y = dv + min(v) - gap
    ax.set_aspect("equal")
    ax.set_xlabel("u, warp (m)")
    ax.set_ylabel("v, fill (m)")
    total = sum(p["area_cut"] for p in panels)
    ax.set_title(f"{len(panels)} panels, compensation warp {warp:.3%} fill {fill:.3%}, "
                 f"cut area {total:.3f} m²", fontsize=9)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()
