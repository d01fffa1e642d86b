#!/usr/bin/python3
"""Writes the hypar roof with its edge cables in sleeves (docs/cables.md, "Form finding: an edge
cable in a sleeve"): each edge one sliding_cable chain, corner to corner through the fabric's
edge nodes (the sleeve points), its 40 kN prescribed force one force along it. One staged
model: form finding, then 0.5 kN/m² snow per plan area in four static steps. Beside it the same
two steps with the fixed edge cables of make_model.py (cable2 segments), for the comparison of
sleeve_numbers.py.
A third model puts friction 0.2 between cable and sleeve.
usage: sleeve_model.py out   (writes out/hypar-sleeve.yaml, out/hypar-sleeve-friction.yaml and
out/hypar-fixed.yaml; their results go to out/sleeve, out/sleeve-friction and out/fixed)"""
import os
import sys
import tempfile
from pathlib import Path

import yaml

sys.dont_write_bytecode = True  # no __pycache__ in the example folder
import make_model  # noqa: E402  (the roof's mesh, fabric, cables and supports)

SNOW = 500.0  # N/m² per plan area, downwards
# The models: name (also of the results folder), its edge cables, the sleeves' friction.
VARIANTS = [("sleeve", "in sleeves", 0.0),
            ("sleeve-friction", "in sleeves with friction 0.2", 0.2),
            ("fixed", "fixed to the edge nodes", 0.0)]


def sleeves(model, friction):
    """The four edge cables' cable2 segments become one sliding_cable chain each (friction μ
    between cable and sleeve on their sections when given)."""
    chains = {name: [segs[0][0]] + [b for _, b in segs]
              for name, segs in make_model.edge_segments().items()}
    elements = [e for e in model["mesh"]["elements"] if e["set"] not in chains]
    for name, chain in chains.items():
        elements.append({"set": name, "type": "sliding_cable", "connectivity": [chain]})
    model["mesh"]["elements"] = elements
    if friction:
        for s in model["sections"]:
            if s["elements"] in chains:
                s["friction"] = friction


def staged(model, title, directory, sleeved):
    model["title"] = title
    del model["analysis"]
    model["functions"] = {"ramp": {"type": "ramp", "duration": 1.0}}
    model["steps"] = [
        # tolerance 2e-5: in sleeves the search levels off at 1.3e-5 of the force scale (the
        # sleeve points sliding along the edge, which the isotropic prestress does not resist)
        {"name": "form", "analysis": {"type": "form_finding", "time": {"end": 1.0, "step": 1.0},
                                      "form_finding": {"tolerance": 2e-5}}},
        # the found shape under its prestress alone, now with the cables' own law: it must
        # not move (the sleeve points free to slide)
        {"name": "prestress", "analysis": {"type": "static", "time": {"end": 1.0, "step": 1.0}}},
        {"name": "snow", "analysis": {"type": "static", "time": {"end": 1.0, "step": 0.25}},
         "loads": [{"type": "pressure", "elements": "roof", "value": SNOW,
                    "direction": [0, 0, -1], "per": "projected", "function": "ramp"}]},
    ]
    model["output"]["directory"] = directory  # beside the model file
    n = make_model.N
    mids = {"south": make_model.node(n // 2, 0), "east": make_model.node(n, n // 2),
            "north": make_model.node(n // 2, n), "west": make_model.node(0, n // 2)}
    hist = model["output"]["history"]
    for edge, node in mids.items():
        for c in "xyz":
            hist.append({"name": f"mid_{edge}_{c}", "quantity": "position", "node": node,
                         "component": c})
    if sleeved:  # the chains follow the roof's 400 quads: elements 401 .. 404
        for k, edge in enumerate(mids):
            hist.append({"name": f"T_{edge}", "quantity": "force", "element": 401 + k})
            # the material through the sleeve point at mid-edge
            hist.append({"name": f"slip_{edge}", "quantity": "slip", "element": 401 + k,
                         "node": mids[edge]})


def main(out):
    os.makedirs(out, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        form = Path(tmp, "hypar-form.yaml")
        make_model.main(str(form))
        text = form.read_text()
    for name, what, friction in VARIANTS:
        model = yaml.safe_load(text)
        sleeved = name != "fixed"
        if sleeved:
            sleeves(model, friction)
        staged(model, f"hypar roof 10 m x 10 m, edge cables {what}: form finding, snow", name,
               sleeved)
        Path(out, f"hypar-{name}.yaml").write_text(
            "# Written by sleeve_model.py (examples/hypar-roof)\n" +
            yaml.safe_dump(model, sort_keys=False, width=100))


if __name__ == "__main__":
    main(*sys.argv[1:])
