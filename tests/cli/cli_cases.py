#!/usr/bin/python3
"""Table-driven command-line tests of velum: bad inputs (each validation rule, malformed YAML,
broken .msh files, an unwritable output folder) and a few good ones. Every case asserts the
exit status and a key phrase of the message; a crash (signal, sanitizer report) fails.

usage: cli_cases.py VELUM DATA_DIR WORK_DIR [CASE_NAME_SUBSTRING]
"""
import copy
import os
import shutil
import subprocess
import sys

import yaml

VELUM, DATA, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
ONLY = sys.argv[4] if len(sys.argv) > 4 else ""

# A valid base model: a 2x1 quad4 sheet with a cable along its top edge.
BASE = {
    "title": "cli base",
    "mesh": {
        "nodes": [[1, 0, 0, 0], [2, 1, 0, 0], [3, 2, 0, 0], [4, 0, 1, 0], [5, 1, 1, 0],
                  [6, 2, 1, 0]],
        "elements": [
            {"set": "sheet", "type": "quad4", "connectivity": [[1, 2, 5, 4], [2, 3, 6, 5]]},
            {"set": "lines", "type": "cable2", "connectivity": [[4, 5], [5, 6]]},
        ],
        "node_sets": {"left": [1, 4], "right": {"box": [1.9, -0.1, -0.1, 2.1, 1.1, 0.1]}},
    },
    "materials": {
        "iso": {"type": "isotropic", "E": 1000.0, "nu": 0.3, "density": 1.0},
        "line": {"type": "cable", "E": 1.0e4, "density": 0.5},
    },
    "sections": [
        {"elements": "sheet", "material": "iso", "thickness": 0.1},
        {"elements": "lines", "material": "line", "area": 0.01},
    ],
    "boundary": [{"nodes": "left", "fix": ["x", "y", "z"]}],
    "loads": [{"type": "edge", "nodes": "right", "force_per_length": [1.0, 0, 0],
               "function": "ramp1"}],
    "functions": {"ramp1": {"type": "ramp", "duration": 0.01}},
    "analysis": {"type": "dynamic", "integrator": {"scheme": "generalized-alpha", "rho_inf": 0.8},
                 "time": {"end": 0.02, "step": 0.005}},
    "output": {"interval": 0.01, "history": [
        {"name": "ux", "quantity": "displacement", "node": 6, "component": "x"}]},
}


def mutate(**changes):
    """A copy of BASE with dotted-path changes; value None deletes the key."""
    m = copy.deepcopy(BASE)
    for path, value in changes.items():
        keys = path.split("__")
        node = m
        for k in keys[:-1]:
            node = node[int(k)] if isinstance(node, list) else node[k]
        last = keys[-1]
        if isinstance(node, list):
            node[int(last)] = value
        elif value is None:
            del node[last]
        else:
            node[last] = value
    return yaml.safe_dump(m, sort_keys=False)


def with_mesh_file(msh, extra=""):
    return f"""mesh:
  file: {msh}
materials:
  iso: {{type: isotropic, E: 1000.0, nu: 0.3, density: 1.0}}
sections:
  - {{elements: sheet, material: iso, thickness: 0.1}}
boundary:
  - {{nodes: left, fix: [x, y, z]}}
  - {{nodes: sheet, fix: [z]}}
loads:
  - {{type: point, nodes: corner, force: [0.1, 0.1, 0]}}
analysis:
  type: static
  time: {{end: 1.0, step: 0.5}}
{extra}"""


def msh_truncated():
    text = open(os.path.join(DATA, "square_quad4_v22.msh")).read()
    return text[: len(text) // 2]


def msh_binary_truncated():
    data = open(os.path.join(DATA, "square_quad9_v41_binary.msh"), "rb").read()
    return data[: int(len(data) * 0.6)]


# (name, model text, extra files {name: text|bytes}, extra args, expected status, phrases)
CASES = [
    # ---- YAML itself ----
    ("yaml_syntax", "mesh: [1, 2\nmaterials: {", {}, [], 1, ["YAML syntax error", "model.yaml:"]),
    ("yaml_tab_indent", "mesh:\n\tnodes: []\n", {}, [], 1, ["YAML syntax error"]),
    ("root_not_mapping", "- 1\n- 2\n", {}, [], 1, ["must be a mapping"]),
    ("empty_file", "", {}, [], 1, ["must be a mapping"]),
    ("model_file_missing", None, {}, [], 1, ["cannot open the model file"]),
    # ---- unknown keys and types ----
    ("unknown_root_key", mutate(materails=1), {}, [], 1, ["materails: unknown key", "did you mean 'materials'"]),
    ("unknown_material_key", mutate(materials__iso__nuu=0.3), {}, [], 1, ["materials.iso.nuu", "did you mean 'nu'"]),
    ("unknown_time_key", mutate(analysis__time__ende=1), {}, [], 1, ["did you mean 'end'"]),
    ("unknown_section_key", mutate(sections__0__thicknes=0.1), {}, [], 1, ["did you mean 'thickness'"]),
    ("wrong_type_E", mutate(materials__iso__E="stiff"), {}, [], 1, ["materials.iso.E: expected a number"]),
    ("wrong_type_nodes", mutate(mesh__nodes="many"), {}, [], 1, ["mesh.nodes: expected a list"]),
    ("wrong_type_adaptive", mutate(analysis__time__adaptive="maybe"), {}, [], 1, ["expected true or false"]),
    ("wrong_type_materials", mutate(materials=[1, 2]), {}, [], 1, ["materials: expected a mapping"]),
    # ---- missing keys ----
    ("missing_mesh", mutate(mesh=None), {}, [], 1, ["mesh: required key is missing"]),
    ("missing_materials", mutate(materials=None), {}, [], 1, ["materials: required key is missing"]),
    ("missing_time", mutate(analysis__time=None), {}, [], 1, ["analysis.time: required key is missing"]),
    ("missing_thickness", mutate(sections__0__thickness=None), {}, [], 1, ["sections[0].thickness: required key is missing"]),
    ("missing_area", mutate(sections__1__area=None), {}, [], 1, ["sections[1].area: required key"]),
    ("missing_density", mutate(materials__iso__density=None), {}, [], 1, ["materials.iso.density: required key"]),
    # ---- materials ----
    ("poisson_half", mutate(materials__iso__nu=0.5), {}, [], 1, ["materials.iso.nu", "Poisson's ratio"]),
    ("negative_E", mutate(materials__iso__E=-5), {}, [], 1, ["must be positive"]),
    ("negative_density", mutate(materials__iso__density=-1), {}, [], 1, ["density must not be negative"]),
    ("ortho_not_admissible", mutate(materials__iso={"type": "orthotropic", "E1": 1, "E2": 100, "nu12": 3.0, "G12": 1, "density": 1}), {}, [], 1, ["materials.iso", "must be below E1/E2"]),
    ("aniso_eta_too_large", mutate(materials__iso={"type": "anisotropic", "E1": 1, "E2": 1, "nu12": 0.3, "G12": 0.4, "eta1": 3, "eta2": 3, "density": 1}), {}, [], 1, ["material 'iso'", "not admissible"]),
    ("matrix_unsymmetric", mutate(materials__iso={"type": "matrix", "Q": [[1, 0.3, 0], [0.1, 1, 0], [0, 0, 0.3]], "density": 1}), {}, [], 1, ["must be symmetric"]),
    ("matrix_indefinite", mutate(materials__iso={"type": "matrix", "Q": [[1, 2, 0], [2, 1, 0], [0, 0, 0.3]], "density": 1}), {}, [], 1, ["semi-definite"]),
    ("unknown_material_type", mutate(materials__iso__type="isotropik"), {}, [], 1, ["unknown material type", "did you mean 'isotropic'"]),
    ("fibers_empty", mutate(materials__iso={"type": "fibers", "fibers": [], "density": 1}), {}, [], 1, ["expected a list of {E, angle}"]),
    # ---- mesh ----
    ("duplicate_node_id", mutate(mesh__nodes=BASE["mesh"]["nodes"] + [[3, 5, 5, 0]]), {}, [], 1, ["duplicate node id 3"]),
    ("dangling_node", mutate(mesh__elements__0__connectivity=[[1, 2, 5, 4], [2, 3, 6, 99]]), {}, [], 1, ["undefined node 99"]),
    ("connectivity_length", mutate(mesh__elements__0__connectivity=[[1, 2, 5], [2, 3, 6, 5]]), {}, [], 1, ["needs 4 node ids"]),
    ("unknown_element_type", mutate(mesh__elements__0__type="quad5"), {}, [], 1, ["unknown element type 'quad5'"]),
    ("degenerate_quad", mutate(mesh__elements__0__connectivity=[[1, 2, 3, 2], [2, 3, 6, 5]]), {}, [], 1, ["degenerate or inverted"]),
    ("zero_length_cable", mutate(mesh__nodes=BASE["mesh"]["nodes"] + [[7, 2, 1, 0]], mesh__elements__1__connectivity=[[4, 5], [6, 7]]), {}, [], 1, ["zero length"]),
    ("box_empty", mutate(mesh__node_sets__right={"box": [5, 5, 5, 6, 6, 6]}), {}, [], 1, ["contains no node"]),
    ("box_inverted", mutate(mesh__node_sets__right={"box": [2, 2, 2, 1, 1, 1]}), {}, [], 1, ["maximum below its minimum"]),
    ("no_nodes_no_file", mutate(mesh={"node_sets": {}}), {}, [], 1, ["give a mesh file"]),
    # ---- sections ----
    ("undefined_element_set", mutate(sections__0__elements="shet"), {}, [], 1, ["undefined element set 'shet'", "did you mean 'sheet'"]),
    ("undefined_material", mutate(sections__0__material="isso"), {}, [], 1, ["undefined material 'isso'", "did you mean 'iso'"]),
    ("cable_law_on_membrane", mutate(sections__0__material="line"), {}, [], 1, ["is a cable law"]),
    ("membrane_law_on_cable", mutate(sections__1__material="iso"), {}, [], 1, ["is a membrane law"]),
    ("set_without_section", mutate(sections=[BASE["sections"][0]]), {}, [], 1, ["element set 'lines' has no section"]),
    ("section_twice", mutate(sections=BASE["sections"] + [BASE["sections"][0]]), {}, [], 1, ["already has a section"]),
    ("axes_collinear", mutate(sections__0__axes={"points": [1, 2, 3]}), {}, [], 1, ["do not define a plane"]),
    ("axes_undefined_node", mutate(sections__0__axes={"points": [1, 2, 77]}), {}, [], 1, ["undefined node 77"]),
    ("integration_unknown", mutate(sections__0__integration="lobatto"), {}, [], 1, ["sections[0].integration", "unknown integration 'lobatto' (gauss | nodal)"]),
    ("integration_nodal_tri6", mutate(mesh__nodes=BASE["mesh"]["nodes"] + [[7, 1, 0.5, 0], [8, 0, 0.5, 0]], mesh__elements__0={"set": "sheet", "type": "tri6", "connectivity": [[1, 3, 4, 2, 7, 8]]}, sections__0__integration="nodal"), {}, [], 1, ["nodal integration is available for tri3, quad4 and quad9, not tri6"]),
    # ---- boundary, loads, functions ----
    ("undefined_node_set", mutate(boundary__0__nodes="lefft"), {}, [], 1, ["undefined node set 'lefft'", "did you mean 'left'"]),
    ("bad_fix_component", mutate(boundary__0__fix=["x", "w"]), {}, [], 1, ["unknown component 'w'"]),
    ("fix_and_displacement", mutate(boundary__0__displacement=[0, 0, 0]), {}, [], 1, ["exactly one of fix, displacement or symmetry"]),
    ("symmetry_zero_normal", mutate(boundary=[{"nodes": "left", "fix": ["x", "y", "z"]}, {"nodes": 2, "symmetry": {"normal": [0, 0, 0]}}]), {}, [], 1, ["normal must not be zero"]),
    ("undefined_function", mutate(loads__0__function="ramp2"), {}, [], 1, ["undefined function 'ramp2'", "did you mean 'ramp1'"]),
    ("ramp_without_duration", mutate(functions__ramp1={"type": "ramp"}), {}, [], 1, ["functions.ramp1.duration: required key"]),
    ("table_not_increasing", mutate(functions__ramp1={"type": "table", "points": [[0, 0], [1, 1], [0.5, 2]]}), {}, [], 1, ["increase strictly"]),
    ("unknown_function_type", mutate(functions__ramp1={"type": "sine"}), {}, [], 1, ["unknown function type 'sine'"]),
    ("unknown_load_type", mutate(loads__0={"type": "presure", "elements": "sheet", "value": 1}), {}, [], 1, ["unknown load type 'presure'", "did you mean 'pressure'"]),
    ("pressure_on_cables", mutate(loads__0={"type": "pressure", "elements": "lines", "value": 1}), {}, [], 1, ["pressure acts on membranes"]),
    ("gas_open_surface", mutate(loads__0={"type": "gas", "elements": "sheet", "initial_pressure": 1.1e5, "ambient": 1e5}), {}, [], 1, ["loads[0].elements", "the surface is not closed"]),
    ("gas_on_cables", mutate(loads__0={"type": "gas", "elements": "lines", "initial_pressure": 1.1e5}), {}, [], 1, ["gas acts on membranes"]),
    ("gas_without_pressure", mutate(loads__0={"type": "gas", "elements": "sheet"}), {}, [], 1, ["initial_pressure"]),
    ("gas_undefined_amount", mutate(loads__0={"type": "gas", "elements": "sheet", "initial_pressure": 1.1e5, "amount": "fil"}), {}, [], 1, ["undefined function 'fil'"]),
    ("gas_history_without_gas", mutate(output__history=[{"name": "V", "quantity": "gas_volume", "load": 0}]), {}, [], 1, ["the model has no gas load"]),
    ("edge_load_no_edge", mutate(loads__0={"type": "edge", "nodes": [2, 5], "force_per_length": [1, 0, 0]}), {}, [], 1, ["no membrane boundary edge"]),
    ("point_load_bad_force", mutate(loads__0={"type": "point", "nodes": 6, "force": [1, 0]}), {}, [], 1, ["three numbers"]),
    ("mass_not_positive", mutate(masses=[{"node": 6, "mass": 0}]), {}, [], 1, ["the mass must be positive"]),
    # ---- analysis ----
    ("end_not_positive", mutate(analysis__time__end=0), {}, [], 1, ["analysis.time.end", "must be positive"]),
    ("step_not_positive", mutate(analysis__time__step=-0.1), {}, [], 1, ["analysis.time.step", "must be positive"]),
    ("min_step_above_step", mutate(analysis__time__min_step=0.1), {}, [], 1, ["min_step (0.1) is larger than step"]),
    ("step_longer_than_run", mutate(analysis__time__step=1.0), {}, [], 1, ["longer than the run"]),
    ("unknown_scheme", mutate(analysis__integrator__scheme="generalised-alpha"), {}, [], 1, ["did you mean 'generalized-alpha'"]),
    ("rho_inf_out_of_range", mutate(analysis__integrator__rho_inf=1.5), {}, [], 1, ["rho_inf must lie in [0, 1]"]),
    ("central_difference_static", mutate(analysis__type="static", analysis__integrator__scheme="central-difference"), {}, [], 1, ["needs type: dynamic"]),
    ("unknown_analysis_type", mutate(analysis__type="quasistatic"), {}, [], 1, ["unknown analysis type"]),
    ("petsc_not_built", mutate(analysis__linear_solver="petsc"), {}, [], 1, ["not available in this build"]),
    ("unknown_linear_solver", mutate(analysis__linear_solver="superlu"), {}, [], 1, ["unknown linear solver 'superlu'"]),
    ("misspelt_linear_solver", mutate(analysis__linear_solver="mumsp"), {}, [], 1, ["unknown linear solver 'mumsp'", "did you mean 'mumps'"]),
    ("newton_zero_iterations", mutate(analysis__newton={"max_iterations": 0}), {}, [], 1, ["at least one iteration"]),
    # ---- output ----
    ("line_search_not_boolean", mutate(analysis__newton={"tolerance": 1e-8, "line_search": "maybe"}), {}, [], 1, ["analysis.newton.line_search"]),
    ("history_unknown_quantity", mutate(output__history=[{"name": "a", "quantity": "displacment", "node": 6, "component": "x"}]), {}, [], 1, ["did you mean 'displacement'"]),
    ("history_point_outside", mutate(output__history=[{"name": "a", "quantity": "stress", "point": [5, 5, 0], "component": "s11"}]), {}, [], 1, ["lies in no membrane element"]),
    ("history_duplicate_name", mutate(output__history=[{"name": "a", "quantity": "kinetic_energy"}, {"name": "a", "quantity": "strain_energy"}]), {}, [], 1, ["duplicate history name 'a'"]),
    ("history_undefined_node", mutate(output__history=[{"name": "a", "quantity": "velocity", "node": 42, "component": "z"}]), {}, [], 1, ["undefined node 42"]),
    ("history_bad_unit", mutate(output__history=[{"name": "a", "quantity": "fiber_angle_change", "point": [0.5, 0.5, 0], "unit": "grad"}]), {}, [], 1, ["unknown unit 'grad'"]),
    ("history_bad_stress_component", mutate(output__history=[{"name": "a", "quantity": "stress", "point": [0.5, 0.5, 0], "component": "s33"}]), {}, [], 1, ["unknown stress component 's33'"]),
    ("interval_negative", mutate(output__interval=-1), {}, [], 1, ["output interval must be positive"]),
    # ---- several errors reported together, with lines ----
    ("several_errors", mutate(materials__iso__E="x", analysis__time__end=-1, sections__0__material="nope"), {}, [], 1, ["materials.iso.E", "analysis.time.end", "undefined material 'nope'", "3 errors"]),
    ("line_number", "title: t\nmesh:\n  nodes: [[1, 0, 0, 0]]\n  bogus: 1\n", {}, [], 1, ["model.yaml:4: mesh.bogus: unknown key"]),
    # ---- Gmsh files ----
    ("msh_missing", with_mesh_file("nothere.msh"), {}, [], 1, ["cannot open the mesh file"]),
    ("msh_truncated", with_mesh_file("trunc.msh"), {"trunc.msh": msh_truncated}, [], 1, ["mesh.file", "trunc.msh"]),
    ("msh_binary_truncated", with_mesh_file("truncb.msh"), {"truncb.msh": msh_binary_truncated}, [], 1, ["mesh.file", "cannot read the Gmsh file"]),
    ("msh_garbage", with_mesh_file("garbage.msh"), {"garbage.msh": lambda: bytes(range(256)) * 8}, [], 1, ["not a Gmsh mesh file"]),
    ("msh_garbage_after_header", with_mesh_file("g2.msh"), {"g2.msh": lambda: "$MeshFormat\n9.9 x y\n$EndMeshFormat\n$Nodes\nzz\n"}, [], 1, ["mesh.file", "g2.msh"]),
    ("msh_id_collision", with_mesh_file("SQ22").replace("  file: SQ22", "  file: SQ22\n  nodes: [[3, 9, 9, 9]]"), {}, [], 1, ["duplicate node id 3"]),
    # ---- output folder and command line ----
    ("unwritable_output", mutate(), {"afile": lambda: "x"}, ["-o", "{dir}/afile/out"], 3, ["cannot create the output directory"]),
    ("cli_missing_model", "", {}, ["--no-model"], 1, ["MODEL is required"]),
    ("cli_unknown_option", mutate(), {}, ["--frobnicate"], 1, ["frobnicate"]),
    # ---- a solve that fails: exit 2, summary says failed ----
    ("solve_fails", mutate(analysis__type="static", loads__0={"type": "pressure", "elements": "sheet", "value": 1.0}, sections=[BASE["sections"][0]], mesh__elements=[BASE["mesh"]["elements"][0]], analysis__time={"end": 1.0, "step": 0.5, "min_step": 0.1}, output__interval=0.5), {}, [], 2, ["the solve failed at t = ", "summary.json:failed"]),
    # ---- good inputs ----
    ("good_base_check", mutate(), {}, ["check"], 0, ["is valid", "units"]),
    ("good_base_run", mutate(), {}, [], 0, ["converged"]),
    ("good_msh22", with_mesh_file("SQ22"), {}, ["check"], 0, ["quad4 4", "is valid"]),
    ("good_msh41", with_mesh_file("SQ41"), {}, [], 0, ["converged"]),
    ("good_msh41_binary_quad9", with_mesh_file("SQ41B"), {}, [], 0, ["converged"]),
    ("good_symmetry", mutate(boundary=[{"nodes": "left", "fix": ["x", "y", "z"]}, {"nodes": [2, 3, 5, 6], "symmetry": {"normal": [0, 0, 1]}}]), {}, [], 0, ["converged"]),
]


def run_case(name, text, files, args, status, phrases):
    d = os.path.join(WORK, name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    model = os.path.join(d, "model.yaml")
    if text is not None:
        text = (text.replace("SQ22", os.path.join(DATA, "square_quad4_v22.msh"))
                    .replace("SQ41B", os.path.join(DATA, "square_quad9_v41_binary.msh"))
                    .replace("SQ41", os.path.join(DATA, "square_quad4_v41.msh")))
        with open(model, "w") as f:
            f.write(text)
    for fname, make in files.items():
        data = make()
        with open(os.path.join(d, fname), "wb" if isinstance(data, bytes) else "w") as f:
            f.write(data)
    args = [a.replace("{dir}", d) for a in args]
    if args and args[0] == "check":
        cmd = [VELUM, "check", model]
    elif args and args[0] == "--no-model":
        cmd = [VELUM, "run"]
    else:
        cmd = [VELUM, "run", model, "--threads", "1"] + args
        if "-o" not in args:
            cmd += ["-o", os.path.join(d, "out")]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    out = p.stdout + p.stderr
    problems = []
    if p.returncode < 0 or "Sanitizer" in out or "runtime error:" in out:
        problems.append(f"crashed (status {p.returncode})")
    elif p.returncode != status:
        problems.append(f"exit status {p.returncode}, expected {status}")
    for ph in phrases:
        if ph.startswith("summary.json:"):
            want = ph.split(":", 1)[1]
            try:
                import json
                s = json.load(open(os.path.join(d, "out", "summary.json")))
                if s.get("status") != want:
                    problems.append(f"summary.json status {s.get('status')}, expected {want}")
            except OSError as e:
                problems.append(f"no summary.json: {e}")
        elif ph not in out:
            problems.append(f"message lacks '{ph}'")
    return problems, out


def main():
    from concurrent.futures import ThreadPoolExecutor
    cases = [c for c in CASES if not ONLY or ONLY in c[0]]
    with ThreadPoolExecutor(max_workers=2) as pool:
        results = list(pool.map(lambda c: run_case(*c), cases))
    failed = 0
    n = len(cases)
    for case, (problems, out) in zip(cases, results):
        if problems:
            failed += 1
            print(f"FAIL {case[0]}: {'; '.join(problems)}\n---- output ----\n{out}----")
        else:
            print(f"ok   {case[0]}")
    bad = sum(1 for c in CASES if c[4] != 0 and (not ONLY or ONLY in c[0]))
    print(f"{n - failed}/{n} cases passed ({bad} bad-input cases)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
