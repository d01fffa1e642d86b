#!/usr/bin/python3
"""The processes exchange with their neighbours only (issue 46): a long strip on 4 processes.

Usage: mpi_neighbours.py VELUM OUTDIR

A 24 x 2 quad4 orthotropic prestressed strip held at both ends, its nodes numbered across the
strip first, so that the row rule cuts it into four bands along its length: process 0 and 3
each share nodes with one process, 1 and 2 with two, and no process with one it does not
touch (summary.json `processes.neighbours` must be [1, 2, 2, 1]). Each shared-node sum (the
reactions, the lumped masses, the frames' averaged fields) and each exchange of the cut's
equations goes from a process to those neighbours only, point to point. Two analyses, each on
one process (no mpirun) and on `mpirun -np 4`: a static one under a pressure and gravity
(every history column within 1e-8 of its largest) and an explicit central-difference one
(1e-9), with the same status and steps.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mpi_cases import compare, fresh, history, run  # noqa: E402

NX, NY, H = 24, 2, 0.1


def model(kind):
    # Node id 1 + j + (NY + 1) i: across the strip first.
    nid = lambda i, j: 1 + j + (NY + 1) * i  # noqa: E731
    nodes = [[nid(i, j), i * H, j * H, 0.0] for i in range(NX + 1) for j in range(NY + 1)]
    quads = [[nid(i, j), nid(i + 1, j), nid(i + 1, j + 1), nid(i, j + 1)]
             for i in range(NX) for j in range(NY)]
    ends = [nid(0, j) for j in range(NY + 1)] + [nid(NX, j) for j in range(NY + 1)]
    left = [nid(0, j) for j in range(NY + 1)]
    mid, quarter = nid(NX // 2, 1), nid(NX // 4, 0)
    explicit = kind == "explicit"
    analysis = ({"type": "dynamic", "integrator": {"scheme": "central-difference"},
                 "time": {"end": 0.02, "step": 1.0e-5}, "damping": {"mass": 20.0}}
                if explicit else
                {"type": "static", "time": {"end": 1.0, "step": 0.25},
                 "newton": {"tolerance": 1e-11, "max_iterations": 30}})
    analysis["linear_solver"] = "petsc"
    return {
        "title": f"a strip in four bands, {kind}",
        "mesh": {"nodes": nodes,
                 "elements": [{"set": "sheet", "type": "quad4", "connectivity": quads}],
                 "node_sets": {"ends": ends, "left": left}},
        "materials": {"fabric": {"type": "orthotropic", "E1": 2.0e5, "E2": 1.0e5, "nu12": 0.3,
                                 "G12": 3.0e4, "density": 0.5}},
        "sections": [{"elements": "sheet", "material": "fabric", "thickness": 0.01,
                      "prestress": [100, 50, 0], "axes": {"points": [1, 2, 4]}}],
        "boundary": [{"nodes": "ends", "fix": ["x", "y", "z"]}],
        "loads": [{"type": "pressure", "elements": "sheet", "value": 2.0, "function": "ramp"},
                  {"type": "gravity", "acceleration": [0, 0, -9.81], "function": "ramp"}],
        "functions": {"ramp": {"type": "ramp", "duration": 0.01 if explicit else 1.0}},
        "analysis": analysis,
        "output": {"directory": "out", "interval": 0.01 if explicit else 0.5, "fields": True,
                   "history": [
                       {"name": "mid_uz", "quantity": "displacement", "node": mid,
                        "component": "z"},
                       {"name": "q_ux", "quantity": "displacement", "node": quarter,
                        "component": "x"},
                       {"name": "left_Rx", "quantity": "reaction", "nodes": "left",
                        "component": "x"},
                       {"name": "left_Rz", "quantity": "reaction", "nodes": "left",
                        "component": "z"},
                       {"name": "E_strain", "quantity": "strain_energy"}]},
    }


def main():
    velum, out = sys.argv[1], sys.argv[2]
    env = fresh(out)
    errors = []
    for kind, tolerance in (("static", 1e-8), ("explicit", 1e-9)):
        d = os.path.join(out, kind)
        os.makedirs(d)
        path = os.path.join(d, "model.json")  # JSON is YAML
        with open(path, "w") as f:
            json.dump(model(kind), f)
        one, four = os.path.join(d, "one"), os.path.join(d, "np4")
        run([velum, "run", path, "-q", "-o", one], env)
        run(["mpirun", "-np", "4", velum, "run", path, "-q", "-o", four], env)
        errors += compare(history(os.path.join(one, "history.csv")),
                          history(os.path.join(four, "history.csv")), f"{kind} on 4", tolerance)
        s1 = json.load(open(os.path.join(one, "summary.json")))
        s4 = json.load(open(os.path.join(four, "summary.json")))
        if s1.get("status") != "converged" or s4.get("status") != s1.get("status") \
                or s4.get("steps") != s1.get("steps"):
            errors.append(f"{kind}: status {s4.get('status')} in {s4.get('steps')} steps on 4, "
                          f"{s1.get('status')} in {s1.get('steps')} on one")
        procs = s4.get("processes", {})
        if procs.get("neighbours") != [1, 2, 2, 1]:
            errors.append(f"{kind}: neighbours {procs.get('neighbours')} (elements "
                          f"{procs.get('elements')}), expected [1, 2, 2, 1]: four bands")
    if errors:
        sys.exit("FAIL:\n" + "\n".join(errors))
    print("a strip on 4 processes: neighbours only, the one-process results")


if __name__ == "__main__":
    main()
