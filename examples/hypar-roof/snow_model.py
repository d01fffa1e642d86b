#!/usr/bin/python3
"""Turns the form-finding run's DIR/form.yaml into the snow analyses: 0.5 kN/m² per plan area,
downwards, in four static load steps, on the found shape with its prestress; once elastic and
once with wrinkling (the fabric carries no compression).
usage: snow_model.py out/form/form.yaml out"""
import sys
from pathlib import Path

import yaml


def main(form, out):
    model = yaml.safe_load(Path(form).read_text())
    model["title"] = "hypar roof 10 m x 10 m, 0.5 kN/m2 snow on the found shape"
    model["loads"] = [{"type": "pressure", "elements": "roof", "value": 500.0,
                       "direction": [0, 0, -1], "per": "projected", "function": "ramp"}]
    model["functions"] = {"ramp": {"type": "ramp", "duration": 1.0}}
    model["analysis"]["time"] = {"end": 1.0, "step": 0.25}
    for wrinkling in (False, True):
        name = "snow-wrinkling" if wrinkling else "snow"
        for s in model["sections"]:
            if s["elements"] == "roof":
                if wrinkling:
                    s["wrinkling"] = True
                else:
                    s.pop("wrinkling", None)
        model["output"]["directory"] = name
        Path(out, name + ".yaml").write_text(yaml.safe_dump(model, sort_keys=False))


if __name__ == "__main__":
    main(*sys.argv[1:])
