#!/usr/bin/python3
"""Runs an example through velum and reads the results back with meshio: the PVD series, the
array names and sizes of every frame, and values checked against history.csv and
summary.json.

usage: readback.py VELUM MODEL.yaml WORK_DIR
"""
import csv
import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np

VELUM, MODEL, WORK = sys.argv[1:4]
shutil.rmtree(WORK, ignore_errors=True)
p = subprocess.run([VELUM, "run", MODEL, "-o", WORK, "--threads", "1", "--quiet"],
                   capture_output=True, text=True)
assert p.returncode == 0, f"velum failed ({p.returncode}):\n{p.stdout}{p.stderr}"

summary = json.load(open(os.path.join(WORK, "summary.json")))
for key in ["status", "steps", "newton_iterations", "factorizations", "wall_seconds",
            "final_time", "dofs", "elements", "energy"]:
    assert key in summary, f"summary.json lacks {key}"
assert summary["status"] == "converged"
for key in ["kinetic", "strain", "external_work", "damping"]:
    assert key in summary["energy"], f"summary.json energy lacks {key}"

# steps.csv: one row per accepted step; its iterations and factorisations add up to
# summary.json's, a step factorises at most once per iteration, and each row's residual list
# has one norm per iteration plus the converged one.
steps = list(csv.DictReader(open(os.path.join(WORK, "steps.csv"))))
assert len(steps) == summary["steps"], f"{len(steps)} rows in steps.csv, {summary['steps']} steps"
assert sum(int(r["iterations"]) for r in steps) == summary["newton_iterations"]
assert sum(int(r["factorizations"]) for r in steps) == summary["factorizations"]
for r in steps:
    assert 0 <= int(r["factorizations"]) <= int(r["iterations"]) + 1, r  # +1: inertia confirmed
    res = [float(v) for v in r["residuals"].split()]
    assert len(res) >= int(r["iterations"]) + 1 or int(r["iterations"]) == 0, r
    assert all(np.isfinite(res)), r
assert abs(float(steps[-1]["time"]) - summary["final_time"]) <= 1e-9 * (1 + summary["final_time"])

rows = list(csv.reader(open(os.path.join(WORK, "history.csv"))))
header, rows = rows[0], [[float(v) for v in r] for r in rows[1:]]
assert header[0] == "time", header
col = {name: i for i, name in enumerate(header)}

root = ET.parse(os.path.join(WORK, "results.pvd")).getroot()
datasets = root.findall("./Collection/DataSet")
assert len(datasets) == len(rows), f"{len(datasets)} frames but {len(rows)} history rows"
times = [float(d.get("timestep")) for d in datasets]
assert np.allclose(times, [r[0] for r in rows]), "frame times differ from history times"
assert abs(times[-1] - summary["final_time"]) < 1e-9 * max(1, abs(times[-1]))

point_arrays = {"displacement": 3, "velocity": 3}
cell_arrays = {"true_stress_max": 1, "true_stress_min": 1, "stress_dir_max": 3,
               "stress_dir_min": 3, "fiber_angle_change": 1, "force": 1}
for k, d in enumerate(datasets):
    mesh = meshio.read(os.path.join(WORK, d.get("file")))
    n_cells = sum(len(c.data) for c in mesh.cells)
    assert n_cells == summary["elements"], (n_cells, summary["elements"])
    for name, comps in point_arrays.items():
        a = mesh.point_data[name]
        assert a.shape == (len(mesh.points), comps), (name, a.shape)
        assert np.all(np.isfinite(a))
    for name, comps in cell_arrays.items():
        blocks = mesh.cell_data[name]
        total = sum(len(b) for b in blocks)
        assert total == n_cells, (name, total)
        for cells, b in zip(mesh.cells, blocks):
            assert (b.shape[1] if b.ndim == 2 else 1) == comps, (name, b.shape)
            # A field that does not apply to the cell type is NaN there (absent in ParaView).
            applies = (name == "force") == cells.type.startswith("line")
            assert np.all(np.isfinite(b)) if applies else np.all(np.isnan(b)), (name, cells.type)
    smax = np.concatenate(mesh.cell_data["true_stress_max"])
    smin = np.concatenate(mesh.cell_data["true_stress_min"])
    smax, smin = smax[np.isfinite(smax)], smin[np.isfinite(smin)]
    assert np.all(smax >= smin - 1e-9 * (1 + np.abs(smax))), "max principal below min"
    # Values against history.csv (columns by the example's names, where present).
    U, V = mesh.point_data["displacement"], mesh.point_data["velocity"]
    for name, arr in [("centre_uz", U), ("centre_vz", V)]:
        if name in col:
            # the history node: find it by matching the value at this frame
            val = rows[k][col[name]]
            assert np.min(np.abs(arr[:, 2] - val)) <= 1e-9 * (1 + abs(val)), (name, val)
    if k == len(datasets) - 1:
        dirs = np.concatenate(mesh.cell_data["stress_dir_max"])
        norms = np.linalg.norm(dirs[np.all(np.isfinite(dirs), axis=1)], axis=1)
        assert np.all((np.abs(norms - 1) < 1e-6) | (norms == 0)), "stress_dir_max not unit"
        if "centre_uz" in col:
            assert abs(U[:, 2]).max() > 0, "no deflection at the end"
        if "E_kin" in col:
            assert abs(rows[-1][col["E_kin"]] - summary["energy"]["kinetic"]) <= 1e-8 * (1 + abs(summary["energy"]["kinetic"]))
        if "W_ext" in col:
            assert abs(rows[-1][col["W_ext"]] - summary["energy"]["external_work"]) <= 1e-8 * (1 + abs(summary["energy"]["external_work"]))
print(f"read back {len(datasets)} frames of {summary['elements']} elements; "
      f"{len(header) - 1} history columns; final time {summary['final_time']}")
