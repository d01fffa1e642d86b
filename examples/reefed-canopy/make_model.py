"""Writes the reefed C9 canopy: tools/c9-parachute's quarter-symmetric C9 model with a reefing
line (a sliding_cable) through rings at the skirt's seam nodes, its length a time function:
reefed to 0.4 of the skirt's flat circumference while the canopy inflates, held, then let out
to the full length (disreefed). Arguments after the output path go to tools/c9-parachute
(--along 6 --across 1: the coarse canopy the CLI test runs)."""
import math
import os
import subprocess
import sys

import yaml

here = os.path.dirname(os.path.abspath(__file__))
out, extra = sys.argv[1], sys.argv[2:]
tool = os.path.join(here, "..", "..", "tools", "c9-parachute")
base = out + ".c9.yaml"
subprocess.run([sys.executable, tool, "--end", "3.0", "--interval", "0.05", "--rho-inf", "0",
                "--title", "C9 canopy reefed, then disreefed", "-o", base, *extra], check=True)
model = yaml.safe_load(open(base))
os.remove(base)
radius = max(math.hypot(x, y) for _, x, y, z in model["mesh"]["nodes"])
# Rings at the seams' skirt nodes: on the flat skirt circle (the nodes between seams lie on
# the gores' straight edges, inside it), in order of angle from the plane y = 0.
rings = sorted((math.atan2(y, x), n) for n, x, y, z in model["mesh"]["nodes"]
               if abs(math.hypot(x, y) - radius) < 1e-9 * radius and abs(z) < 1e-12)
chain = [n for _, n in rings]
line_id = sum(len(block["connectivity"]) for block in model["mesh"]["elements"]) + 1
model["mesh"]["elements"].append(
    {"set": "reefing_line", "type": "sliding_cable", "connectivity": [chain]})
model["sections"].append(
    {"elements": "reefing_line", "material": "cord", "area": 1.0e-4, "reefing": "reef"})
# The line's material length over its flat length: 1, drawn in to 0.4 while the pressure
# ramps, held to 1.5 s, let out to 1 by 2.0 s.
model["functions"]["reef"] = {"type": "table",
                              "points": [[0, 1], [0.3, 0.4], [1.5, 0.4], [2.0, 1.0]]}
model["output"]["fields"] = "--fields" in extra
model["output"]["history"] += [
    {"name": "ring_first_x", "quantity": "position", "node": chain[0], "component": "x"},
    {"name": "ring_last_y", "quantity": "position", "node": chain[-1], "component": "y"},
    {"name": "line_force", "quantity": "force", "element": line_id}]
with open(out, "w") as f:
    f.write("# Written by examples/reefed-canopy/make_model.py: " + " ".join(extra) + "\n")
    f.write(f"# reefing line through {len(chain)} rings, element {line_id}; flat skirt radius "
            f"{radius:g} ft\n")
    yaml.safe_dump(model, f, default_flow_style=None, sort_keys=False, width=100)
