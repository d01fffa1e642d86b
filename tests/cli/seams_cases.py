#!/usr/bin/env python3
"""Issue 45: `velum seams` through the command line. The example hypar roof (pattern_model.py,
one set `roof`) form-found, then cut by its four geodesic seams into 5 panels, and by the same
seams given as node paths along the mesh lines, which must give back the example's 5 strip
panels element for element; a plate cut across its triangles, flattened by `velum pattern`
straight from the model; bad input: a point off the surface, a seam ending inside, a seam that
leaves one panel where two are named, a node path off the element edges, an unknown node.
Usage: seams_cases.py VELUM WORKDIR."""
import os
import re
import subprocess
import sys

import yaml

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples",
                       "hypar-roof")
sys.dont_write_bytecode = True
sys.path.insert(0, EXAMPLE)
import pattern_model  # noqa: E402


def run(args, ok=True):
    p = subprocess.run(args, capture_output=True, text=True, timeout=240)
    if ok and p.returncode != 0:
        raise SystemExit(f"{' '.join(args)}: exit {p.returncode}: {p.stderr}")
    return p


def panels_of(path):
    """Per element set of a written model: its triangles as sorted node tuples."""
    out = {}
    for e in yaml.safe_load(open(path))["mesh"]["elements"]:
        out.setdefault(e["set"], set()).update(tuple(sorted(c)) for c in e["connectivity"])
    return out


PLATE = """title: plate cut by seams
mesh:
  nodes: {nodes}
  elements:
    - {{set: sheet, type: tri3, connectivity: {tris}}}
  node_sets:
    edge: {{box: [-0.01, -0.01, -0.01, 0.01, 2.01, 0.01]}}
materials:
  pvc: {{type: isotropic, E: 1.0e9, nu: 0.3, density: 1000.0}}
sections:
  - {{elements: sheet, material: pvc, thickness: 1.0e-3}}
boundary:
  - {{nodes: edge, fix: [x, y, z]}}
analysis:
  type: static
  time: {{end: 1.0, step: 1.0}}
patterns:
  seams: {seams}
{panels}  compensation: [0.0, 0.0]
"""


def plate(seams, panels=""):
    nu, nv = 6, 4
    nodes = [[j * (nu + 1) + i + 1, 0.5 * i, 0.5 * j, 0.0] for j in range(nv + 1) for i in range(nu + 1)]
    tris = []
    for j in range(nv):
        for i in range(nu):
            a = j * (nu + 1) + i + 1
            tris += [[a, a + 1, a + nu + 2], [a, a + nu + 2, a + nu + 1]]
    return PLATE.format(nodes=nodes, tris=tris, seams=seams, panels=panels)


def main():
    velum, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    failures = []
    # The hypar: geodesic seams on the found shape.
    model, form = os.path.join(work, "hypar.yaml"), os.path.join(work, "form")
    run([sys.executable, os.path.join(EXAMPLE, "pattern_model.py"), model, form])
    run([velum, "run", model, "-q"])
    cut = os.path.join(work, "hypar-panels.yaml")
    print(run([velum, "seams", form, "-o", cut]).stdout.strip())
    strips = {name: {tuple(sorted(t)) for t in tris} for name, tris in pattern_model.panels().items()}
    got = panels_of(cut)
    names = [n for n in got if n.startswith("panel_")]
    if names != list(strips):
        failures.append(f"geodesic seams: panels {names}, expected {list(strips)}")
    # The same seams along the mesh lines (node paths): the example's strips exactly.
    data = yaml.safe_load(open(os.path.join(form, "form.yaml")))
    N, node = pattern_model.N, pattern_model.node
    data["patterns"]["seams"] = [
        {"nodes": [node(i, s - i) for i in range(N + 1) if 0 <= s - i <= N]}
        for s in range(pattern_model.BAND, 2 * N, pattern_model.BAND)]
    paths = os.path.join(work, "hypar-paths.yaml")
    yaml.safe_dump(data, open(paths, "w"), default_flow_style=None)
    cut_paths = os.path.join(work, "hypar-paths-panels.yaml")
    print(run([velum, "seams", paths, "-o", cut_paths]).stdout.strip().splitlines()[-1])
    got = panels_of(cut_paths)
    for name, tris in strips.items():
        if got.get(name) != tris:
            failures.append(f"node-path seams: {name} has {len(got.get(name, ()))} triangles, "
                            f"not the example's {len(tris)}")
    # A plate cut across its triangles, then flattened by velum pattern from the model itself.
    d = os.path.join(work, "plate")
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "model.yaml")
    open(path, "w").write(plate("[{points: [[0.0, 0.37, 0.0], [3.0, 1.71, 0.0]]}]",
                                "  panels: [low, high]\n"))
    p = run([velum, "pattern", path, "-o", os.path.join(d, "patterns")])
    print(p.stdout.strip().splitlines()[-1])
    areas = {q["name"]: q["area_3d"] for q in
             __import__("json").load(open(os.path.join(d, "patterns", "patterns.json")))["panels"]}
    below = 3 * (0.37 + 1.71) / 2
    if set(areas) != {"low", "high"} or abs(areas["low"] + areas["high"] - 6.0) > 1e-9 or \
            abs(areas["low"] - below) > 0.45 * 0.71 * 3.3:
        failures.append(f"plate: panel areas {areas}, expected {below} and {6 - below}")
    cut_model = yaml.safe_load(open(os.path.join(d, "patterns", "panels.yaml")))
    if len(cut_model["mesh"]["node_sets"]["edge"]) < 5:  # the supported edge keeps its nodes
        failures.append(f"plate: node set edge {cut_model['mesh']['node_sets']['edge']}")

    bad = {
        "off": (plate("[{points: [[0.0, 0.37, 0.3], [3.0, 1.71, 0.0]]}]"),
                "patterns.seams[0].points[0]", "off the shape"),
        "inside": (plate("[{points: [[0.0, 0.37, 0.0], [1.3, 0.9, 0.0]]}]"),
                   "patterns.seams[0].points[1]", "inside the surface"),
        "open": (plate("[{points: [[0.0, 0.37, 0.0], [1.5, 1.0, 0.0]]}]"),
                 "patterns.seams[0]", "does not close a panel"),
        "count": (plate("[{points: [[0.0, 0.37, 0.0], [3.0, 1.71, 0.0]]}]", "  panels: [a, b, c]\n"),
                  "patterns.panels", "into 2 panels"),
        "path": (plate("[{nodes: [1, 3]}]"), "patterns.seams[0].nodes", "not joined by an element edge"),
        "unknown": (plate("[{points: [1, 9999]}]"), "patterns.seams[0].points[1]", "undefined node 9999"),
    }
    for name, (text, key, want) in bad.items():
        d = os.path.join(work, "bad_" + name)
        os.makedirs(d, exist_ok=True)
        path = os.path.join(d, "model.yaml")
        open(path, "w").write(text)
        p = run([velum, "seams", path, "-o", os.path.join(d, "cut.yaml")], ok=False)
        msg = p.stderr.strip()
        print(f"bad {name}: exit {p.returncode}: {msg.splitlines()[0] if msg else ''}")
        if p.returncode != 1 or key not in msg or want not in msg or not re.search(r"model\.yaml:\d+", msg):
            failures.append(f"bad {name}: exit {p.returncode}, {msg!r}")
    for f in failures:
        print("FAIL:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
