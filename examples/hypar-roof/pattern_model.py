#!/usr/bin/python3
"""Writes hypar-pattern.yaml: the hypar roof of make_model.py meshed with triangles, one
element set `roof`, with the patterns: block that velum seams and velum pattern read: four
seams along the warp (the high diagonal), geodesics on the found shape between edge nodes, that
cut it into five strip panels, and the compensation by the strain of the prestress in the
fabric's own law. With `strips` the roof is written already cut into the five strips (sets
panel_1 ... panel_5 along mesh lines), as before the seams tool.
Usage: pattern_model.py [OUT.yaml [FORM_DIR [seams|strips]]]."""
import math
import sys

from make_model import CABLE_FORCE, FILL, H, L, N, T, WARP, edge_cables, edge_segments, node

E1, E2, NU12 = 600e3 / T, 450e3 / T, 0.3  # the pvc of make_model.py
BAND = 8  # panel width in cells, across the warp (i + j is constant along the warp)


def compensation():
    """The flat panel shrunk by c stretches by 1 / (1 - c) when sewn: its Green strain must
    be the prestress's, g = C^-1 s of the orthotropic law."""
    s1, s2 = WARP / T, FILL / T
    g1 = s1 / E1 - NU12 * s2 / E1
    g2 = s2 / E2 - NU12 * s1 / E1
    return [1 - 1 / math.sqrt(1 + 2 * g) for g in (g1, g2)]


def panels():
    """Triangles split along the (i+1, j)-(i, j+1) diagonal, so that every band of constant
    i + j is bounded by mesh lines; panel k holds the triangles whose lowest i + j is in
    [k BAND, (k + 1) BAND)."""
    out = {}
    for j in range(N):
        for i in range(N):
            low = [node(i, j), node(i + 1, j), node(i, j + 1)]
            high = [node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)]
            for tri, s in ((low, i + j), (high, i + j + 1)):
                out.setdefault(f"panel_{s // BAND + 1}", []).append(tri)
    return out


def seams():
    """The seams: between the edge nodes where the strips of panels() part (i + j = 8, 16,
    24, 32), each a geodesic on the shape velum seams cuts in."""
    out = []
    for s in range(BAND, 2 * N, BAND):
        a = (s, 0) if s <= N else (N, s - N)
        b = (0, s) if s <= N else (s - N, N)
        out.append((node(*a), node(*b)))
    return out


def main(path="hypar-pattern.yaml", form_dir="out/pattern-form", mode="seams"):
    lines = ["# Written by pattern_model.py: the hypar roof cut into panels (examples/hypar-roof)",
             "title: hypar roof 10 m x 10 m in 5 panels, form finding and cutting patterns",
             "mesh:", "  nodes:"]
    for j in range(N + 1):
        for i in range(N + 1):
            u, v = i / N, j / N
            lines.append(f"    - [{node(i, j)}, {L * u:.6g}, {L * v:.6g}, "
                         f"{H * (u * (1 - v) + v * (1 - u)):.6g}]")
    lines.append("  elements:")
    sets = panels()
    if mode == "seams":
        sets = {"roof": [t for tris in sets.values() for t in tris]}
    for name, tris in sets.items():
        lines.append(f"    - {{set: {name}, type: tri3, connectivity: [" +
                     ", ".join("[" + ", ".join(map(str, t)) + "]" for t in tris) + "]}")
    lines += edge_cables()
    lines += [
        "  node_sets:",
        f"    corners: [{node(0, 0)}, {node(N, 0)}, {node(N, N)}, {node(0, N)}]",
        "materials:",
        f"  pvc: {{type: orthotropic, E1: {E1:.6g}, E2: {E2:.6g}, nu12: {NU12}, "
        f"G12: {30e3 / T:.6g}, density: {1.0 / T:.6g}}}",
        "  strand: {type: cable, E: 1.6e11, density: 7850}",
        "sections:",
    ]
    for name in sets:
        lines.append(f"  - {{elements: {name}, material: pvc, thickness: {T}, "
                     f"axes: {{points: [[{L}, 0, 0], [0, {L}, 0], [0, 0, 1]]}}, "
                     f"prestress: [{WARP / T:.6g}, {FILL / T:.6g}, 0.0]}}")
    for name in edge_segments():
        lines.append(f"  - {{elements: {name}, material: strand, area: 1.13e-4, "
                     f"prestress: {CABLE_FORCE:.6g}}}")
    c = compensation()
    lines += [
        "boundary:",
        "  - {nodes: corners, fix: [x, y, z]}",
        "analysis:",
        "  type: form_finding",
        "  time: {end: 1.0, step: 1.0}",
        "patterns:",
    ]
    if mode == "seams":
        lines.append("  seams:")
        lines += [f"    - {{points: [{a}, {b}]}}" for a, b in seams()]
    lines += [
        f"  panels: [{', '.join(panels())}]",
        f"  compensation: [{c[0]:.6g}, {c[1]:.6g}]",
        "  seam_allowance: 0.03",
        "output:",
        f"  directory: {form_dir}",
    ]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(*sys.argv[1:])
