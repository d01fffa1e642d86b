"""`bench/compare-ccx --explicit N`: explicit dynamics side by side with CalculiX (issue 46).

The square of compare-ccx (side 1.2/sqrt(2) m, E = 588 MPa, nu = 0.4, t = 0.6 mm, edges held,
a small dome so that the flat sheet is not singular) on an N x N quad4 mesh, struck at t = 0 by
a 5 kPa follower pressure held constant, run to the same end time by central differences in
both codes, each at its own stable step: Velum at 0.9 of its estimate (membrane wave speed
over the element), CalculiX's *DYNAMIC, EXPLICIT with its automatic increment (with DIRECT
CalculiX 2.20 never advances past t = 0 on membranes). CalculiX expands each M3D4 membrane
into a layer of bricks, so its stable step is set by the wave crossing the thickness: about a
hundred times shorter than the membrane's own. Printed: steps, CPU, CPU per element-step, the
centre's height at the end (CalculiX prints the centre at every increment: that is how its
increments are counted), and the CPU ratio for the same simulated time.
"""
import csv
import json
import math
import os


def write_velum(d, m, end, write_msh):
    write_msh(os.path.join(d, "mesh.msh"), m)
    sets = "\n".join(f"    {k}: [{', '.join(map(str, v))}]" for k, v in m["sets"].items())
    with open(os.path.join(d, "model.yaml"), "w") as f:
        f.write(f"""title: compare-ccx explicit
mesh:
  file: mesh.msh
  node_sets:
{sets}
materials:
  film: {{type: isotropic, E: {m['E']!r}, nu: {m['nu']!r}, density: 1000.0}}
sections:
  - {{elements: sheet, material: film, thickness: {m['t']!r}}}
boundary:
  - {{nodes: edge, fix: [x, y, z]}}
loads:
  - {{type: pressure, elements: sheet, value: {m['p']!r}}}
analysis:
  type: dynamic
  integrator: {{scheme: central-difference}}
  time: {{end: {end!r}, step: {end!r}}}
output:
  directory: out
  interval: {end!r}
  fields: false
  history:
    - {{name: zc, quantity: position, node: {m['centre']}, component: z}}
""")


def write_ccx(d, m, end):
    with open(os.path.join(d, "run.inp"), "w") as f:
        f.write("*HEADING\ncompare-ccx explicit\n*NODE\n")
        for k, (x, y, z) in m["nodes"].items():
            f.write(f"{k},{x:.12g},{y:.12g},{z:.12g}\n")
        f.write("*ELEMENT,TYPE=M3D4,ELSET=EALL\n")
        for e, c in enumerate(m["elems"], 1):
            f.write(f"{e},{','.join(map(str, c))}\n")
        f.write("*NSET,NSET=EDGE\n")
        edge = m["sets"]["edge"]
        for i in range(0, len(edge), 12):
            f.write(",".join(map(str, edge[i:i + 12])) + "\n")
        f.write(f"*NSET,NSET=CENTRE\n{m['centre']}\n*BOUNDARY\nEDGE,1,3\n")
        f.write(f"*MATERIAL,NAME=FILM\n*ELASTIC\n{m['E']!r},{m['nu']!r}\n*DENSITY\n1000.\n"
                f"*MEMBRANE SECTION,ELSET=EALL,MATERIAL=FILM\n{m['t']!r}\n")
        # held from t = 0 (CalculiX ramps a load over the step unless told otherwise)
        f.write("*SURFACE,NAME=SLOAD,TYPE=ELEMENT\nEALL,SNEG\n*AMPLITUDE,NAME=HELD\n0.,1.,1.,1.\n")
        f.write(f"*STEP,NLGEOM,INC=100000000\n*DYNAMIC,EXPLICIT\n{end / 100!r},{end!r}\n"
                f"*DSLOAD,AMPLITUDE=HELD\nSLOAD,P,{m['p']!r}\n*NODE PRINT,NSET=CENTRE,FREQUENCY=1\nU\n"
                "*END STEP\n")


def run(args, square_mesh, write_msh, timed):
    n, end = args.explicit, args.explicit_end
    m = square_mesh(n, incs=1)
    elements = len(m["elems"])
    base = os.path.join(args.out, f"explicit-{n}")
    rows = []
    d = os.path.join(base, "velum")
    os.makedirs(d, exist_ok=True)
    write_velum(d, m, end, write_msh)
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    rc, wall, cpu, rss, out = timed([args.velum, "run", "model.yaml", "-o", "out", "--quiet",
                                     "--threads", "1"], d, env)
    try:
        s = json.load(open(os.path.join(d, "out", "summary.json")))
        steps = s.get("steps", float("nan"))
        hist = list(csv.reader(open(os.path.join(d, "out", "history.csv"))))
        zc = float(hist[-1][1])
    except (OSError, ValueError, IndexError, KeyError):
        steps, zc = float("nan"), float("nan")
    rows.append(dict(code="velum", rc=rc, cpu=cpu, steps=steps, zc=zc))
    d = os.path.join(base, "ccx")
    os.makedirs(d, exist_ok=True)
    write_ccx(d, m, end)
    try:
        rc, wall, cpu, rss, out = timed(["ccx", "-i", "run"], d, env, args.ccx_timeout)
    except Exception:  # subprocess.TimeoutExpired
        rc, cpu = -1, float("nan")
    steps, zc = float("nan"), float("nan")
    try:
        # the centre's displacement is printed at every increment (the .sta file stays empty
        # in explicit runs): the blocks count the increments
        blocks = open(os.path.join(d, "run.dat")).read().split("displacements")
        steps = len(blocks) - 1
        dat = blocks[-1]
        vals = [ln.split() for ln in dat.strip().splitlines()[1:] if ln.split()]
        zc = m["nodes"][m["centre"]][2] + float(vals[-1][3])
    except (OSError, ValueError, IndexError):
        pass
    rows.append(dict(code="ccx", rc=rc, cpu=cpu, steps=steps, zc=zc))
    print(f"explicit square n = {n} ({elements} quad4), 5 kPa from t = 0 to {end:g} s, one thread")
    print("| code | exit | steps | CPU s | µs per element-step | centre z at the end [m] |")
    print("|---|---:|---:|---:|---:|---:|")
    for r in rows:
        steps = r["steps"]
        per = 1e6 * r["cpu"] / (elements * steps) if math.isfinite(steps) and steps > 0 else float("nan")
        print(f"| {r['code']} | {r['rc']} | {r['steps']} | {r['cpu']:.3f} | {per:.3f} | {r['zc']:.6g} |")
    z0 = m["nodes"][m["centre"]][2]
    print(f"free flight (no membrane force) would reach {z0 + 0.5 * m['p'] / (1000.0 * m['t']) * end ** 2:.6g} m; "
          f"a load ramped over the step, {z0 + m['p'] / (6000.0 * m['t']) * end ** 2:.6g} m")
    v, c = rows
    if v["cpu"] > 0 and math.isfinite(c["cpu"]):
        print(f"CPU ratio CalculiX / Velum for the same simulated time: {c['cpu'] / v['cpu']:.0f}x")
    with open(os.path.join(base, "results.json"), "w") as f:
        json.dump(rows, f, indent=1)
