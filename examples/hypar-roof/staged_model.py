#!/usr/bin/python3
"""Writes the hypar roof as one staged model (docs/fabric-structures.md, "One model, several
steps"): form finding, a prestress check, 0.5 kN/m² snow per plan area, then a wind gust
(follower suction) on the snowed roof, solved dynamically. From the form-finding model of
make_model.py.
usage: staged_model.py hypar-form.yaml out/hypar-staged.yaml"""
import sys
from pathlib import Path

import yaml

SNOW = 500.0  # N/m² per plan area, downwards
GUST = 300.0  # N/m² suction (uplift), follower: along g1 x g2, which points up here


def main(form, path):
    model = yaml.safe_load(Path(form).read_text())
    model["title"] = "hypar roof 10 m x 10 m: form finding, prestress, snow, gust"
    del model["analysis"]
    model["functions"] = {
        "ramp": {"type": "ramp", "duration": 1.0},
        # step time: up in 0.1 s, held 0.2 s, down by 0.4 s
        "gust": {"type": "table", "points": [[0, 0], [0.1, 1], [0.3, 1], [0.4, 0]]},
    }
    def snow(**more):
        return dict({"type": "pressure", "elements": "roof", "value": SNOW,
                     "direction": [0, 0, -1], "per": "projected"}, **more)
    model["steps"] = [
        {"name": "form", "analysis": {"type": "form_finding", "time": {"end": 1.0, "step": 1.0}}},
        # the found shape under its prestress alone: it must not move
        {"name": "prestress", "analysis": {"type": "static", "time": {"end": 1.0, "step": 1.0}}},
        {"name": "snow", "analysis": {"type": "static", "time": {"end": 1.0, "step": 0.25}},
         "loads": [snow(function="ramp")]},
        # snow held (constant), a gust of suction on top; the corners stay pinned
        {"name": "gust", "analysis": {"type": "dynamic", "time": {"end": 0.6, "step": 0.01},
                                      "integrator": {"scheme": "generalized-alpha",
                                                     "rho_inf": 0.8}},
         "loads": [snow(), {"type": "pressure", "elements": "roof", "value": GUST,
                          "function": "gust"}]},
    ]
    model["output"]["directory"] = "staged"  # beside the model file: out/staged
    model["output"]["history"].insert(
        1, {"name": "centre_uz", "quantity": "displacement",
            "node": model["output"]["history"][0]["node"], "component": "z"})
    model["output"]["history"] += [
        {"name": "kinetic", "quantity": "kinetic_energy"},
        {"name": "strain", "quantity": "strain_energy"},
        {"name": "work", "quantity": "external_work"},
    ]
    Path(path).write_text("# Written by staged_model.py (examples/hypar-roof)\n" +
                          yaml.safe_dump(model, sort_keys=False, width=100))


if __name__ == "__main__":
    main(*sys.argv[1:])
