#!/usr/bin/env python3
"""Path following on two processes (issue 18): a shallow two-bar truss snapping through,
traced by arc length (cylindrical and Riks) and by displacement control, with
linear_solver: petsc, on one process and under mpirun -np 2. Its one free equation is owned by
the first process: the second holds no equation and no element, and must still take every
decision the first takes (the reductions over the equations). The histories must agree within
1e-8 of each column's largest value.

Usage: mpi_path.py VELUM OUTDIR
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mpi_cases  # noqa: E402

TRUSS = """title: shallow two-bar truss snapping through
mesh:
  nodes: [[1, -1, 0, 0], [2, 1, 0, 0], [3, 0, 0.2, 0]]
  elements:
    - {set: bars, type: cable2, connectivity: [[1, 3], [2, 3]]}
materials:
  svk: {type: cable, E: 1000.0, density: 1.0, compression: true}
sections:
  - {elements: bars, material: svk, area: 1.0}
boundary:
  - {nodes: [1, 2], fix: [x, y, z]}
  - {nodes: 3, fix: [x, z]}
loads:
  - {type: point, nodes: 3, force: [0, -1.0, 0], function: linear}
functions:
  linear: {type: table, points: [[-1000, -1000], [1000, 1000]]}
analysis:
  type: static
  linear_solver: petsc
  time: {end: END, step: STEP}
  path: PATH
output:
  directory: out
  fields: false
  history:
    - {name: v, quantity: displacement, node: 3, component: y}
    - {name: R, quantity: reaction, nodes: [1, 2], component: y}
"""

CASES = {
    "cylindrical": ("4.3549", "0.29", "{method: arc_length, constraint: cylindrical}"),
    "riks": ("4.3549", "0.29", "{method: arc_length, constraint: riks}"),
    "displacement": ("1.0", "0.05",
                     "{method: displacement, node: 3, component: y, displacement: -0.35}"),
}


def main():
    velum, out = sys.argv[1], sys.argv[2]
    env = mpi_cases.fresh(out)
    errors, rows = [], []
    for name, (end, step, path) in CASES.items():
        text = TRUSS.replace("END", end).replace("STEP", step).replace("PATH", path)
        model = os.path.join(out, f"{name}.yaml")
        with open(model, "w") as f:
            f.write(text)
        one, two = os.path.join(out, f"{name}-np1"), os.path.join(out, f"{name}-np2")
        mpi_cases.run([velum, "run", model, "-o", one, "-q", "--threads", "1"], env)
        mpi_cases.run(["mpirun", "-np", "2", "--oversubscribe", "--bind-to", "none", velum, "run",
                       model, "-o", two, "-q", "--threads", "1"], env)
        ref, got = (mpi_cases.history(os.path.join(d, "history.csv")) for d in (one, two))
        if len(ref[1]) < 5:
            errors.append(f"{name}: only {len(ref[1])} history rows on one process")
        errors += mpi_cases.compare(ref, got, f"{name}, 2 processes vs one")
        rows.append(f"{name} {len(ref[1])}")
    if errors:
        sys.exit("FAIL:\n" + "\n".join(errors))
    print(f"ok: path following on 2 processes (one without equations) agrees within 1e-8: "
          f"{', '.join(rows)} rows")


if __name__ == "__main__":
    main()
