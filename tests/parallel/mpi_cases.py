#!/usr/bin/env python3
"""Runs on several MPI processes give the one-process history (issue 18).

Usage: mpi_cases.py VELUM OUTDIR CASE [NP ...]

CASE is static, dynamic or pressure: a quarter of a square membrane on two symmetry planes,
held at its outer edges, with a payload hung under its centre by three cables (one along the
axis, where both planes meet, and one in each plane). The payload's node is numbered just past
the middle, so that with two or three processes the equations of a cable's two ends, and of
nodes on the symmetry planes, fall on different processes. Each case runs once on one process
(no mpirun) with `linear_solver: auto`, once with `petsc`, then under `mpirun -np N` for each N;
every history column must agree with the one-process `petsc` and `auto` runs within 1e-8 of the
column's largest magnitude, and only one set of result files may appear. The frames: on one
process the one-process files; on N > 1, per frame a .pvtu naming N pieces whose cells are
every cell once, with the one-process frame's values within 1e-8 of each field's largest. Under mpirun each
process computes only its share of the elements: summary.json `processes.elements` must be the
partition predicted here (which puts a boundary through a cable and the symmetry planes).
"""
import csv
import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

N = 6  # quad4 per side


def model(case, solver, partition=None):
    h = 1.0 / N
    grid = [(i * h, j * h) for j in range(N + 1) for i in range(N + 1)]
    middle = len(grid) // 2 + 1
    nodes, ids = [], {}
    next_id = 1
    for k, (x, y) in enumerate(grid):
        if k == middle:  # the payload's node in the middle of the numbering
            nodes.append([next_id, 0.0, 0.0, -0.6])
            payload = next_id
            next_id += 1
        nodes.append([next_id, x, y, 0.0])
        ids[k] = next_id
        next_id += 1
    quads = []
    for j in range(N):
        for i in range(N):
            k = i + (N + 1) * j
            quads.append([ids[k], ids[k + 1], ids[k + N + 2], ids[k + N + 1]])
    centre = ids[0]
    rim_x = ids[N]  # (1, 0, 0): on the plane y = 0
    rim_y = ids[N * (N + 1)]  # (0, 1, 0): on the plane x = 0
    outer = [ids[k] for k, (x, y) in enumerate(grid) if x > 1 - 1e-9 or y > 1 - 1e-9]
    plane_x = [ids[k] for k, (x, y) in enumerate(grid) if x < 1e-9] + [payload]
    plane_y = [ids[k] for k, (x, y) in enumerate(grid) if y < 1e-9] + [payload]
    dynamic = case == "dynamic"
    pressure = 0.0 if case == "static" else (40.0 if dynamic else 60.0)
    loads = [
        "  - {type: gravity, acceleration: [0, 0, -9.81], function: ramp}",
        f"  - {{type: point, nodes: {ids[N + 2]}, force: [0, 0, -0.4], function: ramp}}",
    ]
    if pressure:
        loads.append(f"  - {{type: pressure, elements: sheet, value: {pressure}, function: ramp}}")
    if dynamic:
        analysis = """  type: dynamic
  integrator: {scheme: generalized-alpha, rho_inf: 0.8}
  time: {end: 0.04, step: 4.0e-3, min_step: 1.0e-7, adaptive: true}
  damping: {mass: 5.0}"""
        drag = ", drag: {rho: 1.2, cd_area: 0.5}"
    else:
        analysis = """  type: static
  time: {end: 1.0, step: 0.25, min_step: 1.0e-4, adaptive: true}"""
        drag = ""
    # analysis.petsc_options through the command line: PORD ordering in the dynamic case.
    options = '\n  petsc_options: "-mat_mumps_icntl_7 4"' if dynamic and solver == "petsc" else ""
    if partition:
        options += f"\n  partition: {partition}"
    return f"""title: quarter membrane on two symmetry planes with a payload on three cables ({case})
mesh:
  nodes: {json.dumps(nodes)}
  elements:
    - {{set: sheet, type: quad4, connectivity: {json.dumps(quads)}}}
    - {{set: lines, type: cable2, connectivity: [[{centre}, {payload}], [{payload}, {rim_x}], [{payload}, {rim_y}]]}}
  node_sets:
    outer: {json.dumps(outer)}
    plane_x: {json.dumps(plane_x)}
    plane_y: {json.dumps(plane_y)}
materials:
  fabric: {{type: orthotropic, E1: 2.0e5, E2: 1.2e5, nu12: 0.3, G12: 4.0e4, density: 0.5}}
  line: {{type: cable, E: 5.0e6, density: 2.0, compression: false}}
sections:
  - {{elements: sheet, material: fabric, thickness: 0.01, prestress: [200, 200, 0]}}
  - {{elements: lines, material: line, area: 1.0e-4}}
masses:
  - {{node: {payload}, mass: 0.3{drag}}}
boundary:
  - {{nodes: outer, fix: [x, y, z]}}
  - {{nodes: plane_x, symmetry: {{normal: [1, 0, 0]}}}}
  - {{nodes: plane_y, symmetry: {{normal: [0, 1, 0]}}}}
loads:
{chr(10).join(loads)}
functions:
  ramp: {{type: ramp, duration: {0.02 if dynamic else 1.0}}}
analysis:
{analysis}
  newton: {{tolerance: 1.0e-11, max_iterations: 30}}
  linear_solver: {solver}{options}
output:
  directory: out
  interval: {0.01 if dynamic else 0.25}
  fields: true
  history:
    - {{name: centre_uz, quantity: displacement, node: {centre}, component: z}}
    - {{name: payload_uz, quantity: displacement, node: {payload}, component: z}}
    - {{name: rim_Rz, quantity: reaction, nodes: outer, component: z}}
    - {{name: plane_Rx, quantity: reaction, nodes: plane_x, component: x}}
    - {{name: smax, quantity: stress, point: [0.4, 0.3, 0.0], component: max_principal}}
    - {{name: E_strain, quantity: strain_energy}}
    - {{name: W_ext, quantity: external_work}}
    - {{name: E_kin, quantity: kinetic_energy}}
"""


def partition(case, n):
    """The element partition velum uses on n processes (src/assembly/assembler.cpp): an element
    belongs to the process owning the row of its lowest equation, rows split in n contiguous
    even ranges; equations in node order (symmetry nodes have two, fixed nodes none). Returns
    the owner of each element (sheet, then lines), the cable and quad connectivities and the
    symmetry-plane nodes; the nodes come from the model text."""
    text = model(case, "petsc")
    import re
    nodes = json.loads(re.search(r"nodes: (\[\[.*?\]\])\n", text).group(1))
    outer = set(json.loads(re.search(r"outer: (\[.*?\])\n", text).group(1)))
    px = set(json.loads(re.search(r"plane_x: (\[.*?\])\n", text).group(1)))
    py = set(json.loads(re.search(r"plane_y: (\[.*?\])\n", text).group(1)))
    first, count = {}, 0
    for nid, *_ in nodes:
        if nid not in outer:
            first[nid] = count
        count += 0 if nid in outer else 3 - (nid in px) - (nid in py)
    base, extra = divmod(count, n)
    starts = [r * base + min(r, extra) for r in range(n)]

    def owner(elem):
        lowest = min(first[v] for v in elem if v in first)
        return max(r for r in range(n) if starts[r] <= lowest)

    quads = json.loads(re.search(r"set: sheet, type: quad4, connectivity: (\[\[.*?\]\])",
                                 text).group(1))
    cables = json.loads(re.search(r"set: lines, type: cable2, connectivity: (\[\[.*?\]\])",
                                  text).group(1))
    return [owner(e) for e in quads + cables], quads, cables, px | py


def partition_errors(case, n):
    """The partition must put a boundary through a cable (elements meeting at one of its
    nodes computed by different processes) and through the symmetry planes (their nodes in
    elements of several processes)."""
    own, quads, cables, planes = partition(case, n)
    elems = quads + cables
    errors = []
    cut = [c for k, c in enumerate(cables)
           if any(own[j] != own[len(quads) + k] for j, e in enumerate(elems) if set(e) & set(c))]
    if not cut:
        errors.append(f"{n} processes: no partition boundary through a cable")
    on_planes = {own[j] for j, e in enumerate(elems) if set(e) & planes}
    if len(on_planes) < 2:
        errors.append(f"{n} processes: the symmetry planes lie on processes {sorted(on_planes)}")
    return errors, [own.count(r) for r in range(n)]


def series(folder):
    root = ET.parse(os.path.join(folder, "results.pvd")).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def frame_errors(one, d, n, skip=(), floor=None):
    """Frames on n processes: one process's files (n = 1), or per frame a .pvtu naming n
    pieces frames/frame_NNNNN/frame_NNNNN_K.vtu that together hold every cell once and every
    node, with the one-process frame's values (within 1e-8 of each field's largest value, or
    of floor(name, frame) when larger; fields named in `skip` are not compared)."""
    import meshio
    import numpy as np
    errors = []
    ref, got = series(one), series(d)
    if [t for t, _ in ref] != [t for t, _ in got]:
        return [f"{n} processes: results.pvd times {got}, one process {ref}"]
    expected = sorted(os.listdir(os.path.join(one, "frames")))
    if n > 1:
        expected = sorted(f"{os.path.splitext(f)[0]}{x}" for f in expected for x in (".pvtu", ""))
    if sorted(os.listdir(os.path.join(d, "frames"))) != expected:
        errors.append(f"{n} processes: frames/ holds {sorted(os.listdir(os.path.join(d, 'frames')))}"
                      f", expected {expected}")
    for (t, ref_file), (_, file) in zip(ref, got):
        whole = meshio.read(os.path.join(one, ref_file))
        if n == 1:
            if file != ref_file:
                errors.append(f"1 process: results.pvd names {file}, one process {ref_file}")
            continue
        stem = os.path.splitext(os.path.basename(ref_file))[0]
        if file != f"frames/{stem}.pvtu":
            errors.append(f"{n} processes: results.pvd names {file}")
            continue
        pvtu = os.path.join(d, file)
        sources = [p.get("Source") for p in ET.parse(pvtu).getroot().iter("Piece")]
        if sources != [f"{stem}/{stem}_{k}.vtu" for k in range(n)]:
            errors.append(f"{n} processes: {file} names the pieces {sources}")
            continue
        pieces = [meshio.read(os.path.join(os.path.dirname(pvtu), s)) for s in sources]
        cells = np.concatenate([np.concatenate(p.cell_data["cell_index"]) for p in pieces])
        ncells = sum(len(b.data) for b in whole.cells)
        if sorted(cells.tolist()) != list(range(ncells)):
            errors.append(f"{n} processes, t = {t}: the pieces hold cells {sorted(cells)}, "
                          f"expected each of {ncells} once")
            continue
        if min(len(p.cell_data["cell_index"][0]) for p in pieces) == 0:
            errors.append(f"{n} processes, t = {t}: a piece holds no cell")
        nodes = np.concatenate([p.point_data["node_index"] for p in pieces])
        if set(nodes.tolist()) != set(range(len(whole.points))):
            errors.append(f"{n} processes, t = {t}: the pieces do not hold every node")
        whole_conn = [c for b in whole.cells for c in b.data]
        for name, ref_blocks in whole.cell_data.items():
            if name in skip:
                continue
            ref_values = np.concatenate(ref_blocks)
            scale = np.nanmax(np.abs(ref_values)) if np.isfinite(ref_values).any() else 0
            scale = max(scale, floor(name, whole) if floor else 0)
            for p in pieces:
                at = np.concatenate(p.cell_data["cell_index"])
                values = np.concatenate(p.cell_data[name])
                same_nan = (np.isnan(values) == np.isnan(ref_values[at])).all()
                diff = np.nan_to_num(np.abs(values - ref_values[at]))
                if not same_nan or diff.max(initial=0) > 1e-8 * max(scale, 1e-300):
                    errors.append(f"{n} processes, t = {t}: cell field {name} differs")
                    break
        for name, ref_values in list(whole.point_data.items()) + [("Points", whole.points)]:
            if name in skip:
                continue
            scale = np.nanmax(np.abs(ref_values)) if np.isfinite(ref_values).any() else 0
            scale = max(scale, floor(name, whole) if floor else 0)
            for p in pieces:
                values = p.points if name == "Points" else p.point_data[name]
                at = p.point_data["node_index"]
                same_nan = (np.isnan(values) == np.isnan(ref_values[at])).all()
                diff = np.nan_to_num(np.abs(values - ref_values[at]))
                if not same_nan or diff.max(initial=0) > 1e-8 * max(scale, 1e-300):
                    errors.append(f"{n} processes, t = {t}: point field {name} differs")
                    break
        for p in pieces:  # each cell's nodes, as the one-process frame's
            at = np.concatenate(p.cell_data["cell_index"])
            conn = [p.point_data["node_index"][c] for b in p.cells for c in b.data]
            if any(list(c) != list(whole_conn[k]) for c, k in zip(conn, at)):
                errors.append(f"{n} processes, t = {t}: a piece's connectivity differs")
                break
    return errors


def history(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(v) for v in r] for r in rows[1:]]


def compare(ref, got, what, tolerance=1e-8):
    head_r, rows_r = ref
    head_g, rows_g = got
    if head_r != head_g or len(rows_r) != len(rows_g):
        return [f"{what}: columns or rows differ ({len(rows_r)} vs {len(rows_g)} rows)"]
    errors = []
    for c, name in enumerate(head_r):
        scale = max(abs(r[c]) for r in rows_r)
        worst = max(abs(a[c] - b[c]) for a, b in zip(rows_r, rows_g))
        if worst > tolerance * max(scale, 1e-300):
            errors.append(f"{what}: column {name} differs by {worst:.3g} (largest {scale:.3g})")
    return errors


def run(cmd, env):
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    if p.returncode != 0:
        sys.exit(f"FAIL: {' '.join(cmd)} exited {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p


def fresh(out):
    """An empty output folder `out` and the environment of a test's runs: one thread each,
    mpirun allowed as root and on more processes than cores."""
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    return dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
                OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")


def main():
    velum, out, case = sys.argv[1], sys.argv[2], sys.argv[3]
    counts = [int(n) for n in sys.argv[4:]] or [2, 3]
    env = fresh(out)
    for solver in ("auto", "petsc"):
        with open(os.path.join(out, f"{solver}.yaml"), "w") as f:
            f.write(model(case, solver))
    refs = {}
    for solver in ("auto", "petsc"):
        d = os.path.join(out, f"one-{solver}")
        run([velum, "run", os.path.join(out, f"{solver}.yaml"), "-o", d, "-q", "--threads", "1"],
            env)
        refs[solver] = history(os.path.join(d, "history.csv"))
    errors = compare(refs["auto"], refs["petsc"], "petsc vs auto, one process")
    expected = {}
    for n in counts:
        if n < 2:
            continue
        found, expected[n] = partition_errors(case, n)
        errors += found
    for n in counts:
        d = os.path.join(out, f"np{n}")
        p = run(["mpirun", "-np", str(n), "--oversubscribe", "--bind-to", "none", velum, "run",
                 os.path.join(out, "petsc.yaml"), "-o", d, "--threads", "1"], env)
        got = history(os.path.join(d, "history.csv"))
        for solver, ref in refs.items():
            errors += compare(ref, got, f"{n} processes vs one ({solver})")
        summary = json.load(open(os.path.join(d, "summary.json")))
        if summary.get("status") != "converged":
            errors.append(f"{n} processes: summary status {summary.get('status')}")
        # Each process computed only its share of the elements: the predicted partition.
        if n > 1:
            share = [int(e) for e in summary.get("processes", {}).get("elements", [])]
            if share != expected[n] or sum(share) != summary["elements"] or max(share) >= sum(
                    share):
                errors.append(f"{n} processes: elements per process {share}, expected "
                              f"{expected[n]} of {summary['elements']}")
            if f"{n} processes compute" not in p.stderr:
                errors.append(f"{n} processes: the console should give the partition")
        if p.stderr.count("velum: converged") != 1:
            errors.append(f"{n} processes: the console should hear one process, got:\n{p.stderr}")
        one = os.path.join(out, "one-petsc")
        mine, theirs = sorted(os.listdir(d)), sorted(os.listdir(one))
        if mine != theirs:
            errors.append(f"{n} processes: the folder holds {mine}, one process wrote {theirs}")
        errors += frame_errors(one, d, n)
    if case == "static":  # PT-Scotch's partition of the element graph (analysis.partition)
        with open(os.path.join(out, "scotch.yaml"), "w") as f:
            f.write(model(case, "petsc", "scotch"))
        d = os.path.join(out, "np2-scotch")
        p = run(["mpirun", "-np", "2", "--oversubscribe", "--bind-to", "none", velum, "run",
                 os.path.join(out, "scotch.yaml"), "-o", d, "--threads", "1"], env)
        got = history(os.path.join(d, "history.csv"))
        for solver, ref in refs.items():
            errors += compare(ref, got, f"2 processes, scotch, vs one ({solver})")
        procs = json.load(open(os.path.join(d, "summary.json"))).get("processes", {})
        share = procs.get("elements", [])
        if procs.get("partition") != "scotch" or "scotch partition" not in p.stderr:
            errors.append(f"scotch: partition {procs.get('partition')}, console:\n{p.stderr}")
        if len(share) != 2 or min(share) == 0 or sum(share) != len(partition(case, 2)[0]):
            errors.append(f"scotch: elements per process {share}")
        if not procs.get("shared_nodes", 0) > 0:
            errors.append(f"scotch: shared nodes {procs.get('shared_nodes')}")
        errors += frame_errors(os.path.join(out, "one-petsc"), d, 2)
    if errors:
        sys.exit("FAIL:\n" + "\n".join(errors))
    rows = len(refs["petsc"][1])
    print(f"ok: {case}: {rows} history rows, {len(refs['petsc'][0])} columns agree on "
          f"1 (auto, petsc) and {', '.join(map(str, counts))} processes within 1e-8")


if __name__ == "__main__":
    main()
