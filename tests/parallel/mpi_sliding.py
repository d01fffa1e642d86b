#!/usr/bin/env python3
"""A sliding cable with friction on 2 processes (issue 44): the capstan over a fixed pulley
node (tests/cli/data/sliding/capstan.yaml) gives the one-process history within 1e-8, its `slip`
column included (the slip's interior node is a place in the chain, not a node index of the
piece); checkpointed at t = 1 and restarted on 2 processes, it goes on as the run never
stopped.

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
    # Checkpointed on 2 processes at t = 1 (the slip committed) and continued with --restart on 2: the history of the run never stopped,
    # through the sticking half (where only the committed slip holds the force). The slips are
    # saved in the one-process order (each chain from the process holding it); until
    # 2026-12-04 such a checkpoint was refused.
    with open(model) as f:
        saving = f.read().replace("output:\n", "output:\n  checkpoint: {interval: 0.5}\n", 1)
    if "end: 2.0" not in saving:
        sys.exit("FAIL: capstan.yaml: no end time 2.0 to stop at 1.0")
    whole_m, first_m = (os.path.join(out, f) for f in ("whole.yaml", "first.yaml"))
    with open(whole_m, "w") as f:
        f.write(saving)
    with open(first_m, "w") as f:
        f.write(saving.replace("end: 2.0", "end: 1.0"))
    mpirun = ["mpirun", "-np", "2", velum, "run"]
    whole, cont = os.path.join(out, "whole"), os.path.join(out, "restarted")
    run(mpirun + [whole_m, "-q", "-o", whole], env)
    run(mpirun + [first_m, "-q", "-o", cont], env)
    stopped = history(os.path.join(cont, "history.csv"))
    try:
        run(mpirun + [whole_m, "--restart", cont, "-q"], env)
    except subprocess.TimeoutExpired:
        sys.exit("FAIL: a restart of the slips on 2 processes hangs")
    got = history(os.path.join(cont, "history.csv"))
    errors = []
    if not len(stopped[1]) < len(got[1]) or got[1][-1][0] != 2.0:
        errors.append(f"the restart did not continue to t = 2 ({len(stopped[1])} rows before, "
                      f"{len(got[1])} after)")
    errors += compare(history(os.path.join(whole, "history.csv")), got,
                      "capstan, restarted vs uninterrupted, 2 processes")
    errors += compare(ref, got, "capstan, restarted on 2 processes vs one process")
    if errors:
        sys.exit("FAIL:\n" + "\n".join(errors))
    print(f"a checkpoint of the slips on 2 processes restarts: {len(got[1])} history rows "
          f"({len(stopped[1])} before the restart), the uninterrupted history")

if __name__ == "__main__":
    main()
