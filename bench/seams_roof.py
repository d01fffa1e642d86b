#!/usr/bin/python3
"""Writes the model of bench/pattern_bench.cpp's roof for `velum seams` (docs/patterns.md,
"Seams", Time): a 4 m hypar (0.8 m twist) of 224 x 224 cells as 100,352 tri3 in one set, its
edges x = 0 and x = 4 m held, with seven geodesic seams between nodes of those edges (from y = k/2 m to k/2 + 1/4 m)
that cut it into eight strips. Usage: seams_roof.py OUT.yaml [CELLS]."""
import sys


def main(path, n=224):
    n = int(n)
    node = lambda i, j: 1 + j * (n + 1) + i  # noqa: E731
    out = [f"title: hypar roof of {2 * n * n} tri3 cut by seams", "mesh:", "  nodes:"]
    for j in range(n + 1):
        for i in range(n + 1):
            u, v = i / n, j / n
            out.append(f"    - [{node(i, j)}, {4 * u:.9g}, {4 * v:.9g}, {0.8 * (u * (1 - v) + v * (1 - u)):.9g}]")
    tris = []
    for j in range(n):
        for i in range(n):
            tris.append(f"[{node(i, j)}, {node(i + 1, j)}, {node(i + 1, j + 1)}]")
            tris.append(f"[{node(i, j)}, {node(i + 1, j + 1)}, {node(i, j + 1)}]")
    out.append("  elements:")
    out.append("    - {set: roof, type: tri3, connectivity: [" + ", ".join(tris) + "]}")
    out.append("  node_sets:")
    out.append(f"    edges: [{', '.join(str(node(i, j)) for j in range(n + 1) for i in (0, n))}]")
    out += ["materials:", "  pvc: {type: isotropic, E: 6.0e8, nu: 0.3, density: 1000.0}",
            "sections:", "  - {elements: roof, material: pvc, thickness: 1.0e-3}",
            "boundary:", "  - {nodes: edges, fix: [x, y, z]}",
            "analysis:", "  type: static", "  time: {end: 1.0, step: 1.0}",
            "patterns:", "  seams:"]
    per = n // 8
    # Slanted: from (0, k/2) to (4, k/2 + 1/4) m, across the triangles, not along mesh lines.
    out += [f"    - {{points: [{node(0, k * per)}, {node(n, k * per + per // 2)}]}}" for k in range(1, 8)]
    out.append("  compensation: [0.0, 0.0]")
    open(path, "w").write("\n".join(out) + "\n")


if __name__ == "__main__":
    main(*sys.argv[1:])
