#!/usr/bin/env python3
"""A sliding cable with friction on 2 processes (issue 44): the capstan over a fixed pulley
node (tests/cli/data/sliding/capstan.yaml) gives the one-process history within 1e-8, its `slip`
column included (the slip's interior node is a place in the chain, not a node index of the
piece).

Usage: mpi_sliding.py VELUM DATA OUTDIR
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mpi_cases import compare, fresh, history, run  # noqa: E402


def main():
    velum, data, out = sys.argv[1], sys.argv[2], sys.argv[3]
    env = fresh(out)
    text = open(os.path.join(data, "sliding", "capstan.yaml")).read()
    if "analysis: {type: static," not in text:
        sys.exit("FAIL: capstan.yaml: no analysis line to set the solver in")
    model = os.path.join(out, "capstan.yaml")
    with open(model, "w") as f:
        f.write(text.replace("analysis: {type: static,",
                             "analysis: {linear_solver: petsc, type: static,")
                .replace("  nodes: [[1,", "  nodes: [[11, 5, 0, 0], [12, 6, 0, 0], [1,", 1)
                .replace("connectivity: [[1, 2, 3]]}\n", "connectivity: [[1, 2, 3]]}\n"
                         "    - {set: guy, type: cable2, connectivity: [[11, 12]]}\n", 1)
                .replace("sections:\n", "sections:\n  - {elements: guy, material: rope, "
                         "area: 1.0e-4}\n", 1)
                .replace("boundary:\n", "boundary:\n  - {nodes: [11], fix: [x, y, z]}\n"
                         "  - {nodes: [12], fix: [y, z]}\n", 1)
                .replace("loads:\n", "loads:\n  - {type: point, nodes: [12], "
                         "force: [500.0, 0, 0], function: pull}\n", 1))
    one, two = os.path.join(out, "one"), os.path.join(out, "two")
    run([velum, "run", model, "-q", "-o", one], env)
    run(["mpirun", "-np", "2", velum, "run", model, "-q", "-o", two], env)
    ref = history(os.path.join(one, "history.csv"))
    if "s" not in ref[0] or max(abs(r[ref[0].index("s")]) for r in ref[1]) == 0:
        sys.exit("FAIL: the capstan's history has no slip that moves")
    errors = compare(ref, history(os.path.join(two, "history.csv")), "capstan, 2 processes")
    if errors:
        sys.exit("FAIL:\n" + "\n".join(errors))
    print("sliding cable with friction on 2 processes: the one-process history, slip included")
    # A checkpoint of the slips on 2 processes is refused on every process at once: refused on
    # the process holding the chain alone, it left the other in the checkpoint's collectives
    # for ever (a hang).
    with open(model) as f:
        saving = f.read().replace("output:\n", "output:\n  checkpoint: {interval: 0.5}\n", 1)
    model_cp = os.path.join(out, "capstan-checkpoint.yaml")
    with open(model_cp, "w") as f:
        f.write(saving)
    try:
        p = subprocess.run(["mpirun", "-np", "2", velum, "run", model_cp, "-q", "-o",
                            os.path.join(out, "checkpoint")], env=env, capture_output=True,
                           text=True, timeout=120)
    except subprocess.TimeoutExpired:
        sys.exit("FAIL: a checkpoint of the slips on 2 processes hangs")
    if p.returncode == 0 or "cannot yet be saved from a run on several processes" not in p.stderr:
        sys.exit(f"FAIL: a checkpoint of the slips on 2 processes: exit {p.returncode}, {p.stderr}")
    print("a checkpoint of the slips on 2 processes is refused (exit "
          f"{p.returncode}), not a hang")


if __name__ == "__main__":
    main()
