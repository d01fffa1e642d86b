#!/usr/bin/env python3
"""Each process holds its piece of the model only (issue 18): examples that reach what a piece
must get right on 1 and 2 processes.

Usage: mpi_pieces.py VELUM EXAMPLES OUTDIR

- hypar-roof/hypar-form.yaml: form finding (every update sets up the piece's own elements on
  the new reference), cables on the edges, reactions over node sets;
- airbag-gas/model.yaml: a gas chamber (its volume summed over the pieces) with history of
  its pressure and volume;
- braided-sheet-small/model.yaml: a dynamic quad9 sheet pulled by an edge load (the mesh's
  boundary edges found while the mesh is whole: a piece's own boundary would also count the
  cut between the processes), stresses and fibre angles at points;
- a strip (below): a prescribed motion, a point mass on another process's node, a node in no
  element;
- a flat unstressed square: by plain Newton-Raphson the run fails naming the same unconstrained
  DOFs as on one process; with the line search it solves, as on one process.

Each runs once on one process without mpirun and once under `mpirun -np 2`, both with
`linear_solver: petsc`; every history column must agree within 1e-8 of its largest magnitude,
and the two-process frames must be pieces that together hold every cell once and every node,
with the one-process values (mpi_cases.frame_errors).
"""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mpi_cases import compare, frame_errors, fresh, history, run  # noqa: E402

EXAMPLES = ["hypar-roof/hypar-form.yaml", "airbag-gas/model.yaml",
            "braided-sheet-small/model.yaml"]


def strip():
    """A dynamic 12 x 2 quad4 strip held at its left end and pulled by a prescribed motion of
    its right end (eliminated equations on both processes' nodes), sagging under gravity,
    with a point mass on a node near the right end (the second process's elements; the
    first process holds its diagonal block) and a node no element holds (fixed by the
    reader; on the first process's frame piece only)."""
    nx, ny, h = 12, 2, 0.1
    nodes = [[1 + i + (nx + 1) * j, i * h, j * h, 0.0] for j in range(ny + 1) for i in range(nx + 1)]
    free = len(nodes) + 1
    nodes.append([free, 0.5, -0.5, 0.0])
    quads = [[1 + i + (nx + 1) * j, 2 + i + (nx + 1) * j, 2 + i + (nx + 1) * (j + 1),
              1 + i + (nx + 1) * (j + 1)] for j in range(ny) for i in range(nx)]
    left = [1 + (nx + 1) * j for j in range(ny + 1)]
    right = [1 + nx + (nx + 1) * j for j in range(ny + 1)]
    return f"""title: a strip pulled at one end, sagging, and a falling point mass beside it
mesh:
  nodes: {nodes}
  elements:
    - {{set: sheet, type: quad4, connectivity: {quads}}}
  node_sets:
    left: {left}
    right: {right}
materials:
  fabric: {{type: orthotropic, E1: 2.0e5, E2: 1.0e5, nu12: 0.3, G12: 3.0e4, density: 0.5}}
sections:
  - {{elements: sheet, material: fabric, thickness: 0.01, prestress: [100, 50, 0]}}
masses:
  - {{node: {nx + (nx + 1)}, mass: 0.2}}
boundary:
  - {{nodes: left, fix: [x, y, z]}}
  - {{nodes: right, displacement: [0.02, 0, 0], function: ramp}}
loads:
  - {{type: gravity, acceleration: [0, 0, -9.81], function: ramp}}
functions:
  ramp: {{type: ramp, duration: 0.02}}
analysis:
  type: dynamic
  integrator: {{scheme: generalized-alpha, rho_inf: 0.8}}
  time: {{end: 0.04, step: 4.0e-3, min_step: 1.0e-7, adaptive: true}}
  newton: {{tolerance: 1.0e-11, max_iterations: 30}}
  linear_solver: petsc
output:
  directory: out
  interval: 0.01
  fields: true
  history:
    - {{name: mid_uz, quantity: displacement, node: {1 + nx // 2 + (nx + 1)}, component: z}}
    - {{name: mass_uz, quantity: displacement, node: {nx + (nx + 1)}, component: z}}
    - {{name: free_uz, quantity: displacement, node: {free}, component: z}}
    - {{name: left_Rx, quantity: reaction, nodes: left, component: x}}
    - {{name: right_Rx, quantity: reaction, nodes: right, component: x}}
    - {{name: W_ext, quantity: external_work}}
    - {{name: E_kin, quantity: kinetic_energy}}
"""


# Principal directions: a unit vector whose sign is free (and which is any in-plane direction
# where the stress is isotropic, as after form finding): compared by direction_errors below,
# not entry by entry.
SIGN_FREE = ("stress_dir_max", "stress_dir_min")


def direction_errors(one, two):
    """The principal directions of the two-process frames against one process's, up to their
    sign, at every cell whose principal stresses differ by more than 1e-6 of the largest (where
    the directions are defined): within 1e-6."""
    import xml.etree.ElementTree as ET

    import meshio
    import numpy as np
    from mpi_cases import series
    errors = []
    for (t, ref_file), (_, file) in zip(series(one), series(two)):
        whole = meshio.read(os.path.join(one, ref_file))
        smax = np.concatenate(whole.cell_data["true_stress_max"])
        smin = np.concatenate(whole.cell_data["true_stress_min"])
        defined = np.nan_to_num(smax - smin) > 1e-6 * np.nanmax(np.abs(smax))
        pvtu = os.path.join(two, file)
        for piece in ET.parse(pvtu).getroot().iter("Piece"):
            p = meshio.read(os.path.join(os.path.dirname(pvtu), piece.get("Source")))
            at = np.concatenate(p.cell_data["cell_index"])
            for name in SIGN_FREE:
                ref = np.concatenate(whole.cell_data[name])[at]
                got = np.concatenate(p.cell_data[name])
                off = np.minimum(np.abs(got - ref).max(axis=1), np.abs(got + ref).max(axis=1))
                if (np.nan_to_num(off[defined[at]], nan=1.0) > 1e-6).any():
                    errors.append(f"t = {t}: {name} differs where the stress is not isotropic")
    return errors


def noise_floor(name, frame):
    """Round-off of a field that is nearly zero everywhere (the shear after an isotropic form
    finding: 2e-9 against stresses of 3e6) is judged against the frame's largest stress (or
    force per length) instead of its own largest value; an angle against one degree."""
    import numpy as np
    if "angle" in name:
        return 1.0
    for kind in ("stress", "force_per_length"):
        if kind in name:
            related = [np.nanmax(np.abs(np.concatenate(v))) for k, v in frame.cell_data.items()
                       if kind in k and k not in SIGN_FREE]
            return max(related, default=0.0)
    return 0.0


def flat(search=False):
    """A flat, unstressed square under pressure: its normal DOFs have no stiffness. By plain
    Newton-Raphson the run must fail naming the same first DOFs on two processes as on one
    (each process finds its own; the first process's message lists the first in the global
    numbering). With the line search (`search`) the first correction borrows a small tension's
    stiffness (summed over the processes' shares) and the run solves, alike on both."""
    n, h = 6, 0.1
    nodes = [[1 + i + (n + 1) * j, i * h, j * h, 0.0] for j in range(n + 1) for i in range(n + 1)]
    quads = [[1 + i + (n + 1) * j, 2 + i + (n + 1) * j, 2 + i + (n + 1) * (j + 1),
              1 + i + (n + 1) * (j + 1)] for j in range(n) for i in range(n)]
    edge = [p[0] for p in nodes if min(p[1], p[2]) < 1e-9 or max(p[1], p[2]) > n * h - 1e-9]
    # The lower rows' normal DOFs held too: most of the first process's owned equations are
    # then in the plane, and the first 8 without stiffness lie on both processes.
    low = [p[0] for p in nodes if p[0] not in edge and p[2] < 2.5 * h]
    return f"""title: a flat unstressed square under pressure (singular)
mesh:
  nodes: {nodes}
  elements:
    - {{set: sheet, type: quad4, connectivity: {quads}}}
  node_sets:
    edge: {edge}
    low: {low}
materials:
  fabric: {{type: isotropic, E: 1.0e5, nu: 0.3, density: 1.0}}
sections:
  - {{elements: sheet, material: fabric, thickness: 0.01}}
boundary:
  - {{nodes: edge, fix: [x, y, z]}}
  - {{nodes: low, fix: [z]}}
loads:
  - {{type: pressure, elements: sheet, value: 1.0}}
analysis:
  type: static
  time: {{end: 1.0, step: 1.0}}
  linear_solver: petsc
  newton: {{line_search: {"true" if search else "false"}}}
output:
  history:
    - {{name: uz, quantity: displacement, node: 25, component: z}}
"""


def singular_message(cmd, env):
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    found = re.search(r"\d+ unconstrained DOF\(s\)[^)]*\)", p.stderr)
    return p.returncode, found.group(0) if found else None


def with_petsc(text):
    """The model with analysis.linear_solver: petsc (replacing any solver it names)."""
    text = re.sub(r"(?m)^  linear_solver:.*\n", "", text)
    return re.sub(r"(?m)^analysis:\n", "analysis:\n  linear_solver: petsc\n", text, count=1)


def main():
    velum, examples, out = sys.argv[1], sys.argv[2], sys.argv[3]
    env = fresh(out)
    errors = []
    for example in EXAMPLES + ["strip"]:
        name = example.split("/")[0]
        if example == "strip":
            text = strip()
        else:
            with open(os.path.join(examples, example)) as f:
                text = with_petsc(f.read())
        if "linear_solver: petsc" not in text:
            sys.exit(f"FAIL: {example}: no analysis section to set the solver in")
        model = os.path.join(out, f"{name}.yaml")
        with open(model, "w") as f:
            f.write(text)
        one, two = os.path.join(out, f"{name}-1"), os.path.join(out, f"{name}-2")
        run([velum, "run", model, "-o", one, "-q", "--threads", "1"], env)
        run(["mpirun", "-np", "2", velum, "run", model, "-o", two, "-q", "--threads", "1"], env)
        errors += compare(history(os.path.join(one, "history.csv")),
                          history(os.path.join(two, "history.csv")), f"{name}, 2 processes")
        if os.path.isdir(os.path.join(one, "frames")):
            errors += [f"{name}: {e}" for e in frame_errors(one, two, 2, SIGN_FREE, noise_floor)]
            errors += [f"{name}: {e}" for e in direction_errors(one, two)]
    model = os.path.join(out, "flat.yaml")
    with open(model, "w") as f:
        f.write(flat())
    one = singular_message([velum, "run", model, "-o", os.path.join(out, "flat-1"), "--threads",
                            "1"], env)
    two = singular_message(["mpirun", "-np", "2", velum, "run", model, "-o",
                            os.path.join(out, "flat-2"), "--threads", "1"], env)
    if one[0] == 0 or two[0] == 0 or not one[1] or one[1] != two[1]:
        errors.append(f"flat square: one process {one}, two processes {two}: expected a failure "
                      "naming the same unconstrained DOFs")
    model = os.path.join(out, "flat-search.yaml")
    with open(model, "w") as f:
        f.write(flat(search=True))
    one, two = os.path.join(out, "flat-search-1"), os.path.join(out, "flat-search-2")
    run([velum, "run", model, "-o", one, "-q", "--threads", "1"], env)
    run(["mpirun", "-np", "2", velum, "run", model, "-o", two, "-q", "--threads", "1"], env)
    first = history(os.path.join(one, "history.csv"))
    second = history(os.path.join(two, "history.csv"))
    if not first[1][-1][1] > 1e-3:  # the centre lifted by the pressure
        errors.append(f"flat square with the line search: centre deflection {first[1]}")
    errors += compare(first, second, "flat square with the line search, 2 processes")
    if errors:
        sys.exit("FAIL:\n" + "\n".join(errors))
    print(f"ok: {len(EXAMPLES)} examples and the strip on 2 processes")


if __name__ == "__main__":
    main()
