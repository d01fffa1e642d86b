#!/usr/bin/python3
"""Issue 47: what an Abaqus/CalculiX deck has and Velum has too, through `velum import`
(docs/inp-import.md):
- several *STEPs become `steps:` (loads ramped on from where the step before left them, held
  when a step does not redefine them, removed by OP=NEW; prescribed motions continued), and
  end where one step with the final loads ends;
- *STATIC, RIKS becomes analysis.path (arc length): the shallow truss snaps through on its
  analytic curve;
- *INITIAL CONDITIONS, TYPE=STRESS becomes the sections' prestress: a flat prestressed sheet
  under pressure runs as its hand-written twin does;
- *NODE PRINT, *OUTPUT, HISTORY / *NODE OUTPUT and *ENERGY OUTPUT become history columns;
- node lines with the normal's direction cosines (fields 5-7) are read;
- *INCLUDE of a file of data lines inside a *NODE block, quoted names with blanks and commas;
- `velum import deck.inp -o deck.inp` is refused and leaves the deck as it was.

usage: inp_mappings.py VELUM WORK_DIR
"""
import csv
import os
import shutil
import subprocess
import sys

import yaml

VELUM, WORK = sys.argv[1:3]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what[:800])
    if not cond:
        failures.append(what)


def velum(*args):
    p = subprocess.run([VELUM, *args], capture_output=True, text=True, timeout=120)
    return p.returncode, p.stdout + p.stderr


def write(name, text):
    path = os.path.join(WORK, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def import_and_run(name, deck_text):
    """Imports deck_text, runs it; (import output, model dict, last history row or None)."""
    deck = write(name + ".inp", deck_text)
    model = os.path.join(WORK, name + ".yaml")
    rc, text = velum("import", deck, "-o", model)
    if rc != 0:
        return text, None, None
    out = os.path.join(WORK, name + "_out")
    rc2, text2 = velum("run", model, "-o", out, "--threads", "1", "--quiet")
    m = yaml.safe_load(open(model))
    if rc2 != 0:
        return text + text2, m, None
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
    return text, m, rows


MESH = """*NODE, NSET=ALL
1, 0., 0., 0.
2, 1., 0., 0.
3, 1., 1., 0.
4, 0., 1., 0.
*NSET, NSET=TIP
2, 3
*ELEMENT, TYPE=M3D4, ELSET=S
1, 1, 2, 3, 4
*MATERIAL, NAME=M
*ELASTIC
100., 0.3
*DENSITY
1.
*MEMBRANE SECTION, ELSET=S, MATERIAL=M
0.1
*BOUNDARY
1, 1, 3
4, 1, 3
ALL, 3, 3
"""
PRINT = "*NODE PRINT, NSET=TIP\nU1\n"


def step(body, name="", procedure="*STATIC\n0.5, 1.\n"):
    return f"*STEP, NLGEOM{', NAME=' + name if name else ''}\n{procedure}{body}{PRINT}*END STEP\n"


def u1(rows, node=2):
    return float(rows[-1][f"U1_{node}"]) if rows else None


# ---- several steps ----
_, _, one = import_and_run("one_step", MESH + step("*CLOAD\nTIP, 1, 2.\n"))
text, m, two = import_and_run("two_steps", MESH + step("*CLOAD\nTIP, 1, 1.\n", "pull")
                              + step("*CLOAD\nTIP, 1, 2.\n", "pull more"))
check(m is not None and [s["name"] for s in m.get("steps", [])] == ["pull", "pull more"],
      f"two steps: written as steps: ({text})")
check(one and two and abs(u1(two) - u1(one)) < 1e-6 * abs(u1(one)),
      f"two steps (1 then 2) end where one step (2) ends: {u1(two)} vs {u1(one)}")
if m:
    loads2 = m["steps"][1]["loads"]
    check(sorted(l.get("function", "held") for l in loads2) == ["held", "step_ramp_2"]
          and sorted(l["force"][0] for l in loads2) == [1, 1],
          f"two steps: step 2 holds 1 and ramps on by 1: {loads2}")
if two:
    check(sorted({r["analysis_step"] for r in two}) == ["1", "2"], "two steps: analysis_step column")
_, _, held = import_and_run("held", MESH + step("*CLOAD\nTIP, 1, 1.\n") + step(""))
_, _, half = import_and_run("one_half", MESH + step("*CLOAD\nTIP, 1, 1.\n"))
check(held and half and abs(u1(held) - u1(half)) < 1e-6 * abs(u1(half)),
      f"a step that gives no loads holds them: {u1(held) if held else None} vs {u1(half) if half else None}")
_, _, removed = import_and_run("op_new", MESH + step("*CLOAD\nTIP, 1, 1.\n")
                               + step("*CLOAD, OP=NEW\n", procedure="*STATIC\n0.25, 1.\n"))
check(removed is not None and abs(u1(removed)) < 1e-9, f"OP=NEW removes the loads: u1 {u1(removed) if removed else None}")
held_y = "*BOUNDARY\n2, 2, 2\n"
_, _, moved_one = import_and_run("moved_one", MESH + step(held_y + "*BOUNDARY\n2, 1, 1, 0.2\n"))
text, m, moved_two = import_and_run("moved_two", MESH + step(held_y + "*BOUNDARY\n2, 1, 1, 0.1\n")
                                    + step("*BOUNDARY\n2, 1, 1, 0.2\n"))
check(moved_two is not None and abs(u1(moved_two) - 0.2) < 1e-12,
      f"a prescribed motion goes on from where the step before left it: {text[-600:] if moved_two is None else u1(moved_two)}")
check(moved_one is not None and moved_two is not None
      and abs(u1(moved_two, 3) - u1(moved_one, 3)) < 1e-6 * abs(u1(moved_one, 3)),
      "moved in two steps (0.1 then 0.2) ends where one step (0.2) ends")
text, m, moved_three = import_and_run("moved_three", MESH + step(held_y + "*BOUNDARY\n2, 1, 1, 0.1\n")
                                      + step("*BOUNDARY\n2, 1, 1, 0.2\n") + step("*CLOAD\n3, 1, 0.\n")
                                      + step("*BOUNDARY\n2, 1, 1, 0.4\n"))
check(moved_three is not None and abs(u1(moved_three) - 0.4) < 1e-12
      and {r["analysis_step"] for r in moved_three} == {"1", "2", "3", "4"},
      f"a motion held through a step, then continued: {text[-600:] if moved_three is None else u1(moved_three)}")

# ---- RIKS ----
RIKS = """*NODE, NSET=ALL
1, -1., 0., 0.
2, 1., 0., 0.
3, 0., 0.2, 0., 0., 0., 1.
*NSET, NSET=APEX
3
*NSET, NSET=FEET
1, 2
*ELEMENT, TYPE=T3D2, ELSET=BARS
1, 1, 3
2, 2, 3
*MATERIAL, NAME=SVK
*ELASTIC
1000., 0.
*DENSITY
1.
*SOLID SECTION, ELSET=BARS, MATERIAL=SVK
1.
*BOUNDARY
FEET, 1, 3
3, 1, 1
3, 3, 3
*STEP, NLGEOM, INC=200
*STATIC, RIKS
0.29, 1., 1e-6, 1., 4.3549
*CLOAD
3, 2, -1.
*OUTPUT, HISTORY
*NODE OUTPUT, NSET=APEX
U2
*NODE PRINT, NSET=FEET, TOTALS=YES
RF
*ENERGY OUTPUT
ALLSE, ALLWK
*OUTPUT, FIELD
*NODE OUTPUT
U
*END STEP
"""
text, m, rows = import_and_run("riks", RIKS)
check(m is not None and m["analysis"].get("path", {}).get("method") == "arc_length"
      and m["analysis"]["path"].get("max_steps") == 200,
      f"RIKS: analysis.path arc length, max_steps from INC= ({text[-500:]})")
check("normals given on the node lines" in text, "a node line with a normal: read, with a warning")
check("field output" in text, "*OUTPUT, FIELD: said to be in the frames")
if m:
    names = [h["name"] for h in m["output"]["history"]]
    check(names == ["U2_3", "RF1_FEET", "RF2_FEET", "RF3_FEET", "ALLSE", "ALLWK"],
          f"output requests as history columns: {names}")
if rows:
    h, L0 = 0.2, 1.04 ** 0.5
    worst = max(abs(float(r["time"]) - 1000 * (h + float(r["U2_3"])) * (h * h - (h + float(r["U2_3"])) ** 2)
                    / L0 ** 3) for r in rows)
    check(worst < 1e-6, f"RIKS: the snap-through on the analytic curve ({worst:.1e} off)")
    check(min(h + float(r["U2_3"]) for r in rows) < -h and abs(float(rows[-1]["time"]) - 4.3549) < 1e-9,
          "RIKS: through the inverted position to the maximum load factor")
    check(max(abs(float(r["RF2_FEET"]) - float(r["time"])) for r in rows) < 1e-6,
          "RIKS: the feet's reaction is the load")
else:
    check(False, f"RIKS runs: {text[-800:]}")

# ---- initial stress as prestress ----
SHEET = """*NODE, NSET=ALL
1, 0., 0., 0.
2, 1., 0., 0.
3, 2., 0., 0.
4, 0., 1., 0.
5, 1., 1., 0.
6, 2., 1., 0.
7, 0., 2., 0.
8, 1., 2., 0.
9, 2., 2., 0.
*NSET, NSET=EDGE
1, 2, 3, 4, 6, 7, 8, 9
*ELEMENT, TYPE=M3D4, ELSET=S
1, 1, 2, 5, 4
2, 2, 3, 6, 5
3, 4, 5, 8, 7
4, 5, 6, 9, 8
*MATERIAL, NAME=M
*ELASTIC
1000., 0.3
*DENSITY
1.
*MEMBRANE SECTION, ELSET=S, MATERIAL=M
0.1
*INITIAL CONDITIONS, TYPE=STRESS
S, 50., 20., 0.
*BOUNDARY
EDGE, 1, 3
*STEP, NLGEOM
*STATIC
0.5, 1.
*DLOAD
S, P, -1.
*NODE PRINT, NSET=EDGE
RF3
*NODE PRINT
U3
*END STEP
"""
text, m, rows = import_and_run("prestress", SHEET)
check(m is not None and m["sections"][0].get("prestress") == [50, 20, 0],
      f"*INITIAL CONDITIONS, TYPE=STRESS: the section's prestress ({text[-500:]})")
twin = {"mesh": {"nodes": [[i + 1, float(i % 3), float(i // 3), 0.0] for i in range(9)],
                 "elements": [{"set": "S", "type": "quad4",
                               "connectivity": [[1, 2, 5, 4], [2, 3, 6, 5], [4, 5, 8, 7], [5, 6, 9, 8]]}]},
        "materials": {"m": {"type": "isotropic", "E": 1000.0, "nu": 0.3, "density": 1.0}},
        "sections": [{"elements": "S", "material": "m", "thickness": 0.1,
                      "axes": {"points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}, "prestress": [50.0, 20.0, 0.0]}],
        "boundary": [{"nodes": [1, 2, 3, 4, 6, 7, 8, 9], "fix": ["x", "y", "z"]}],
        "loads": [{"type": "pressure", "elements": "S", "value": 1.0, "function": "r"}],
        "functions": {"r": {"type": "ramp", "duration": 1.0}},
        "analysis": {"type": "static", "time": {"end": 1.0, "step": 0.5, "min_step": 1e-5}},
        "output": {"history": [{"name": "w", "quantity": "displacement", "node": 5, "component": "z"}]}}
write("prestress_twin.yaml", yaml.safe_dump(twin))
rc, t2 = velum("run", os.path.join(WORK, "prestress_twin.yaml"), "-o", os.path.join(WORK, "twin_out"), "-q")
if rows and rc == 0:
    w = float(list(csv.DictReader(open(os.path.join(WORK, "twin_out", "history.csv"))))[-1]["w"])
    check(abs(float(rows[-1]["U3_5"]) - w) < 1e-9 * abs(w) and w > 0,
          f"prestressed sheet: centre {rows[-1]['U3_5']} against the YAML twin {w}")
    check(abs(float(rows[-1]["RF3_EDGE"]) + 4.0) < 1e-6, f"pressure 1 on area 4: RF3 {rows[-1]['RF3_EDGE']}")
else:
    check(False, f"prestress runs: {text[-500:]} {t2[-500:]}")

# ---- includes ----
os.makedirs(os.path.join(WORK, "inc"))
with open(os.path.join(WORK, "inc", "node data, part 1.inp"), "w") as f:
    f.write("1, 0., 0., 0.\n2, 1., 0., 0.\n")
with open(os.path.join(WORK, "inc", "more nodes.inp"), "w") as f:
    f.write("3, 1., 1., 0.\n4, 0., 1., 0.\n")
deck = MESH.replace("1, 0., 0., 0.\n2, 1., 0., 0.\n3, 1., 1., 0.\n4, 0., 1., 0.\n",
                    "*INCLUDE, INPUT=\"node data, part 1.inp\"\n*INCLUDE, INPUT='more nodes.inp'\n")
deck_path = os.path.join(WORK, "inc", "deck.inp")
with open(deck_path, "w") as f:
    f.write(deck + step("*CLOAD\nTIP, 1, 1.\n"))
rc, text = velum("import", deck_path, "-o", os.path.join(WORK, "inc", "model.yaml"))
check(rc == 0 and "4 nodes" in text, f"*INCLUDE of data lines inside *NODE, quoted names: {text[-500:]}")

# ---- the deck is not overwritten ----
before = open(deck_path).read()
rc, text = velum("import", deck_path, "-o", deck_path)
check(rc == 1 and "the output is the deck itself" in text and open(deck_path).read() == before,
      f"import -o the deck: refused, deck intact ({rc}: {text[-300:]})")
rc, text = velum("import", deck_path, "-o", os.path.join(WORK, "inc", "..", "inc", "deck.inp"))
check(rc == 1 and open(deck_path).read() == before, "import -o the deck by another path: refused")

print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
