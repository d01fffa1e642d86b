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
  cut between the processes), stresses and fibre angles at points.

Each runs once on one process without mpirun and once under `mpirun -np 2`, both with
`linear_solver: petsc`; every history column must agree within 1e-8 of its largest magnitude,
and the two-process frames must be pieces that together hold every cell once and every node,
with the one-process values (mpi_cases.frame_errors).
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mpi_cases import compare, frame_errors, fresh, history, run  # noqa: E402

EXAMPLES = ["hypar-roof/hypar-form.yaml", "airbag-gas/model.yaml",
            "braided-sheet-small/model.yaml"]


# Principal directions: a unit vector whose sign is free (and which is any in-plane direction
# where the stress is isotropic, as after form finding): round-off may flip it.
SIGN_FREE = ("stress_dir_max", "stress_dir_min")


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


def with_petsc(text):
    """The model with analysis.linear_solver: petsc (replacing any solver it names)."""
    text = re.sub(r"(?m)^  linear_solver:.*\n", "", text)
    return re.sub(r"(?m)^analysis:\n", "analysis:\n  linear_solver: petsc\n", text, count=1)


def main():
    velum, examples, out = sys.argv[1], sys.argv[2], sys.argv[3]
    env = fresh(out)
    errors = []
    for example in EXAMPLES:
        name = example.split("/")[0]
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
    if errors:
        sys.exit("FAIL:\n" + "\n".join(errors))
    print(f"ok: {len(EXAMPLES)} examples on 2 processes")


if __name__ == "__main__":
    main()
