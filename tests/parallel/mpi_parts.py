#!/usr/bin/env python3
"""A model read in parts (issue 46, item 4; docs/parallel.md "Reading the mesh in parts"):
`velum partition MODEL -n 2 -o DIR`, then the model with `mesh: {parts: DIR}` on 2 processes,
each reading only its own part, gives the whole-read run's answers.

Usage: mpi_parts.py VELUM EXAMPLES OUTDIR

- the braided sheet (examples/braided-sheet-small: quad9, sheet axes through node ids, an edge
  load on the mesh's boundary, node sets), dynamic;
- the quarter membrane of mpi_cases.py (static: cables, a point mass on another process's
  node, two symmetry planes, a stress history at a point);
- the staged hypar roof of mpi_staged.py (form finding, prestress, snow, a gust cut short).

Each runs under `mpirun -np 2` twice, whole read (the model as it is) and part read; every
history column must agree within 1e-8 of its largest magnitude, summary.json must say the
same status and steps, and the part read's frames must be pieces with the one-process
frames' values (mpi_cases.frame_errors). Bad input: a node id that no part holds, a parts folder that is not there, the parts read on another
number of processes (3, and 1 without mpirun), `--restart` (not available in parts yet), `velum partition -n 1` and the split of a model
with start positions (mesh.reference_positions) each exit 1 with a message naming the model
file and the key.
"""
import json
import os
import re
import subprocess
import sys

import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mpi_cases import compare, frame_errors, fresh, history, model as quarter, run  # noqa: E402
from mpi_pieces import SIGN_FREE  # noqa: E402
from mpi_staged import floor_for, hypar  # noqa: E402


def with_petsc(d):
    d["analysis"]["linear_solver"] = "petsc"
    return d


def worst(ref, got):
    """The largest difference of a column over its largest magnitude."""
    (_, a), (_, b) = ref, got
    out = 0.0
    for c in range(1, len(a[0])):
        scale = max(abs(r[c]) for r in a) or 1.0
        out = max(out, max(abs(x[c] - y[c]) for x, y in zip(a, b)) / scale)
    return out


def write(path, d):
    with open(path, "w") as f:
        yaml.safe_dump(d, f, sort_keys=False)


def case(velum, name, d, out, env):
    """The whole read and the part read on 2 processes: their history's differences."""
    folder = os.path.join(out, name)
    os.makedirs(folder, exist_ok=True)
    whole = os.path.join(folder, "whole.yaml")
    write(whole, d)
    run([velum, "partition", whole, "-n", "2", "-o", os.path.join(folder, "parts")], env)
    parted = dict(d, mesh={"parts": "parts"})
    parts = os.path.join(folder, "parts.yaml")
    write(parts, parted)
    a, b = os.path.join(folder, "whole-2"), os.path.join(folder, "parts-2")
    run(["mpirun", "-np", "2", velum, "run", whole, "-q", "-o", a], env)
    run(["mpirun", "-np", "2", velum, "run", parts, "-q", "-o", b], env)
    ref, got = history(os.path.join(a, "history.csv")), history(os.path.join(b, "history.csv"))
    errors = compare(ref, got, f"{name}, part read against whole read on 2 processes")
    sa = json.load(open(os.path.join(a, "summary.json")))
    sb = json.load(open(os.path.join(b, "summary.json")))
    for key in ("status", "steps", "newton_iterations"):
        if sa.get(key) != sb.get(key):
            errors.append(f"{name}: summary {key}: whole read {sa.get(key)}, part read "
                          f"{sb.get(key)}")
    if sa.get("status") != "converged":
        errors.append(f"{name}: the whole read did not converge: {sa.get('reason')}")
    # The part read's frames: pieces with the one-process frames' values.
    one = os.path.join(folder, "whole-1")
    run([velum, "run", whole, "-q", "-o", one], env)
    if os.path.isdir(os.path.join(one, "frames")):
        errors += [f"{name}, part read: {e}" for e in frame_errors(one, b, 2, SIGN_FREE, floor_for(d))]
    if not errors:
        print(f"{name}: {len(ref[1])} rows, largest difference {worst(ref, got):.3g} of a "
              "column's largest value")
    return errors, parts


def refused(cmd, env, what, words):
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    if p.returncode != 1:
        return [f"{what}: exit {p.returncode}, expected 1\n{p.stderr}"]
    missing = [w for w in words if w not in p.stderr]
    return [f"{what}: the message does not name {missing}:\n{p.stderr}"] if missing else []


def main():
    velum, examples, out = sys.argv[1], sys.argv[2], sys.argv[3]
    env = fresh(out)
    errors = []
    with open(os.path.join(examples, "braided-sheet-small", "model.yaml")) as f:
        braided = with_petsc(yaml.safe_load(f))
    e, _ = case(velum, "braided", braided, out, env)
    errors += e
    e, parts = case(velum, "quarter", yaml.safe_load(quarter("static", "petsc")), out, env)
    errors += e
    e, _ = case(velum, "hypar", hypar(examples, out), out, env)
    errors += e

    # `velum check` on the parts: one report (the first process's), the model's totals, a line
    # per part whose own elements add up to them.
    p = subprocess.run(["mpirun", "-np", "2", velum, "check", parts], env=env,
                       capture_output=True, text=True, timeout=300)
    whole = subprocess.run([velum, "check", parts.replace("parts.yaml", "whole.yaml")], env=env,
                           capture_output=True, text=True, timeout=300).stdout
    own = [int(m) for m in re.findall(r"^part \d+: .*?, (\d+) own elements", p.stdout, re.M)]
    total = re.search(r"^elements: +(\d+)", whole, re.M)
    nodes = [re.search(r"^nodes: +(\d+)", t, re.M) for t in (p.stdout, whole)]
    if (p.returncode != 0 or p.stdout.count("check:") != 1 or len(own) != 2 or not total
            or sum(own) != int(total.group(1)) or not all(nodes)
            or nodes[0].group(1) != nodes[1].group(1)):
        errors.append(f"velum check on parts (exit {p.returncode}):\n{p.stdout}{p.stderr}")

    # Bad input.
    d = yaml.safe_load(open(parts))
    d["mesh"] = {"parts": "nowhere"}
    missing = os.path.join(out, "quarter", "missing.yaml")
    write(missing, d)
    errors += refused(["mpirun", "-np", "2", velum, "run", missing, "-q", "-o",
                       os.path.join(out, "missing-out")], env, "a parts folder that is not there",
                      [missing, "mesh.parts", "nowhere"])
    d = yaml.safe_load(open(parts))
    d["loads"].append({"type": "point", "nodes": [99999], "force": [0, 0, 1]})
    unknown = os.path.join(out, "quarter", "unknown.yaml")
    write(unknown, d)
    errors += refused(["mpirun", "-np", "2", velum, "run", unknown, "-q", "-o",
                       os.path.join(out, "unknown-out")], env, "a node id in no part",
                      [unknown, "loads[2].nodes", "undefined node 99999"])
    errors += refused(["mpirun", "-np", "2", velum, "run", parts, "-q", "--restart",
                       os.path.join(out, "quarter", "parts-2")], env,
                      "--restart of a model read in parts", [parts, "mesh.parts", "--restart"])
    errors += refused(["mpirun", "-np", "3", velum, "run", parts, "-q", "-o",
                       os.path.join(out, "three")], env, "2 parts on 3 processes",
                      [parts, "mesh.parts", "2 parts", "3 processes"])
    errors += refused([velum, "run", parts, "-q", "-o", os.path.join(out, "one")], env,
                      "2 parts on 1 process", [parts, "mesh.parts", "2 parts", "mpirun -np 2"])
    errors += refused([velum, "partition", os.path.join(out, "quarter", "whole.yaml"), "-n", "1",
                       "-o", os.path.join(out, "n1")], env, "velum partition -n 1", ["-n 1"])
    flat = os.path.join(examples, "airbag-flat-reference", "model.yaml")
    errors += refused([velum, "partition", flat, "-n", "2", "-o", os.path.join(out, "flat")], env,
                      "a split of start positions", [flat, "mesh.reference_positions"])
    if errors:
        sys.exit("FAIL:\n" + "\n".join(errors))
    print("parts on 2 processes: the whole read's answers")


if __name__ == "__main__":
    main()
