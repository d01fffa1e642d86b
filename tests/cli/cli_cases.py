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
# A build with PETSc (issue 18) links it: `linear_solver: petsc` is then valid.
# `velum` itself starts without PETSc and hands such runs to velum-mpi beside it.
_with_petsc = os.path.join(os.path.dirname(VELUM), "velum-mpi")
HAVE_PETSC = b"libpetsc" in subprocess.run(["ldd", _with_petsc if os.path.exists(_with_petsc) else VELUM],
                                           capture_output=True).stdout
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


def msh_text(name="square_quad4_v22.msh"):
    return open(os.path.join(DATA, name)).read()


def msh_edit(old, new, name="square_quad4_v22.msh"):
    """A copy of a test mesh with one text replacement (which must apply)."""
    def make():
        text = msh_text(name)
        assert old in text, old
        return text.replace(old, new, 1)
    return make


def dup_line(after, extra):
    """The base model with `extra` inserted after the line `after` (a duplicate key)."""
    text = mutate()
    assert after in text, after
    return text.replace(after, after + extra, 1)


def billion_laughs():
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    for i in range(1, 10):
        lines.append(f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]")
    return "\n".join(lines) + "\n" + mutate()


def hist(name):
    return mutate(output__history=[{"name": name, "quantity": "kinetic_energy"}])


def fix_all(*entries):
    return mutate(boundary=list(entries), loads=[], functions=None)


SEVEN = [[1, 0, 0, 0], [2, 1, 0, 0], [3, 2, 0, 0], [4, 0, 1, 0], [5, 1, 1, 0], [6, 2, 1, 0]]
LONG = "x" * 1_000_000



# A 2x2 quad4 square as an Abaqus/CalculiX deck (mesh.file: m.inp; docs/inp-import.md).
INP_SQUARE = """** 2x2 square
*NODE, NSET=ALL
1, 0., 0., 0.
2, 0.5, 0., 0.
3, 1., 0., 0.
4, 0., 0.5, 0.
5, 0.5, 0.5, 0.
6, 1., 0.5, 0.
7, 0., 1., 0.
8, 0.5, 1., 0.
9, 1., 1., 0.
*ELEMENT, TYPE=M3D4, ELSET=sheet
1, 1, 2, 5, 4
2, 2, 3, 6, 5
3, 4, 5, 8, 7
4, 5, 6, 9, 8
*NSET, NSET=left
1, 4, 7
*NSET, NSET=corner
9
*MATERIAL, NAME=M
"""


def inp_edit(old, new):
    """The square deck with one text replacement (which must apply)."""
    def make():
        assert old in INP_SQUARE, old
        return INP_SQUARE.replace(old, new, 1)
    return make


# (name, model text, extra files {name: text|bytes}, extra args, expected status, phrases)

# Staged models (`steps:`, docs/model-format.md "Analysis steps"): the base model, static, with
# its analysis moved into the steps.
STATIC_STEP = {"type": "static", "time": {"end": 1.0, "step": 0.5}}
STAGED_BOUNDARY = [{"nodes": "left", "fix": ["x", "y", "z"]}, {"nodes": [2, 3, 5, 6], "fix": ["z"]}]


def staged(steps, **changes):
    changes.setdefault("analysis", None)
    changes.setdefault("functions", None)
    changes.setdefault("loads__0__function", None)
    changes.setdefault("output__interval", None)
    changes.setdefault("boundary", STAGED_BOUNDARY)
    m = yaml.safe_load(mutate(**changes))
    m["steps"] = steps
    return yaml.safe_dump(m, sort_keys=False)


def line_of(text, needle, nth=1):
    """1-based line of the nth line of `text` holding `needle`."""
    seen = 0
    for i, line in enumerate(text.splitlines(), 1):
        if needle in line:
            seen += 1
            if seen == nth:
                return i
    raise AssertionError(needle)


def staged_at(steps, needle, nth, key, phrase, **changes):
    """A bad staged model and the message naming its file, line and key."""
    text = staged(steps, **changes)
    return text, [f"model.yaml:{line_of(text, needle, nth)}: {key}", phrase]


ST_DUP = staged_at([{"name": "a", "analysis": STATIC_STEP}, {"name": "a", "analysis": STATIC_STEP}], "name: a", 2, "steps[1].name", "a second step named 'a'")
ST_KEY = staged_at([{"name": "a", "analysis": STATIC_STEP, "lods": []}], "lods", 1, "steps[0].lods", "did you mean 'loads'")
ST_NOAN = staged_at([{"name": "a", "analysis": STATIC_STEP}, {"name": "b"}], "name: b", 1, "steps[1].analysis", "required key is missing")
ST_TIME = staged_at([{"name": "a", "analysis": STATIC_STEP}, {"name": "b", "analysis": {"type": "static", "time": {"end": -1, "step": 0.5}}}], "end: -1", 1, "steps[1].analysis.time.end", "")
ST_FF = staged_at([{"name": "a", "analysis": STATIC_STEP}, {"name": "b", "analysis": {"type": "form_finding", "time": {"end": 1, "step": 1}}}], "type: form_finding", 1, "steps[1].analysis.type", "only the first step can be form_finding")
ST_LOADS = staged_at([{"name": "a", "analysis": STATIC_STEP}, {"name": "b", "analysis": STATIC_STEP, "loads": [{"type": "point", "nodes": 6, "force": [0, 1, 0], "function": "gust"}]}], "function: gust", 1, "steps[1].loads[0].function", "gust")
ST_TOP = staged_at([{"name": "a", "analysis": STATIC_STEP}], "type: dynamic", 1, "analysis", "gives each step its own analysis", analysis=BASE["analysis"])

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
    ("wrinkling_stiffness_without_wrinkling", mutate(sections__0__wrinkling_stiffness=1e-4), {}, [], 1, ["sections[0].wrinkling_stiffness: applies with wrinkling: true only"]),
    ("wrinkling_stiffness_out_of_range", mutate(sections__0__wrinkling=True, sections__0__wrinkling_stiffness=0.5), {}, [], 1, ["sections[0].wrinkling_stiffness: 0.5 is not in (0, 0.1]"]),
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
    # Issue 43: incompressible hyperelastic sheets, each condition of stability on its key.
    ("neo_hookean_mu_zero", mutate(materials__iso={"type": "neo_hookean", "mu": 0, "density": 1}), {}, [], 1, ["model.yaml:", "materials.iso.mu", "must be positive"]),
    ("neo_hookean_unknown_key", mutate(materials__iso={"type": "neo_hookean", "mu": 1e5, "E": 3, "density": 1}), {}, [], 1, ["materials.iso", "E"]),
    ("mooney_rivlin_sum", mutate(materials__iso={"type": "mooney_rivlin", "C1": 1e5, "C2": -2e5, "density": 1}), {}, [], 1, ["model.yaml:", "materials.iso.C1", "C1 + C2 = -100000 must be positive"]),
    ("mooney_rivlin_C2_negative", mutate(materials__iso={"type": "mooney_rivlin", "C1": 1e5, "C2": -0.25e5, "density": 1}), {}, [], 1, ["materials.iso.C2", "C2 = -25000 must not be negative", "equibiaxial stretch of sqrt(-C1/C2) = 2"]),
    ("mooney_rivlin_C1_negative", mutate(materials__iso={"type": "mooney_rivlin", "C1": -1e5, "C2": 2e5, "density": 1}), {}, [], 1, ["materials.iso.C1", "C1 = -100000 must not be negative", "uniaxial stretch of -C2/C1 = 2"]),
    ("neo_hookean_compressible_nu_half", mutate(materials__iso={"type": "neo_hookean", "mu": 1e5, "nu": 0.5, "density": 1}), {}, [], 1, ["model.yaml:", "materials.iso.nu", "must lie in (-1, 0.5) for a compressible sheet", "leave nu out"]),
    ("neo_hookean_compressible_runs", mutate(materials__iso={"type": "neo_hookean", "mu": 1e5, "nu": 0.3, "density": 1}), {}, [], 0, ["converged"]),
    ("mooney_rivlin_missing_C2", mutate(materials__iso={"type": "mooney_rivlin", "C1": 1e5, "density": 1}), {}, [], 1, ["materials.iso.C2: required key is missing"]),
    ("elastoplastic_both_hardenings", mutate(materials__iso={"type": "elastoplastic", "E": 1.1e9, "nu": 0.45, "yield_stress": 16e6, "hardening_curve": [[0, 16e6], [0.1, 25e6]], "density": 1750}), {}, [], 1, ["materials.iso.hardening_curve", "not both"]),
    ("elastoplastic_curve_unsorted", mutate(materials__iso={"type": "elastoplastic", "E": 1.1e9, "nu": 0.45, "hardening_curve": [[0, 16e6], [0.1, 25e6], [0.05, 26e6]], "density": 1750}), {}, [], 1, ["model.yaml:", "materials.iso", "point 3 of the hardening curve: the plastic strains must ascend"]),
    ("elastoplastic_curve_falls", mutate(materials__iso={"type": "elastoplastic", "E": 1.1e9, "nu": 0.45, "hardening_curve": [[0, 16e6], [0.1, 15e6]], "density": 1750}), {}, [], 1, ["point 2 of the hardening curve: the yield stress falls"]),
    ("elastoplastic_no_yield", mutate(materials__iso={"type": "elastoplastic", "E": 1.1e9, "nu": 0.45, "yield_stress": -1, "density": 1750}), {}, [], 1, ["materials.iso.yield_stress", "must be positive"]),
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
    ("pressure_per_without_direction", mutate(loads__0={"type": "pressure", "elements": "sheet", "value": 1, "per": "projected"}), {}, [], 1, ["loads[0].per", "'per' needs a 'direction'"]),
    ("pressure_per_unknown", mutate(loads__0={"type": "pressure", "elements": "sheet", "value": 1, "direction": [0, 0, -1], "per": "projcted"}), {}, [], 1, ["loads[0].per", "expected projected or area", "did you mean 'projected'"]),
    ("pressure_zero_direction", mutate(loads__0={"type": "pressure", "elements": "sheet", "value": 1, "direction": [0, 0, 0]}), {}, [], 1, ["loads[0].direction", "non-zero vector"]),
    ("form_finding_settings_on_static", mutate(analysis__form_finding={"stiffness": 1e-3}), {}, [], 1, ["analysis.form_finding", "need analysis.type: form_finding"]),
    ("form_finding_tolerance_above_one", mutate(analysis__type="form_finding", analysis__form_finding={"tolerance": 2}), {}, [], 1, ["analysis.form_finding.tolerance", "below 1"]),
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
    ("safety_above_one", mutate(analysis__integrator={"scheme": "central-difference", "safety": 1.2}), {}, [], 1, ["model.yaml:", "analysis.integrator.safety", "in (0, 1] (got 1.2)"]),
    ("safety_not_positive", mutate(analysis__integrator={"scheme": "central-difference", "safety": 0}), {}, [], 1, ["model.yaml:", "analysis.integrator.safety", "must be positive"]),
    ("safety_implicit", mutate(analysis__integrator={"scheme": "newmark", "safety": 0.8}), {}, [], 1, ["model.yaml:", "analysis.integrator.safety", "scheme: central-difference"]),
    ("stable_step_unknown", mutate(analysis__integrator={"scheme": "central-difference", "stable_step": "always"}), {}, [], 1, ["model.yaml:", "analysis.integrator.stable_step", "'current'", "(got 'always')"]),
    ("mass_scaling_no_target", mutate(analysis__integrator={"scheme": "central-difference", "mass_scaling": {"target": 1e-5}}), {}, [], 1, ["model.yaml:", "analysis.integrator.mass_scaling", "target_step"]),
    ("mass_scaling_negative", mutate(analysis__integrator={"scheme": "central-difference", "mass_scaling": {"target_step": -1e-5}}), {}, [], 1, ["model.yaml:", "analysis.integrator.mass_scaling.target_step", "must be positive"]),
    ("petsc_not_built", mutate(analysis__linear_solver="petsc"), {}, [], 1, ["not available in this build"]) if not HAVE_PETSC else
    ("petsc_options_without_dash", mutate(analysis__linear_solver="petsc", analysis__petsc_options="ksp_type gmres"), {}, [], 1, ["analysis.petsc_options", "begin with '-'"]),
    ("petsc_options_other_solver", mutate(analysis__petsc_options="-ksp_type gmres"), {}, [], 1, ["petsc_options apply to linear_solver: petsc only"]),
    ("unknown_partition", mutate(analysis__partition="scoth"), {}, [], 1, ["analysis.partition", "unknown partition 'scoth'", "did you mean 'scotch'"]),
    ("unknown_linear_solver", mutate(analysis__linear_solver="superlu"), {}, [], 1, ["unknown linear solver 'superlu'"]),
    ("misspelt_linear_solver", mutate(analysis__linear_solver="mumsp"), {}, [], 1, ["unknown linear solver 'mumsp'", "did you mean 'mumps'"]),
    ("newton_zero_iterations", mutate(analysis__newton={"max_iterations": 0}), {}, [], 1, ["at least one iteration"]),
    # ---- output ----
    ("line_search_not_boolean", mutate(analysis__newton={"tolerance": 1e-8, "line_search": "maybe"}), {}, [], 1, ["analysis.newton.line_search"]),
    ("reuse_across_steps_not_boolean", mutate(analysis__newton={"reuse_across_steps": "maybe"}), {}, [], 1, ["analysis.newton.reuse_across_steps"]),
    ("history_unknown_quantity", mutate(output__history=[{"name": "a", "quantity": "displacment", "node": 6, "component": "x"}]), {}, [], 1, ["did you mean 'displacement'"]),
    ("history_point_outside", mutate(output__history=[{"name": "a", "quantity": "stress", "point": [5, 5, 0], "component": "s11"}]), {}, [], 1, ["lies in no membrane element"]),
    ("history_duplicate_name", mutate(output__history=[{"name": "a", "quantity": "kinetic_energy"}, {"name": "a", "quantity": "strain_energy"}]), {}, [], 1, ["duplicate history name 'a'"]),
    ("history_undefined_node", mutate(output__history=[{"name": "a", "quantity": "velocity", "node": 42, "component": "z"}]), {}, [], 1, ["undefined node 42"]),
    ("history_bad_unit", mutate(output__history=[{"name": "a", "quantity": "fiber_angle_change", "point": [0.5, 0.5, 0], "unit": "grad"}]), {}, [], 1, ["unknown unit 'grad'"]),
    ("history_bad_stress_component", mutate(output__history=[{"name": "a", "quantity": "stress", "point": [0.5, 0.5, 0], "component": "s33"}]), {}, [], 1, ["unknown stress component 's33'"]),
    ("interval_negative", mutate(output__interval=-1), {}, [], 1, ["output interval must be positive"]),
    # ---- hostile YAML: duplicate keys, documents, nesting, aliases, size (issue 14) ----
    ("dup_root_key", mutate() + "materials:\n  x: {type: cable, E: 1, density: 1}\n", {}, [], 1, ["materials: the key 'materials' is given twice (lines"]),
    ("dup_sections", mutate() + "sections: []\n", {}, [], 1, ["the key 'sections' is given twice"]),
    ("dup_nested_key", dup_line("    E: 1000.0\n", "    E: 2000.0\n"), {}, [], 1, ["materials.iso.E: the key 'E' is given twice"]),
    ("dup_flow_key", mutate().replace("title: cli base", "title: cli base\nfunctions: {a: {type: step}, a: {type: step}}").replace("functions:\n  ramp1:", "functionz:\n  ramp1:"), {}, [], 1, ["the key 'a' is given twice"]),
    ("dup_key_lines", "title: a\nmesh: {}\ntitle: b\n", {}, [], 1, ["model.yaml:3: title: the key 'title' is given twice (lines 1 and 3)"]),
    ("dup_key_in_list_item", dup_line("  thickness: 0.1\n", "  thickness: 0.2\n"), {}, [], 1, ["sections[0].thickness: the key 'thickness' is given twice"]),
    ("second_document", mutate() + "---\ntitle: second\n", {}, [], 1, ["a second YAML document", "which began at line 1"]),
    ("second_document_empty_start", "---\n" + mutate() + "---\n{}\n", {}, [], 1, ["a second YAML document"]),
    ("second_document_after_end", mutate() + "...\n---\nmesh: {}\n", {}, [], 1, ["a second YAML document"]),
    ("nesting_too_deep", "title: " + "[" * 40 + "]" * 40 + "\n", {}, [], 1, ["nested more than 32 levels deep"]),
    ("nesting_absurd", "title: " + "[" * 100000 + "]" * 100000 + "\n", {}, [], 1, ["YAML syntax error"]),
    ("alias_bomb", billion_laughs(), {}, [], 1, ["a9: unknown key"]),
    ("model_is_directory", "<dir>", {}, [], 1, ["is a directory, not a model file"]),
    ("model_is_dev_zero", "<link:/dev/zero>", {}, [], 1, ["model.yaml: not a regular file"]),
    ("model_is_fifo", "<fifo>", {}, [], 1, ["not a regular file"]),
    ("model_too_large", "<sparse:300>", {}, [], 1, ["more than the limit of 256 MiB"]),
    ("model_binary_garbage", None, {"model.yaml": lambda: bytes(range(256)) * 64}, [], 1, ["model.yaml"]),
    ("model_nul_bytes", None, {"model.yaml": lambda: b"title: a\x00b\n"}, [], 1, ["model.yaml"]),
    ("check_model_is_directory", "<dir>", {}, ["check"], 1, ["is a directory"]),
    # ---- inputs the fuzzer found (fuzz/, tests/cli/data/fuzz/) ----
    # Found by the Gmsh harness: a binary v4.1 file whose corrupt count made libgmsh ask for 4 TB;
    # Velum's own reader checks every count against the bytes left.
    ("fuzz_gmsh_huge_count", with_mesh_file("m.msh"), {"m.msh": lambda: open(os.path.join(DATA, "fuzz", "gmsh-huge-count.msh"), "rb").read()}, [], 1, ["model.yaml:2: mesh.file:", "m.msh: byte 369: the file is too short for an entity's bounding entities (1099511627778 x 4 bytes asked"]),
    ("fuzz_loadall_hang", None, {"model.yaml": lambda: open(os.path.join(DATA, "fuzz", "loadall-hang.yaml"), "rb").read()}, [], 1, ["model.yaml:94: a second YAML document"]),
    ("fuzz_flow_map_then_comma", "{}\n,\n", {}, [], 1, ["mesh: required key is missing"]),
    ("fuzz_flow_map_then_comma_second_doc", "a: 1\n---\n{}\n,\n", {}, [], 1, ["model.yaml:2: a second YAML document"]),
    # ---- integers out of range ----
    ("max_iterations_above_int", mutate(analysis__newton={"max_iterations": 4294967297}), {}, [], 1, ["analysis.newton.max_iterations", "at most 1000 iterations (got 4294967297)"]),
    ("max_iterations_above_long", mutate(analysis__newton={"max_iterations": 99999999999999999999999}), {}, [], 1, ["analysis.newton.max_iterations: expected an integer count"]),
    ("max_iterations_1001", mutate(analysis__newton={"max_iterations": 1001}), {}, [], 1, ["at most 1000 iterations"]),
    ("max_iterations_negative", mutate(analysis__newton={"max_iterations": -3}), {}, [], 1, ["at least one iteration"]),
    ("max_iterations_fraction", mutate(analysis__newton={"max_iterations": 2.5}), {}, [], 1, ["expected an integer count"]),
    ("max_iterations_bool", mutate(analysis__newton={"max_iterations": True}), {}, [], 1, ["expected an integer count"]),
    ("max_iterations_exponent", mutate(analysis__newton={"max_iterations": "1e3"}), {}, [], 1, ["expected an integer count"]),
    ("node_id_above_long", mutate(mesh__nodes=SEVEN[:5] + [[99999999999999999999, 2, 1, 0]]), {}, [], 1, ["mesh.nodes[5]: expected an integer node id"]),
    ("node_id_fraction", mutate(mesh__nodes=SEVEN[:5] + [[6.5, 2, 1, 0]]), {}, [], 1, ["expected an integer node id"]),
    ("element_id_above_long", mutate(mesh__elements__0={"set": "sheet", "type": "quad4", "connectivity": [[1, 2, 5, 4], [2, 3, 6, 5]], "ids": [1, 99999999999999999999]}), {}, [], 1, ["expected an integer element id"]),
    ("connectivity_id_above_long", mutate(mesh__elements__0__connectivity=[[1, 2, 5, 4], [2, 3, 6, 99999999999999999999]]), {}, [], 1, ["expected an integer node id"]),
    ("coordinate_not_finite", mutate(mesh__nodes=SEVEN[:5] + [[6, 2, ".inf", 0]]), {}, [], 1, ["mesh.nodes[5]: expected a finite number"]),
    ("coordinate_nan", mutate(mesh__nodes=SEVEN[:5] + [[6, 2, ".nan", 0]]), {}, [], 1, ["expected a finite number"]),
    ("coordinate_huge_literal", mutate(mesh__nodes=SEVEN[:5] + [[6, 2, "1e999", 0]]), {}, [], 1, ["mesh.nodes[5]"]),
    # ---- element shapes ----
    ("connectivity_empty", mutate(mesh__elements__0__connectivity=[]), {}, [], 1, ["mesh.elements[0].connectivity: the connectivity list is empty"]),
    ("quad_repeated_node", mutate(mesh__elements__0__connectivity=[[1, 2, 5, 5], [2, 3, 6, 5]]), {}, [], 1, ["element 1 of set 'sheet' (quad4) is degenerate or inverted: it repeats node 5"]),
    ("quad_self_intersecting", mutate(mesh__elements__0__connectivity=[[1, 3, 4, 5]], mesh__elements__1__connectivity=[[4, 5]]), {}, [], 1, ["(quad4) is degenerate or inverted: it crosses itself or folds over at node 4"]),
    ("quad_bowtie_symmetric", mutate(mesh__elements__0__connectivity=[[1, 2, 4, 5], [2, 3, 6, 5]]), {}, [], 1, ["degenerate or inverted: it has no area at its centre"]),
    ("quad_coincident_nodes", mutate(mesh__nodes=SEVEN + [[7, 1, 0, 0]], mesh__elements__0__connectivity=[[1, 2, 7, 4], [2, 3, 6, 5]]), {}, [], 1, ["element 1 of set 'sheet' (quad4) is degenerate or inverted"]),
    ("tri3_collinear", mutate(mesh__elements__0={"set": "sheet", "type": "tri3", "connectivity": [[1, 2, 3], [1, 3, 6]]}), {}, [], 1, ["(tri3) is degenerate or inverted: it has no area"]),
    ("tri3_repeated_node", mutate(mesh__elements__0={"set": "sheet", "type": "tri3", "connectivity": [[1, 3, 1]]}), {}, [], 1, ["(tri3) is degenerate or inverted: it repeats node 1"]),
    ("tri6_folded_midside", mutate(mesh__nodes=SEVEN + [[7, 1, 0.5, 0], [8, 0, 0.5, 0], [9, 1.9, 0, 0]], mesh__elements__0={"set": "sheet", "type": "tri6", "connectivity": [[1, 3, 4, 9, 7, 8]]}), {}, [], 1, ["(tri6) is degenerate or inverted: it crosses itself or folds over at node 3"]),
    ("quad8_folded_midside", mutate(mesh__nodes=SEVEN + [[7, 0.5, 0, 0], [8, 1, 0.5, 0], [9, 0.5, 1, 0], [10, 0, 0.9, 0]], mesh__elements__0={"set": "sheet", "type": "quad8", "connectivity": [[1, 2, 5, 4, 7, 8, 9, 10]]}, mesh__elements__1__connectivity=[[4, 5]], loads=[]), {}, [], 1, ["(quad8) is degenerate or inverted"]),
    ("cable2_repeated_node", mutate(mesh__elements__1__connectivity=[[4, 4], [5, 6]]), {}, [], 1, ["(cable2) is degenerate or inverted: it repeats node 4"]),
    ("cable3_middle_is_end", mutate(mesh__elements__1={"set": "lines", "type": "cable3", "connectivity": [[4, 6, 4]]}), {}, [], 1, ["(cable3) is degenerate or inverted: it repeats node 4"]),
    ("cable3_middle_beyond_end", mutate(mesh__elements__1={"set": "lines", "type": "cable3", "connectivity": [[4, 5, 6]]}), {}, [], 1, ["(cable3) is degenerate or inverted: it folds back on itself"]),
    ("cable3_ends_coincide", mutate(mesh__nodes=SEVEN + [[7, 0, 1, 0]], mesh__elements__1={"set": "lines", "type": "cable3", "connectivity": [[4, 7, 5]]}), {}, [], 1, ["it has zero length"]),
    # ---- boundary conditions that contradict each other or leave nothing to solve ----
    ("fixed_then_prescribed", mutate(boundary=[{"nodes": "left", "fix": ["x"]}, {"nodes": [1], "displacement": [0.1, 0, 0]}]), {}, [], 1, ["boundary[1].nodes: node 1 is given a non-zero displacement of a component here and fixed by boundary[0], line"]),
    ("fixed_then_prescribed_zero_ok", mutate(boundary=[{"nodes": "left", "fix": ["x", "y", "z"]}, {"nodes": "sheet", "fix": ["z"]}, {"nodes": [3, 6], "displacement": [0.01, 0, 0]}]), {}, ["check"], 0, ["is valid"]),
    ("prescribed_then_fixed", mutate(boundary=[{"nodes": [4], "displacement": [0.1, 0, 0]}, {"nodes": "left", "fix": ["x", "y", "z"]}]), {}, [], 1, ["boundary[1].nodes: node 4 is fixed here and given a non-zero displacement there by boundary[0]"]),
    ("prescribed_twice", mutate(boundary=[{"nodes": "left", "displacement": [0, 0, 0]}, {"nodes": [4], "displacement": [0.1, 0, 0]}]), {}, [], 1, ["node 4 is given a displacement here and given a different one by boundary[0]"]),
    ("prescribed_twice_functions", mutate(boundary=[{"nodes": "left", "displacement": [0.1, 0, 0]}, {"nodes": [4], "displacement": [0.1, 0, 0], "function": "ramp1"}]), {}, [], 1, ["given a different one by boundary[0]"]),
    ("prescribed_and_symmetry", mutate(boundary=[{"nodes": "left", "displacement": [0, 0, 0.1]}, {"nodes": "sheet", "symmetry": {"normal": [0, 0, 1]}}]), {}, [], 1, ["is put on a symmetry plane here and given a displacement off it by boundary[0]"]),
    ("symmetry_then_prescribed", mutate(boundary=[{"nodes": "sheet", "symmetry": {"normal": [1, 1, 1]}}, {"nodes": "left", "displacement": [0.1, 0, 0]}]), {}, [], 1, ["is given a displacement off the plane here and put on a symmetry plane by boundary[0]"]),
    ("fixed_on_skew_plane", mutate(boundary=[{"nodes": "left", "fix": ["x", "y", "z"]}, {"nodes": [2, 3], "symmetry": {"normal": [1, 1, 0]}}, {"nodes": [2], "fix": ["z"]}]), {}, [], 1, ["node 2 is fixed here and put on a skew symmetry plane by boundary[1]"]),
    ("skew_plane_on_fixed", mutate(boundary=[{"nodes": "left", "fix": ["x", "y", "z"]}, {"nodes": [1, 2], "symmetry": {"normal": [0, 1, 1]}}]), {}, [], 1, ["node 1 is put on a skew symmetry plane here and fixed by boundary[0]"]),
    ("every_dof_fixed", fix_all({"nodes": "sheet", "fix": ["x", "y", "z"]}), {}, [], 1, ["every degree of freedom is fixed", "0 equations"]),
    ("every_dof_fixed_check", fix_all({"nodes": "sheet", "fix": ["x", "y", "z"]}), {}, ["check"], 1, ["every degree of freedom is fixed"]),
    ("every_dof_prescribed_runs", fix_all({"nodes": "sheet", "displacement": [0.01, 0, 0]}), {}, ["check"], 0, ["is valid"]),
    ("every_dof_fixed_by_parts", fix_all({"nodes": "sheet", "fix": ["x", "y"]}, {"nodes": "sheet", "symmetry": {"normal": [0, 0, 1]}}), {}, [], 1, ["0 equations"]),
    ("every_dof_fixed_component_lists", fix_all({"nodes": "sheet", "fix": ["x"]}, {"nodes": "sheet", "fix": ["y"]}, {"nodes": "sheet", "fix": ["z"]}), {}, [], 1, ["0 equations"]),
    # ---- frames and steps beyond the limits ----
    ("interval_tiny", mutate(output__interval=1e-8), {}, [], 1, ["output.interval", "more than the limit of 1e+04 frames"]),
    ("interval_tiny_no_fields", mutate(output__interval=1e-9, output__fields=False), {}, [], 1, ["more than the limit of 1e+06 history rows"]),
    ("interval_default_tiny_step", mutate(analysis__time={"end": 0.02, "step": 1e-7, "min_step": 1e-8}, output=None), {}, [], 1, ["output.interval (default: time.step)", "more than the limit"]),
    ("end_1e9", mutate(analysis__time={"end": 1e9, "step": 0.005}), {}, [], 1, ["analysis.time.step", "steps, more than the limit of 1e+07"]),
    ("step_tiny", mutate(analysis__time={"end": 1.0, "step": 1e-8, "min_step": 1e-9}, output__interval=0.5), {}, [], 1, ["more than the limit of 1e+07"]),
    # ---- history column names ----
    ("history_name_time", hist("time"), {}, [], 1, ["'time' is the first column already"]),
    ("history_name_cr", hist("a\rb"), {}, [], 1, ["must not hold control characters"]),
    ("history_name_lf", hist("a\nb"), {}, [], 1, ["must not hold control characters"]),
    ("history_name_tab", hist("a\tb"), {}, [], 1, ["must not hold control characters"]),
    ("history_name_comma", hist("a,b"), {}, [], 1, ["must not hold commas or quotes"]),
    ("history_name_double_quote", hist('a"b'), {}, [], 1, ["must not hold commas or quotes"]),
    ("history_name_single_quote", hist("a'b"), {}, [], 1, ["must not hold commas or quotes"]),
    ("history_name_empty", hist(""), {}, [], 1, ["must not be empty"]),
    ("history_name_spaces", hist(" a "), {}, [], 1, ["must not begin or end with a space"]),
    ("history_name_too_long", hist("n" * 65), {}, [], 1, ["at most 64 bytes (got 65)"]),
    ("history_name_invalid_utf8", None, {"model.yaml": lambda: mutate(output__history=[{"name": "BADNAME", "quantity": "kinetic_energy"}]).encode().replace(b"BADNAME", b"a\xff\xfeb")}, [], 1, ["model.yaml"]),
    ("history_name_truncated_utf8", None, {"model.yaml": lambda: mutate(output__history=[{"name": "BADNAME", "quantity": "kinetic_energy"}]).encode().replace(b"BADNAME", b"ab\xc3")}, [], 1, ["model.yaml"]),
    # ---- "did you mean" on huge names stays fast ----
    ("long_unknown_root_key", mutate() + "? " + LONG + "\n: 1\n", {}, [], 1, ["unknown key (did you mean"]),
    ("long_undefined_material", mutate(**{"sections__0__material": "m" * 300_000, "materials__" + "z" * 300_000: {"type": "cable", "E": 1.0, "density": 1.0}}), {}, [], 1, ["undefined material"]),
    ("long_set_names", mutate(sections__0__elements="s" * 400_000, mesh__elements__0__set="t" * 400_000), {}, [], 1, ["undefined element set"]),
    ("long_function_name", mutate(loads__0__function="f" * 500_000, functions={"g" * 500_000: {"type": "step"}}), {}, [], 1, ["undefined function"]),
    # ---- mesh files: counts, values, odd files ----
    ("msh_elements_count_above", with_mesh_file("m.msh"), {"m.msh": msh_edit("$Elements\n7\n", "$Elements\n8\n")}, [], 1, ["m.msh:23: $Elements declares 8 elements but its section holds 7 lines"]),
    ("msh_elements_count_below", with_mesh_file("m.msh"), {"m.msh": msh_edit("$Elements\n7\n", "$Elements\n6\n")}, [], 1, ["$Elements declares 6 elements"]),
    ("msh_nodes_count_below", with_mesh_file("m.msh"), {"m.msh": msh_edit("$Nodes\n9\n", "$Nodes\n8\n")}, [], 1, ["m.msh:11: $Nodes declares 8 nodes"]),
    ("msh_nodes_count_above", with_mesh_file("m.msh"), {"m.msh": msh_edit("$Nodes\n9\n", "$Nodes\n10\n")}, [], 1, ["$Nodes declares 10 nodes"]),
    ("msh41_elements_count", with_mesh_file("m.msh"), {"m.msh": msh_edit("$Elements\n3 7 1 7\n", "$Elements\n3 6 1 7\n", "square_quad4_v41.msh")}, [], 1, ["$Elements declares 6 elements in 3 blocks"]),
    ("msh41_nodes_count", with_mesh_file("m.msh"), {"m.msh": msh_edit("$Nodes\n9 9 1 9\n", "$Nodes\n9 8 1 9\n", "square_quad4_v41.msh")}, [], 1, ["$Nodes declares 8 nodes in 9 blocks"]),
    ("msh_element_line_dropped", with_mesh_file("m.msh"), {"m.msh": lambda: "\n".join(l for i, l in enumerate(msh_text().split("\n")) if i != 24)}, [], 1, ["$Elements declares 7 elements but its section holds 6 lines"]),
    ("msh_nan_coordinate", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n9 0.5000000000003766 0.5000000000003766 0\n", "\n9 nan 0.5 0\n")}, [], 1, ["m.msh: node 9 has a non-finite coordinate"]),
    ("msh_inf_coordinate", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n9 0.5000000000003766 0.5000000000003766 0\n", "\n9 0.5 inf 0\n")}, [], 1, ["non-finite coordinate"]),
    ("msh_huge_coordinate", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n9 0.5000000000003766 0.5000000000003766 0\n", "\n9 0.5 1e999 0\n")}, [], 1, ["m.msh"]),
    ("msh_is_dev_zero", with_mesh_file("/dev/zero"), {}, [], 1, ["/dev/zero: not a regular file"]),
    ("msh_is_directory", with_mesh_file("."), {}, [], 1, ["is a directory, not a mesh file"]),
    ("msh_empty", with_mesh_file("e.msh"), {"e.msh": lambda: ""}, [], 1, ["not a Gmsh mesh file"]),
    ("msh_header_only", with_mesh_file("h.msh"), {"h.msh": lambda: "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"}, [], 1, ["h.msh"]),
    ("msh_repeated_node_in_element", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n4 3 2 1 1 1 5 9 8\n", "\n4 3 2 1 1 1 5 9 5\n")}, [], 1, ["element 4 of set 'sheet' (quad4) is degenerate or inverted: it repeats node 5"]),
    # Velum's own .msh reader: what it refuses, naming the file and the line.
    # Found by the harness of Velum's own reader: a flipped bit makes an entity's physical groups
    # read -2^31 (whose negation overflowed) or 0.
    ("fuzz_gmsh_physical_tag", with_mesh_file("m.msh"), {"m.msh": lambda: open(os.path.join(DATA, "fuzz", "gmsh-int-min-physical.msh"), "rb").read()}, [], 1, ["m.msh: byte", "physical group tag"]),
    ("msh_version_40", with_mesh_file("m.msh"), {"m.msh": msh_edit("2.2 0 8", "4 0 8")}, [], 1, ["m.msh:2: MSH 4 is not read: save the mesh as MSH 4.1 or 2.2"]),
    ("msh_version_unknown", with_mesh_file("m.msh"), {"m.msh": msh_edit("2.2 0 8", "3.0 0 8")}, [], 1, ["m.msh:2: MSH version 3 is not read"]),
    ("msh_data_size_4", with_mesh_file("m.msh"), {"m.msh": msh_edit("2.2 0 8", "2.2 0 4")}, [], 1, ["m.msh:2: data size 4 (8 expected)"]),
    ("msh_unknown_element_type", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n4 3 2 1 1 1 5 9 8\n", "\n4 77 2 1 1 1 5 9 8\n")}, [], 1, ["m.msh:27: element 4: unknown Gmsh element type 77"]),
    ("msh_element_extra_node", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n4 3 2 1 1 1 5 9 8\n", "\n4 3 2 1 1 1 5 9 8 2\n")}, [], 1, ["m.msh:27: element 4 (quad4) has more than its 4 nodes"]),
    ("msh_element_undefined_node", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n4 3 2 1 1 1 5 9 8\n", "\n4 3 2 1 1 1 5 99 8\n")}, [], 1, ["m.msh: element 4 (quad4) refers to node 99, which $Nodes does not define"]),
    ("msh_node_tag_zero", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n1 0 0 0\n", "\n0 0 0 0\n")}, [], 1, ["m.msh:12: node tag 0 is out of range"]),
    ("msh_node_letter", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n2 1 0 0\n", "\n2 1 x 0\n")}, [], 1, ["m.msh:13: a node coordinate: 'x' is not a number"]),
    ("msh_stray_text", with_mesh_file("m.msh"), {"m.msh": msh_edit("$EndNodes\n", "$EndNodes\nhello\n")}, [], 1, ["m.msh:22: unexpected 'hello' between sections"]),
    ("msh_names_unterminated", with_mesh_file("m.msh"), {"m.msh": msh_edit('2 1 "sheet"', '2 1 "sheet')}, [], 1, ["m.msh:8: the physical group's name has no closing quote"]),
    ("msh_volume_element", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n4 3 2 1 1 1 5 9 8\n", "\n4 4 2 1 1 1 5 9 8\n")}, [], 1, ["m.msh: the file holds 1 volume element (first: element 4, tet4)"]),
    ("msh_triangle_in_line_set", with_mesh_file("m.msh"), {"m.msh": msh_edit("\n2 1 2 2 4 4 8\n", "\n2 2 2 2 4 4 8 1\n")}, [], 1, ["element set '2' has no section"]),
    ("msh_crlf_good", with_mesh_file("m.msh"), {"m.msh": lambda: msh_text().replace("\n", "\r\n")}, ["check"], 0, ["is valid"]),
    # ---- several errors reported together, with lines ----
    ("several_errors", mutate(materials__iso__E="x", analysis__time__end=-1, sections__0__material="nope"), {}, [], 1, ["materials.iso.E", "analysis.time.end", "undefined material 'nope'", "3 errors"]),
    ("line_number", "title: t\nmesh:\n  nodes: [[1, 0, 0, 0]]\n  bogus: 1\n", {}, [], 1, ["model.yaml:4: mesh.bogus: unknown key"]),
    # ---- Gmsh files ----
    ("msh_missing", with_mesh_file("nothere.msh"), {}, [], 1, ["cannot open the mesh file"]),
    ("msh_truncated", with_mesh_file("trunc.msh"), {"trunc.msh": msh_truncated}, [], 1, ["mesh.file", "trunc.msh"]),
    ("msh_binary_truncated", with_mesh_file("truncb.msh"), {"truncb.msh": msh_binary_truncated}, [], 1, ["mesh.file", "truncb.msh: byte", "truncated or corrupt"]),
    ("msh_garbage", with_mesh_file("garbage.msh"), {"garbage.msh": lambda: bytes(range(256)) * 8}, [], 1, ["not a Gmsh mesh file"]),
    ("msh_garbage_after_header", with_mesh_file("g2.msh"), {"g2.msh": lambda: "$MeshFormat\n9.9 x y\n$EndMeshFormat\n$Nodes\nzz\n"}, [], 1, ["mesh.file", "g2.msh"]),
    ("msh_id_collision", with_mesh_file("SQ22").replace("  file: SQ22", "  file: SQ22\n  nodes: [[3, 9, 9, 9]]"), {}, [], 1, ["duplicate node id 3"]),
    # ---- output folder and command line ----
    ("unwritable_output", mutate(), {"afile": lambda: "x"}, ["-o", "{dir}/afile/out"], 3, ["cannot create the output directory"]),
    ("cli_missing_model", "", {}, ["--no-model"], 1, ["MODEL is required"]),
    ("cli_unknown_option", mutate(), {}, ["--frobnicate"], 1, ["frobnicate"]),
    # ---- a solve that fails: exit 2, summary says failed ----
    ("solve_fails", mutate(analysis__type="static", loads__0={"type": "pressure", "elements": "sheet", "value": 1.0}, sections=[BASE["sections"][0]], mesh__elements=[BASE["mesh"]["elements"][0]], analysis__time={"end": 1.0, "step": 0.5, "min_step": 0.1}, output__interval=0.5), {}, [], 2, ["the solve failed at t = ", "summary.json:failed"]),
    # ---- analysis steps (steps:) ----
    ("steps_empty", staged([]), {}, [], 1, ["steps: steps is a list of analysis steps", "give at least one"]),
    ("steps_not_a_list", staged({"a": 1}), {}, [], 1, ["steps: steps is a list"]),
    ("steps_duplicate_name", ST_DUP[0], {}, [], 1, ST_DUP[1]),
    ("steps_unknown_key", ST_KEY[0], {}, [], 1, ST_KEY[1]),
    ("steps_no_analysis", ST_NOAN[0], {}, [], 1, ST_NOAN[1]),
    ("steps_bad_time", ST_TIME[0], {}, [], 1, ST_TIME[1]),
    ("steps_form_finding_later", ST_FF[0], {}, [], 1, ST_FF[1]),
    ("steps_loads_undefined_function", ST_LOADS[0], {}, [], 1, ST_LOADS[1]),
    ("steps_and_top_analysis", ST_TOP[0], {}, [], 1, ST_TOP[1]),
    ("steps_no_name", staged([{"analysis": STATIC_STEP}]), {}, [], 1, ["steps[0].name: required key is missing"]),
    ("steps_checkpoint", staged([{"name": "a", "analysis": STATIC_STEP}], output__checkpoint={"steps": 1}), {}, [], 1, ["output.checkpoint", "writes no checkpoints"]),
    ("steps_restart_refused", staged([{"name": "a", "analysis": STATIC_STEP}]), {}, ["--restart", "{dir}/out"], 1, ["--restart: a model with steps", "cannot be restarted"]),
    ("steps_fixed_node_moved", staged([{"name": "pull", "analysis": STATIC_STEP}, {"name": "hold", "analysis": STATIC_STEP, "boundary": STAGED_BOUNDARY + [{"nodes": [6], "fix": ["x"]}]}]), {}, [], 2, ["step 'hold' (2 of 2): node 6 would jump by", "summary.json:failed"]),
    ("good_steps_check", staged([{"name": "pull", "analysis": STATIC_STEP}, {"name": "hold", "analysis": STATIC_STEP}]), {}, ["check"], 0, ["step 1:", "'pull': static, t = 0 to 1", "'hold': static, t = 1 to 2", "held boundary, held loads", "is valid"]),
    ("good_steps_run", staged([{"name": "pull", "analysis": STATIC_STEP}, {"name": "shake", "analysis": {"type": "dynamic", "time": {"end": 0.02, "step": 0.005}}}]), {}, [], 0, ["step 2/2 'shake': dynamic", "converged", "summary.json:converged"]),
    # ---- good inputs ----
    ("good_base_check", mutate(), {}, ["check"], 0, ["is valid", "units"]),
    ("good_base_run", mutate(), {}, [], 0, ["converged"]),
    # A flat, unstressed sheet and straight cables pulled in their plane, statically: no
    # stiffness normal to them at the start (a singular Jacobian before the first correction
    # borrowed a tension's stiffness).
    ("good_static_from_flat", mutate(analysis={"type": "static", "time": {"end": 1.0, "step": 0.5}}, functions__ramp1={"type": "ramp", "duration": 1.0}), {}, [], 0, ["converged", "summary.json:converged"]),
    ("good_msh22", with_mesh_file("SQ22"), {}, ["check"], 0, ["quad4 4", "is valid"]),
    ("good_msh41", with_mesh_file("SQ41"), {}, [], 0, ["converged"]),
    ("good_msh41_binary_quad9", with_mesh_file("SQ41B"), {}, [], 0, ["converged"]),
    ("good_symmetry", mutate(boundary=[{"nodes": "left", "fix": ["x", "y", "z"]}, {"nodes": [2, 3, 5, 6], "symmetry": {"normal": [0, 0, 1]}}]), {}, [], 0, ["converged"]),
    # ---- Abaqus/CalculiX decks as mesh files (tests/cli/inp_cases.py has the importer's) ----
    ("inp_mesh_ok", with_mesh_file("m.inp"), {"m.inp": inp_edit("", "")}, [], 0, ["m.inp:21: *MATERIAL: not read"]),
    ("inp_mesh_undefined_node", with_mesh_file("m.inp"), {"m.inp": inp_edit("4, 5, 6, 9, 8", "4, 5, 6, 99, 8")}, [], 1, ["model.yaml:2: mesh.file:", "m.inp:16: *ELEMENT: element 4 refers to undefined node 99"]),
    ("inp_mesh_element_type", with_mesh_file("m.inp"), {"m.inp": inp_edit("TYPE=M3D4", "TYPE=S4R")}, [], 1, ["m.inp:12: *ELEMENT: element type S4R is not supported"]),
    ("inp_mesh_bad_number", with_mesh_file("m.inp"), {"m.inp": inp_edit("5, 0.5, 0.5, 0.", "5, 0.5, inf, 0.")}, [], 1, ["m.inp:7: *NODE: field 3: 'inf' is not a finite number"]),
    ("inp_mesh_generate", with_mesh_file("m.inp"), {"m.inp": inp_edit("*NSET, NSET=corner\n9", "*NSET, NSET=corner, GENERATE\n9, 1, 1")}, [], 1, ["m.inp:20: *NSET: GENERATE needs first <= last"]),
    ("inp_mesh_nul", with_mesh_file("m.inp"), {"m.inp": inp_edit("*NSET, NSET=left", "*NSET, NS\0ET=left")}, [], 1, ["m.inp:17: a NUL byte"]),
    ("inp_mesh_truncated", with_mesh_file("m.inp"), {"m.inp": inp_edit("4, 5, 6, 9, 8\n", "4, 5, 6,\n")}, [], 1, ["m.inp:16: *ELEMENT: a M3D4 needs an element id and 4 node ids, got 3 fields"]),
]


def run_case(name, text, files, args, status, phrases):
    d = os.path.join(WORK, name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    model = os.path.join(d, "model.yaml")
    if text == "<dir>":
        os.makedirs(model)
        text = None
    elif text is not None and text.startswith("<link:"):
        os.symlink(text[6:-1], model)
        text = None
    elif text == "<fifo>":
        os.mkfifo(model)
        text = None
    elif text is not None and text.startswith("<sparse:"):
        with open(model, "wb") as f:
            f.truncate(int(text[8:-1]) << 20)
        text = None
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
    p = subprocess.run(cmd, capture_output=True, timeout=120)
    p.stdout = p.stdout.decode(errors="replace")
    p.stderr = p.stderr.decode(errors="replace")
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
