#!/usr/bin/python3
"""Writes hypar-form.yaml: the 10 m x 10 m hypar roof of docs/fabric-structures.md, for form
finding. Two high corners 2 m up, orthotropic PVC fabric (warp along the high diagonal),
edge cables, corners pinned. Units: N, m."""
import sys

L, H, N = 10.0, 2.0, 20  # plan side, corner rise, elements per side
WARP, FILL = 3.0e3, 3.0e3  # prestress, N/m (equal: see docs/fabric-structures.md)
T = 1.0e-3  # fabric thickness (stresses per thickness: N/m over T)
CABLE_FORCE = 40.0e3  # N


def node(i, j):
    return 1 + j * (N + 1) + i


def edge_segments():
    """The four edge cables' sets: the cable2 segments along each border."""
    return {
        "cable_south": [(node(k, 0), node(k + 1, 0)) for k in range(N)],
        "cable_east": [(node(N, k), node(N, k + 1)) for k in range(N)],
        "cable_north": [(node(k, N), node(k + 1, N)) for k in range(N)],
        "cable_west": [(node(0, k), node(0, k + 1)) for k in range(N)],
    }


def edge_cables():
    """The element lines of the four edge cables."""
    return [f"    - {{set: {name}, type: cable2, connectivity: [" +
            ", ".join(f"[{a}, {b}]" for a, b in segs) + "]}"
            for name, segs in edge_segments().items()]


def main(path="hypar-form.yaml"):
    lines = ["# Written by make_model.py: form finding of the hypar roof (examples/hypar-roof)",
             "title: hypar roof 10 m x 10 m, form finding", "mesh:", "  nodes:"]
    for j in range(N + 1):
        for i in range(N + 1):
            u, v = i / N, j / N
            z = H * (u * (1 - v) + v * (1 - u))  # bilinear start: corners (L,0) and (0,L) high
            lines.append(f"    - [{node(i, j)}, {L * u:.6g}, {L * v:.6g}, {z:.6g}]")
    lines.append("  elements:")
    quads = [[node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)]
             for j in range(N) for i in range(N)]
    lines.append("    - {set: roof, type: quad4, connectivity: [" +
                 ", ".join("[" + ", ".join(map(str, q)) + "]" for q in quads) + "]}")
    lines += edge_cables()
    lines += [
        "  node_sets:",
        f"    low_sw: [{node(0, 0)}]",
        f"    high_se: [{node(N, 0)}]",
        f"    low_ne: [{node(N, N)}]",
        f"    high_nw: [{node(0, N)}]",
        f"    corners: [{node(0, 0)}, {node(N, 0)}, {node(N, N)}, {node(0, N)}]",
        f"    centre: [{node(N // 2, N // 2)}]",
        "materials:",
        "  # PVC-coated polyester, type II: tensile stiffness 600 kN/m warp, 450 kN/m fill",
        f"  pvc: {{type: orthotropic, E1: {600e3 / T:.6g}, E2: {450e3 / T:.6g}, nu12: 0.3, "
        f"G12: {30e3 / T:.6g}, density: {1.0 / T:.6g}}}",
        "  strand: {type: cable, E: 1.6e11, density: 7850}",
        "sections:",
        "  # warp along the high diagonal (L,0)-(0,L): the sagging direction that carries snow",
        f"  - {{elements: roof, material: pvc, thickness: {T}, "
        f"axes: {{points: [[{L}, 0, 0], [0, {L}, 0], [0, 0, 1]]}}, "
        f"prestress: [{WARP / T:.6g}, {FILL / T:.6g}, 0.0]}}",
    ]
    for name in edge_segments():
        lines.append(f"  - {{elements: {name}, material: strand, area: 1.13e-4, "
                     f"prestress: {CABLE_FORCE:.6g}}}")
    lines += [
        "boundary:",
        "  - {nodes: corners, fix: [x, y, z]}",
        "analysis:",
        "  type: form_finding",
        "  time: {end: 1.0, step: 1.0}",
        "output:",
        "  directory: out/form",
        "  history:",
        "    - {name: centre_z, quantity: position, node: %d, component: z}" % node(N // 2, N // 2),
    ]
    for c in ("low_sw", "high_se", "low_ne", "high_nw"):
        for comp in "xyz":
            lines.append(f"    - {{name: R_{c}_{comp}, quantity: reaction, nodes: {c}, "
                         f"component: {comp}}}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(*sys.argv[1:])
